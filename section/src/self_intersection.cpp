#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "cw4d/complex/tolerances.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/triangulate.hpp"

namespace cw4d {

namespace {

using Vec3 = Eigen::Vector3d;

// The faces of a surface in flat arrays: face f's cycle is [off[f], off[f+1]) of `pts` (its
// corners), of `cyc` (their vertex ids in cycle order) and of `ids` (the same ids, sorted, for
// the shared-vertex test).
struct Faces {
  std::vector<std::uint32_t> off, cyc, ids;
  std::vector<Vec3> pts, normal, lo, hi;
  std::vector<char> convex;  // strictly_convex
};

// Strict interior of face f's planar polygon, tested in the coordinate plane that drops the
// normal's largest component (crossing rule).
bool inside(const Faces& F, std::uint32_t f, const Vec3& x) {
  int a = 0;
  F.normal[f].cwiseAbs().maxCoeff(&a);
  const int u = (a + 1) % 3, v = (a + 2) % 3;
  bool in = false;
  const std::uint32_t b = F.off[f], n = F.off[f + 1] - b;
  for (std::uint32_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec3 &p = F.pts[b + i], &q = F.pts[b + j];
    if ((p[v] > x[v]) != (q[v] > x[v]) &&
        x[u] < (q[u] - p[u]) * (x[v] - p[v]) / (q[v] - p[v]) + p[u])
      in = !in;
  }
  return in;
}

// Some boundary edge of f passes through the interior of g (beyond the tolerance `eps`). The
// edges of f ending at one of the k vertices `shared` with g are not tested: such an edge meets
// g's plane at that corner, on g's boundary, so it cannot pierce g; a crossing of the two faces
// beyond their shared corners passes through an edge of one of them that ends at no shared
// corner (their intersection leaves the face it ends in through such an edge), or runs along
// the segment between two shared corners (chord_crosses).
bool edge_pierces(const Faces& F, std::uint32_t f, std::uint32_t g, double eps,
                  const std::uint32_t* shared, int k) {
  const Vec3& g0 = F.pts[F.off[g]];
  const Vec3& gn = F.normal[g];
  const std::uint32_t b = F.off[f], n = F.off[f + 1] - b;
  auto is_shared = [&](std::uint32_t v) { return std::find(shared, shared + k, v) != shared + k; };
  // (edge i runs from corner i to corner j = i + 1; each corner's distance is computed once)
  double sp = gn.dot(F.pts[b] - g0);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t j = i + 1 == n ? 0 : i + 1;
    const Vec3 &p = F.pts[b + i], &q = F.pts[b + j];
    const double sq = gn.dot(q - g0);
    const double s = sp;
    sp = sq;
    if (!((s > eps && sq < -eps) || (s < -eps && sq > eps))) continue;
    if (k > 0 && (is_shared(F.cyc[b + i]) || is_shared(F.cyc[b + j]))) continue;
    const Vec3 x = p + (s / (s - sq)) * (q - p);
    if (inside(F, g, x)) return true;
  }
  return false;
}

// The vertices faces f and g share (all of them, from their sorted id lists) into `out`.
void shared_vertices(const Faces& F, std::uint32_t f, std::uint32_t g,
                     std::vector<std::uint32_t>& out) {
  out.clear();
  std::uint32_t i = F.off[f], ie = F.off[f + 1], j = F.off[g], je = F.off[g + 1];
  while (i < ie && j < je) {
    if (F.ids[i] == F.ids[j])
      out.push_back(F.ids[i]), ++i, ++j;
    else if (F.ids[i] < F.ids[j])
      ++i;
    else
      ++j;
  }
}

// Whether x lies inside face f farther than eps from each of its edges.
bool deep_inside(const Faces& F, std::uint32_t f, const Vec3& x, double eps) {
  const std::uint32_t b = F.off[f], n = F.off[f + 1] - b;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3 &p = F.pts[b + i], d = F.pts[b + (i + 1) % n] - p;
    const double t = std::clamp(d.dot(x - p) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
    if ((p + t * d - x).norm() <= eps) return false;
  }
  return inside(F, f, x);
}

// Whether vertices u and w follow each other on face f's cycle.
bool on_cycle(const Faces& F, std::uint32_t f, std::uint32_t u, std::uint32_t w) {
  const std::uint32_t b = F.off[f], n = F.off[f + 1] - b;
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t x = F.cyc[b + i], y = F.cyc[b + (i + 1) % n];
    if ((x == u && y == w) || (x == w && y == u)) return true;
  }
  return false;
}

