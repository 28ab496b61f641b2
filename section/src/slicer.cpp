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
#include "general.hpp"

namespace cw4d {

namespace {

constexpr std::uint32_t none = 0xffffffffu;
constexpr int kMaxDim = 4;

// Resizes v to `want` elements, moving dropped ones to `spare` and taking new ones from it, so
// that their own storage is kept.
template <class T>
void resize_keeping(std::vector<T>& v, std::vector<T>& spare, std::size_t want) {
  while (v.size() > want) {
    spare.push_back(std::move(v.back()));
    v.pop_back();
  }
  while (v.size() < want) {
    if (spare.empty()) {
      v.emplace_back();
    } else {
      v.push_back(std::move(spare.back()));
      spare.pop_back();
    }
  }
}

// Calls f(x) for every set bit x of [b, e), in increasing order, clearing those bits; stops
// (returning false) when f does.
template <class F>
bool visit_marked(std::vector<std::uint64_t>& bits, std::uint32_t b, std::uint32_t e, F&& f) {
  if (b >= e) return true;
  for (std::uint32_t w = b >> 6, last = (e - 1) >> 6; w <= last; ++w) {
    std::uint64_t mask = ~std::uint64_t{0};
    if (w == (b >> 6)) mask &= ~std::uint64_t{0} << (b & 63);
    if (w == last) mask &= ~std::uint64_t{0} >> (63 - ((e - 1) & 63));
    std::uint64_t sel = bits[w] & mask;
    bits[w] &= ~mask;
    while (sel) {
      const std::uint32_t x = w * 64 + static_cast<std::uint32_t>(__builtin_ctzll(sel));
      sel &= sel - 1;
      if (!f(x)) return false;
    }
  }
  return true;
}

// Calls f(x) for every nonzero byte x of [b, e), in increasing order, zeroing those bytes (eight
// at a time); stops (returning false) when f does. Byte marks are set with plain stores, where
// bit marks need a read-modify-write of a shared word per mark.
template <class F>
bool visit_marked_bytes(std::uint8_t* marks, std::uint32_t b, std::uint32_t e, F&& f) {
  std::uint32_t x = b;
  for (; x < e && (x & 7u); ++x)
    if (marks[x]) {
      marks[x] = 0;
      if (!f(x)) return false;
    }
  for (; x + 8 <= e; x += 8) {
    std::uint64_t w;
    std::memcpy(&w, marks + x, 8);
    if (!w) continue;
    std::memset(marks + x, 0, 8);
    while (w) {
      const int bit = __builtin_ctzll(w);
      w &= ~(std::uint64_t{0xff} << (bit & ~7));
      if (!f(x + static_cast<std::uint32_t>(bit >> 3))) return false;
    }
  }
  for (; x < e; ++x)
    if (marks[x]) {
      marks[x] = 0;
      if (!f(x)) return false;
    }
  return true;
}

// n.x summed in a fixed order (section/ is built with -ffp-contract=off, so nothing is fused):
// the fast path's plane value is height - d. Its rounding error is below 5 units in the last
// place of |n| |x| + |d|, far inside the ON band (tol::plane_side_ulps), so outside the band
// its sign is the exact sign, as plane_value's is; a sweep computes the height once per vertex
// and gets exactly the slice's value for every offset. (Within a few ulps of the band's edge
// the two evaluations may classify a vertex differently; both answers are valid.)
inline double height(const double* nm, const double* x, int n) {
  double h = nm[0] * x[0];
  for (int i = 1; i < n; ++i) h += nm[i] * x[i];
  return h;
}

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

SliceModel::SliceModel(const Complex& model, const SliceModelOptions& options)
    : model_(&model), serial_(next_serial.fetch_add(1, std::memory_order_relaxed)) {
  const int n = model.ambient_dim();
  dim_ = n;
  top_ = model.top_rank();
  const std::size_t nv = model.count(0);
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
  bool two_ends = top_ >= 1;
  if (two_ends) {
    const Incidence& edges = model.boundary(1);
    for (std::size_t e = 0; e < edges.size() && two_ends; ++e) two_ends = edges.row_size(e) == 2;
  }
  fast_ = (n == 3 || n == 4) && nv > 0 && (top_ == fr || top_ == n) && model.has_facet_normals() &&
          two_ends && every_element_bounds(model, fr - 1);
  if (!fast_) {
    cluster_vertex_ = {0};
    return;
  }
  const std::size_t nf = model.count(fr);
  ranks_.resize(top_ + 1);
  begin_.assign(fr, {});
  const bool clustered = nf >= options.cluster_threshold && options.cluster_size > 0;
  if (!clustered) {
    positions_.assign(p.data(), p.data() + n * nv);
    for (int k = 1; k <= top_; ++k) {
      const Incidence& t = model.boundary(k);
      ranks_[k].offsets = t.offsets();
      ranks_[k].ids = t.all_ids();
      ranks_[k].signs = t.all_signs();
    }
    for (int k = 1; k <= fr; ++k) begin_[k - 1] = {0, static_cast<std::uint32_t>(model.count(k))};
    cluster_vertex_ = {0, static_cast<std::uint32_t>(nv)};
    cluster_vertices_.resize(nv);
    std::iota(cluster_vertices_.begin(), cluster_vertices_.end(), 0u);
    cluster_sphere_.assign(centre_.data(), centre_.data() + n);
    cluster_sphere_.push_back(radius_);
    const auto& fnrm = model.facet_normals();
    facet_normals_.assign(fnrm.data(), fnrm.data() + n * nf);
    build_cofaces();
    find_single_solid();
    return;
  }
  // Clusters: facets sorted by the Morton code of their first vertex, cut into runs of
  // cluster_size; every lower element goes to the first cluster whose facets reach it.
  std::vector<std::uint64_t> key(nf);
  for (std::uint32_t f = 0; f < nf; ++f)
    key[f] = morton(p.col(model.first_vertex(fr, f)).data(), lo.data(), hi.data(), n);
  std::vector<std::uint32_t> facet_order(nf);
  std::iota(facet_order.begin(), facet_order.end(), 0u);
  std::stable_sort(facet_order.begin(), facet_order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  const std::size_t nc = (nf + options.cluster_size - 1) / options.cluster_size;
  // new_id[k][model id] for ranks 0..fr; order[k] = model ids in internal order.
  std::vector<std::vector<std::uint32_t>> new_id(fr + 1), order(fr + 1);
  for (int k = 0; k <= fr; ++k) {
    new_id[k].assign(model.count(k), none);
    order[k].reserve(model.count(k));
  }
  for (int k = 1; k <= fr; ++k) begin_[k - 1].assign(1, 0);
  cluster_vertex_.assign(1, 0);
  std::vector<std::uint32_t> stamp(nv, none), fresh, verts;
  std::vector<std::vector<std::uint32_t>> frontier(fr + 1);
  for (std::size_t c = 0; c < nc; ++c) {
    const std::size_t f0 = c * options.cluster_size, f1 = std::min(nf, f0 + options.cluster_size);
    for (int k = 0; k <= fr; ++k) frontier[k].clear();
    verts.clear();
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
    for (int k = fr; k >= 0; --k) {
      fresh.clear();
      for (auto x : frontier[k])
        if (new_id[k][x] == none) fresh.push_back(x);
      if (k == fr) std::sort(fresh.begin(), fresh.end());
      for (auto x : fresh) {
        new_id[k][x] = static_cast<std::uint32_t>(order[k].size());
        order[k].push_back(x);
      }
      if (k >= 1) begin_[k - 1].push_back(static_cast<std::uint32_t>(order[k].size()));
    }
    for (auto v : frontier[0]) verts.push_back(new_id[0][v]);
    std::sort(verts.begin(), verts.end());
    cluster_vertices_.insert(cluster_vertices_.end(), verts.begin(), verts.end());
    cluster_vertex_.push_back(static_cast<std::uint32_t>(cluster_vertices_.size()));
  }
  // Elements no facet reaches cannot exist here (every_element_bounds).
  vertex_id_ = order[0];
  positions_.resize(n * nv);
  for (std::size_t i = 0; i < nv; ++i)
    for (int j = 0; j < n; ++j) positions_[i * n + j] = p(j, vertex_id_[i]);
  for (int k = 1; k <= top_; ++k) {
    const Incidence& t = model.boundary(k);
    Rank& r = ranks_[k];
    const bool renumbered = k <= fr;
    const std::size_t count = t.size();
    r.offsets.assign(1, 0);
    r.offsets.reserve(count + 1);
    r.ids.reserve(t.entries());
    r.signs.reserve(t.entries());
    if (renumbered) r.model_id = order[k];
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t x = renumbered ? order[k][i] : static_cast<std::uint32_t>(i);
      for (auto id : t.ids(x)) r.ids.push_back(new_id[k - 1][id]);
      const auto sg = t.signs(x);
      r.signs.insert(r.signs.end(), sg.begin(), sg.end());
      r.offsets.push_back(static_cast<std::uint32_t>(r.ids.size()));
    }
  }
  const auto& fnrm = model.facet_normals();
  facet_normals_.resize(n * nf);
  for (std::size_t i = 0; i < nf; ++i)
    for (int j = 0; j < n; ++j) facet_normals_[i * n + j] = fnrm(j, order[fr][i]);
  // Cluster spheres: centre of the box of the cluster's vertices, farthest vertex from it.
  cluster_sphere_.resize(nc * (n + 1));
  for (std::size_t c = 0; c < nc; ++c) {
    double clo[kMaxDim], chi[kMaxDim];
    std::fill(clo, clo + n, std::numeric_limits<double>::infinity());
    std::fill(chi, chi + n, -std::numeric_limits<double>::infinity());
    for (std::uint32_t i = cluster_vertex_[c]; i < cluster_vertex_[c + 1]; ++i)
      for (int j = 0; j < n; ++j) {
        const double x = positions_[cluster_vertices_[i] * n + j];
        clo[j] = std::min(clo[j], x);
        chi[j] = std::max(chi[j], x);
      }
    double* sphere = &cluster_sphere_[c * (n + 1)];
    for (int j = 0; j < n; ++j) sphere[j] = 0.5 * (clo[j] + chi[j]);
    double r2 = 0.0;
    for (std::uint32_t i = cluster_vertex_[c]; i < cluster_vertex_[c + 1]; ++i) {
      double d2 = 0.0;
      for (int j = 0; j < n; ++j) {
        const double d = positions_[cluster_vertices_[i] * n + j] - sphere[j];
        d2 += d * d;
      }
      r2 = std::max(r2, d2);
    }
    sphere[n] = std::sqrt(r2);
  }
  build_cofaces();
  find_single_solid();
}

void SliceModel::find_single_solid() {
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

void SliceModel::build_cofaces() {
  // Edge lengths, for the weld test of each crossing (summed in the order crossing() used to).
  {
    const Rank& E = ranks_[1];
    const std::size_t ne = E.offsets.size() - 1;
    edge_length_.resize(ne);
    const double* P = positions_.data();
    for (std::size_t e = 0; e < ne; ++e) {
      const std::uint32_t a = E.ids[2 * e], b = E.ids[2 * e + 1];
      double len2 = 0.0;
      for (int j = 0; j < dim_; ++j) {
        const double d = P[b * dim_ + j] - P[a * dim_ + j];
        len2 += d * d;
      }
      edge_length_[e] = std::sqrt(len2);
    }
  }
  up_offsets_.assign(top_, {});
  up_ids_.assign(top_, {});
  for (int k = 1; k < top_; ++k) {
    const Rank& above = ranks_[k + 1];
    const std::size_t count = ranks_[k].offsets.size() - 1;
    std::vector<std::uint32_t>& off = up_offsets_[k];
    off.assign(count + 1, 0);
    for (auto id : above.ids) ++off[id + 1];
    for (std::size_t i = 0; i < count; ++i) off[i + 1] += off[i];
    std::vector<std::uint32_t> fill(off.begin(), off.end() - 1);
    up_ids_[k].resize(above.ids.size());
    const std::size_t rows = above.offsets.size() - 1;
    for (std::uint32_t x = 0; x < rows; ++x)
      for (std::uint32_t i = above.offsets[x]; i < above.offsets[x + 1]; ++i)
        up_ids_[k][fill[above.ids[i]]++] = x;
  }
}

bool SliceModel::compiled_from(const Complex& c) const {
  if (&c != model_ || c.ambient_dim() != dim_ || c.top_rank() != top_) return false;
  const auto same = [](const auto* a, const auto* b, std::size_t count) {
    return count == 0 || std::memcmp(a, b, count * sizeof(*a)) == 0;
  };
  const Eigen::MatrixXd& p = c.positions();
  const Eigen::MatrixXd& fn = c.facet_normals();
  if (!fast_) return false;  // (nothing compiled but the verdict)
  if (!vertex_id_.empty() || static_cast<std::size_t>(p.size()) != positions_.size() ||
      static_cast<std::size_t>(fn.size()) != facet_normals_.size() ||
      !same(p.data(), positions_.data(), positions_.size()) ||
      !same(fn.data(), facet_normals_.data(), facet_normals_.size()))
    return false;
  for (int k = 1; k <= top_; ++k) {
    const Incidence& t = c.boundary(k);
    const Rank& r = ranks_[k];
    if (!r.model_id.empty() || t.offsets().size() != r.offsets.size() ||
        t.all_ids().size() != r.ids.size() ||
        !same(t.offsets().data(), r.offsets.data(), r.offsets.size()) ||
        !same(t.all_ids().data(), r.ids.data(), r.ids.size()) ||
        !same(t.all_signs().data(), r.signs.data(), r.signs.size()))
      return false;
  }
  return true;
}

std::size_t SliceModel::bytes() const {
  std::size_t b = solid_sign_.size() + (positions_.size() + edge_length_.size()) * sizeof(double) +
                  facet_normals_.size() * sizeof(double) + vertex_id_.size() * 4 +
                  cluster_vertex_.size() * 4 + cluster_vertices_.size() * 4 +
                  cluster_sphere_.size() * sizeof(double);
  for (const Rank& r : ranks_)
    b += (r.offsets.size() + r.ids.size() + r.model_id.size()) * 4 + r.signs.size();
  for (const auto& v : begin_) b += v.size() * 4;
  for (const auto& v : up_offsets_) b += v.size() * 4;
  for (const auto& v : up_ids_) b += v.size() * 4;
  return b;
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

// --- placement ------------------------------------------------------------------------------

// The plane moved into model space and the maps from model space to the section: computed
// per slice in fixed-size arrays (no allocation).
struct Slicer::Placement {
  int n = 0;
  double nm[kMaxDim] = {};  // A^T n
  double dm = 0.0;          // d - n.t
  double nm_norm = 0.0;
  double tol = 0.0;                  // ON band
  double M[kMaxDim * kMaxDim] = {};  // section coords y = M x + c (row-major, (n-1) x n)
  double c[kMaxDim] = {};
  double N[kMaxDim * kMaxDim] = {};  // projected normals: basis^T A^{-T} (row-major)
  bool reflect = false;
  const Hyperplane* plane = nullptr;
  double basis[kMaxDim * kMaxDim] = {};  // n x (n-1) column-major
  double A[kMaxDim * kMaxDim] = {};      // row-major
  double t[kMaxDim] = {};

  // Everything that does not depend on the plane offset.
  // xf == nullptr: the identity.
  void set(const SliceModel& m, const Hyperplane& p, const AffineTransform* xf) {
    n = m.dim();
    plane = &p;
    for (int i = 0; i < n; ++i) {
      t[i] = xf ? xf->translation()[i] : 0.0;
      for (int j = 0; j < n; ++j) A[i * n + j] = xf ? xf->linear()(i, j) : (i == j ? 1.0 : 0.0);
    }
    for (int j = 0; j < n; ++j) {
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += A[i * n + j] * p.normal[i];
      nm[j] = sum;
    }
    double nn = 0.0;
    for (int j = 0; j < n; ++j) nn += nm[j] * nm[j];
    nm_norm = std::sqrt(nn);
    hyperplane_basis(p.normal.data(), n, basis);
    const int o = n - 1;
    if (!xf) {
      // The identity: every sum below adds exact zeros to one term, which leaves that term
      // (+ 0.0 turns a -0 into the +0 such a sum starts from); the inverse is exact, no reflection.
      for (int r = 0; r < o; ++r)
        for (int j = 0; j < n; ++j) M[r * n + j] = N[r * n + j] = basis[r * n + j] + 0.0;
      reflect = false;
      return;
    }
    for (int r = 0; r < o; ++r)
      for (int j = 0; j < n; ++j) {
        double sum = 0.0;
        for (int i = 0; i < n; ++i) sum += basis[r * n + i] * A[i * n + j];
        M[r * n + j] = sum;
      }
    // A^{-1} by Gauss-Jordan with partial pivoting; the determinant's sign on the way.
    double a[kMaxDim * kMaxDim], inv[kMaxDim * kMaxDim];
    std::copy(A, A + n * n, a);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) inv[i * n + j] = i == j ? 1.0 : 0.0;
    int sign = 1;
    for (int k = 0; k < n; ++k) {
      int piv = k;
      for (int i = k + 1; i < n; ++i)
        if (std::abs(a[i * n + k]) > std::abs(a[piv * n + k])) piv = i;
      if (piv != k) {
        for (int j = 0; j < n; ++j)
          std::swap(a[k * n + j], a[piv * n + j]), std::swap(inv[k * n + j], inv[piv * n + j]);
        sign = -sign;
      }
      const double d = a[k * n + k];
      if (d < 0.0) sign = -sign;
      for (int j = 0; j < n; ++j) a[k * n + j] /= d, inv[k * n + j] /= d;
      for (int i = 0; i < n; ++i) {
        if (i == k) continue;
        const double f = a[i * n + k];
        for (int j = 0; j < n; ++j)
          a[i * n + j] -= f * a[k * n + j], inv[i * n + j] -= f * inv[k * n + j];
      }
    }
    reflect = sign < 0;
    // N = basis^T A^{-T}: N[r][j] = sum_i basis_i,r * inv[j][i].
    for (int r = 0; r < o; ++r)
      for (int j = 0; j < n; ++j) {
        double sum = 0.0;
        for (int i = 0; i < n; ++i) sum += basis[r * n + i] * inv[j * n + i];
        N[r * n + j] = sum;
      }
  }

  // The plane offset d (world) for this slice.
  double offset = 0.0;  // the world-space plane offset of this slice

  void set_offset(const SliceModel& m, double d) {
    offset = d;
    double nt = 0.0;
    for (int i = 0; i < n; ++i) nt += plane->normal[i] * t[i];
    dm = d - nt;
    tol = on_plane_tolerance(nm_norm, m.max_norm_, dm);
    const int o = n - 1;
    for (int r = 0; r < o; ++r) {
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += basis[r * n + i] * (t[i] - d * plane->normal[i]);
      c[r] = sum;
    }
  }

  // Whether the sphere (model space) can touch the plane, beyond the ON band.
  bool meets(const double* centre, double radius) const {
    double dist = -dm, cn = 0.0;
    for (int i = 0; i < n; ++i) dist += nm[i] * centre[i], cn += centre[i] * centre[i];
    const double margin =
        tol::bounding_sphere_margin_rel * (nm_norm * (radius + std::sqrt(cn)) + std::abs(dm)) + tol;
    return std::abs(dist) <= nm_norm * radius + margin;
  }
};

// --- slicing --------------------------------------------------------------------------------

namespace {

void clear_to_empty(SliceBuffers& out, int dim) {
  out.forget_topology();
  out.dim = dim;
  out.coords.clear();
  out.vertex_source.clear();
  out.set_ranks(0);  // (no tables: the empty section has only rank 0)
  out.facet_normals.clear();
  out.fallback = FallbackReason::None;
}

}  // namespace

void Slicer::slice(const SliceModel& model, const Hyperplane& plane, SliceBuffers& out,
                   const SliceOptions& options) {
  slice_placed(model, plane, nullptr, out, options);
}

void Slicer::slice(const SliceModel& m, const Hyperplane& plane, const AffineTransform& xf,
                   SliceBuffers& out, const SliceOptions& options) {
  slice_placed(m, plane, &xf, out, options);
}

void Slicer::slice_placed(const SliceModel& m, const Hyperplane& plane, const AffineTransform* xf,
                          SliceBuffers& out, const SliceOptions& options) {
  auto general = [&] {
    if (xf)
      general_slice(m, plane, *xf, out);
    else
      general_slice(m, plane, AffineTransform::identity(m.dim()), out);
  };
  if (!m.fast() || plane.dim() != m.dim() || (xf && xf->dim() != m.dim())) {
    general();  // (which throws InputError for mismatched dimensions)
    return;
  }
  Placement pl;
  pl.set(m, plane, xf);
  near_parallel_ = tol::near_parallel_edge * pl.nm_norm;
  pl.set_offset(m, plane.offset);
  if (options.reuse_topology && reuse(m, pl, options, out)) {
    ++cached_count_;
    return;
  }
  reason_ = FallbackReason::None;
  kernel_ = options.kernel;
  if (!fast_slice(m, pl, options, out)) general();
}

void Slicer::general_slice(const SliceModel& m, const Hyperplane& plane, const AffineTransform& xf,
                           SliceBuffers& out) {
  const Section sec = section_general(m.complex(), plane, xf);
  const Complex& c = sec.complex;
  out.dim = c.ambient_dim();
  out.plane = plane;
  out.coords.assign(c.positions().data(), c.positions().data() + c.positions().size());
  out.vertex_source = sec.vertex_source;
  out.boundary.resize(c.top_rank());
  for (int r = 1; r <= c.top_rank(); ++r) out.boundary[r - 1] = c.boundary(r);
  out.source = sec.source;
  out.facet_normals.assign(c.facet_normals().data(),
                           c.facet_normals().data() + c.facet_normals().size());
  out.general = true;
  out.fallback = m.fast() ? reason_ : FallbackReason::Model;
  out.reused_topology = false;
  out.cache_valid_ = false;
}

bool Slicer::emit_loops(std::span<Term> chain, std::uint32_t source, SliceBuffers& out,
                        std::vector<Term>& image) {
  // As the general path's emit_faces: signed section edges chained into closed loops, each
  // loop one polygon in cycle order; loops start at the smallest unused tail.
  Incidence& edges = out.boundary[0];
  steps_.clear();
  for (const Term& t : chain) {
    const auto e = edges.ids(t.id);
    const int sign = t.coef > 0 ? 1 : -1;
    if (std::abs(t.coef) != 1) return fail(FallbackReason::Multiplicity);
    steps_.push_back({sign > 0 ? e[0] : e[1], sign > 0 ? e[1] : e[0], t.id, sign, false});
  }
  // With distinct tails any sort gives the general path's order (repeated tails, a pinched
  // cut, are left to the general path); a cell's cut usually has a handful of steps.
  // A total order (steps leaving one vertex by edge, then direction), so the loops a vertex
  // starts several of come out the same with every standard library's sort.
  const auto before = [](const Step& a, const Step& b) {
    if (a.tail != b.tail) return a.tail < b.tail;
    if (a.edge != b.edge) return a.edge < b.edge;
    return a.sign < b.sign;
  };
  if (steps_.size() <= 16) {
    for (std::size_t i = 1; i < steps_.size(); ++i)
      for (std::size_t j = i; j > 0 && before(steps_[j], steps_[j - 1]); --j)
        std::swap(steps_[j], steps_[j - 1]);
  } else {
    std::sort(steps_.begin(), steps_.end(), before);
  }
  for (std::size_t i = 1; i < steps_.size(); ++i)
    if (steps_[i].tail == steps_[i - 1].tail) return fail(FallbackReason::CellCut);
  auto find_from = [&](std::uint32_t tail) -> Step* {
    auto it = std::lower_bound(steps_.begin(), steps_.end(), tail,
                               [](const Step& s, std::uint32_t v) { return s.tail < v; });
    for (; it != steps_.end() && it->tail == tail; ++it)
      if (!it->used) return &*it;
    return nullptr;
  };
  Incidence& faces = out.boundary[1];
  for (std::size_t start = 0; start < steps_.size(); ++start) {
    if (steps_[start].used) continue;
    row_ids_.clear();
    row_signs_.clear();
    Step* cur = &steps_[start];
    bool closed = false;
    while (cur && !cur->used) {
      cur->used = true;
      row_ids_.push_back(cur->edge);
      row_signs_.push_back(static_cast<std::int8_t>(cur->sign));
      if (cur->head == steps_[start].tail) {
        closed = true;
        break;
      }
      cur = find_from(cur->head);
    }
    if (!closed || row_ids_.size() < 3) return fail(FallbackReason::CellCut);  // (dropped there)
    image.push_back({static_cast<std::uint32_t>(faces.size()), 1});
    faces.add_row(row_ids_, row_signs_);
    out.source[2].push_back(source);
  }
  return true;
}

bool Slicer::emit_element(const SliceModel& m, int k, std::uint32_t x, SliceBuffers& out,
                          std::vector<std::uint32_t>& facets, std::vector<Term>& image) {
  combine_chain(chain_);  // as the general path does
  if (chain_.empty()) return true;
  const SliceModel::Rank& R = m.ranks_[k];
  const int fr = m.dim_ - 1;
  const std::uint32_t model_x = R.model_id.empty() ? x : R.model_id[x];
  if (k == 2) {
    if (chain_.size() != 2 || chain_[0].coef != -chain_[1].coef || std::abs(chain_[0].coef) != 1)
      return fail(FallbackReason::FaceCut);  // cut in more than two points: the general path
    const bool first_is_tail = chain_[0].coef < 0;
    const std::uint32_t ends[2] = {first_is_tail ? chain_[0].id : chain_[1].id,
                                   first_is_tail ? chain_[1].id : chain_[0].id};
    const std::int8_t signs[2] = {-1, 1};
    image.push_back({static_cast<std::uint32_t>(out.boundary[0].size()), 1});
    out.boundary[0].add_row(ends, signs);
    out.source[1].push_back(model_x);
    if (k == fr) facets.push_back(x);
  } else if (k == 3) {
    const std::size_t before = image.size();
    if (!emit_loops(chain_, model_x, out, image)) return false;
    if (k == fr) facets.insert(facets.end(), image.size() - before, x);
  } else {
    row_ids_.clear();
    row_signs_.clear();
    for (const Term& t : chain_) {
      if (std::abs(t.coef) != 1) return fail(FallbackReason::Multiplicity);
      row_ids_.push_back(t.id);
      row_signs_.push_back(static_cast<std::int8_t>(t.coef));
    }
    Incidence& table = out.boundary[k - 2];
    image.push_back({static_cast<std::uint32_t>(table.size()), 1});
    table.add_row(row_ids_, row_signs_);
    out.source[k - 1].push_back(model_x);
  }
  return true;
}

void Slicer::mark_parents(const SliceModel& m, int k, std::uint32_t x) {
  const std::vector<std::uint32_t>& off = m.up_offsets_[k];
  const std::vector<std::uint32_t>& ids = m.up_ids_[k];
  std::vector<std::uint64_t>& bits = mark_[k + 1];
  for (std::uint32_t i = off[x]; i < off[x + 1]; ++i)
    bits[ids[i] >> 6] |= std::uint64_t{1} << (ids[i] & 63);
}

bool Slicer::fast_slice(const SliceModel& m, const Placement& pl, const SliceOptions& options,
                        SliceBuffers& out) {
  prepare(m);
  if (fast_slice_marked(m, pl, options, out)) return true;
  clear_marks(m);
  return false;
}

void Slicer::clear_marks(const SliceModel& m) {
  // Given up half way: no marks may survive into the next slice.
  for (int k = 1; k <= m.top_; ++k) std::fill(mark_[k].begin(), mark_[k].end(), 0);
}

void Slicer::prepare(const SliceModel& m) {
  const int top = m.top_;
  const std::size_t nv = m.positions_.size() / m.dim_;
  if (++gen_ == 0) {  // wrapped: forget every stamp
    for (auto& im : images_) std::fill(im.begin(), im.end(), Image{});
    std::fill(edge_img_.begin(), edge_img_.end(), 0);
    std::fill(face_img_.begin(), face_img_.end(), FaceImage{});
    gen_ = 1;
  }
  if (top >= 2) {
    const std::size_t ne = m.ranks_[1].offsets.size() - 1, nf = m.ranks_[2].offsets.size() - 1;
    if (edge_img_.size() < ne) edge_img_.resize(ne, 0);
    if (face_img_.size() < nf) face_img_.resize(nf);
  }
  if (s_.size() < nv) s_.resize(nv), side_.resize(nv);
  if (images_.size() < static_cast<std::size_t>(top + 1))
    images_.resize(top + 1), terms_.resize(top + 1);
  if (mark_.size() < static_cast<std::size_t>(top + 1)) mark_.resize(top + 1);
  for (int k = 1; k <= top; ++k) {
    const std::size_t count = m.ranks_[k].offsets.size() - 1;
    if (images_[k].size() < count) images_[k].resize(count);
    terms_[k].clear();
    if (mark_[k].size() < (count + 63) / 64) mark_[k].resize((count + 63) / 64, 0);
  }
}

void Slicer::start_buffers(const SliceModel& m, const Placement& pl, SliceBuffers& out) {
  const int n = m.dim_;
  out.reused_topology = false;
  out.general = false;
  out.fallback = FallbackReason::None;
  out.cache_valid_ = false;
  out.dim = n - 1;
  out.plane.normal = pl.plane->normal;
  out.plane.offset = pl.offset;
  out.coords.clear();
  out.vertex_source.clear();
  section_edge_.clear();
  facet_internal_.clear();
  out.set_ranks(std::max(1, std::min(m.top_ - 1, n - 1)));
  out.facet_normals.clear();
}

namespace {

// A crossing the fast paths leave to the general one: on an edge nearly parallel to the plane
// (section_general places it on the facets' hyperplanes) or within the weld distance of an end.
// The one rule for crossing() and kernel_slice, so both fall back alike.
inline bool needs_general(double sa, double sb, double t, double len, double near_parallel,
                          double weld) {
  return std::abs(sa - sb) < near_parallel * len || t * len <= weld || (1.0 - t) * len <= weld;
}

}  // namespace

bool Slicer::crossing(const SliceModel& m, std::uint32_t e, double* t_out) const {
  const std::uint32_t a = m.ranks_[1].ids[2 * e], b = m.ranks_[1].ids[2 * e + 1];
  const double t = s_[a] / (s_[a] - s_[b]);
  const double len = m.edge_length_[e];
  *t_out = t;
  return !needs_general(s_[a], s_[b], t, len, near_parallel_, m.weld_);
}

bool Slicer::add_crossing(const SliceModel& m, std::uint32_t e, SliceBuffers& out) {
  double t;
  if (!crossing(m, e, &t)) return fail(FallbackReason::Weld);
  const SliceModel::Rank& E = m.ranks_[1];
  const std::uint32_t a = E.ids[2 * e];
  const std::uint32_t v = static_cast<std::uint32_t>(out.vertex_source.size());
  out.vertex_source.push_back({E.model_id.empty() ? e : E.model_id[e], 1, t});
  section_edge_.push_back(e);
  images_[1][e] = {gen_, static_cast<std::uint32_t>(terms_[1].size()), 1};
  terms_[1].push_back({v, side_[a] < 0 ? 1 : -1});
  mark_parents(m, 1, e);
  return true;
}

bool Slicer::fast_slice_marked(const SliceModel& m, const Placement& pl,
                               const SliceOptions& options, SliceBuffers& out) {
  const int n = m.dim_;
  const std::size_t nc = m.cluster_count();
  touched_.clear();
  for (std::size_t c = 0; c < nc; ++c)
    if (!options.cull ||
        pl.meets(&m.cluster_sphere_[c * (n + 1)], m.cluster_sphere_[c * (n + 1) + n]))
      touched_.push_back(static_cast<std::uint32_t>(c));
  // Signed values of the touched clusters' vertices (of all vertices, once each, when every
  // cluster is touched: the clusters' vertex lists share their border vertices).
  const double* P = m.positions_.data();
  auto value = [&](std::uint32_t v) {
    const double s = height(pl.nm, P + v * n, n) - pl.dm;
    const Side side = classify_side(s, pl.tol);
    s_[v] = s;
    side_[v] = static_cast<std::int8_t>(side);
    return side != Side::On;  // on the plane: symbolic perturbation, the general path
  };
  if (touched_.size() == nc && n == 4) {
    // Every vertex (each belongs to a cluster): one pass without early exits, the same values
    // and sides as `value` gives.
    const std::uint32_t nv = static_cast<std::uint32_t>(m.positions_.size() / 4);
    const double n0 = pl.nm[0], n1 = pl.nm[1], n2 = pl.nm[2], n3 = pl.nm[3], dm = pl.dm;
    const double tol = pl.tol;
    double* sv = s_.data();
    std::int8_t* sd = side_.data();
    bool on = false;
    for (std::uint32_t v = 0; v < nv; ++v) {
      const double* x = P + 4 * v;
      double h = n0 * x[0];
      h += n1 * x[1];
      h += n2 * x[2];
      h += n3 * x[3];
      const double sval = h - dm;
      const std::int8_t sgn = static_cast<std::int8_t>((sval > tol) - (sval < -tol));
      sv[v] = sval;
      sd[v] = sgn;
      on |= sgn == 0;
    }
    if (on) return fail(FallbackReason::OnPlane);
  } else if (touched_.size() == nc && nc > 1) {
    const std::uint32_t nv = static_cast<std::uint32_t>(m.positions_.size() / n);
    for (std::uint32_t v = 0; v < nv; ++v)
      if (!value(v)) return fail(FallbackReason::OnPlane);
  } else {
    for (auto c : touched_)
      for (std::uint32_t i = m.cluster_vertex_[c]; i < m.cluster_vertex_[c + 1]; ++i)
        if (!value(m.cluster_vertices_[i])) return fail(FallbackReason::OnPlane);
  }
  if (kernel_ && n == 4 && m.top_ >= 3) {
    const int done = kernel_slice(m, pl, out);
    if (done == 0) return false;
    if (done > 0) {
      if (options.reuse_topology) remember(m, pl, out);
      ++fast_count_;
      return true;
    }
    clear_marks(m);  // something for the generic gathering: it cuts the slice from the start
  }
  // Rank 1: a section vertex per crossing edge, in id order.
  start_buffers(m, pl, out);
  const SliceModel::Rank& E = m.ranks_[1];
  for (auto c : touched_)
    for (std::uint32_t e = m.begin_[0][c]; e < m.begin_[0][c + 1]; ++e)
      if (side_[E.ids[2 * e]] != side_[E.ids[2 * e + 1]] && !add_crossing(m, e, out)) return false;
  if (out.vertex_source.empty()) {
    clear_to_empty(out, n - 1);
    if (options.reuse_topology) remember(m, pl, out);
    ++fast_count_;
    return true;
  }
  if (!cut_upper(m, pl, out)) return false;
  // The topology cache is kept only for callers that use it (animation frames).
  if (options.reuse_topology) remember(m, pl, out);
  ++fast_count_;
  return true;
}

int Slicer::kernel_slice(const SliceModel& m, const Placement& pl, SliceBuffers& out,
                         bool marked_edges) {
  // A section vertex per crossing edge, a section edge per face with exactly two crossings, a
  // polygon per cell whose section edges form one loop: the buffers the generic gathering
  // writes for such a slice (tested element for element), in the same order, written once.
  // Each face and cell reads its boundary's images straight from one stamped word per element.
  start_buffers(m, pl, out);
  constexpr std::uint64_t kGen = 0xffffffff00000000ull;
  constexpr std::uint32_t kFlip = 0x80000000u, kIndex = 0x7fffffffu;
  const std::uint64_t g = std::uint64_t{gen_} << 32;
  const SliceModel::Rank& E = m.ranks_[1];
  const SliceModel::Rank& F = m.ranks_[2];
  const SliceModel::Rank& C = m.ranks_[3];
  const std::uint32_t* edge_ends = E.ids.data();
  const std::int8_t* side = side_.data();
  const double* s = s_.data();
  const double* edge_length = m.edge_length_.data();
  const double weld = m.weld_;
  const double near_parallel = near_parallel_;
  std::uint64_t* edge_img = edge_img_.data();
  FaceImage* face_img = face_img_.data();
  // Byte marks of the faces and cells to visit, all zero between slices (cleared by the visits,
  // or wholly when the kernel stops half way).
  if (face_mark_.size() < F.offsets.size() - 1) face_mark_.resize(F.offsets.size() - 1, 0);
  if (cell_mark_.size() < C.offsets.size() - 1) cell_mark_.resize(C.offsets.size() - 1, 0);
  std::uint8_t* face_marks = face_mark_.data();
  std::uint8_t* cell_marks = cell_mark_.data();
  auto stop = [&](int result) {
    std::fill(face_mark_.begin(), face_mark_.end(), 0);
    std::fill(cell_mark_.begin(), cell_mark_.end(), 0);
    return result;
  };
  const std::uint32_t* edge_up = m.up_offsets_[1].data();
  const std::uint32_t* edge_up_ids = m.up_ids_[1].data();
  const std::uint32_t* face_up = m.up_offsets_[2].data();
  const std::uint32_t* face_up_ids = m.up_ids_[2].data();
  // Rank 1: the crossings, in id order cluster by cluster.
  std::uint32_t cut_faces_bound = 0;
  for (auto c : touched_) {
    // The crossing edges first: listed without a branch (the sides are unpredictable), or
    // those a sweep marked.
    const std::uint32_t e0 = m.begin_[0][c], e1 = m.begin_[0][c + 1];
    if (crossing_ids_.size() < e1 - e0) crossing_ids_.resize(e1 - e0);
    std::uint32_t* list = crossing_ids_.data();
    std::uint32_t count = 0;
    if (marked_edges) {
      visit_marked(mark_[1], e0, e1, [&](std::uint32_t e) {
        list[count++] = e;
        return true;
      });
    } else {
      for (std::uint32_t e = e0; e < e1; ++e) {
        list[count] = e;
        count += side[edge_ends[2 * e]] != side[edge_ends[2 * e + 1]];
      }
    }
    const std::uint32_t v0 = static_cast<std::uint32_t>(out.vertex_source.size());
    out.vertex_source.resize(v0 + count);
    section_edge_.resize(v0 + count);
    VertexSource* vs = out.vertex_source.data();
    std::uint32_t* vertex_edge = section_edge_.data();
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint32_t e = list[i];
      const std::uint32_t a = edge_ends[2 * e], b = edge_ends[2 * e + 1];
      const double t = s[a] / (s[a] - s[b]);
      const double len = edge_length[e];
      if (needs_general(s[a], s[b], t, len, near_parallel, weld)) {  // as crossing()
        reason_ = FallbackReason::Weld;
        return stop(0);
      }
      const std::uint32_t v = v0 + i;
      vs[v] = {E.model_id.empty() ? e : E.model_id[e], 1, t};
      vertex_edge[v] = e;
      // The crossing's coefficient in the edge's cut: +1 when the tail is below.
      edge_img[e] = g | v | (side[a] < 0 ? 0u : kFlip);
      for (std::uint32_t i = edge_up[e]; i < edge_up[e + 1]; ++i) face_marks[edge_up_ids[i]] = 1;
      cut_faces_bound += edge_up[e + 1] - edge_up[e];
    }
  }
  if (out.vertex_source.empty()) {
    clear_to_empty(out, m.dim_ - 1);
    return 1;
  }
  // Rank 2: a face with two crossings of opposite coefficients gives the section edge from the
  // one with -1 to the one with +1.
  Incidence::Storage edges = out.boundary[0].storage();
  edges.ids.resize(2 * std::size_t{cut_faces_bound});
  std::uint32_t* edge_row = edges.ids.data();
  std::uint32_t nse = 0, cut_cells_bound = 0;
  {
    const std::uint32_t* off = F.offsets.data();
    const std::uint32_t* ids = F.ids.data();
    const std::int8_t* signs = F.signs.data();
    std::vector<std::uint32_t>& src_store = out.source[1];
    src_store.resize(cut_faces_bound);
    std::uint32_t* src = src_store.data();
    auto face = [&](std::uint32_t x) -> bool {
      std::uint32_t v[2];
      int coef[2];
      int cnt = 0;
      for (std::uint32_t i = off[x], end = off[x + 1]; i < end; ++i) {
        const std::uint64_t img = edge_img[ids[i]];
        if ((img & kGen) != g) continue;
        if (cnt == 2) return false;
        const std::uint32_t low = static_cast<std::uint32_t>(img);
        v[cnt] = low & kIndex;
        coef[cnt] = (low & kFlip) ? signs[i] : -signs[i];
        ++cnt;
      }
      if (cnt != 2 || v[0] == v[1] || coef[0] != -coef[1]) return false;
      const bool first_is_tail = coef[0] < 0;
      edge_row[2 * nse] = first_is_tail ? v[0] : v[1];
      edge_row[2 * nse + 1] = first_is_tail ? v[1] : v[0];
      face_img[x] = {gen_, nse, edge_row[2 * nse], edge_row[2 * nse + 1]};
      src[nse] = F.model_id.empty() ? x : F.model_id[x];
      ++nse;
      for (std::uint32_t i = face_up[x]; i < face_up[x + 1]; ++i) cell_marks[face_up_ids[i]] = 1;
      cut_cells_bound += face_up[x + 1] - face_up[x];
      return true;
    };
    for (auto c : touched_)
      if (!visit_marked_bytes(face_marks, m.begin_[1][c], m.begin_[1][c + 1], face))
        return stop(-1);
    src_store.resize(nse);
  }
  edges.ids.resize(2 * std::size_t{nse});
  edges.signs.resize(2 * std::size_t{nse});
  edges.offsets.resize(std::size_t{nse} + 1);
  for (std::uint32_t i = 0; i <= nse; ++i) edges.offsets[i] = 2 * i;
  for (std::uint32_t i = 0; i < nse; ++i) edges.signs[2 * i] = -1, edges.signs[2 * i + 1] = 1;
  // Rank 3 (the facets): the steps of a cell's section edges, one leaving each section vertex
  // (stamped per cell), followed from the smallest tail; one loop through every step is the
  // polygon the generic gathering chains (loops start at the smallest tail, steps follow
  // heads). A pinch, an open chain or several loops: the generic gathering.
  const std::size_t nsv = out.vertex_source.size();
  if (loop_step_.size() < nsv) loop_step_.resize(nsv, LoopStep{0, 0, 0});
  LoopStep* step = loop_step_.data();
  Incidence::Storage polys = out.boundary[1].storage();
  polys.ids.resize(cut_cells_bound);
  polys.signs.resize(cut_cells_bound);
  std::uint32_t* poly_ids = polys.ids.data();
  std::int8_t* poly_signs = polys.signs.data();
  std::uint32_t entries = 0;
  const bool above = m.top_ > 3;
  const bool chains_above = above && !m.single_solid_;
  {
    const std::uint32_t* off = C.offsets.data();
    const std::uint32_t* ids = C.ids.data();
    const std::int8_t* signs = C.signs.data();
    std::vector<std::uint32_t>& src_store = out.source[2];
    src_store.resize(cut_cells_bound);
    facet_internal_.resize(cut_cells_bound);
    polys.offsets.resize(std::size_t{cut_cells_bound} + 1);
    std::uint32_t* src = src_store.data();
    std::uint32_t* facet = facet_internal_.data();
    std::uint32_t* poly_off = polys.offsets.data();
    std::uint32_t npoly = 0;
    auto cell = [&](std::uint32_t x) -> bool {
      if (++stamp_ == 0) {  // wrapped: forget every stamp
        for (std::size_t i = 0; i < loop_step_.size(); ++i) loop_step_[i].stamp = 0;
        stamp_ = 1;
      }
      const std::uint32_t st = stamp_;
      std::uint32_t lo = 0xffffffffu, ns = 0;
      for (std::uint32_t i = off[x], end = off[x + 1]; i < end; ++i) {
        const FaceImage img = face_img[ids[i]];
        if (img.gen != gen_) continue;
        const std::uint32_t se = img.edge;
        const bool forward = signs[i] < 0;  // the step's sign, -signs[i], is +1
        const std::uint32_t tail = forward ? img.tail : img.head;
        const std::uint32_t head = forward ? img.head : img.tail;
        if (step[tail].stamp == st) return false;  // a pinch (or a face listed twice)
        step[tail] = {st, head, forward ? se : se | kFlip};
        lo = std::min(lo, tail);
        ++ns;
      }
      if (ns < 3) return false;
      std::uint32_t cur = lo;
      for (std::uint32_t k = 0;;) {
        const LoopStep sp = step[cur];
        if (sp.stamp != st) return false;  // the chain does not close
        poly_ids[entries] = sp.edge & kIndex;
        poly_signs[entries] = (sp.edge & kFlip) ? -1 : 1;
        ++entries;
        ++k;
        cur = sp.head;
        if (cur == lo) {
          if (k != ns) return false;  // several loops
          break;
        }
        if (k == ns) return false;
      }
      const std::uint32_t poly = npoly++;
      poly_off[npoly] = entries;
      src[poly] = C.model_id.empty() ? x : C.model_id[x];
      facet[poly] = x;
      if (above) {
        if (chains_above) {
          images_[3][x] = {gen_, static_cast<std::uint32_t>(terms_[3].size()), 1};
          terms_[3].push_back({poly, 1});
        }
        mark_parents(m, 3, x);
      }
      return true;
    };
    for (auto c : touched_)
      if (!visit_marked_bytes(cell_marks, m.begin_[2][c], m.begin_[2][c + 1], cell))
        return stop(-1);
    src_store.resize(npoly);
    facet_internal_.resize(npoly);
    polys.offsets.resize(std::size_t{npoly} + 1);
  }
  polys.ids.resize(entries);
  polys.signs.resize(entries);
  kernel_count_ += nse + out.source[2].size();
  return cut_upper(m, pl, out, 4) ? 1 : 0;  // (the rank-4 marks are the generic path's bits)
}

bool Slicer::cut_upper(const SliceModel& m, const Placement& pl, SliceBuffers& out, int from) {
  const int fr = m.dim_ - 1;
  const int top = m.top_;
  // Ranks 2..top: only the elements a crossing reaches (marked through the cofaces), in
  // increasing id order within each touched cluster, so the order is that of a full scan.
  for (int k = from; k <= top; ++k) {
    const SliceModel::Rank& R = m.ranks_[k];
    const std::size_t count = R.offsets.size() - 1;
    std::vector<std::uint64_t>& bits = mark_[k];
    // (rank k - 1 is complete: its images and terms stay put while rank k is cut)
    const Image* below = images_[k - 1].data();
    const Term* below_terms = terms_[k - 1].data();
    const std::uint32_t* offsets = R.offsets.data();
    const std::uint32_t* ids = R.ids.data();
    const std::int8_t* signs = R.signs.data();
    const std::uint32_t gen = gen_;
    auto process = [&](std::uint32_t x) -> bool {
      chain_.clear();
      for (std::uint32_t i = offsets[x], end = offsets[x + 1]; i < end; ++i) {
        const Image img = below[ids[i]];
        if (img.gen != gen) continue;
        for (std::uint32_t j = img.begin; j < img.begin + img.count; ++j)
          chain_.push_back({below_terms[j].id, -signs[i] * below_terms[j].coef});
      }
      if (chain_.empty()) return true;
      const std::uint32_t first = static_cast<std::uint32_t>(terms_[k].size());
      if (!emit_element(m, k, x, out, facet_internal_, terms_[k])) return false;
      const std::uint32_t produced = static_cast<std::uint32_t>(terms_[k].size()) - first;
      images_[k][x] = {gen_, first, produced};
      if (produced > 0 && k < top) mark_parents(m, k, x);
      return true;
    };
    // The specialised kernel. A convex face is cut in exactly two crossings: one section edge
    // from the crossing whose chain coefficient is -1 to the one with +1, as the generic
    // gathering gives after combine_chain. A cell whose faces each gave one section edge is
    // chained through a next map (the step leaving each section vertex, stamped per cell) from
    // its smallest tail; when that one loop uses every step it is the polygon emit_loops
    // builds (loops start at the smallest tail, steps follow heads). Anything else (more
    // crossings, a face twice, a pinch, several loops, an open chain) goes to `process`, which
    // decides it exactly as before. Returns 1 when done, -1 for `process`.
    Incidence& out_edges = out.boundary[0];
    auto face_kernel = [&](std::uint32_t x) -> int {
      std::uint32_t v[2];
      int c[2];
      int cnt = 0;
      for (std::uint32_t i = offsets[x], end = offsets[x + 1]; i < end; ++i) {
        const Image img = below[ids[i]];
        if (img.gen != gen) continue;
        if (cnt == 2) return -1;
        const Term& t = below_terms[img.begin];
        v[cnt] = t.id;
        c[cnt] = -signs[i] * t.coef;
        ++cnt;
      }
      if (cnt != 2 || v[0] == v[1] || c[0] != -c[1]) return -1;
      const std::uint32_t ends[2] = {c[0] < 0 ? v[0] : v[1], c[0] < 0 ? v[1] : v[0]};
      static constexpr std::int8_t kEdgeSigns[2] = {-1, 1};
      const std::uint32_t first = static_cast<std::uint32_t>(terms_[k].size());
      terms_[k].push_back({static_cast<std::uint32_t>(out_edges.size()), 1});
      out_edges.add_row(ends, kEdgeSigns);
      out.source[1].push_back(R.model_id.empty() ? x : R.model_id[x]);
      if (k == fr) facet_internal_.push_back(x);
      images_[k][x] = {gen, first, 1};
      if (k < top) mark_parents(m, k, x);
      return 1;
    };
    const std::uint32_t* edge_ends = out_edges.all_ids().data();
    auto cell_kernel = [&](std::uint32_t x) -> int {
      if (++stamp_ == 0) {  // wrapped: forget every stamp
        std::fill(vertex_stamp_.begin(), vertex_stamp_.end(), 0u);
        std::fill(edge_stamp_.begin(), edge_stamp_.end(), 0u);
        stamp_ = 1;
      }
      const std::uint32_t st = stamp_;
      steps_.clear();
      std::uint32_t lo = none, start = 0;
      for (std::uint32_t i = offsets[x], end = offsets[x + 1]; i < end; ++i) {
        const Image img = below[ids[i]];
        if (img.gen != gen) continue;
        if (img.count != 1) return -1;
        const Term& t = below_terms[img.begin];
        if (edge_stamp_[t.id] == st) return -1;
        edge_stamp_[t.id] = st;
        const int sign = -signs[i] * t.coef;
        const std::uint32_t tail = edge_ends[2 * t.id + (sign > 0 ? 0 : 1)];
        const std::uint32_t head = edge_ends[2 * t.id + (sign > 0 ? 1 : 0)];
        if (vertex_stamp_[tail] == st) return -1;  // a pinch
        vertex_stamp_[tail] = st;
        vertex_next_[tail] = static_cast<std::uint32_t>(steps_.size());
        if (tail < lo) lo = tail, start = static_cast<std::uint32_t>(steps_.size());
        steps_.push_back({tail, head, t.id, sign, false});
      }
      const std::size_t ns = steps_.size();
      if (ns < 3) return -1;
      row_ids_.clear();
      row_signs_.clear();
      std::uint32_t cur = start;
      for (;;) {
        const Step& sp = steps_[cur];
        row_ids_.push_back(sp.edge);
        row_signs_.push_back(static_cast<std::int8_t>(sp.sign));
        if (sp.head == lo) break;
        if (row_ids_.size() == ns || vertex_stamp_[sp.head] != st) return -1;
        cur = vertex_next_[sp.head];
      }
      if (row_ids_.size() != ns) return -1;  // several loops
      Incidence& faces = out.boundary[1];
      const std::uint32_t first = static_cast<std::uint32_t>(terms_[k].size());
      terms_[k].push_back({static_cast<std::uint32_t>(faces.size()), 1});
      faces.add_row(row_ids_, row_signs_);
      out.source[2].push_back(R.model_id.empty() ? x : R.model_id[x]);
      if (k == fr) facet_internal_.push_back(x);
      images_[k][x] = {gen, first, 1};
      if (k < top) mark_parents(m, k, x);
      return 1;
    };
    const bool use_kernel = kernel_ && (k == 2 || (k == 3 && fr == 3));
    if (use_kernel && k == 3) {
      const std::size_t nsv = out.vertex_source.size(), nse = out_edges.size();
      if (vertex_stamp_.size() < nsv) vertex_stamp_.resize(nsv, 0), vertex_next_.resize(nsv);
      if (edge_stamp_.size() < nse) edge_stamp_.resize(nse, 0);
    }
    auto kernel_process = [&](std::uint32_t x) -> bool {
      if ((k == 2 ? face_kernel(x) : cell_kernel(x)) > 0) {
        ++kernel_count_;
        return true;
      }
      ++generic_count_;
      return process(x);
    };
    auto visit = [&](std::uint32_t b, std::uint32_t e) {
      return use_kernel ? visit_marked(bits, b, e, kernel_process)
                        : visit_marked(bits, b, e, process);
    };
    if (k == top && m.single_solid_ && k == 3) {
      // The one solid of a polyhedron: its cut's boundary is every section edge, with the
      // sign of the edge's facet in the solid (no gathering over the solid's long row).
      if (bits[0] & 1u) {
        bits[0] = 0;
        chain_.clear();
        for (std::uint32_t i = 0; i < facet_internal_.size(); ++i)
          chain_.push_back({i, -m.solid_sign_[facet_internal_[i]]});
        image_.clear();
        if (!emit_loops(chain_, R.model_id.empty() ? 0 : R.model_id[0], out, image_)) return false;
      }
      continue;
    }
    if (k == top && m.single_solid_) {
      // The one solid bounded by every facet once: its cut is every section facet, in order
      // (a rank >= 3 element lists its facets; finish_fast gives them sign +1).
      if (bits[0] & 1u) {
        bits[0] = 0;
        Incidence& table = out.boundary[k - 2];
        const std::uint32_t nf = static_cast<std::uint32_t>(out.boundary[k - 3].size());
        row_ids_.resize(nf);
        row_signs_.assign(nf, 1);
        for (std::uint32_t i = 0; i < nf; ++i) row_ids_[i] = i;
        table.add_row(row_ids_, row_signs_);
        out.source[k - 1].push_back(R.model_id.empty() ? 0 : R.model_id[0]);
      }
      continue;
    }
    if (k <= fr) {
      for (auto c : touched_)
        if (!visit(m.begin_[k - 1][c], m.begin_[k - 1][c + 1])) return false;
    } else if (!visit(0, static_cast<std::uint32_t>(count))) {
      return false;
    }
  }
  return finish_fast(m, pl, out, section_edge_, facet_internal_);
}

void Slicer::remember(const SliceModel& m, const Placement& pl, SliceBuffers& out) {
  out.cache_model_ = m.serial_;
  out.cache_touched_ = touched_;
  out.cache_side_.clear();
  for (auto c : touched_)
    for (std::uint32_t i = m.cluster_vertex_[c]; i < m.cluster_vertex_[c + 1]; ++i)
      out.cache_side_.push_back(side_[m.cluster_vertices_[i]]);
  out.cache_edge_ = section_edge_;
  out.cache_facet_ = facet_internal_;
  out.cache_reflect_ = pl.reflect;
  out.cache_valid_ = true;
}

bool Slicer::finish_fast(const SliceModel& m, const Placement& pl, SliceBuffers& out,
                         std::span<const std::uint32_t> section_edge,
                         std::span<const std::uint32_t> facet_internal) {
  const int n = m.dim_;
  // Orientation as section(): the facets' cuts face outward for even n, inward for odd n, and
  // a reflecting transform reverses them once more; solids list their facets with +1.
  const int ofr = n - 2;
  if (pl.reflect != (n % 2 == 1)) {
    Incidence& table = out.boundary[ofr - 1];
    for (std::size_t f = 0; f < table.size(); ++f) {
      auto ids = table.ids_mut(f);
      auto signs = table.signs_mut(f);
      if (ofr == 1) {
        std::swap(ids[0], ids[1]);
      } else {
        std::reverse(ids.begin(), ids.end());
        std::reverse(signs.begin(), signs.end());
        for (auto& s : signs) s = static_cast<std::int8_t>(-s);
      }
    }
  }
  if (static_cast<int>(out.boundary.size()) >= n - 1 && n - 1 >= 2) {
    Incidence& solids = out.boundary[n - 2];
    for (std::size_t i = 0; i < solids.size(); ++i)
      for (auto& s : solids.signs_mut(i)) s = 1;
  }
  return write_geometry(m, pl, out, section_edge, facet_internal);
}

namespace {

// The vertex and facet-normal passes of write_geometry with the dimension fixed at compile
// time (the loops unroll; the arithmetic is the same, term for term). False when a facet is
// nearly parallel to the plane.
template <int N>
bool geometry_pass(const double* P, const std::uint32_t* edge_ids, const double* M, const double* c,
                   const double* Nm, const double* facet_normals,
                   std::span<const std::uint32_t> section_edge, const VertexSource* source,
                   std::span<const std::uint32_t> facet_internal, double* coords, double* normals) {
  constexpr int O = N - 1;
  // Vertices: y = M ((1 - t) a + t b) + c.
  for (std::size_t i = 0; i < section_edge.size(); ++i) {
    const std::uint32_t e = section_edge[i];
    const double* pa = P + edge_ids[2 * e] * N;
    const double* pb = P + edge_ids[2 * e + 1] * N;
    const double t = source[i].t;
    double x[N];
    for (int j = 0; j < N; ++j) x[j] = (1.0 - t) * pa[j] + t * pb[j];
    for (int r = 0; r < O; ++r) {
      double sum = c[r];
      for (int j = 0; j < N; ++j) sum += M[r * N + j] * x[j];
      coords[i * O + r] = sum;
    }
  }
  // Facet normals: the model facets' normals through A^{-T}, projected, unit.
  for (std::size_t f = 0; f < facet_internal.size(); ++f) {
    const double* nf = facet_normals + facet_internal[f] * N;
    double y[O], len2 = 0.0;
    for (int r = 0; r < O; ++r) {
      double sum = 0.0;
      for (int j = 0; j < N; ++j) sum += Nm[r * N + j] * nf[j];
      y[r] = sum;
      len2 += sum * sum;
    }
    const double len = std::sqrt(len2);
    // Nearly parallel to the plane: the general path's area vector.
    if (len < tol::near_parallel_normal) return false;
    for (int r = 0; r < O; ++r) normals[f * O + r] = y[r] / len;
  }
  return true;
}

}  // namespace

bool Slicer::write_geometry(const SliceModel& m, const Placement& pl, SliceBuffers& out,
                            std::span<const std::uint32_t> section_edge,
                            std::span<const std::uint32_t> facet_internal) {
  const int n = m.dim_;
  const int o = n - 1;
  out.coords.resize(section_edge.size() * o);
  out.facet_normals.resize(facet_internal.size() * o);
  const auto pass = n == 4 ? geometry_pass<4> : geometry_pass<3>;
  if (!pass(m.positions_.data(), m.ranks_[1].ids.data(), pl.M, pl.c, pl.N, m.facet_normals_.data(),
            section_edge, out.vertex_source.data(), facet_internal, out.coords.data(),
            out.facet_normals.data()))
    return fail(FallbackReason::NearParallel);
  return true;
}

bool Slicer::reuse(const SliceModel& m, const Placement& pl, const SliceOptions& options,
                   SliceBuffers& out) {
  if (!out.cache_valid_ || out.cache_model_ != m.serial_ || out.cache_reflect_ != pl.reflect)
    return false;
  const int n = m.dim_;
  const std::size_t nv = m.positions_.size() / n;
  const std::size_t nc = m.cluster_count();
  if (s_.size() < nv) s_.resize(nv), side_.resize(nv);
  touched_.clear();
  for (std::size_t c = 0; c < nc; ++c)
    if (!options.cull ||
        pl.meets(&m.cluster_sphere_[c * (n + 1)], m.cluster_sphere_[c * (n + 1) + n]))
      touched_.push_back(static_cast<std::uint32_t>(c));
  if (touched_ != out.cache_touched_) return false;
  const double* P = m.positions_.data();
  std::size_t k = 0;
  for (auto c : touched_)
    for (std::uint32_t i = m.cluster_vertex_[c]; i < m.cluster_vertex_[c + 1]; ++i, ++k) {
      const std::uint32_t v = m.cluster_vertices_[i];
      const double s = height(pl.nm, P + v * n, n) - pl.dm;
      const Side side = classify_side(s, pl.tol);
      if (side == Side::On || static_cast<std::int8_t>(side) != out.cache_side_[k]) return false;
      s_[v] = s;
    }
  // Same sides: the same connectivity. New crossing parameters, positions and normals.
  for (std::size_t i = 0; i < out.cache_edge_.size(); ++i)
    if (!crossing(m, out.cache_edge_[i], &out.vertex_source[i].t)) return false;
  out.plane = *pl.plane;
  if (!write_geometry(m, pl, out, out.cache_edge_, out.cache_facet_)) return false;
  out.reused_topology = true;
  out.general = false;
  out.fallback = FallbackReason::None;
  return true;
}

// --- sweeps ---------------------------------------------------------------------------------

void Slicer::sweep(const SliceModel& m, const Eigen::VectorXd& normal,
                   std::span<const double> offsets, const AffineTransform& xf,
                   std::vector<SliceBuffers>& out, unsigned threads) {
  if (offsets.empty()) {
    out.clear();
    return;
  }
  const Hyperplane proto = Hyperplane::from(normal, offsets[0]);
  for (double d : offsets)
    if (!std::isfinite(d)) throw InputError("hyperplane offset is not finite");
  check_section_input(m.complex(), proto, xf);
  out.resize(offsets.size());
  std::vector<std::uint32_t>& order = sweep_order_;
  order.resize(offsets.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return offsets[a] < offsets[b]; });
  threads = resolve_threads(threads);
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, order.size()));
  if (threads <= 1) {
    sweep_layers(m, proto, xf, offsets, order, out);
    return;
  }
  // Consecutive groups of layers in offset order, one Slicer per extra thread (kept for the
  // next sweep); each thread writes only its own entries of out.
  if (helpers_.size() < threads - 1) helpers_.resize(threads - 1);
  std::vector<std::size_t> before(threads - 1);
  for (unsigned t = 0; t + 1 < threads; ++t) before[t] = helpers_[t].fast_count_;
  const std::size_t per = (order.size() + threads - 1) / threads;
  fork_join(threads, [&](unsigned t) {
    const std::size_t b = std::min(order.size(), t * per),
                      e = std::min(order.size(), (t + 1) * per);
    if (b < e)
      (t == 0 ? *this : helpers_[t - 1])
          .sweep_layers(m, proto, xf, offsets,
                        std::span<const std::uint32_t>(order).subspan(b, e - b), out);
  });
  for (unsigned t = 0; t + 1 < threads; ++t) fast_count_ += helpers_[t].fast_count_ - before[t];
}

