#pragma once
// The ranked, index-based CW complex of cw4d.
//
// Rank 0 holds vertex coordinates (ambient_dim x V, one column per vertex). Every element of
// rank k >= 1 holds the ids of its (k-1)-dimensional boundary elements with an orientation sign
// (+1 / -1), in compressed rows (offsets + ids + signs); the same table type serves every rank.
//
// Row conventions:
//  * rank 1 (edges): exactly [tail, head] with signs [-1, +1], i.e. boundary = head - tail.
//  * rank 2 (faces): signed edge ids in cycle order; a sign of +1 means the edge is traversed
//    tail -> head, and the head of each entry is the tail of the next (the last closes the loop).
//  * rank k >= 3: signed ids of (k-1)-elements in no particular order, such that the boundary of
//    the boundary cancels (the sum of sign * boundary(child) is zero).
//
// A "closed" complex in R^n stores the boundary of a solid: its facets are the elements of rank
// n-1 and every ridge (rank n-2) bounds exactly two facets with opposite signs. Facets are
// oriented outward (Stokes convention: an oriented frame (e_1..e_{n-1}) of a facet satisfies
// det(N, e_1, ..., e_{n-1}) > 0 for its outward normal N; in R^3 that is the usual
// counter-clockwise-seen-from-outside rule). An optional element of rank n is the solid itself,
// with sign +1 for every outward facet. The structure is not tied to four dimensions.
#include <Eigen/Core>

#include <array>
#include <cassert>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cw4d/complex/index.hpp"

namespace cw4d {

/// One compressed table of boundaries: row i lists the ids and signs of element i's boundary.
/// A table with no rows holds no storage (constructing one allocates nothing); its offsets()
/// are still {0}.
class Incidence {
 public:
  std::size_t size() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
  bool empty() const { return size() == 0; }
  std::size_t entries() const { return ids_.size(); }
  std::size_t row_size(std::size_t row) const {
    assert(row < size());
    return offsets_[row + 1] - offsets_[row];
  }
  std::span<const std::uint32_t> ids(std::size_t row) const {
    return {ids_.data() + offsets_[row], row_size(row)};
  }
  std::span<const std::int8_t> signs(std::size_t row) const {
    return {signs_.data() + offsets_[row], row_size(row)};
  }
  std::span<std::uint32_t> ids_mut(std::size_t row) {
    return {ids_.data() + offsets_[row], row_size(row)};
  }
  std::span<std::int8_t> signs_mut(std::size_t row) {
    return {signs_.data() + offsets_[row], row_size(row)};
  }

  /// Appends a row and returns its index. ids and signs have the same length.
  std::uint32_t add_row(std::span<const std::uint32_t> ids, std::span<const std::int8_t> signs);
  void reserve(std::size_t rows, std::size_t entries);
  void clear();

  /// Row i's entries are [offsets()[i], offsets()[i + 1]); size() + 1 values, the first 0.
  const std::vector<std::uint32_t>& offsets() const {
    return offsets_.empty() ? no_rows_offsets() : offsets_;
  }
  const std::vector<std::uint32_t>& all_ids() const { return ids_; }
  const std::vector<std::int8_t>& all_signs() const { return signs_; }

  /// The three arrays themselves, for writers that lay out many rows in place (resize, then
  /// fill). The caller restores the invariant: offsets starts with 0, does not decrease and
  /// ends with ids.size() == signs.size(); or all three are left empty (a table of no rows,
  /// the state of a new table, whose offsets array is empty until a row is written).
  struct Storage {
    std::vector<std::uint32_t>& offsets;
    std::vector<std::uint32_t>& ids;
    std::vector<std::int8_t>& signs;
  };
  Storage storage() { return {offsets_, ids_, signs_}; }

  /// The table's own invariants: offsets start with 0, never decrease and end at entries() ==
  /// signs' length, every id is below lower_count (the number of elements one rank down) and
  /// every sign is +1 or -1. For assert()s on data cw4d built itself; validate() checks data
  /// from outside and reports what is wrong.
  bool well_formed(std::size_t lower_count) const;
  /// The part of well_formed that makes rows readable: offsets start with 0, never decrease and
  /// end at entries() == the signs' length (or all three arrays are empty).
  bool rows_readable() const;

 private:
  static const std::vector<std::uint32_t>& no_rows_offsets();

  std::vector<std::uint32_t> offsets_;  // empty: no rows (read as {0})
  std::vector<std::uint32_t> ids_;
  std::vector<std::int8_t> signs_;
};

/// A color with components in [0, 1].
struct Rgba {
  float r = 1, g = 1, b = 1, a = 1;
  friend bool operator==(const Rgba&, const Rgba&) = default;
};

/// A stamp that names one state of a Complex: drawn from one process-wide counter, so that no
/// two states of any complexes in the process share a stamp. Copies and moves take fresh stamps
/// (a moved-from object has changed too).
class Revision {
 public:
  Revision() : value_(next()) {}
  Revision(const Revision&) : value_(next()) {}
  Revision(Revision&& other) noexcept : value_(next()) { other.value_ = next(); }
  Revision& operator=(const Revision&) {
    value_ = next();
    return *this;
  }
  Revision& operator=(Revision&& other) noexcept {
    value_ = next();
    other.value_ = next();
    return *this;
  }
  ~Revision() = default;