// Faces f and g that are not coplanar and share two vertices u and w meet along the segment uw
// (it lies in both planes). Unless uw is an edge of both, the faces cross there when its midpoint
// is on each face: on an edge uw of it, or inside it beyond eps. (In the icosahedral 120-cell
// {3,5,5/2} two icosahedral cells share the five edges of a pentagon, the vertex figure of both,
// whose disc lies inside both: they pass through each other there, and a plane cuts them in two
// polygons crossing along the chord between their cuts of two pentagon edges. No edge of either
// polygon pierces the other.)
bool chord_crosses(const Faces& F, std::uint32_t f, std::uint32_t g, double eps,
                   const std::uint32_t* shared, int k) {
  if (k < 2 ||
      (k == 2 && on_cycle(F, f, shared[0], shared[1]) && on_cycle(F, g, shared[0], shared[1])))
    return false;  // (a common edge, the usual neighbours)
  if (F.normal[f].cross(F.normal[g]).norm() <= tol::self_intersection_rel) return false;
  auto corner = [&](std::uint32_t h, std::uint32_t v) -> const Vec3& {
    std::uint32_t c = F.off[h];
    while (F.cyc[c] != v) ++c;
    return F.pts[c];
  };
  for (int a = 0; a < k; ++a)
    for (int c = a + 1; c < k; ++c) {
      const std::uint32_t u = shared[a], w = shared[c];
      const bool edge_f = on_cycle(F, f, u, w), edge_g = on_cycle(F, g, u, w);
      if (edge_f && edge_g) continue;
      const Vec3 m = 0.5 * (corner(f, u) + corner(f, w));
      if ((edge_f || deep_inside(F, f, m, eps)) && (edge_g || deep_inside(F, g, m, eps)))
        return true;
    }
  return false;
}

// A strictly convex polygon (every turn strictly left about `normal` in the projection that
// drops its largest component, and the edge directions turning once: the x-direction of the
// edges changes sign exactly twice) is simple; is_simple_face decides every other face.
bool strictly_convex(const Vec3* p, std::uint32_t n, const Vec3& normal) {
  if (n < 3) return false;
  int a = 0;
  normal.cwiseAbs().maxCoeff(&a);
  int u = (a + 1) % 3, v = (a + 2) % 3;
  if (normal[a] < 0) std::swap(u, v);
  int changes = 0, last = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3 &x = p[i], &y = p[(i + 1) % n], &z = p[(i + 2) % n];
    const double turn = (y[u] - x[u]) * (z[v] - y[v]) - (y[v] - x[v]) * (z[u] - y[u]);
    if (!(turn > 0.0)) return false;
    const double dx = y[u] - x[u];
    const int sg = dx > 0.0 ? 1 : dx < 0.0 ? -1 : 0;
    if (sg != 0) {
      if (last != 0 && sg != last) ++changes;
      last = sg;
    }
  }
  // (the change across the closing edge, from the last signed edge to the first)
  for (std::uint32_t i = 0; i < n; ++i) {
    const double dx = p[(i + 1) % n][u] - p[i][u];
    const int sg = dx > 0.0 ? 1 : dx < 0.0 ? -1 : 0;
    if (sg != 0) {
      if (sg != last) ++changes;
      break;
    }
  }
  return changes == 2;
}

}  // namespace

