#include "cw4d/section/section.hpp"

#include "cw4d/section/provenance.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/section/slicer.hpp"
#include "general.hpp"

namespace cw4d {

namespace {

struct Term {
  std::uint32_t id;
  int coef;
};

// Images of the model's elements of one rank: for element i, the signed section elements
// (terms) its cut consists of, in compressed rows.
struct ImageTable {
  std::vector<std::uint32_t> offsets{0};
  std::vector<Term> terms;
  void push(std::span<const Term> t) {
    terms.insert(terms.end(), t.begin(), t.end());
    offsets.push_back(static_cast<std::uint32_t>(terms.size()));
  }
  std::span<const Term> row(std::uint32_t i) const {
    return {terms.data() + offsets[i], offsets[i + 1] - offsets[i]};
  }
};

// The order of points along the line they lie on, deterministically: the points are projected
// on the direction from the first point to the farthest one and sorted by that coordinate, ties
// (coincident projections) broken by the points' order in the input, which is the order of
// their ids in the combined chain. Returns the permutation.
template <class At>
std::vector<std::size_t> order_along_line(std::size_t n, At at) {
  std::size_t far = 0;
  double best = -1.0;
  for (std::size_t i = 1; i < n; ++i) {
    const double d = (at(i) - at(0)).squaredNorm();
    if (d > best) best = d, far = i;
  }
  const Eigen::VectorXd dir = at(far) - at(0);
  std::vector<double> key(n);
  for (std::size_t i = 0; i < n; ++i) key[i] = (at(i) - at(0)).dot(dir);
  std::vector<std::size_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  return order;
}

// The ON band made consistent with the geometry. Counting an ON vertex v as lying on the plane
// moves every crossing of the plane with the line of an edge (v, b) to v: by |t| |b - v| with
// t = s_v / (s_v - s_b). For a vertex of an element that is nearly parallel to the plane that
// distance is not small (a plane tilted 1e-12 rad from a cell of the 120-cell would snap every
// vertex within 0.2 of the cut line of that cell, bending the cell's cut polygon off its
// plane). So v stays ON only while the move is within the weld distance along every edge to a
// vertex that is not ON; otherwise it takes the sign of its own value s_v (exact: plane_value),
// which may in turn move its ON neighbours: settled to the fixed point, in vertex order. What
// remains ON is either exactly on the plane or within rounding of it with every crossing near,
// so the section is the exact section of the given plane up to the weld distance, except that
// a plane within the ON band of a whole element (every vertex of a cell, say, and steep edges
// leaving it) contains that element.
void settle_on_band(const Complex& model, const std::vector<double>& s, std::vector<Side>& side,
                    double weld) {
  const std::size_t nv = model.count(0), ne = model.top_rank() >= 1 ? model.count(1) : 0;
  std::vector<std::uint32_t> start(nv + 1, 0), adj(2 * ne);
  for (std::uint32_t e = 0; e < ne; ++e) {
    const auto [a, b] = model.edge(e);
    ++start[a + 1];
    ++start[b + 1];
  }
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::uint32_t e = 0; e < ne; ++e) {
    const auto [a, b] = model.edge(e);
    adj[fill[a]++] = b;
    adj[fill[b]++] = a;
  }
  const auto& p = model.positions();
  std::vector<std::uint32_t> work;
  for (std::uint32_t v = 0; v < nv; ++v)
    if (side[v] == Side::On) work.push_back(v);
  std::reverse(work.begin(), work.end());  // popped in vertex order
  while (!work.empty()) {
    const std::uint32_t v = work.back();
    work.pop_back();
    if (side[v] != Side::On || s[v] == 0.0) continue;
    bool far = false;
    for (std::uint32_t i = start[v]; i < start[v + 1] && !far; ++i) {
      const std::uint32_t b = adj[i];
      if (side[b] == Side::On) continue;
      // |t| |b - v| > weld, without dividing (|s_b| exceeds the band, |s_v| does not).
      far = std::abs(s[v]) * (p.col(b) - p.col(v)).norm() > weld * std::abs(s[v] - s[b]);
    }
    if (!far) continue;
    side[v] = s[v] > 0.0 ? Side::Positive : Side::Negative;
    for (std::uint32_t i = start[v]; i < start[v + 1]; ++i)
      if (side[adj[i]] == Side::On) work.push_back(adj[i]);
  }
}

// Crossings on edges nearly parallel to the plane, placed on the model's cells. A crossing at
// t = s_a / (s_a - s_b) moves along its edge by |b - a| / |s_a - s_b| times any error in s_a or
// s_b, and the vertices of a cell are coplanar only up to their rounding: for a plane tilted
// 1e-12 rad from a cell of the 120-cell, rounding of 1e-15 moves the crossings on that cell's
// edges by 1e-3, so its cut polygon is neither planar nor convex. So where sin(edge, plane) =
// |s_a - s_b| / (|n| |b - a|) is below tol::near_parallel_edge, the crossing is instead the
// point of the plane nearest (least squares, each equation normalised to distance within the
// plane) to the hyperplanes of the model's facets that contain the edge, each the facet's
// outward normal N through the mean of N . x over its vertices. Every such crossing of one
// facet then satisfies that facet's one plane equation, so the facet's cut is planar, and the
// section is the cut of the polytope of those facet hyperplanes. The equations are formed with
// the normal split as N = sigma n + Delta (Delta exact for N close to +-n), so a cell nearly
// parallel to the plane keeps its tilt to full relative precision.
//
// The sides of the ends of those edges are decided in the same polytope: a vertex's value is
// the signed distance from the plane of the point where the hyperplanes of its facets meet
// (solved in the same frame, from the same equations), not n.x - d of its rounded position.
// Rounding of the positions puts the plane's trace in a nearly parallel cell only to within
// (rounding / tilt) (1e-3 of the cell at 1e-13 rad): a vertex that close to the trace could
// otherwise be on one side by its own value and on the other in the facet hyperplanes, and the
// crossing the facets place on one of its edges would fall beyond the edge's end.
struct PlaneFrame {
  Eigen::VectorXd unit, origin;  // unit normal, a point of the plane
  double offset = 0.0;
  Eigen::MatrixXd basis;  // n x (n-1)
};

class FacetPlanes {
 public:
  // The edges nearly parallel to the plane (by the vertices' own values s), and for the model
  // not moved (world != nullptr) the section's own frame, so that z below are the section
  // coordinates themselves: the point o + B z of the frame is the point of the section, and an
  // error in z is an error of the same size in the section.
  FacetPlanes(const Complex& model, const Eigen::VectorXd& nm, double dm,
              const std::vector<double>& s, const Hyperplane* world)
      : model_(model), n_(model.ambient_dim()), len_n_(nm.norm()) {
    const int fr = n_ - 1;
    if (!model.has_facet_normals() || model.top_rank() < fr || fr < 2 || model.count(1) == 0)
      return;
    const auto& p = model.positions();
    parallel_.assign(model.count(1), 0);
    bool any = false;
    for (std::uint32_t e = 0; e < model.count(1); ++e) {
      const auto [a, b] = model.edge(e);
      const double len = (p.col(b) - p.col(a)).norm();
      if (std::abs(s[a] - s[b]) < tol::near_parallel_edge * len_n_ * len) parallel_[e] = any = 1;
    }
    if (!any) {
      parallel_.clear();
      return;
    }
    // The facets above an edge or a vertex's edges (place, settle_values), found by walking up
    // the ranks, edges -> faces -> ... -> facets, through parent lists in compressed rows.
    wanted_.assign(model.count(0), 0);
    for (std::uint32_t e = 0; e < model.count(1); ++e) {
      if (!parallel_[e]) continue;
      const auto [a, b] = model.edge(e);
      wanted_[a] = wanted_[b] = 1;
    }
    parent_start_.resize(fr + 1);
    parent_ids_.resize(fr + 1);
    up_mark_.resize(fr + 1);
    for (int r = 2; r <= fr; ++r) {
      const Incidence& table = model.boundary(r);
      auto& offsets = parent_start_[r];
      auto& ids = parent_ids_[r];
      offsets.assign(model.count(r - 1) + 1, 0);
      for (std::uint32_t x = 0; x < table.size(); ++x)
        for (auto id : table.ids(x)) ++offsets[id + 1];
      for (std::size_t i = 1; i < offsets.size(); ++i) offsets[i] += offsets[i - 1];
      ids.resize(offsets.back());
      std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
      for (std::uint32_t x = 0; x < table.size(); ++x)  // parents in increasing order
        for (auto id : table.ids(x)) ids[fill[id]++] = x;
      up_mark_[r].assign(model.count(r), 0);
    }
    rows_.resize(model.count(fr));
    have_row_.assign(model.count(fr), 0);
    row_u_.resize(model.count(fr) * static_cast<std::size_t>(n_ - 1));
    nf_.resize(n_);
    u_.resize(n_ - 1);
    frame_.unit = world ? world->normal : Eigen::VectorXd(nm / len_n_);
    frame_.offset = world ? world->offset : dm / len_n_;
    frame_.origin = frame_.offset * frame_.unit;
    frame_.basis = hyperplane_basis(frame_.unit);
    for (int j = 0; j < n_ - 1; ++j) basis_cols_.emplace_back(frame_.basis.col(j));
    seen_.resize(n_ - 1);
    for (int k = 0; k < n_ - 1; ++k) seen_[k].assign(model.count(k), 0);
  }