  std::uint64_t value() const { return value_; }
  void bump() { value_ = next(); }

 private:
  static std::uint64_t next() noexcept;
  std::uint64_t value_;
};

class Complex {
 public:
  /// An empty complex whose vertices live in R^ambient_dim (ambient_dim >= 1).
  explicit Complex(int ambient_dim = 4);

  int ambient_dim() const { return dim_; }
  /// Highest rank that has a boundary table (0 when there are only vertices).
  int top_rank() const { return static_cast<int>(boundaries_.size()); }
  /// Number of elements of a rank (0 for ranks above top_rank()).
  std::size_t count(int rank) const;
  /// Counts of ranks 0..top_rank().
  std::vector<std::size_t> fvector() const;
  bool empty() const { return count(0) == 0; }

  /// A stamp of the complex's current state, unique in the process: every non-const member
  /// (the *_mut() accessors, set_*, add_edge, flip, truncate, assignment) and every copy or move
  /// takes a new one. Caches keyed on (address, revision), as section()'s compiled models, see
  /// a change only through these calls: a reference returned by a *_mut() accessor marks the
  /// complex changed when it is taken, so writes through a reference kept past a later read by
  /// such a cache are not seen. Take the accessor again, or call touch(), after such writes.
  std::uint64_t revision() const { return revision_.value(); }
  /// Marks the complex changed (a new revision()), for writes through a kept reference.
  void touch() { revision_.bump(); }

  /// Rank of the facets, ambient_dim - 1.
  int facet_rank() const { return dim_ - 1; }
  /// True when the rank-ambient_dim element (the solid) is stored.
  bool has_solid() const { return top_rank() >= dim_ && count(dim_) > 0; }

  // --- vertices -------------------------------------------------------------------------
  /// ambient_dim x V, column i is vertex i.
  const Eigen::MatrixXd& positions() const { return positions_; }
  Eigen::MatrixXd& positions_mut() {
    touch();
    return positions_;
  }
  auto position(std::uint32_t v) const { return positions_.col(v); }
  /// Replaces all vertex positions (rows must equal ambient_dim).
  void set_positions(Eigen::MatrixXd positions);

  // --- boundaries -------------------------------------------------------------------------
  /// Boundary table of rank k (1 <= k <= top_rank()).
  const Incidence& boundary(int rank) const { return boundaries_.at(rank - 1); }
  /// Boundary table of rank k, created (with lower empty tables) when missing.
  Incidence& boundary_mut(int rank);
  /// Drops every table above max_rank.
  void truncate(int max_rank);

  /// Edge e as (tail, head).
  std::array<std::uint32_t, 2> edge(std::uint32_t e) const {
    assert(!boundaries_.empty() && boundaries_[0].row_size(e) == 2);
    auto ids = boundaries_[0].ids(e);
    return {ids[0], ids[1]};
  }
  /// Appends an edge tail -> head and returns its id.
  std::uint32_t add_edge(std::uint32_t tail, std::uint32_t head);

  /// Reverses the orientation of element i of a rank (rank 1: swap ends; rank 2: reverse the
  /// cycle; rank >= 3: negate the signs). Callers keep higher ranks consistent.
  void flip(int rank, std::uint32_t i);

  /// Vertices of face f in cycle order (the tail of each signed edge).
  std::vector<std::uint32_t> face_cycle(std::uint32_t f) const;
  /// Some vertex of element i of a rank (the first reached through first boundary entries).
  std::uint32_t first_vertex(int rank, std::uint32_t i) const;
  /// Sorted, unique vertex ids of element i of a rank.
  std::vector<std::uint32_t> vertices_of(int rank, std::uint32_t i) const;

  // --- per-element data -----------------------------------------------------------------
  /// Outward unit normals of the facets, ambient_dim x count(facet_rank()); empty (0 columns)
  /// when not computed.
  const Eigen::MatrixXd& facet_normals() const { return facet_normals_; }
  void set_facet_normals(Eigen::MatrixXd normals) {
    touch();
    facet_normals_ = std::move(normals);
  }
  bool has_facet_normals() const {
    return facet_normals_.cols() > 0 &&
           static_cast<std::size_t>(facet_normals_.cols()) == count(facet_rank());
  }

  /// The structural invariants of the data model (for assert()s, as Incidence::well_formed):
  /// ambient_dim rows of positions, every table well formed against the rank below, every edge
  /// row exactly [tail, head] with signs [-1, +1], every face row one closed walk (the head of
  /// each signed edge is the tail of the next; in R^2, where rank 2 is the solid, not checked).
  bool well_formed() const;

  /// Optional colors of the elements of a rank (empty vector = no colors).
  const std::vector<Rgba>& colors(int rank) const;
  std::vector<Rgba>& colors_mut(int rank);

 private:
  int dim_;
  Eigen::MatrixXd positions_;
  std::vector<Incidence> boundaries_;  // boundaries_[k-1] = table of rank k
  Eigen::MatrixXd facet_normals_;
  std::vector<std::vector<Rgba>> colors_;  // colors_[k] = colors of rank k
  Revision revision_;
};

}  // namespace cw4d