void Slicer::sweep_layers(const SliceModel& m, const Hyperplane& plane, const AffineTransform& xf,
                          std::span<const double> offsets, std::span<const std::uint32_t> layers,
                          std::vector<SliceBuffers>& out) {
  const std::size_t L = layers.size();
  if (L == 0) return;
  kernel_ = true;
  auto single = [&](std::uint32_t k) {
    slice(m, Hyperplane{plane.normal, offsets[k]}, xf, out[k]);
  };
  if (!m.fast()) {
    for (auto k : layers) single(k);
    return;
  }
  const int n = m.dim_;
  const std::size_t nv = m.positions_.size() / n;
  const std::size_t nc = m.cluster_count();
  Placement pl;
  pl.set(m, plane, &xf);
  near_parallel_ = tol::near_parallel_edge * pl.nm_norm;
  // Per layer (in offset order): the model-space offset and the ON band.
  layer_d_.resize(L);
  layer_tol_.resize(L);
  double max_tol = 0.0;
  for (std::size_t j = 0; j < L; ++j) {
    pl.set_offset(m, offsets[layers[j]]);
    layer_d_[j] = pl.dm;
    layer_tol_[j] = pl.tol;
    max_tol = std::max(max_tol, pl.tol);
  }
  const double* D = layer_d_.data();
  auto first_above = [&](double h) {  // first layer with d > h
    return static_cast<std::uint32_t>(std::upper_bound(D, D + L, h) - D);
  };
  // Heights once per vertex. A vertex within a layer's ON band sends that layer to slice().
  const double* P = m.positions_.data();
  height_.resize(nv);
  layer_bad_.assign(L, 0);
  for (std::size_t v = 0; v < nv; ++v) {
    const double h = height(pl.nm, P + v * n, n);
    height_[v] = h;
    const double delta = 2.0 * max_tol;
    for (std::uint32_t j = static_cast<std::uint32_t>(std::lower_bound(D, D + L, h - delta) - D);
         j < L && D[j] <= h + delta; ++j)
      if (classify_side(h - D[j], layer_tol_[j]) == Side::On) layer_bad_[j] = 1;
  }
  // Without ON vertices, edge (a, b) crosses layer j exactly when lo < d_j < hi for its end
  // heights lo < hi (the sign of the rounded h - d is the sign of h - d). Edges enter the
  // active set at the first layer above lo (bucketed by that layer) and leave it at the first
  // layer at or above hi (dropped before the layer is built), so each layer sees exactly its
  // crossing edges.
  const SliceModel::Rank& E = m.ranks_[1];
  const std::uint32_t ne = static_cast<std::uint32_t>(E.offsets.size() - 1);
  bucket_offsets_.assign(L + 2, 0);
  edge_top_.resize(ne);
  edge_start_.resize(ne);
  for (std::uint32_t e = 0; e < ne; ++e) {
    const double ha = height_[E.ids[2 * e]], hb = height_[E.ids[2 * e + 1]];
    const std::uint32_t j = first_above(std::min(ha, hb));
    edge_start_[e] = j;
    edge_top_[e] = std::max(ha, hb);
    ++bucket_offsets_[j + 1];
  }
  for (std::size_t j = 0; j <= L; ++j) bucket_offsets_[j + 1] += bucket_offsets_[j];
  bucket_ids_.resize(ne);
  {
    std::vector<std::uint32_t>& fill = bucket_fill_;
    fill.assign(bucket_offsets_.begin(), bucket_offsets_.end() - 1);
    for (std::uint32_t e = 0; e < ne; ++e) bucket_ids_[fill[edge_start_[e]]++] = e;
  }
  active_.clear();
  for (std::size_t j = 0; j < L; ++j) {
    const double d = D[j];
    for (std::uint32_t i = bucket_offsets_[j]; i < bucket_offsets_[j + 1]; ++i)
      active_.push_back(bucket_ids_[i]);
    std::size_t keep = 0;
    for (std::uint32_t e : active_)
      if (edge_top_[e] > d) active_[keep++] = e;
    active_.resize(keep);
    const std::uint32_t k = layers[j];
    if (layer_bad_[j]) {
      single(k);
      continue;
    }
    SliceBuffers& o = out[k];
    pl.set_offset(m, offsets[k]);
    prepare(m);
    touched_.clear();
    for (std::size_t c = 0; c < nc; ++c)
      if (pl.meets(&m.cluster_sphere_[c * (n + 1)], m.cluster_sphere_[c * (n + 1) + n]))
        touched_.push_back(static_cast<std::uint32_t>(c));
    // The crossing edges in increasing id order (marked, then visited cluster by cluster as a
    // slice visits them).
    std::vector<std::uint64_t>& edge_bits = mark_[1];
    for (std::uint32_t e : active_) {
      const std::uint32_t a = E.ids[2 * e], b = E.ids[2 * e + 1];
      s_[a] = height_[a] - d;
      s_[b] = height_[b] - d;
      side_[a] = s_[a] < 0.0 ? -1 : 1;
      side_[b] = s_[b] < 0.0 ? -1 : 1;
      edge_bits[e >> 6] |= std::uint64_t{1} << (e & 63);
    }
    if (n == 4 && m.top_ >= 3) {  // the slice's own kernel on the marked crossings
      if (kernel_slice(m, pl, o, true) > 0) {
        ++fast_count_;
        continue;
      }
      clear_marks(m);
      single(k);  // degenerate, or for the generic gathering: exactly what slice() gives
      continue;
    }
    start_buffers(m, pl, o);
    bool ok = true;
    for (auto c : touched_)
      if (!visit_marked(edge_bits, m.begin_[0][c], m.begin_[0][c + 1],
                        [&](std::uint32_t e) { return add_crossing(m, e, o); })) {
        ok = false;
        break;
      }
    if (ok && o.vertex_source.empty()) {
      clear_to_empty(o, n - 1);
      ++fast_count_;
      continue;
    }
    if (ok && cut_upper(m, pl, o)) {
      ++fast_count_;
      continue;
    }
    clear_marks(m);
    single(k);  // a degenerate layer: exactly what slice() gives
  }
}