  bool active() const { return !parallel_.empty(); }
  bool parallel(std::uint32_t e) const { return !parallel_.empty() && parallel_[e]; }
  const PlaneFrame& frame() const { return frame_; }

  // The ends of the nearly parallel edges: s replaced by the value of the point where their
  // facets' hyperplanes meet (times |n|, as s), where those pin a point.
  //
  // Only where the new value can be read. After this pass s is read for the side of every
  // vertex (classify_side with `tolerance`), for the crossings of edges whose ends differ in
  // side or lie ON, and for the non-ON neighbours of ON vertices (settle_on_band). A vertex
  // whose side no settling can change (certain below), with every neighbour certain and on its
  // side, is read only for its side, so it keeps its own value: the same sections, bit for
  // bit, without its solve. The bound: the settled point y* is the least-squares meet of the
  // vertex's facet hyperplanes, solved only when the normal matrix's smallest eigenvalue is at
  // least 1e-6 (invertible), so |y* - y_v| <= |r| / sqrt(1e-6) for the vertex's own point y_v
  // and its residuals r_f = N_f . p_v - level_f; the value moves by at most |n| times that.
  // Twice that factor, plus 1e-9 of the model's scale for the rounding of every term, keeps it
  // a bound with a wide margin. `max_norm` is the largest vertex norm.
  void settle_values(std::vector<double>& s, double tolerance, double max_norm) {
    if (!active()) return;
    const std::size_t nv = model_.count(0);
    const std::vector<char>& wanted = wanted_;
    // The facets above each wanted vertex's edges, in increasing order, in compressed rows:
    // around[start[v], start[v + 1]).
    std::vector<std::uint32_t> edge_start(nv + 1, 0), edge_ids(2 * model_.count(1));
    for (std::uint32_t e = 0; e < model_.count(1); ++e) {
      const auto [a, b] = model_.edge(e);
      ++edge_start[a + 1];
      ++edge_start[b + 1];
    }
    for (std::size_t v = 0; v < nv; ++v) edge_start[v + 1] += edge_start[v];
    {
      std::vector<std::uint32_t> fill(edge_start.begin(), edge_start.end() - 1);
      for (std::uint32_t e = 0; e < model_.count(1); ++e) {
        const auto [a, b] = model_.edge(e);
        edge_ids[fill[a]++] = e;
        edge_ids[fill[b]++] = e;
      }
    }
    std::vector<std::uint32_t> start(nv + 1, 0), around;
    for (std::uint32_t v = 0; v < nv; ++v) {
      if (wanted[v]) {
        const std::vector<std::uint32_t>& facets =
            facets_above({edge_ids.data() + edge_start[v], edge_ids.data() + edge_start[v + 1]});
        around.insert(around.end(), facets.begin(), facets.end());
      }
      start[v + 1] = static_cast<std::uint32_t>(around.size());
    }
    // certain[v]: classify_side gives v the same side before and after settling.
    const auto& p = model_.positions();
    const auto& normals = model_.facet_normals();
    const double slack = 1e-9 * (max_norm + std::abs(frame_.offset));
    std::vector<char> certain(nv), settle(nv, 0);
    for (std::uint32_t v = 0; v < nv; ++v) {
      double bound = 0.0;
      if (wanted[v]) {
        double r2 = 0.0;
        for (std::uint32_t i = start[v]; i < start[v + 1]; ++i) {
          const std::uint32_t f = around[i];
          const double r = normals.col(f).dot(p.col(v)) - row_of(f).level;
          r2 += r * r;
        }
        bound = len_n_ * (2e3 * std::sqrt(r2) + slack);
      }
      certain[v] = std::abs(s[v]) > tolerance + bound;
      settle[v] = wanted[v] && !certain[v];
    }
    for (std::uint32_t e = 0; e < model_.count(1); ++e) {
      const auto [a, b] = model_.edge(e);
      if (!(certain[a] && certain[b] && (s[a] > 0.0) == (s[b] > 0.0))) settle[a] = settle[b] = 1;
    }
    Eigen::MatrixXd m(n_, n_);
    Eigen::VectorXd rhs(n_), row(n_), hi(n_), lo(n_), g(n_), dy(n_), coef(2 * n_), at(2 * n_);
    Eigen::VectorXd work(n_);
    EigenSolver eig(n_);
    for (std::uint32_t v = 0; v < nv; ++v) {
      if (!wanted[v] || !settle[v]) continue;
      const std::span<const std::uint32_t> list(around.data() + start[v],
                                                around.data() + start[v + 1]);
      // Unknowns (z, sigma): the point o + B z + sigma n; a facet's equation in them is
      // (B^T N) . z + (N . n) sigma = level - N . o.
      m.setZero();
      rhs.setZero();
      for (const std::uint32_t f : list) {
        const Row& r = row_of(f);
        row.head(n_ - 1) = u_of(f);
        row[n_ - 1] = r.c;
        for (int j = 0; j < n_; ++j)  // m += row row^T, element by element
          for (int i = 0; i < n_; ++i) m(i, j) += row[i] * row[j];
        rhs += r.rhs * row;
      }
      // One decomposition of m serves the solve and both refinements below.
      eig.compute(m);
      if (!invertible(eig)) continue;
      solve(eig, rhs, work, hi);
      // sigma must be exact to far below the rounding of a solve in doubles: it is ~tilt x
      // (distance from the trace), so an absolute error of 1e-16 is a move of 1e-16 / tilt
      // across the trace (1e-4 at 1e-12 rad), and a vertex that near the trace would take
      // the other side than place() (whose normalised rows have no such loss) finds, which
      // then puts the crossing beyond the edge's end and leaves it at its rounded t: a cut
      // polygon off its plane, a non-convex section. So the solution is refined, kept as an
      // unevaluated sum hi + lo, with residuals in twice the working precision (plane_value):
      // every row's coefficients and right-hand side are exact to full relative precision,
      // so sigma becomes exact to about 1e-30 absolute.
      lo.setZero();
      for (int pass = 0; pass < 2; ++pass) {
        g.setZero();
        at << hi, lo;
        for (const std::uint32_t f : list) {
          const Row& r = row_of(f);
          row.head(n_ - 1) = u_of(f);
          row[n_ - 1] = r.c;
          coef << row, row;
          g -= plane_value(coef, r.rhs, at.data()) * row;  // (rhs - row . y) row
        }
        solve(eig, g, work, dy);
        lo += dy;
        for (int j = 0; j < n_; ++j) {  // renormalised: hi + lo exactly, |lo| <= ulp(hi) / 2
          const double sum = hi[j] + lo[j], z = sum - hi[j];
          lo[j] = (hi[j] - (sum - z)) + (lo[j] - z);
          hi[j] = sum;
        }
      }
      s[v] = (hi[n_ - 1] + lo[n_ - 1]) * len_n_;
    }
  }

