#include "cw4d/complex/complex.hpp"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <functional>
#include <stdexcept>

namespace cw4d {

std::uint32_t Incidence::add_row(std::span<const std::uint32_t> ids,
                                 std::span<const std::int8_t> signs) {
  assert(ids.size() == signs.size());
  assert(ids_.size() + ids.size() < no_index && offsets_.size() < no_index);
  if (offsets_.empty()) offsets_.push_back(0);
  ids_.insert(ids_.end(), ids.begin(), ids.end());
  signs_.insert(signs_.end(), signs.begin(), signs.end());
  offsets_.push_back(static_cast<std::uint32_t>(ids_.size()));
  return static_cast<std::uint32_t>(offsets_.size() - 2);
}

const std::vector<std::uint32_t>& Incidence::no_rows_offsets() {
  static const std::vector<std::uint32_t> offsets{0};
  return offsets;
}

bool Incidence::rows_readable() const {
  if (offsets_.empty()) return ids_.empty() && signs_.empty();
  if (offsets_.front() != 0 || offsets_.back() != ids_.size() || ids_.size() != signs_.size())
    return false;
  unsigned down = 0;  // (a reduction without a branch per entry: the compiler vectorises it)
  for (std::size_t i = 0; i + 1 < offsets_.size(); ++i)
    down |= static_cast<unsigned>(offsets_[i] > offsets_[i + 1]);
  return down == 0;
}

bool Incidence::well_formed(std::size_t lower_count) const {
  if (!rows_readable()) return false;
  // Reductions without a branch per entry (the compiler vectorises them): a table is checked
  // whenever a model is compiled for slicing.
  std::uint32_t top = 0;
  for (const std::uint32_t id : ids_) top = std::max(top, id);
  unsigned odd = 0;  // a sign other than -1 or +1: s + 1 other than 0 or 2
  for (const std::int8_t s : signs_) odd |= static_cast<std::uint8_t>(s + 1) & 0xFDu;
  return odd == 0 && (ids_.empty() || top < lower_count);
}

void Incidence::reserve(std::size_t rows, std::size_t entries) {
  offsets_.reserve(rows + 1);
  ids_.reserve(entries);
  signs_.reserve(entries);
}

void Incidence::clear() {
  offsets_.clear();
  ids_.clear();
  signs_.clear();
}

std::uint64_t Revision::next() noexcept {
  // Each thread takes its stamps from blocks of its own (one atomic addition per block, not a
  // locked instruction per stamp): the blocks are disjoint, so every stamp is still unique in
  // the process (and never 0).
  constexpr std::uint64_t kBlock = 4096;
  static std::atomic<std::uint64_t> counter{0};
  thread_local std::uint64_t at = 0, end = 0;
  if (at == end) {
    at = counter.fetch_add(kBlock, std::memory_order_relaxed) + 1;
    end = at + kBlock;
  }
  return at++;
}

Complex::Complex(int ambient_dim) : dim_(ambient_dim), positions_(ambient_dim, 0) {
  if (ambient_dim < 1) throw std::invalid_argument("cw4d::Complex: ambient_dim must be >= 1");
}

std::size_t Complex::count(int rank) const {
  if (rank < 0) return 0;
  if (rank == 0) return static_cast<std::size_t>(positions_.cols());
  if (rank > top_rank()) return 0;
  return boundaries_[rank - 1].size();
}

std::vector<std::size_t> Complex::fvector() const {
  std::vector<std::size_t> f;
  for (int k = 0; k <= top_rank(); ++k) f.push_back(count(k));
  return f;
}

void Complex::set_positions(Eigen::MatrixXd positions) {
  if (positions.rows() != dim_)
    throw std::invalid_argument("cw4d::Complex::set_positions: wrong number of rows");
  touch();
  positions_ = std::move(positions);
}

Incidence& Complex::boundary_mut(int rank) {
  if (rank < 1) throw std::invalid_argument("cw4d::Complex::boundary_mut: rank must be >= 1");
  touch();
  if (static_cast<int>(boundaries_.size()) < rank) boundaries_.resize(rank);
  return boundaries_[rank - 1];
}

void Complex::truncate(int max_rank) {
  touch();
  if (max_rank < static_cast<int>(boundaries_.size())) boundaries_.resize(std::max(0, max_rank));
}

bool Complex::well_formed() const {
  if (positions_.rows() != dim_) return false;
  for (int r = 1; r <= top_rank(); ++r)
    if (!boundaries_[r - 1].well_formed(count(r - 1))) return false;
  if (top_rank() >= 1) {
    const Incidence& edges = boundaries_[0];
    for (std::size_t e = 0; e < edges.size(); ++e)
      if (edges.row_size(e) != 2 || edges.signs(e)[0] != -1 || edges.signs(e)[1] != 1) return false;
  }
  // Each face row is one closed walk, every head the next tail (in R^2 rank 2 is the solid: its
  // row may list several loops).
  if (top_rank() >= 2 && dim_ >= 3) {
    const Incidence& faces = boundaries_[1];
    for (std::size_t f = 0; f < faces.size(); ++f) {
      const auto ids = faces.ids(f);
      const auto signs = faces.signs(f);
      for (std::size_t i = 0; i < ids.size(); ++i) {
        const std::size_t j = (i + 1) % ids.size();
        const auto a = edge(ids[i]), b = edge(ids[j]);
        if ((signs[i] > 0 ? a[1] : a[0]) != (signs[j] > 0 ? b[0] : b[1])) return false;
      }
    }
  }
  return true;
}

std::uint32_t Complex::add_edge(std::uint32_t tail, std::uint32_t head) {
  const std::uint32_t ids[2] = {tail, head};
  const std::int8_t signs[2] = {-1, 1};
  return boundary_mut(1).add_row(ids, signs);
}

void Complex::flip(int rank, std::uint32_t i) {
  Incidence& table = boundary_mut(rank);
  auto ids = table.ids_mut(i);
  auto signs = table.signs_mut(i);
  if (rank == 1) {
    std::swap(ids[0], ids[1]);
  } else if (rank == 2) {
    std::reverse(ids.begin(), ids.end());
    std::reverse(signs.begin(), signs.end());
    for (auto& s : signs) s = static_cast<std::int8_t>(-s);
  } else {
    for (auto& s : signs) s = static_cast<std::int8_t>(-s);
  }
}

std::vector<std::uint32_t> Complex::face_cycle(std::uint32_t f) const {
  const Incidence& faces = boundary(2);
  auto ids = faces.ids(f);
  auto signs = faces.signs(f);
  std::vector<std::uint32_t> cycle;
  cycle.reserve(ids.size());
  for (std::size_t i = 0; i < ids.size(); ++i) {
    auto e = edge(ids[i]);
    cycle.push_back(signs[i] > 0 ? e[0] : e[1]);
  }
  return cycle;
}

std::uint32_t Complex::first_vertex(int rank, std::uint32_t i) const {
  while (rank > 0) {
    const Incidence& table = boundary(rank);
    auto ids = table.ids(i);
    auto signs = table.signs(i);
    if (rank == 1) return ids[0];
    if (rank == 2) {
      auto e = edge(ids[0]);
      return signs[0] > 0 ? e[0] : e[1];
    }
    i = ids[0];
    --rank;
  }
  return i;
}

std::vector<std::uint32_t> Complex::vertices_of(int rank, std::uint32_t i) const {
  std::vector<std::uint32_t> current{i};
  for (int k = rank; k >= 1; --k) {
    std::vector<std::uint32_t> next;
    const Incidence& table = boundary(k);
    for (auto x : current) {
      auto ids = table.ids(x);
      next.insert(next.end(), ids.begin(), ids.end());
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    current = std::move(next);
  }
  return current;
}

const std::vector<Rgba>& Complex::colors(int rank) const {
  static const std::vector<Rgba> none;
  if (rank < 0 || rank >= static_cast<int>(colors_.size())) return none;
  return colors_[rank];
}

std::vector<Rgba>& Complex::colors_mut(int rank) {
  if (rank < 0) throw std::invalid_argument("cw4d::Complex::colors_mut: negative rank");
  touch();
  if (static_cast<int>(colors_.size()) <= rank) colors_.resize(rank + 1);
  return colors_[rank];
}

}  // namespace cw4d
