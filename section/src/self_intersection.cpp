#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "cw4d/complex/tolerances.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/triangulate.hpp"

namespace cw4d {

namespace {

using Vec3 = Eigen::Vector3d;

struct Face {
  std::vector<std::uint32_t> cycle;
  std::vector<Vec3> pts;
  Vec3 normal;  // unit
  Vec3 lo, hi;  // bounding box
};

// Strict interior of a planar polygon, tested in the coordinate plane that drops the normal's
// largest component (crossing rule).
bool inside(const Face& f, const Vec3& x) {
  int a = 0;
  f.normal.cwiseAbs().maxCoeff(&a);
  const int u = (a + 1) % 3, v = (a + 2) % 3;
  bool in = false;
  const std::size_t n = f.pts.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec3 &p = f.pts[i], &q = f.pts[j];
    if ((p[v] > x[v]) != (q[v] > x[v]) &&
        x[u] < (q[u] - p[u]) * (x[v] - p[v]) / (q[v] - p[v]) + p[u])
      in = !in;
  }
  return in;
}

// Some boundary edge of f passes through the interior of g (beyond the tolerance `eps`).
bool edge_pierces(const Face& f, const Face& g, double eps) {
  const Vec3& g0 = g.pts[0];
  for (std::size_t i = 0; i < f.pts.size(); ++i) {
    const Vec3 &p = f.pts[i], &q = f.pts[(i + 1) % f.pts.size()];
    const double sp = g.normal.dot(p - g0), sq = g.normal.dot(q - g0);
    if (!((sp > eps && sq < -eps) || (sp < -eps && sq > eps))) continue;
    const Vec3 x = p + (sp / (sp - sq)) * (q - p);
    if (inside(g, x)) return true;
  }
  return false;
}

}  // namespace

bool self_intersects(const Complex& surface) {
  if (surface.ambient_dim() != 3 || surface.top_rank() < 2) return false;
  const std::uint32_t nf = static_cast<std::uint32_t>(surface.count(2));
  std::vector<Face> faces(nf);
  Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
  for (std::uint32_t f = 0; f < nf; ++f) {
    if (!is_simple_face(surface, f)) return true;
    Face& F = faces[f];
    F.cycle = surface.face_cycle(f);
    Vec3 area = Vec3::Zero();
    for (auto v : F.cycle) F.pts.push_back(surface.positions().col(v));
    for (std::size_t i = 0; i < F.pts.size(); ++i) area += F.pts[i].cross(F.pts[(i + 1) % F.pts.size()]);
    F.normal = area.normalized();
    F.lo = F.hi = F.pts[0];
    for (const Vec3& p : F.pts) F.lo = F.lo.cwiseMin(p), F.hi = F.hi.cwiseMax(p);
    std::sort(F.cycle.begin(), F.cycle.end());
    lo = lo.cwiseMin(F.lo);
    hi = hi.cwiseMax(F.hi);
  }
  const double eps = tol::self_intersection_rel * (hi - lo).norm();
  // Sweep along x over the bounding boxes; faces sharing a vertex are neighbours of a surface
  // and are not compared (a crossing between them is not detected).
  std::vector<std::uint32_t> order(nf);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](auto a, auto b) { return faces[a].lo.x() < faces[b].lo.x(); });
  for (std::size_t i = 0; i < nf; ++i) {
    const Face& F = faces[order[i]];
    for (std::size_t j = i + 1; j < nf && faces[order[j]].lo.x() <= F.hi.x() + eps; ++j) {
      const Face& G = faces[order[j]];
      if ((F.lo.array() > G.hi.array() + eps).any() || (G.lo.array() > F.hi.array() + eps).any())
        continue;
      std::vector<std::uint32_t> shared;
      std::set_intersection(F.cycle.begin(), F.cycle.end(), G.cycle.begin(), G.cycle.end(),
                            std::back_inserter(shared));
      if (!shared.empty()) continue;
      if (edge_pierces(F, G, eps) || edge_pierces(G, F, eps)) return true;
    }
  }
  return false;
}

}  // namespace cw4d