  // Section vertices v on nearly parallel edges: positions (model space) moved onto the facets'
  // hyperplanes, t updated, and (frame the section's own) their section coordinates recorded.
  void place(Section& sec, Eigen::MatrixXd& positions, double weld,
             std::vector<std::pair<std::uint32_t, Eigen::VectorXd>>* coords) {
    if (!active()) return;
    const auto& p = model_.positions();
    for (std::uint32_t v = 0; v < sec.vertex_source.size(); ++v) {
      VertexSource& src = sec.vertex_source[v];
      if (src.rank != 1 || !parallel_[src.element]) continue;
      Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n_ - 1, n_ - 1);
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_ - 1);
      const std::uint32_t edge = src.element;
      for (const std::uint32_t f : facets_above({&edge, 1})) {
        const Row& r = row_of(f);
        u_ = u_of(f);
        const double w = u_.norm();
        if (!(w > 0.0)) continue;
        m += u_ * u_.transpose() / (w * w);
        rhs += (r.rhs / (w * w)) * u_;
      }
      // The facets' traces must pin the point: a well-conditioned system, else t stays.
      const auto z = solve(m, rhs);
      if (!z) continue;
      const Eigen::VectorXd x = frame_.origin + frame_.basis * *z;
      const auto [a, b] = model_.edge(src.element);
      const Eigen::VectorXd ab = p.col(b) - p.col(a);
      const double len2 = ab.squaredNorm();
      const double t = (x - p.col(a)).dot(ab) / len2;
      // On the edge, up to the weld distance beyond its ends (the sides were decided in the
      // same hyperplanes; an end within that distance of the plane may be on either side).
      const double slack = weld / std::sqrt(len2);
      if (!(t > -slack && t < 1.0 + slack)) continue;
      positions.col(v) = x;
      src.t = std::clamp(t, 0.0, 1.0);
      if (coords) coords->push_back({v, *z});
    }
  }

 private:
  // Facet f's equation in the frame; its u = B^T N is u_of(f).
  struct Row {
    double c = 0.0;      // N . n
    double rhs = 0.0;    // level - N . o
    double level = 0.0;  // N . x over the facet's vertices, averaged
  };

  const Row& row_of(std::uint32_t f) {
    Row& r = rows_[f];
    if (have_row_[f]) return r;
    have_row_[f] = 1;
    const auto& p = model_.positions();
    nf_ = model_.facet_normals().col(f);
    const Eigen::VectorXd& nf = nf_;
    const std::vector<std::uint32_t>& verts = facet_vertices(f);
    double level = 0.0;
    for (auto v : verts) level += nf.dot(p.col(v));
    level /= static_cast<double>(verts.size());
    r.level = level;
    // B^T nf to full relative precision (each entry a compensated dot product): for a facet
    // nearly parallel to the plane it is tiny, and its direction decides the trace.
    double* u = row_u_.data() + static_cast<std::size_t>(f) * (n_ - 1);
    for (int j = 0; j < n_ - 1; ++j) u[j] = plane_value(basis_cols_[j], 0.0, nf.data());
    r.c = plane_value(frame_.unit, 0.0, nf.data());
    // nf . (origin + B z) = level  <=>  u . z = level - nf . origin
    r.rhs = -plane_value(nf, level, frame_.origin.data());
    return r;
  }

  // The vertices of facet f in increasing order (Complex::vertices_of's list), walked down the
  // ranks with a stamp per element instead of a sorted list per rank.
  const std::vector<std::uint32_t>& facet_vertices(std::uint32_t f) {
    walk_.assign(1, f);
    for (int k = n_ - 1; k >= 1; --k) {
      const Incidence& table = model_.boundary(k);
      std::vector<std::uint32_t>& seen = seen_[k - 1];
      ++stamp_;
      walk_next_.clear();
      for (auto x : walk_)
        for (auto id : table.ids(x))
          if (seen[id] != stamp_) {
            seen[id] = stamp_;
            walk_next_.push_back(id);
          }
      walk_.swap(walk_next_);
    }
    std::sort(walk_.begin(), walk_.end());
    return walk_;
  }

  using EigenSolver = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>;

  // m y = rhs for m symmetric positive semi-definite; nullopt when m is nearly singular.
  static std::optional<Eigen::VectorXd> solve(const Eigen::MatrixXd& m,
                                              const Eigen::VectorXd& rhs) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(m);
    if (!invertible(eig)) return std::nullopt;
    return solve(eig, rhs);
  }
  static bool invertible(const EigenSolver& eig) { return !(eig.eigenvalues().minCoeff() < 1e-6); }
  // m y = rhs from m's decomposition (invertible(eig)), into y, with a work vector: V (D^-1
  // (V^T rhs)), product by product.
  static Eigen::VectorXd solve(const EigenSolver& eig, const Eigen::VectorXd& rhs) {
    Eigen::VectorXd work(rhs.size()), y(rhs.size());
    solve(eig, rhs, work, y);
    return y;
  }
  static void solve(const EigenSolver& eig, const Eigen::VectorXd& rhs, Eigen::VectorXd& work,
                    Eigen::VectorXd& y) {
    work.noalias() = eig.eigenvectors().transpose() * rhs;
    work = eig.eigenvalues().cwiseInverse().asDiagonal() * work;
    y.noalias() = eig.eigenvectors() * work;
  }

  const Complex& model_;
  int n_;
  double len_n_;
  std::vector<char> parallel_;
  std::vector<char> wanted_;  // per vertex: an end of a nearly parallel edge
  // parent_ids_[r][parent_start_[r][x], parent_start_[r][x + 1]): the elements of rank r whose
  // boundary has element x of rank r - 1, in increasing order (r = 2 .. facet rank).
  std::vector<std::vector<std::uint32_t>> parent_start_, parent_ids_;
  // facets_above's walk: the elements of the current rank, and a stamp per element of each rank
  std::vector<std::vector<std::uint32_t>> up_mark_;
  std::vector<std::uint32_t> up_walk_, up_next_;
  std::uint32_t up_stamp_ = 0;

  // The facets whose boundary reaches one of `edges`, in increasing order (valid until the
  // next call).
  const std::vector<std::uint32_t>& facets_above(std::span<const std::uint32_t> edges) {
    up_walk_.assign(edges.begin(), edges.end());
    ++up_stamp_;
    for (int r = 2; r <= n_ - 1; ++r) {
      std::vector<std::uint32_t>& mark = up_mark_[r];
      const std::vector<std::uint32_t>& first = parent_start_[r];
      const std::vector<std::uint32_t>& ids = parent_ids_[r];
      up_next_.clear();
      for (const std::uint32_t x : up_walk_)
        for (std::uint32_t i = first[x]; i < first[x + 1]; ++i)
          if (mark[ids[i]] != up_stamp_) {
            mark[ids[i]] = up_stamp_;
            up_next_.push_back(ids[i]);
          }
      up_walk_.swap(up_next_);
    }
    std::sort(up_walk_.begin(), up_walk_.end());
    return up_walk_;
  }
  PlaneFrame frame_;
  std::vector<Row> rows_;  // per facet, made on first use (have_row_)
  std::vector<char> have_row_;
  std::vector<double> row_u_;  // n - 1 per facet: the rows' u = B^T N
  Eigen::Map<const Eigen::VectorXd> u_of(std::uint32_t f) const {
    return {row_u_.data() + static_cast<std::size_t>(f) * (n_ - 1), n_ - 1};
  }
  Eigen::VectorXd nf_, u_;                   // row_of's facet normal; place's copy of a row's u
  std::vector<Eigen::VectorXd> basis_cols_;  // frame_.basis's columns
  // facet_vertices' walk: the elements of the current rank, and a stamp per element of each rank
  std::vector<std::uint32_t> walk_, walk_next_;
  std::vector<std::vector<std::uint32_t>> seen_;
  std::uint32_t stamp_ = 0;
};