// --- scenes ---------------------------------------------------------------------------------

SceneSlicer::SceneSlicer(const Scene& scene, const SliceModelOptions& options) : dim_(scene.dim()) {
  std::unordered_map<const Complex*, const SliceModel*> compiled;
  for (const SceneObject& obj : scene.objects) {
    const Complex* c = obj.complex.get();
    auto it = compiled.find(c);
    if (it == compiled.end()) {
      models_.push_back(std::make_unique<SliceModel>(*c, options));
      it = compiled.emplace(c, models_.back().get()).first;
    }
    const SliceModel& m = *it->second;
    // The sphere in the world: centre moved, radius stretched by the largest singular value.
    const double stretch =
        Eigen::JacobiSVD<Eigen::MatrixXd>(obj.transform.linear()).singularValues()(0);
    const Eigen::VectorXd centre = obj.transform.apply(m.centre());
    const double radius = stretch * m.radius();
    objects_.push_back({&m, obj.transform});
    centres_.insert(centres_.end(), centre.data(), centre.data() + centre.size());
    // Culled when |n.c - d| > radius + margin (tol::bounding_sphere_margin_rel of the size).
    reach_.push_back(radius + tol::bounding_sphere_margin_rel * (radius + centre.norm()));
  }
}

void SceneSlicer::slice(const Hyperplane& plane, std::vector<SliceBuffers>& out, unsigned threads,
                        const SliceOptions& options) {
  if (!objects_.empty() && plane.dim() != dim_)
    throw InputError("hyperplane in R^" + std::to_string(plane.dim()) + " for a scene in R^" +
                     std::to_string(dim_));
  out.resize(objects_.size());
  threads = resolve_threads(threads);
  threads = static_cast<unsigned>(
      std::max<std::size_t>(1, std::min<std::size_t>(threads, objects_.size())));
  if (slicers_.size() < threads) slicers_.resize(threads);
  // The culling pass: one flat array of world-space spheres.
  std::vector<char>& culled = culled_;
  culled.assign(objects_.size(), 0);
  std::size_t touched = objects_.size();
  if (options.cull) {
    const double* nrm = plane.normal.data();
    const double* c = centres_.data();
    const int dim = dim_;
    touched = 0;
    for (std::size_t i = 0; i < objects_.size(); ++i, c += dim) {
      double dist = -plane.offset;
      for (int j = 0; j < dim; ++j) dist += nrm[j] * c[j];
      culled[i] = std::abs(dist) > reach_[i];
      touched += !culled[i];
    }
  }
  touched_ = touched;
  auto run = [&](unsigned t, std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      if (culled[i]) {
        clear_to_empty(out[i], dim_ - 1);
        out[i].plane = plane;
        out[i].general = !objects_[i].model->fast();  // as the general path's empty result
        out[i].fallback = out[i].general ? FallbackReason::Model : FallbackReason::None;
        out[i].reused_topology = false;
        continue;
      }
      slicers_[t].slice(*objects_[i].model, plane, objects_[i].transform, out[i], options);
    }
  };
  // Blocks of consecutive objects; each thread writes only its own entries of out.
  const std::size_t per = (objects_.size() + threads - 1) / threads;
  fork_join(threads, [&](unsigned t) {
    run(t, std::min(objects_.size(), t * per), std::min(objects_.size(), (t + 1) * per));
  });
}