bool self_intersects(const Complex& surface) {
  if (surface.ambient_dim() != 3 || surface.top_rank() < 2) return false;
  const std::uint32_t nf = static_cast<std::uint32_t>(surface.count(2));
  thread_local Faces F;
  const Incidence& faces = surface.boundary(2);
  const Incidence& edges = surface.boundary(1);
  const Eigen::MatrixXd& P = surface.positions();
  F.off.resize(nf + 1);
  F.off[0] = 0;
  F.cyc.clear();
  F.ids.clear();
  F.pts.clear();
  F.normal.resize(nf);
  F.convex.resize(nf);
  F.lo.resize(nf);
  F.hi.resize(nf);
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (std::uint32_t f = 0; f < nf; ++f) {
    // The cycle: the tail of each edge as the face traverses it (Complex::face_cycle).
    const auto ids = faces.ids(f);
    const auto signs = faces.signs(f);
    const std::uint32_t b = static_cast<std::uint32_t>(F.pts.size());
    for (std::size_t i = 0; i < ids.size(); ++i) {
      const auto e = edges.ids(ids[i]);
      const std::uint32_t v = signs[i] > 0 ? e[0] : e[1];
      F.cyc.push_back(v);
      F.ids.push_back(v);
      F.pts.push_back(P.col(v));
    }
    const std::uint32_t n = static_cast<std::uint32_t>(F.pts.size()) - b;
    F.off[f + 1] = b + n;
    Vec3 area = Vec3::Zero();
    for (std::uint32_t i = 0; i < n; ++i) area += F.pts[b + i].cross(F.pts[b + (i + 1) % n]);
    F.convex[f] = strictly_convex(&F.pts[b], n, area);
    if (!F.convex[f] && !is_simple_face(surface, f)) return true;
    F.normal[f] = area.normalized();
    Vec3 flo = F.pts[b], fhi = F.pts[b];
    for (std::uint32_t i = 1; i < n; ++i)
      flo = flo.cwiseMin(F.pts[b + i]), fhi = fhi.cwiseMax(F.pts[b + i]);
    F.lo[f] = flo;
    F.hi[f] = fhi;
    std::sort(F.ids.begin() + b, F.ids.end());
    lo = lo.cwiseMin(flo);
    hi = hi.cwiseMax(fhi);
  }
  const double eps = tol::self_intersection_rel * (hi - lo).norm();
  // Pairs of faces whose boxes (grown by eps) overlap, through a uniform grid of cells of about
  // the mean face extent: each face is listed in the cells its box covers, and a pair is
  // tested in the one cell holding the lower corner of the two boxes' intersection. Faces
  // sharing vertices are compared too: by their edges away from the shared corners, and along
  // the segments joining two shared corners (chord_crosses).
  double mean = 0.0;
  for (std::uint32_t f = 0; f < nf; ++f) mean += (F.hi[f] - F.lo[f]).maxCoeff();
  mean = nf > 0 ? mean / nf : 0.0;
  const Vec3 span = hi - lo;
  double h = std::max({mean, span.maxCoeff() / 1024.0, eps, 1e-300});
  int g[3];
  for (;;) {
    double cells = 1.0;
    for (int a = 0; a < 3; ++a) {
      g[a] = std::max(1, static_cast<int>(std::min(1024.0, std::ceil(span[a] / h))));
      cells *= g[a];
    }
    if (cells <= 32.0 * nf + 64.0) break;
    h *= 1.5;
  }
  const double inv_h = 1.0 / h;
  auto cell_of = [&](const Vec3& x, int a) {
    return std::clamp(static_cast<int>((x[a] - lo[a]) * inv_h), 0, g[a] - 1);
  };
  const std::size_t ncell = static_cast<std::size_t>(g[0]) * g[1] * g[2];
  thread_local std::vector<std::uint32_t> cell_off, cell_ids;
  cell_off.assign(ncell + 1, 0);
  const Vec3 grow = Vec3::Constant(eps);
  // Faces covering more than 27 cells (much larger than the mean) are tested against every
  // face instead, so no pair is met in many cells.
  thread_local std::vector<char> big;
  big.assign(nf, 0);
  auto range = [&](std::uint32_t f, int* r) {
    const Vec3 a = F.lo[f] - grow, b = F.hi[f] + grow;
    for (int k = 0; k < 3; ++k) r[2 * k] = cell_of(a, k), r[2 * k + 1] = cell_of(b, k);
    return (r[1] - r[0] + 1) * (r[3] - r[2] + 1) * (r[5] - r[4] + 1);
  };
  auto for_cells = [&](std::uint32_t f, auto&& fn) {
    int r[6];
    range(f, r);
    for (int z = r[4]; z <= r[5]; ++z)
      for (int y = r[2]; y <= r[3]; ++y)
        for (int x = r[0]; x <= r[1]; ++x) fn((static_cast<std::size_t>(z) * g[1] + y) * g[0] + x);
  };
  thread_local std::vector<std::uint32_t> bigs;
  bigs.clear();
  for (std::uint32_t f = 0; f < nf; ++f) {
    int r[6];
    if (range(f, r) > 27) {
      big[f] = 1;
      bigs.push_back(f);
      continue;
    }
    for_cells(f, [&](std::size_t c) { ++cell_off[c + 1]; });
  }
  for (std::size_t c = 0; c < ncell; ++c) cell_off[c + 1] += cell_off[c];
  cell_ids.resize(cell_off[ncell]);
  thread_local std::vector<std::uint32_t> fill;
  fill.assign(cell_off.begin(), cell_off.end() - 1);
  for (std::uint32_t f = 0; f < nf; ++f)
    if (!big[f]) for_cells(f, [&](std::size_t c) { cell_ids[fill[c]++] = f; });
  auto overlap = [&](std::uint32_t f, std::uint32_t q) {
    const Vec3 &flo = F.lo[f], &fhi = F.hi[f], &glo = F.lo[q], &ghi = F.hi[q];
    return !(flo.x() > ghi.x() + eps || flo.y() > ghi.y() + eps || flo.z() > ghi.z() + eps ||
             glo.x() > fhi.x() + eps || glo.y() > fhi.y() + eps || glo.z() > fhi.z() + eps);
  };
  auto test = [&](std::uint32_t f, std::uint32_t q) {
    thread_local std::vector<std::uint32_t> common;
    shared_vertices(F, f, q, common);
    const std::uint32_t* shared = common.data();
    const int k = static_cast<int>(common.size());
    // Two convex faces with a common edge meet only in it (the line of their planes' meeting).
    if (k == 2 && F.convex[f] && F.convex[q] && on_cycle(F, f, shared[0], shared[1]) &&
        on_cycle(F, q, shared[0], shared[1]))
      return false;
    return edge_pierces(F, f, q, eps, shared, k) || edge_pierces(F, q, f, eps, shared, k) ||
           chord_crosses(F, f, q, eps, shared, k);
  };
  for (std::size_t c = 0; c < ncell; ++c)
    for (std::uint32_t i = cell_off[c]; i < cell_off[c + 1]; ++i) {
      const std::uint32_t f = cell_ids[i];
      for (std::uint32_t j = i + 1; j < cell_off[c + 1]; ++j) {
        const std::uint32_t q = cell_ids[j];
        if (!overlap(f, q)) continue;
        const Vec3 corner = F.lo[f].cwiseMax(F.lo[q]) - grow;
        if ((static_cast<std::size_t>(cell_of(corner, 2)) * g[1] + cell_of(corner, 1)) * g[0] +
                cell_of(corner, 0) !=
            c)
          continue;  // (tested in the cell of the lower corner of the boxes' intersection)
        if (test(f, q)) return true;
      }
    }
  for (std::size_t i = 0; i < bigs.size(); ++i)
    for (std::uint32_t q = 0; q < nf; ++q)
      if (q != bigs[i] && (!big[q] || q > bigs[i]) && overlap(bigs[i], q) && test(bigs[i], q))
        return true;
  return false;
}

}  // namespace cw4d