struct CutResult {
  Section section;
  Eigen::MatrixXd model_positions;  // n x V: section vertices in model space
};

// One pass of the layered algorithm with on-plane vertices counted on side `tie`.
class Cutter {
 public:
  Cutter(const Complex& model, const std::vector<double>& s, const std::vector<Side>& side, int tie,
         bool degenerate, double weld)
      : m_(model),
        s_(s),
        side_(side),
        tie_(tie),
        degenerate_(degenerate),
        weld_(weld),
        n_(model.ambient_dim()),
        out_(model.ambient_dim() - 1) {}

  CutResult run();

 private:
  int perturbed(std::uint32_t v) const {
    return side_[v] == Side::On ? tie_ : static_cast<int>(side_[v]);
  }
  std::uint32_t add_vertex(const Eigen::VectorXd& x, VertexSource src) {
    pos_.insert(pos_.end(), x.data(), x.data() + x.size());
    vsrc_.push_back(src);
    return static_cast<std::uint32_t>(vsrc_.size() - 1);
  }
  void cut_edges();
  void cut_rank(int k);
  // Output element of rank r from a boundary chain; returns terms referencing it.
  void emit_edges(std::vector<Term>& chain, std::uint32_t source, std::vector<Term>& image);
  void emit_faces(std::vector<Term>& chain, std::uint32_t source, std::vector<Term>& image);
  void emit_higher(int r, std::vector<Term>& chain, std::uint32_t source, std::vector<Term>& image);
  std::uint32_t dedupe(int r, std::vector<Term>& row, std::uint32_t source, int* rel_sign);
  CutResult finish(const std::vector<Term>& top_facets, const std::vector<Term>& top_solids);
  void expand_multiples(int r, std::vector<Term>& chain);

  const Complex& m_;
  const std::vector<double>& s_;
  const std::vector<Side>& side_;
  int tie_;
  bool degenerate_;
  double weld_;
  int n_;
  Complex out_;
  std::vector<double> pos_;  // model-space positions of section vertices, n_ per vertex
  std::vector<VertexSource> vsrc_;
  std::vector<std::vector<std::uint32_t>> src_;  // src_[r]: model element of rank r+1
  std::vector<ImageTable> images_;               // images_[k]: images of model rank k
  std::unordered_map<std::uint64_t, std::uint32_t> edge_index_;
  std::vector<std::map<std::vector<std::uint32_t>, std::uint32_t>> row_index_;
};