// --- conversion -----------------------------------------------------------------------------

Section to_section(const SliceBuffers& b) {
  Section sec = to_section_untested(b);
  sec.self_intersecting = self_intersects(sec.complex);
  return sec;
}

Section to_section_untested(const SliceBuffers& b) {
  Section sec;
  const int dim = b.dim;
  sec.frame = HyperplaneFrame(b.plane);
  Complex c(dim);
  const Eigen::Index nv = static_cast<Eigen::Index>(b.vertex_source.size());
  c.set_positions(Eigen::Map<const Eigen::MatrixXd>(b.coords.data(), dim, nv));
  for (std::size_t r = 1; r <= b.boundary.size(); ++r)
    c.boundary_mut(static_cast<int>(r)) = b.boundary[r - 1];
  const int ofr = dim - 1;
  if (ofr >= 1 && c.count(ofr) > 0 && !b.facet_normals.empty())
    c.set_facet_normals(Eigen::Map<const Eigen::MatrixXd>(
        b.facet_normals.data(), dim, static_cast<Eigen::Index>(b.facet_normals.size()) / dim));
  sec.vertex_source = b.vertex_source;
  sec.source = b.source;
  if (sec.source.empty()) sec.source.resize(1);
  sec.complex = std::move(c);
  return sec;
}

}  // namespace cw4d
