#include "cw4d/section/slicer.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <thread>
#include <unordered_map>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/fork_join.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/section/provenance.hpp"
#include "general.hpp"
#include "slicer_detail.hpp"

namespace cw4d {

namespace {

// Morton code of a point quantised to `bits` bits per coordinate inside [lo, hi].
std::uint64_t morton(const double* x, const double* lo, const double* hi, int n) {
  const int bits = 64 / n;
  const double cells = std::ldexp(1.0, bits) - 1.0;
  std::uint64_t q[kMaxDim] = {};
  for (int i = 0; i < n; ++i) {
    const double span = hi[i] - lo[i];
    const double f = span > 0.0 ? (x[i] - lo[i]) / span : 0.0;
    q[i] = static_cast<std::uint64_t>(std::clamp(f, 0.0, 1.0) * cells);
  }
  std::uint64_t key = 0;
  for (int b = bits - 1; b >= 0; --b)
    for (int i = 0; i < n; ++i) key = (key << 1) | ((q[i] >> b) & 1u);
  return key;
}

// Whether every element of rank k < n-1 bounds an element of rank k + 1 (so every piece the
// fast path cuts reaches a facet, as the general path's pruning requires).
bool every_element_bounds(const Complex& c, int below_rank) {
  for (int k = 1; k <= below_rank + 1 && k <= c.top_rank(); ++k) {
    std::vector<char> used(c.count(k - 1), 0);
    for (auto id : c.boundary(k).all_ids()) used[id] = 1;
    if (std::find(used.begin(), used.end(), 0) != used.end()) return false;
  }
  return true;
}

}  // namespace

const char* to_string(FallbackReason r) {
  switch (r) {
    case FallbackReason::None:
      return "none";
    case FallbackReason::Model:
      return "model";
    case FallbackReason::OnPlane:
      return "on-plane";
    case FallbackReason::Weld:
      return "weld";
    case FallbackReason::FaceCut:
      return "face-cut";
    case FallbackReason::CellCut:
      return "cell-cut";
    case FallbackReason::Multiplicity:
      return "multiplicity";
    case FallbackReason::NearParallel:
      return "near-parallel";
  }
  return "?";
}

// --- SliceModel -------------------------------------------------------------------------------

namespace {
std::atomic<std::uint64_t> next_serial{1};
}  // namespace

SliceModel::Compiled::Compiled(const Complex& model, const SliceModelOptions& options)
    : model_(&model), serial_(next_serial.fetch_add(1, std::memory_order_relaxed)) {
  check_tables(model);
  fingerprint_ = model_fingerprint(model);
  const int n = model.ambient_dim();
  dim_ = n;
  top_ = model.top_rank();
  const std::size_t nv = model.count(0);
  nv_ = nv;
  const auto& p = model.positions();
  // Bounding box, sphere and the largest vertex norm (the tolerance scale of section()).
  centre_ = Eigen::VectorXd::Zero(n);
  double max_norm2 = 0.0;
  Eigen::VectorXd lo = Eigen::VectorXd::Zero(n), hi = Eigen::VectorXd::Zero(n);
  if (nv > 0) {
    lo = p.rowwise().minCoeff();
    hi = p.rowwise().maxCoeff();
    centre_ = 0.5 * (lo + hi);
    radius_ = (p.colwise() - centre_).colwise().norm().maxCoeff();
    for (std::size_t v = 0; v < nv; ++v)
      max_norm2 = std::max(max_norm2, p.col(static_cast<Eigen::Index>(v)).squaredNorm());
  }
  max_norm_ = std::sqrt(max_norm2);
  weld_ = tol::weld_rel * (hi - lo).norm();
  const int fr = n - 1;
  // Edges as the complex's convention has them, [tail, head] with signs [-1, +1] (then their
  // offsets and signs are implied: only the ends are compiled).
  bool two_ends = top_ >= 1;
  if (two_ends) {
    const Incidence& edges = model.boundary(1);
    two_ends = edges.entries() == 2 * edges.size();
    const auto& off = edges.offsets();
    const auto& sg = edges.all_signs();
    for (std::size_t e = 0; e < edges.size() && two_ends; ++e)
      two_ends = off[e + 1] == 2 * (e + 1) && sg[2 * e] == -1 && sg[2 * e + 1] == 1;
  }
  fast_ = (n == 3 || n == 4) && nv > 0 && (top_ == fr || top_ == n) && model.has_facet_normals() &&
          two_ends && every_element_bounds(model, fr - 1);
  for (int k = 0; k <= top_ && fast_; ++k)  // (ids with a free top bit: the coface signs)
    fast_ = model.count(k) <= kUpIndex;
  if (!fast_) {
    cluster_vertex_ = {0};
    return;
  }
  const std::size_t nf = model.count(fr);
  ranks_.resize(top_ + 1);
  begin_.assign(fr, {});
  clustered_ = nf >= options.cluster_threshold && options.cluster_size > 0;
  if (!clustered_) {
    positions_.assign(p.data(), p.data() + n * nv);
    for (int k = 1; k <= top_; ++k) {
      const Incidence& t = model.boundary(k);
      ranks_[k].count = t.size();
      ranks_[k].ids = t.all_ids();
      if (k == 1) continue;  // (implied offsets and signs)
      ranks_[k].offsets = t.offsets();
      ranks_[k].signs = t.all_signs();
    }
    for (int k = 1; k <= fr; ++k) begin_[k - 1] = {0, static_cast<std::uint32_t>(model.count(k))};
    {
      cluster_vertex_ = {0};
      std::vector<std::uint32_t> all(nv);
      std::iota(all.begin(), all.end(), 0u);
      add_cluster(all);
    }
    cluster_sphere_.assign(centre_.data(), centre_.data() + n);
    cluster_sphere_.push_back(radius_);
    const auto& fnrm = model.facet_normals();
    facet_normals_.assign(fnrm.data(), fnrm.data() + n * nf);
    build_cofaces();
    find_single_solid();
    build_tet_tables();
    return;
  }
  // Clusters: facets sorted by the Morton code of their first vertex, cut into runs of
  // cluster_size; every lower element goes to the first cluster whose facets reach it.
  // Vertices keep the model's ids (their positions are read from the model, not copied).
  std::vector<std::uint32_t> facet_order(nf);
  {
    std::vector<std::uint64_t> key(nf);
    for (std::uint32_t f = 0; f < nf; ++f)
      key[f] = morton(p.col(model.first_vertex(fr, f)).data(), lo.data(), hi.data(), n);
    std::iota(facet_order.begin(), facet_order.end(), 0u);
    std::stable_sort(facet_order.begin(), facet_order.end(),
                     [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  }
  const std::size_t nc = (nf + options.cluster_size - 1) / options.cluster_size;
  // new_id[k][model id] for ranks 1..fr; order[k] = model ids in internal order.
  std::vector<std::vector<std::uint32_t>> new_id(fr + 1), order(fr + 1);
  for (int k = 1; k <= fr; ++k) {
    new_id[k].assign(model.count(k), no_index);
    order[k].reserve(model.count(k));
  }
  for (int k = 1; k <= fr; ++k) begin_[k - 1].assign(1, 0);
  cluster_vertex_.assign(1, 0);
  std::vector<std::uint32_t> fresh;
  std::vector<std::vector<std::uint32_t>> frontier(fr + 1);
  for (std::size_t c = 0; c < nc; ++c) {
    const std::size_t f0 = c * options.cluster_size, f1 = std::min(nf, f0 + options.cluster_size);
    for (int k = 0; k <= fr; ++k) frontier[k].clear();
    for (std::size_t i = f0; i < f1; ++i) frontier[fr].push_back(facet_order[i]);
    // Walk down: the cluster's elements of each rank (all of them, for the vertex list), and
    // those not yet owned by an earlier cluster.
    for (int k = fr; k >= 1; --k) {
      std::vector<std::uint32_t>& below = frontier[k - 1];
      const Incidence& t = model.boundary(k);
      for (auto x : frontier[k])
        for (auto id : t.ids(x)) below.push_back(id);
      std::sort(below.begin(), below.end());
      below.erase(std::unique(below.begin(), below.end()), below.end());
    }
    for (int k = fr; k >= 1; --k) {
      fresh.clear();
      for (auto x : frontier[k])
        if (new_id[k][x] == no_index) fresh.push_back(x);
      if (k == fr) std::sort(fresh.begin(), fresh.end());
      for (auto x : fresh) {
        new_id[k][x] = static_cast<std::uint32_t>(order[k].size());
        order[k].push_back(x);
      }
      begin_[k - 1].push_back(static_cast<std::uint32_t>(order[k].size()));
    }
    add_cluster(frontier[0]);
  }
  // Elements no facet reaches cannot exist here (every_element_bounds). Each renumbering table
  // is freed as soon as the rank above it is written (the compile's peak).
  std::vector<std::uint32_t>().swap(facet_order);
  std::vector<std::uint32_t>().swap(fresh);
  for (auto& f : frontier) std::vector<std::uint32_t>().swap(f);
  for (int k = 1; k <= top_; ++k) {
    const Incidence& t = model.boundary(k);
    Rank& r = ranks_[k];
    const bool renumbered = k <= fr;
    const std::size_t count = t.size();
    r.count = count;
    r.ids.reserve(t.entries());
    if (renumbered) r.model_id = std::move(order[k]);
    if (k == 1) {  // (vertex ids kept; implied offsets and signs)
      for (std::size_t i = 0; i < count; ++i)
        for (auto id : t.ids(r.model_id[i])) r.ids.push_back(id);
      continue;
    }
    r.offsets.assign(1, 0);
    r.offsets.reserve(count + 1);
    r.signs.reserve(t.entries());
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t x = renumbered ? r.model_id[i] : static_cast<std::uint32_t>(i);
      for (auto id : t.ids(x)) r.ids.push_back(new_id[k - 1][id]);
      const auto sg = t.signs(x);
      r.signs.insert(r.signs.end(), sg.begin(), sg.end());
      r.offsets.push_back(static_cast<std::uint32_t>(r.ids.size()));
    }
    std::vector<std::uint32_t>().swap(new_id[k - 1]);
  }
  // (No copy of the facet normals: a slice reads the complex's through ranks_[fr].model_id.)
  const double* P = positions();
  // Cluster spheres: centre of the box of the cluster's vertices, farthest vertex from it.
  cluster_sphere_.resize(nc * (n + 1));
  for (std::size_t c = 0; c < nc; ++c) {
    double clo[kMaxDim], chi[kMaxDim];
    std::fill(clo, clo + n, std::numeric_limits<double>::infinity());
    std::fill(chi, chi + n, -std::numeric_limits<double>::infinity());
    each_cluster_vertex(static_cast<std::uint32_t>(c), [&](std::uint32_t v) {
      for (int j = 0; j < n; ++j) {
        const double x = P[std::size_t{v} * n + j];
        clo[j] = std::min(clo[j], x);
        chi[j] = std::max(chi[j], x);
      }
      return true;
    });
    double* sphere = &cluster_sphere_[c * (n + 1)];
    for (int j = 0; j < n; ++j) sphere[j] = 0.5 * (clo[j] + chi[j]);
    double r2 = 0.0;
    each_cluster_vertex(static_cast<std::uint32_t>(c), [&](std::uint32_t v) {
      double d2 = 0.0;
      for (int j = 0; j < n; ++j) {
        const double d = P[std::size_t{v} * n + j] - sphere[j];
        d2 += d * d;
      }
      r2 = std::max(r2, d2);
      return true;
    });
    sphere[n] = std::sqrt(r2);
  }
  build_cofaces();
  find_single_solid();
  build_tet_tables();
}

void SliceModel::Compiled::add_cluster(std::span<const std::uint32_t> vertices) {
  std::uint32_t last = 0xffffffffu;
  for (const std::uint32_t v : vertices) {
    const std::uint32_t d = v - last;  // (>= 1; below 2^31: ids fit in kUpIndex)
    last = v;
    if (d < 0x8000u) {
      cluster_vertices_.push_back(static_cast<std::uint16_t>(d));
    } else {
      cluster_vertices_.push_back(static_cast<std::uint16_t>(0x8000u | (d >> 16)));
      cluster_vertices_.push_back(static_cast<std::uint16_t>(d & 0xffffu));
    }
  }
  cluster_vertex_.push_back(static_cast<std::uint32_t>(cluster_vertices_.size()));
}

void SliceModel::Compiled::find_single_solid() {
  single_solid_ = false;
  solid_sign_.clear();
  if (top_ != dim_ || ranks_[top_].offsets.size() != 2) return;
  const std::size_t nf = ranks_[dim_ - 1].offsets.size() - 1;
  if (ranks_[top_].ids.size() != nf) return;
  std::vector<std::int8_t> sign(nf, 0);
  for (std::size_t i = 0; i < nf; ++i) {
    const auto id = ranks_[top_].ids[i];
    if (sign[id] != 0) return;
    sign[id] = ranks_[top_].signs[i];
  }
  single_solid_ = true;
  if (dim_ == 3) solid_sign_ = std::move(sign);
}

void SliceModel::Compiled::build_cofaces() {
  // The range of the edges' lengths, for the weld test of each crossing (CrossingTest).
  {
    const Rank& E = ranks_[1];
    const std::size_t ne = E.count;
    const double* P = positions();
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    for (std::size_t e = 0; e < ne; ++e) {
      const double len = edge_length(P, dim_, E.ids[2 * e], E.ids[2 * e + 1]);
      if (len < lo) lo = len;  // (a NaN length changes neither: its tests are false anyway)
      if (len > hi) hi = len;
    }
    edge_min_ = lo;
    edge_max_ = hi;
  }
  up_offsets_.assign(top_, {});
  up_ids_.assign(top_, {});
  up_stride_.assign(top_, 0);
  for (int k = 1; k < top_; ++k) {
    const Rank& above = ranks_[k + 1];
    const std::size_t count = ranks_[k].count;
    std::vector<std::uint32_t>& off = up_offsets_[k];
    off.assign(count + 1, 0);
    for (auto id : above.ids) ++off[id + 1];
    // Every element with the same number of cofaces (a valid model's ridges: two facets each):
    // the offsets are implied.
    std::uint32_t stride = count > 0 ? off[1] : 0;
    for (std::size_t i = 0; i < count && stride > 0; ++i)
      if (off[i + 1] != stride) stride = 0;
    for (std::size_t i = 0; i < count; ++i) off[i + 1] += off[i];
    up_ids_[k].resize(above.ids.size());
    const std::size_t rows = above.count;
    for (std::uint32_t x = 0; x < rows; ++x)  // (off[id] is the fill cursor of id's list)
      for (std::uint32_t i = above.offsets[x]; i < above.offsets[x + 1]; ++i)
        up_ids_[k][off[above.ids[i]]++] = x | (above.signs[i] < 0 ? kUpNegative : 0u);
    if (stride > 0) {
      up_stride_[k] = stride;
      std::vector<std::uint32_t>().swap(off);
    } else {
      for (std::size_t i = count; i > 0; --i) off[i] = off[i - 1];  // (the cursors: ends)
      off[0] = 0;
    }
  }
  unit_signs_ = true;
  for (int k = 2; k <= std::min(top_, 3); ++k)
    for (auto sg : ranks_[k].signs) unit_signs_ = unit_signs_ && (sg == 1 || sg == -1);
  small_cells_ = false;
  if (top_ >= 3)
    for (std::size_t x = 0; x < ranks_[3].count && !small_cells_; ++x)
      small_cells_ = ranks_[3].offsets[x + 1] - ranks_[3].offsets[x] <= 4;
  triangle_faces_ = top_ >= 2;
  if (top_ >= 2)
    for (std::size_t x = 0; x < ranks_[2].count && triangle_faces_; ++x)
      triangle_faces_ = ranks_[2].offsets[x + 1] - ranks_[2].offsets[x] <= 3;
}

void SliceModel::Compiled::build_tet_tables() {
  // Each pattern's polygon decided here as the kernel's face and cell passes decide it at slice
  // time (the same rules on the same combinatorics), once per cell instead of once per slice.
  tet_vertices_.clear();
  tet_cases_.clear();
  if (dim_ != 4 || top_ < 3 || !unit_signs_) return;
  const Rank& E = ranks_[1];
  const Rank& F = ranks_[2];
  const Rank& C = ranks_[3];
  const std::size_t nc = C.offsets.size() - 1;
  for (std::size_t x = 0; x < nc; ++x)                 // tables only when every cell has four faces
    if (C.offsets[x + 1] - C.offsets[x] != 4) return;  // (and, below, is a tetrahedron)
  std::vector<std::uint32_t> verts(4 * nc);
  std::vector<std::uint16_t> cases(16 * nc, 7);
  for (std::size_t x = 0; x < nc; ++x) {
    const std::uint32_t b = C.offsets[x];
    std::uint32_t v[24];  // both ends of the three edges of each of the four faces
    int nv = 0;
    for (int i = 0; i < 4; ++i) {
      const std::uint32_t f = C.ids[b + i];
      if (F.offsets[f + 1] - F.offsets[f] != 3) return;
      for (int j = 0; j < i; ++j)
        if (C.ids[b + j] == f) return;
      for (std::uint32_t k = F.offsets[f]; k < F.offsets[f + 1]; ++k)
        for (int end = 0; end < 2; ++end) v[nv++] = E.ids[2 * F.ids[k] + end];
    }
    int nu = 0;  // the distinct vertices, ascending (insertion into a short list)
    for (int i = 0; i < nv; ++i) {
      const std::uint32_t y = v[i];
      int j = 0;
      while (j < nu && v[j] < y) ++j;
      if (j < nu && v[j] == y) continue;
      if (nu == 4) return;  // more than four vertices
      for (int k = nu; k > j; --k) v[k] = v[k - 1];
      v[j] = y;
      ++nu;
    }
    if (nu != 4) return;
    std::copy(v, v + 4, &verts[4 * x]);
    for (std::uint32_t pattern = 1; pattern < 15; ++pattern) {
      const auto above = [&](std::uint32_t vertex) {
        const int k = static_cast<int>(std::find(v, v + 4, vertex) - v);
        return ((pattern >> k) & 1u) != 0;
      };
      // Steps (tail edge, head edge, position in the cell, forward) of the cut faces.
      std::uint32_t tails[4], heads[4], pos[4];
      bool fwd[4];
      int ns = 0;
      bool ok = true;
      for (std::uint32_t i = 0; i < 4 && ok; ++i) {
        const std::uint32_t f = C.ids[b + i];
        std::uint32_t ends[3];
        bool plus[3];
        int nx = 0;
        for (std::uint32_t k = F.offsets[f]; k < F.offsets[f + 1]; ++k) {
          const std::uint32_t e = F.ids[k];
          const bool a_above = above(E.ids[2 * e]);
          if (a_above == above(E.ids[2 * e + 1])) continue;
          ends[nx] = e;
          plus[nx] = (F.signs[k] < 0) != a_above;  // the crossing's coefficient is +1
          ++nx;
        }
        if (nx == 0) continue;
        if (nx != 2 || plus[0] == plus[1] || ends[0] == ends[1]) {
          ok = false;
          break;
        }
        const std::uint32_t tail = plus[0] ? ends[1] : ends[0];
        const std::uint32_t head = plus[0] ? ends[0] : ends[1];
        fwd[ns] = C.signs[b + i] < 0;
        tails[ns] = fwd[ns] ? tail : head;
        heads[ns] = fwd[ns] ? head : tail;
        pos[ns] = i;
        ++ns;
      }
      if (!ok || ns < 3) continue;
      int lo = 0;
      for (int i = 0; i < ns; ++i) {
        for (int j = 0; j < i; ++j) ok = ok && tails[i] != tails[j];
        if (tails[i] < tails[lo]) lo = i;
      }
      if (!ok) continue;
      std::uint16_t code = static_cast<std::uint16_t>(ns);
      int cur = lo, k = 0;
      for (; k < ns; ++k) {
        code = static_cast<std::uint16_t>(code | pos[cur] << (3 + 2 * k) |
                                          (fwd[cur] ? 0u : 1u) << (11 + k));
        int next = -1;
        for (int j = 0; j < ns; ++j)
          if (tails[j] == heads[cur]) next = j;
        if (next < 0 || (next == lo) != (k + 1 == ns)) break;
        cur = next;
      }
      if (k == ns) cases[16 * x + pattern] = code;
    }
  }
  tet_vertices_ = std::move(verts);
  tet_cases_ = std::move(cases);
}

namespace {
// The signs -1, +1 of an edge as one 16-bit word (in memory order).
const std::uint16_t kEdgeSigns = [] {
  const std::int8_t pair[2] = {-1, 1};
  std::uint16_t w;
  std::memcpy(&w, pair, 2);
  return w;
}();
}  // namespace

bool SliceModel::Compiled::compiled_from(const Complex& c) const {
  if (&c != model_ || c.ambient_dim() != dim_ || c.top_rank() != top_) return false;
  const auto same = [](const auto* a, const auto* b, std::size_t count) {
    return count == 0 || std::memcmp(a, b, count * sizeof(*a)) == 0;
  };
  const Eigen::MatrixXd& p = c.positions();
  const Eigen::MatrixXd& fn = c.facet_normals();
  if (!fast_) return false;  // (nothing compiled but the verdict)
  if (clustered_ || static_cast<std::size_t>(p.size()) != positions_.size() ||
      static_cast<std::size_t>(fn.size()) != facet_normals_.size() ||
      !same(p.data(), positions_.data(), positions_.size()) ||
      !same(fn.data(), facet_normals_.data(), facet_normals_.size()))
    return false;
  for (int k = 1; k <= top_; ++k) {
    const Incidence& t = c.boundary(k);
    const Rank& r = ranks_[k];
    if (!r.model_id.empty() || t.size() != r.count || t.all_ids().size() != r.ids.size() ||
        t.all_signs().size() != t.all_ids().size() ||
        !same(t.all_ids().data(), r.ids.data(), r.ids.size()))
      return false;
    if (k == 1) {  // still [tail, head] with signs [-1, +1] (branch-free passes)
      const std::uint32_t* off = t.offsets().data();
      const std::int8_t* sg = t.all_signs().data();
      std::uint32_t bad = 0;
      const std::size_t rows = r.count + 1;
      for (std::size_t e = 0; e < rows; ++e) bad |= off[e] ^ static_cast<std::uint32_t>(2 * e);
      for (std::size_t e = 0; e < r.count; ++e) {
        std::uint16_t pair;  // the bytes -1, +1
        std::memcpy(&pair, sg + 2 * e, 2);
        bad |= pair ^ kEdgeSigns;
      }
      if (bad != 0) return false;
    } else if (!same(t.offsets().data(), r.offsets.data(), r.offsets.size()) ||
               !same(t.all_signs().data(), r.signs.data(), r.signs.size())) {
      return false;
    }
  }
  return true;
}

std::size_t SliceModel::Compiled::bytes() const {
  std::size_t b = solid_sign_.size() + positions_.size() * sizeof(double) +
                  tet_vertices_.size() * 4 + tet_cases_.size() * 2 +
                  facet_normals_.size() * sizeof(double) + cluster_vertex_.size() * 4 +
                  cluster_vertices_.size() * 2 + cluster_sphere_.size() * sizeof(double);
  for (const Rank& r : ranks_)
    b += (r.offsets.size() + r.ids.size() + r.model_id.size()) * 4 + r.signs.size();
  for (const auto& v : begin_) b += v.size() * 4;
  for (const auto& v : up_offsets_) b += v.size() * 4;
  b += up_stride_.size() * 4;
  for (const auto& v : up_ids_) b += v.size() * 4;
  return b;
}

// --- the facade -----------------------------------------------------------------------------

SliceModel::SliceModel(const Complex& model, const SliceModelOptions& options)
    : compiled_(std::make_unique<Compiled>(model, options)) {}
SliceModel::~SliceModel() = default;
SliceModel::SliceModel(SliceModel&&) noexcept = default;
SliceModel& SliceModel::operator=(SliceModel&&) noexcept = default;
SliceModel::SliceModel(const SliceModel& other)
    : compiled_(std::make_unique<Compiled>(*other.compiled_)) {}
SliceModel& SliceModel::operator=(const SliceModel& other) {
  if (this != &other) compiled_ = std::make_unique<Compiled>(*other.compiled_);
  return *this;
}
const Complex& SliceModel::complex() const {
  return compiled_->complex();
}
int SliceModel::dim() const {
  return compiled_->dim_;
}
bool SliceModel::fast() const {
  return compiled_->fast_;
}
std::size_t SliceModel::cluster_count() const {
  return compiled_->cluster_count();
}
const Eigen::VectorXd& SliceModel::centre() const {
  return compiled_->centre_;
}
double SliceModel::radius() const {
  return compiled_->radius_;
}
bool SliceModel::compiled_from(const Complex& model) const {
  return compiled_->compiled_from(model);
}
std::size_t SliceModel::bytes() const {
  return compiled_->bytes();
}

void SliceBuffers::set_ranks(int top) {
  // Tables beyond `top` are parked, not freed, so that their storage serves later slices.
  resize_keeping(boundary, spare_tables_, static_cast<std::size_t>(top));
  for (auto& b : boundary) b.clear();
  resize_keeping(source, spare_sources_, static_cast<std::size_t>(top) + 1);
  for (auto& v : source) v.clear();
}

std::size_t SliceBuffers::fan_triangles() const {
  if (boundary.size() < 2) return 0;
  std::size_t t = 0;
  const Incidence& faces = boundary[1];
  for (std::size_t f = 0; f < faces.size(); ++f) t += faces.row_size(f) - 2;
  return t;
}

}  // namespace cw4d