void Cutter::cut_edges() {
  const std::size_t ne = m_.count(1);
  ImageTable& img = images_[1];
  img.offsets.reserve(ne + 1);
  // Section vertices that stand for a model vertex: one on the plane, or one that a crossing
  // point lies within the weld distance of. All their crossings become one section vertex.
  std::vector<std::uint32_t> at_vertex(m_.count(0), no_index);
  const auto& p = m_.positions();
  for (std::uint32_t e = 0; e < ne; ++e) {
    const auto [a, b] = m_.edge(e);
    const int pa = perturbed(a), pb = perturbed(b);
    if (pa == pb) {
      img.push({});
      continue;
    }
    const int coef =
        pa < 0 ? 1 : -1;  // +1 when the edge runs from the negative side to the positive
    std::uint32_t v;
    if (side_[a] == Side::On || side_[b] == Side::On) {
      const std::uint32_t on = side_[a] == Side::On ? a : b;
      if (at_vertex[on] == no_index) at_vertex[on] = add_vertex(p.col(on), {on, 0, 0.0});
      v = at_vertex[on];
    } else {
      const double t = s_[a] / (s_[a] - s_[b]);
      const double len = (p.col(b) - p.col(a)).norm();
      std::uint32_t near = no_index;
      if (t * len <= weld_)
        near = a;
      else if ((1.0 - t) * len <= weld_)
        near = b;
      if (near != no_index && at_vertex[near] != no_index) {
        v = at_vertex[near];
      } else {
        v = add_vertex((1.0 - t) * p.col(a) + t * p.col(b), {e, 1, t});
        if (near != no_index) at_vertex[near] = v;
      }
      if (near != no_index) degenerate_ = true;  // pieces may collapse: cancel them as chains
    }
    const Term term{v, coef};
    img.push({&term, 1});
  }
}

std::uint32_t Cutter::dedupe(int r, std::vector<Term>& row, std::uint32_t source, int* rel) {
  Incidence& table = out_.boundary_mut(r);
  std::vector<std::uint32_t> ids(row.size());
  std::vector<std::int8_t> signs(row.size());
  for (std::size_t i = 0; i < row.size(); ++i) {
    ids[i] = row[i].id;
    signs[i] = static_cast<std::int8_t>(row[i].coef);
  }
  *rel = 1;
  if (degenerate_) {
    std::vector<std::uint32_t> key = ids;
    std::sort(key.begin(), key.end());
    if (static_cast<int>(row_index_.size()) <= r) row_index_.resize(r + 1);
    auto [it, fresh] =
        row_index_[r].try_emplace(std::move(key), static_cast<std::uint32_t>(table.size()));
    if (!fresh) {
      // Same boundary set: the same element, possibly with the opposite orientation.
      const std::uint32_t existing = it->second;
      auto eids = table.ids(existing);
      auto esigns = table.signs(existing);
      for (std::size_t i = 0; i < eids.size(); ++i)
        if (eids[i] == ids[0]) *rel = esigns[i] == signs[0] ? 1 : -1;
      return existing;
    }
  }
  if (static_cast<int>(src_.size()) <= r) src_.resize(r + 1);
  src_[r].push_back(source);
  return table.add_row(ids, signs);
}

void Cutter::emit_edges(std::vector<Term>& chain, std::uint32_t source, std::vector<Term>& image) {
  auto make_edge = [&](std::uint32_t tail, std::uint32_t head) {
    int rel = 1;
    std::uint32_t id;
    if (degenerate_) {
      const std::uint64_t key =
          (static_cast<std::uint64_t>(std::min(tail, head)) << 32) | std::max(tail, head);
      auto [it, fresh] = edge_index_.try_emplace(key, static_cast<std::uint32_t>(out_.count(1)));
      if (fresh) {
        id = out_.add_edge(tail, head);
        src_[1].push_back(source);
      } else {
        id = it->second;
        rel = out_.edge(id)[0] == tail ? 1 : -1;
      }
    } else {
      id = out_.add_edge(tail, head);
      src_[1].push_back(source);
    }
    image.push_back({id, rel});
  };
  if (chain.size() == 2 && chain[0].coef == -chain[1].coef && std::abs(chain[0].coef) == 1) {
    const bool first_is_tail = chain[0].coef < 0;
    make_edge(first_is_tail ? chain[0].id : chain[1].id, first_is_tail ? chain[1].id : chain[0].id);
    return;
  }
  // A non-convex (or self-intersecting) face cut in more than two points. The chain is the
  // boundary of the face's cut, a 1-chain on the cut line: sorted along the line, the segment
  // between consecutive points p_i, p_{i+1} carries the multiplicity w_i = -(c_0 + ... + c_i)
  // (c the points' coefficients), the face's winding number there. For a simple non-convex
  // face that is the even-odd pairing (w alternates 1, 0, 1, ...); a star face such as a
  // pentagram gives w = 2 in its core. The order along the line is decided by order_along_line.
  struct Point {
    std::uint32_t id;
    int coef;
  };
  std::vector<Point> pts;
  for (const Term& t : chain) pts.push_back({t.id, t.coef});
  if (pts.size() < 2) return;
  auto at = [&](std::uint32_t v) { return Eigen::Map<const Eigen::VectorXd>(&pos_[v * n_], n_); };
  const std::vector<std::size_t> order =
      order_along_line(pts.size(), [&](std::size_t i) { return at(pts[i].id); });
  int running = 0;
  for (std::size_t k = 0; k + 1 < order.size(); ++k) {
    running += pts[order[k]].coef;
    const int w = -running;
    const std::uint32_t a = pts[order[k]].id, b = pts[order[k + 1]].id;
    // Outside the face, or one section vertex. Two distinct vertices at the same position (a
    // plane through the point where two edges of a star polytope cross) still bound a segment
    // of zero length: dropping it would leave the cell's chain of segments open there.
    if (w == 0 || a == b) continue;
    const std::size_t before = image.size();
    make_edge(a, b);  // directed along the line; the multiplicity and direction go in the sign
    image[before].coef *= w;
  }
}

