#pragma once
// What the slicer's translation units share: small loops over marks, the fixed-order height,
// the placement of the plane in model space, and the rule for crossings left to the general
// path. Private to section/src (not installed).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "cw4d/complex/tolerances.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/slicer.hpp"
#include "slice_model_compiled.hpp"

namespace cw4d {

namespace slicer_detail {

inline constexpr int kMaxDim = 4;

// Resizes v to `want` elements, moving dropped ones to `spare` and taking new ones from it, so
// that their own storage is kept.
template <class T>
inline void resize_keeping(std::vector<T>& v, std::vector<T>& spare, std::size_t want) {
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
inline bool visit_marked(std::vector<std::uint64_t>& bits, std::uint32_t b, std::uint32_t e,
                         F&& f) {
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
inline bool visit_marked_bytes(std::uint8_t* marks, std::uint32_t b, std::uint32_t e, F&& f) {
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

inline void clear_to_empty(SliceBuffers& out, int dim) {
  out.forget_topology();
  out.dim = dim;
  out.coords.clear();
  out.vertex_source.clear();
  out.set_ranks(0);  // (no tables: the empty section has only rank 0)
  out.facet_normals.clear();
  out.fallback = FallbackReason::None;
}

// A crossing the fast paths leave to the general one: on an edge nearly parallel to the plane
// (section_general places it on the facets' hyperplanes) or within the weld distance of an end.
// The one rule for crossing() and kernel_slice, so both fall back alike.
inline bool needs_general(double sa, double sb, double t, double len, double near_parallel,
                          double weld) {
  return std::abs(sa - sb) < near_parallel * len || t * len <= weld || (1.0 - t) * len <= weld;
}

// The length of the edge from vertex a to vertex b (n coordinates per vertex in P), summed in
// a fixed order: the one length the weld and near-parallel tests use.
inline double edge_length(const double* P, int n, std::uint32_t a, std::uint32_t b) {
  double len2 = 0.0;
  for (int j = 0; j < n; ++j) {
    const double d = P[std::size_t{b} * n + j] - P[std::size_t{a} * n + j];
    len2 += d * d;
  }
  return std::sqrt(len2);
}

}  // namespace slicer_detail

// needs_general for crossings of the model's edges without a stored length per edge: the
// model's shortest and longest edge decide almost every crossing (a rounded product is monotone
// in its factors, so a test that fails for the longest edge fails for every shorter one, and
// one that fails for the shortest fails for every longer one); only the rest compute the
// edge's length from its ends, as the compile does, so the decision is the same bit for bit.
struct SliceModel::Compiled::CrossingTest {
  const double* P;
  int n;
  double shortest, longest, weld, near_parallel;
  bool operator()(std::uint32_t a, std::uint32_t b, double sa, double sb, double t) const {
    if (!(std::abs(sa - sb) < near_parallel * longest) && !(t * shortest <= weld) &&
        !((1.0 - t) * shortest <= weld))
      return false;
    return slicer_detail::needs_general(sa, sb, t, slicer_detail::edge_length(P, n, a, b),
                                        near_parallel, weld);
  }
};

inline SliceModel::Compiled::CrossingTest SliceModel::Compiled::crossing_test(
    double near_parallel) const {
  return {positions(), dim_, edge_min_, edge_max_, weld_, near_parallel};
}

using namespace slicer_detail;  // (the slicer files only)

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
  void set(const SliceModel::Compiled& m, const Hyperplane& p, const AffineTransform* xf) {
    // The loops at a fixed trip count for R^4 and R^3 (the same operations in the same order).
    if (m.dim() == 4)
      set_dim<4>(m, p, xf);
    else if (m.dim() == 3)
      set_dim<3>(m, p, xf);
    else
      set_dim<0>(m, p, xf);
  }

  template <int D>
  void set_dim(const SliceModel::Compiled& m, const Hyperplane& p, const AffineTransform* xf) {
    const int n = D > 0 ? D : m.dim();  // (a constant for the loops when D > 0)
    this->n = n;
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
    hyperplane_basis(p.normal.data(), n, basis);  // (fixed-size loops for n = 3, 4 there too)
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

  void set_offset(const SliceModel::Compiled& m, double d) {
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

}  // namespace cw4d