void Cutter::emit_faces(std::vector<Term>& chain, std::uint32_t source, std::vector<Term>& image) {
  // Chain the signed edges into closed loops; each loop becomes one face in cycle order.
  struct Step {
    std::uint32_t tail, head, edge;
    int sign;
    bool used;
  };
  std::vector<Step> steps;
  for (const Term& t : chain) {
    const auto e = out_.edge(t.id);
    const int sign = t.coef > 0 ? 1 : -1;
    for (int i = 0; i < std::abs(t.coef); ++i)
      steps.push_back({sign > 0 ? e[0] : e[1], sign > 0 ? e[1] : e[0], t.id, sign, false});
  }
  // A total order (steps leaving one vertex by edge, then direction), so the loops a vertex
  // starts several of come out the same with every standard library's sort.
  std::sort(steps.begin(), steps.end(), [](const Step& a, const Step& b) {
    if (a.tail != b.tail) return a.tail < b.tail;
    if (a.edge != b.edge) return a.edge < b.edge;
    return a.sign < b.sign;
  });
  auto find_from = [&](std::uint32_t tail) -> Step* {
    auto it = std::lower_bound(steps.begin(), steps.end(), tail,
                               [](const Step& s, std::uint32_t v) { return s.tail < v; });
    for (; it != steps.end() && it->tail == tail; ++it)
      if (!it->used) return &*it;
    return nullptr;
  };
  std::vector<Term> loop;
  for (std::size_t start = 0; start < steps.size(); ++start) {
    if (steps[start].used) continue;
    loop.clear();
    Step* cur = &steps[start];
    bool closed = false;
    while (cur && !cur->used) {
      cur->used = true;
      loop.push_back({cur->edge, cur->sign});
      if (cur->head == steps[start].tail) {
        closed = true;
        break;
      }
      cur = find_from(cur->head);
    }
    // An open walk (only from inconsistent, e.g. self-intersecting, input) or a degenerate
    // remnant cannot bound a polygon.
    if (!closed || loop.size() < 3) continue;
    int rel = 1;
    const std::uint32_t id = dedupe(2, loop, source, &rel);
    image.push_back({id, rel});
  }
}

void Cutter::emit_higher(int r, std::vector<Term>& chain, std::uint32_t source,
                         std::vector<Term>& image) {
  int rel = 1;
  const std::uint32_t id = dedupe(r, chain, source, &rel);
  image.push_back({id, rel});
}

void Cutter::cut_rank(int k) {
  const Incidence& table = m_.boundary(k);
  const ImageTable& below = images_[k - 1];
  ImageTable& img = images_[k];
  img.offsets.reserve(table.size() + 1);
  std::vector<Term> chain, image;
  for (std::uint32_t x = 0; x < table.size(); ++x) {
    chain.clear();
    image.clear();
    auto ids = table.ids(x);
    auto signs = table.signs(x);
    for (std::size_t i = 0; i < ids.size(); ++i)
      for (const Term& t : below.row(ids[i])) chain.push_back({t.id, -signs[i] * t.coef});
    combine_chain(chain);
    if (!chain.empty()) {
      if (k == 2)
        emit_edges(chain, x, image);
      else if (k == 3)
        emit_faces(chain, x, image);
      else
        emit_higher(k - 1, chain, x, image);
    }
    img.push(image);
  }
}

CutResult Cutter::run() {
  const int top = m_.top_rank();
  images_.resize(top + 1);
  src_.resize(std::max(2, top));
  out_.boundary_mut(std::max(1, std::min(top - 1, n_ - 1)));
  images_[0].offsets.assign(m_.count(0) + 1, 0);
  if (top >= 1) cut_edges();
  for (int k = 2; k <= top; ++k) cut_rank(k);
  // The facets of the section are the cuts of the model's facets; coincident pieces cancel.
  std::vector<Term> facets, solids;
  const int fr = n_ - 1;
  if (fr >= 1 && fr <= top) {
    for (std::uint32_t f = 0; f < m_.count(fr); ++f)
      for (const Term& t : images_[fr].row(f)) facets.push_back(t);
    if (degenerate_) {
      combine_chain(facets);
      // Deduplication merged equal pieces into one element with a multiplicity (a star cell's
      // cut runs twice around its core; two cells may cut to the same polygon): the section
      // is a chain, so such a piece is written once per unit of its coefficient, as the
      // generic cut writes it, or its volume and its edges' balance would be lost.
      if (fr >= 2) expand_multiples(fr - 1, facets);
    }
  }
  if (n_ <= top)
    for (std::uint32_t s = 0; s < m_.count(n_); ++s)
      for (const Term& t : images_[n_].row(s)) solids.push_back(t);
  return finish(facets, solids);
}

// Terms of `chain` (elements of output rank r) with |coef| > 1 become |coef| terms of
// coefficient +-1 on copies of their element (same boundary, same source).
void Cutter::expand_multiples(int r, std::vector<Term>& chain) {
  std::size_t extra = 0;
  for (const Term& t : chain) extra += static_cast<std::size_t>(std::abs(t.coef) - 1);
  if (extra == 0) return;
  Incidence& table = out_.boundary_mut(r);
  std::vector<std::uint32_t> ids;
  std::vector<std::int8_t> signs;
  const std::size_t n = chain.size();
  for (std::size_t i = 0; i < n; ++i) {
    const int copies = std::abs(chain[i].coef);
    if (copies == 1) continue;
    const int unit = chain[i].coef > 0 ? 1 : -1;
    const std::uint32_t id = chain[i].id;
    chain[i].coef = unit;
    for (int k = 1; k < copies; ++k) {
      auto row_ids = table.ids(id);
      auto row_signs = table.signs(id);
      ids.assign(row_ids.begin(), row_ids.end());
      signs.assign(row_signs.begin(), row_signs.end());
      src_[r].push_back(src_[r][id]);
      chain.push_back({table.add_row(ids, signs), unit});
    }
  }
}

CutResult Cutter::finish(const std::vector<Term>& facets, const std::vector<Term>& solids) {
  const int on = n_ - 1;   // dimension of the section
  const int ofr = on - 1;  // rank of the section's facets
  const int otop = out_.top_rank();
  Section sec;
  // Keep what the surviving facets (and solids) reach, drop the rest, renumber.
  std::vector<std::vector<char>> keep(otop + 1);
  keep[0].assign(vsrc_.size(), 0);
  for (int r = 1; r <= otop; ++r) keep[r].assign(out_.count(r), 0);
  std::vector<int> facet_flip(ofr >= 0 && ofr <= otop ? keep[ofr].size() : 0, 0);
  for (const Term& t : facets) {
    if (ofr < 0 || ofr > otop) break;
    keep[ofr][t.id] = 1;
    facet_flip[t.id] = t.coef < 0;
  }
  for (const Term& t : solids)
    if (on <= otop) keep[on][t.id] = 1;
  for (int r = otop; r >= 1; --r) {
    const Incidence& table = out_.boundary(r);
    for (std::uint32_t x = 0; x < table.size(); ++x)
      if (keep[r][x])
        for (auto id : table.ids(x)) keep[r - 1][id] = 1;
  }
  std::vector<std::vector<std::uint32_t>> remap(otop + 1);
  for (int r = 0; r <= otop; ++r) {
    remap[r].assign(keep[r].size(), no_index);
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < keep[r].size(); ++i)
      if (keep[r][i]) remap[r][i] = next++;
  }
  Complex result(on);
  Eigen::MatrixXd positions(
      n_, static_cast<Eigen::Index>(std::count(keep[0].begin(), keep[0].end(), 1)));
  for (std::size_t v = 0; v < keep[0].size(); ++v)
    if (keep[0][v]) {
      positions.col(remap[0][v]) = Eigen::Map<const Eigen::VectorXd>(&pos_[v * n_], n_);
      sec.vertex_source.push_back(vsrc_[v]);
    }
  sec.source.resize(otop + 1);
  std::vector<std::uint32_t> ids;
  for (int r = 1; r <= otop; ++r) {
    const Incidence& table = out_.boundary(r);
    Incidence& dst = result.boundary_mut(r);
    for (std::uint32_t x = 0; x < table.size(); ++x) {
      if (!keep[r][x]) continue;
      auto src_ids = table.ids(x);
      ids.assign(src_ids.begin(), src_ids.end());
      for (auto& id : ids) id = remap[r - 1][id];
      dst.add_row(ids, table.signs(x));
      sec.source[r].push_back(src_[r][x]);
    }
  }
  if (ofr >= 1)  // (points, the facets of a 1D section, carry no orientation)
    for (std::size_t f = 0; f < facet_flip.size(); ++f)
      if (facet_flip[f] && keep[ofr][f]) result.flip(ofr, remap[ofr][f]);
  sec.complex = std::move(result);
  return {std::move(sec), std::move(positions)};
}

// The invariants of a section of `model` (for assert()s): a well-formed complex one dimension
// down, one vertex source per vertex naming a model vertex or edge, and per rank k >= 1 one
// source per element naming a model element of rank k + 1.
[[maybe_unused]] bool well_formed_section(const Section& sec, const Complex& model) {
  const Complex& c = sec.complex;
  if (!c.well_formed() || c.ambient_dim() != model.ambient_dim() - 1 ||
      sec.vertex_source.size() != c.count(0))
    return false;
  for (const VertexSource& vs : sec.vertex_source)
    if (vs.rank > 1 || vs.element >= model.count(vs.rank)) return false;
  for (int r = 1; r <= c.top_rank(); ++r) {
    if (static_cast<std::size_t>(r) >= sec.source.size()) {
      if (c.count(r) > 0) return false;
      continue;
    }
    const auto& src = sec.source[r];
    if (src.size() != c.count(r)) return false;
    for (auto x : src)
      if (x >= model.count(r + 1)) return false;
  }
  return true;
}

}  // namespace

void check_section_input(const Complex& model, const Hyperplane& plane, const AffineTransform& xf) {
  const int n = model.ambient_dim();
  if (n < 2) throw InputError("section needs a model of dimension >= 2");
  if (plane.dim() != n)
    throw InputError("hyperplane in R^" + std::to_string(plane.dim()) + " for a model in R^" +
                     std::to_string(n));
  if (xf.dim() != n)
    throw InputError("transform of R^" + std::to_string(xf.dim()) + " for a model in R^" +
                     std::to_string(n));
}

Section section_general(const Complex& model, const Hyperplane& plane, const AffineTransform& xf) {
  check_tables(model);
  return general_cut(model, plane, xf);  // (which checks the dimensions)
}

Section general_cut(const Complex& model, const Hyperplane& plane, const AffineTransform& xf,
                    bool test_self_intersection) {
  check_section_input(model, plane, xf);
  const int n = model.ambient_dim();
  // The plane in model space: n.(A x + t) = d  <=>  (A^T n).x = d - n.t
  const Eigen::VectorXd nm = xf.linear().transpose() * plane.normal;
  const double dm = plane.offset - plane.normal.dot(xf.translation());
  // One pass over the vertices: signed values and the largest vertex norm. ON means within the
  // rounding error of s = nm.x - dm (see tolerances.hpp).
  const std::size_t nv = model.count(0);
  const auto& p = model.positions();
  std::vector<double> s(nv);
  double max_norm2 = 0.0;
  for (std::size_t v = 0; v < nv; ++v) {
    const auto x = p.col(static_cast<Eigen::Index>(v));
    s[v] = plane_value(nm, dm, x.data());
    max_norm2 = std::max(max_norm2, x.squaredNorm());
  }
  const double tolerance = on_plane_tolerance(nm.norm(), std::sqrt(max_norm2), dm);
  const bool unmoved = xf.linear().isIdentity(0.0) && xf.translation().isZero(0.0);
  FacetPlanes facets(model, nm, dm, s, unmoved ? &plane : nullptr);
  facets.settle_values(s, tolerance, std::sqrt(max_norm2));
  std::vector<Side> side(nv);
  bool any_on = false;
  for (std::size_t v = 0; v < nv; ++v) {
    side[v] = classify_side(s[v], tolerance);
    any_on |= side[v] == Side::On;
  }
  // Crossing points within the weld distance of a model vertex (relative to the model's size)
  // merge into it, and ON vertices stay ON only where that moves no crossing farther.
  double weld = 0.0;
  if (nv > 0) {
    const Bounds box = bounds(model);
    weld = tol::weld_rel * (box.max - box.min).norm();
  }
  if (any_on) settle_on_band(model, s, side, weld);
  bool any_pos = false, any_neg = false;
  any_on = false;
  for (std::size_t v = 0; v < nv; ++v) {
    any_on |= side[v] == Side::On;
    any_pos |= side[v] == Side::Positive;
    any_neg |= side[v] == Side::Negative;
  }
  CutResult cut;
  cut.section.complex = Complex(n - 1);
  cut.model_positions.resize(n, 0);
  if ((any_pos && any_neg) || any_on) {
    cut = Cutter(model, s, side, +1, any_on, weld).run();
    if (cut.model_positions.cols() == 0 && any_on)
      cut = Cutter(model, s, side, -1, true, weld).run();
    if (cut.model_positions.cols() == 0) {
      // Nothing cut (a plane between the components of a model, say): the same empty section
      // as a plane that misses the model.
      cut = CutResult{};
      cut.section.complex = Complex(n - 1);
      cut.model_positions.resize(n, 0);
    }
  }
  std::vector<std::pair<std::uint32_t, Eigen::VectorXd>> placed;
  if (cut.model_positions.cols() > 0)
    facets.place(cut.section, cut.model_positions, weld, unmoved ? &placed : nullptr);
  Section sec = std::move(cut.section);
  const Eigen::MatrixXd& model_pos = cut.model_positions;
  sec.frame = HyperplaneFrame(plane);
  if (sec.source.empty()) sec.source.resize(1);
  // Section vertices: model -> world -> plane coordinates.
  Eigen::MatrixXd world = (xf.linear() * model_pos).colwise() + xf.translation();
  Eigen::MatrixXd coords = sec.frame.basis.transpose() * (world.colwise() - sec.frame.origin());
  for (const auto& [v, z] : placed) coords.col(v) = z;
  sec.complex.set_positions(std::move(coords));
  // Orientation. The cut of a facet C carries the orientation "(m, frame) positive in C" (m
  // the plane normal projected into C), and the cut's boundary is -sum(sign * cut of child).
  // Measured against the section coordinates, whose frame is (b_1..b_{n-1}) with
  // det(b_1..b_{n-1}, n) = +1, those cuts face outward for even n and inward for odd n.
  // A reflecting model transform reverses everything once more.
  Eigen::FullPivLU<Eigen::MatrixXd> lu(xf.linear());
  const int ofr = n - 2;
  const bool reflect = lu.determinant() < 0.0;
  if ((reflect != (n % 2 == 1)) && ofr >= 1)
    for (std::uint32_t f = 0; f < sec.complex.count(ofr); ++f) sec.complex.flip(ofr, f);
  sec.source_fingerprint = model_fingerprint(model);
  if (sec.complex.top_rank() >= n - 1 && n - 1 >= 2) {
    Incidence& solids = sec.complex.boundary_mut(n - 1);
    for (std::uint32_t i = 0; i < solids.size(); ++i)
      for (auto& sign : solids.signs_mut(i)) sign = 1;
  }
  // Facet normals: the source facets' outward normals, moved to world space and projected.
  if (ofr >= 1 && sec.complex.count(ofr) > 0) {
    const Eigen::MatrixXd inv_t = lu.inverse().transpose();
    Eigen::MatrixXd normals(n - 1, sec.complex.count(ofr));
    for (std::uint32_t f = 0; f < sec.complex.count(ofr); ++f) {
      Eigen::VectorXd nrm = Eigen::VectorXd::Zero(n - 1);
      if (model.has_facet_normals()) {
        const Eigen::VectorXd w = inv_t * model.facet_normals().col(sec.source[ofr][f]);
        nrm = sec.frame.basis.transpose() * w;
      }
      if (nrm.norm() < tol::near_parallel_normal) nrm = facet_area_vector(sec.complex, f);
      const double len = nrm.norm();
      normals.col(f) = len > 0.0 ? Eigen::VectorXd(nrm / len) : nrm;
    }
    sec.complex.set_facet_normals(std::move(normals));
  }
  sec.self_intersecting = test_self_intersection && self_intersects(sec.complex);
  assert(well_formed_section(sec, model));
  return sec;
}

namespace {

// Whether every vertex lies in the inner closed half-space of every facet's hyperplane (its
// outward facet normal through its first vertex), up to 1e-12 of the largest vertex norm: far
// below what self_intersects resolves (tol::self_intersection_rel), so the sections of a model
// that passes cannot self-intersect visibly. Skipped (false) when facets x vertices exceeds
// 10^8 (about a second once per model), where it would cost more than it saves.
bool convex_certificate(const Complex& c) {
  const int fr = c.facet_rank();
  if (fr < 1 || c.top_rank() < fr || !c.has_facet_normals()) return false;
  const std::size_t nf = c.count(fr), nv = c.count(0);
  if (nf == 0 || static_cast<double>(nf) * static_cast<double>(nv) > 1e8) return false;
  const Eigen::MatrixXd& p = c.positions();
  const double slack = 1e-12 * std::sqrt(p.colwise().squaredNorm().maxCoeff());
  Eigen::RowVectorXd h(static_cast<Eigen::Index>(nv));  // heights along facet f's normal
  for (std::uint32_t f = 0; f < nf; ++f) {
    h.noalias() = c.facet_normals().col(f).transpose() * p;
    if (h.maxCoeff() > h(c.first_vertex(fr, f)) + slack) return false;
  }
  return true;
}

// Per thread: the last models compiled for section(), each with the address and revision() of
// the complex it was compiled from. A complex at that address with that revision is the same
// state (revisions are unique in the process and change with every non-const call), so it is
// used without reading the complex; another revision is compared in full (compiled_from), so
// a complex changed back, or a new one with the same arrays, still reuses its model. One
// Slicer and one SliceBuffers serve every call, so repeated calls allocate only the Section
// they return.
struct SectionScratch {
  static constexpr std::size_t kModels = 4;
  std::unique_ptr<SliceModel> models[kModels];
  const Complex* source[kModels] = {};
  std::uint64_t revision[kModels] = {};
  std::size_t next = 0;
  Slicer slicer;
  SliceBuffers buffers;

  bool convex[kModels] = {};

  // The compiled model and whether the complex is convex (convex_certificate).
  std::pair<const SliceModel*, bool> compiled(const Complex& model) {
    for (std::size_t i = 0; i < kModels; ++i)
      if (models[i] && source[i] == &model && revision[i] == model.revision())
        return {models[i].get(), convex[i]};
    for (std::size_t i = 0; i < kModels; ++i) {
      if (models[i] && models[i]->compiled_from(model)) {
        revision[i] = model.revision();
        return {models[i].get(), convex[i]};
      }
    }
    const std::size_t i = next;
    next = (next + 1) % kModels;
    models[i] = std::make_unique<SliceModel>(model, SliceModelOptions::unclustered());
    source[i] = &model;
    revision[i] = model.revision();
    convex[i] = models[i]->fast() && convex_certificate(model);
    return {models[i].get(), convex[i]};
  }
};

// section() with the model placed by *xf, or unmoved (xf == nullptr: the slicer's identity
// placement, which gives the identity transform's buffers bit for bit without building it).
Section section_placed(const Complex& model, const Hyperplane& plane, const AffineTransform* xf) {
  if (xf) {
    check_section_input(model, plane, *xf);
  } else {
    const int n = model.ambient_dim();
    if (n < 2 || plane.dim() != n)  // (check_section_input's messages)
      check_section_input(model, plane, AffineTransform::identity(n));
  }
  // The hot path when the model allows it (slicer.hpp); it falls back to the general cut.
  thread_local SectionScratch scratch;
  const auto [compiled, convex] = scratch.compiled(model);
  if (!compiled->fast())
    return general_cut(model, plane, xf ? *xf : AffineTransform::identity(model.ambient_dim()));
  if (xf)
    scratch.slicer.slice(*compiled, plane, *xf, scratch.buffers);
  else
    scratch.slicer.slice(*compiled, plane, scratch.buffers);
  // A convex polytope's section by a plane in general position (the fast path) is a convex
  // polytope whose faces are strictly convex polygons: nothing to test for self-intersection.
  Section sec = convex && !scratch.buffers.general ? to_section_untested(scratch.buffers)
                                                   : to_section(scratch.buffers);
  assert(well_formed_section(sec, model));
  return sec;
}

}  // namespace

Section section(const Complex& model, const Hyperplane& plane, const AffineTransform& xf) {
  return section_placed(model, plane, &xf);
}

Section section(const Complex& model, const Hyperplane& plane) {
  return section_placed(model, plane, nullptr);
}

}  // namespace cw4d
