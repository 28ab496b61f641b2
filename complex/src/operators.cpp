#include "cw4d/complex/operators.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/complex/validate.hpp"

namespace cw4d {

namespace {

// Largest resolution of the round shapes: a duocylinder of N = 1000 has 10^6 vertices.
constexpr int max_resolution = 1000;

void require_closed(const Complex& c, const std::string& what) {
  const ValidationReport report = validate(c);
  if (!report.ok()) throw InputError(what + " needs a closed, valid complex: " + report.summary());
}

// The operators promise validated output; a failure here is a bug or a degenerate input that
// slipped through the input checks, so it names the element.
Complex checked(Complex c, const std::string& what) {
  const ValidationReport report = validate(c);
  if (!report.ok()) {
    const ValidationIssue& first = report.issues.front();
    throw TopologyError(first.rank, {first.id},
                        what + ": result is not valid: " + report.summary());
  }
  return c;
}

void check_round(const char* what, double r, int n) {
  if (!std::isfinite(r) || r <= 0.0)
    throw InputError(std::string(what) + ": radius must be positive, got " + std::to_string(r));
  if (n < 3 || n > max_resolution)
    throw InputError(std::string(what) + ": resolution must be 3.." +
                     std::to_string(max_resolution) + ", got " + std::to_string(n));
}

Complex scaled(Complex c, double s) {
  c.positions_mut() *= s;
  return c;
}

Eigen::VectorXd facet_normal(const Complex& c, std::uint32_t f) {
  if (c.has_facet_normals()) return c.facet_normals().col(f);
  return facet_area_vector(c, f).normalized();
}

double diameter(const Complex& c) {
  const Bounds b = bounds(c);
  return (b.max - b.min).norm();
}

// Vertex cycle of a closed polygon given by its edges (a 2D complex).
std::vector<std::uint32_t> polygon_cycle(const Complex& c) {
  std::vector<std::vector<std::uint32_t>> adj(c.count(0));
  for (std::uint32_t e = 0; e < c.count(1); ++e) {
    const auto ed = c.edge(e);
    adj[ed[0]].push_back(ed[1]);
    adj[ed[1]].push_back(ed[0]);
  }
  std::vector<std::uint32_t> out{0};
  std::uint32_t prev = no_index, cur = 0;
  while (true) {
    if (adj[cur].size() != 2) throw InputError("polygon boundary is not a cycle");
    const std::uint32_t next = adj[cur][0] != prev ? adj[cur][0] : adj[cur][1];
    if (next == out[0]) break;
    if (out.size() >= c.count(0)) throw InputError("polygon boundary is not one cycle");
    out.push_back(next);
    prev = cur;
    cur = next;
  }
  if (out.size() != c.count(0)) throw InputError("polygon boundary is not one cycle");
  return out;
}

}  // namespace

bool is_convex(const Complex& c) {
  const int fr = c.facet_rank();
  if (fr < 0 || c.top_rank() < fr || c.count(fr) == 0) return false;
  const double eps = tol::planarity_rel * diameter(c);
  for (std::uint32_t f = 0; f < c.count(fr); ++f) {
    const Eigen::VectorXd n = facet_normal(c, f);
    const double d = n.dot(c.position(c.first_vertex(fr, f)));
    if ((n.transpose() * c.positions()).maxCoeff() > d + eps) return false;
  }
  return true;
}

Complex make_pyramid(const Complex& base, double height) {
  if (!std::isfinite(height) || height == 0.0)
    throw InputError("pyramid: height must be finite and non-zero");
  require_closed(base, "pyramid");
  const int n = base.ambient_dim();
  const auto nv = static_cast<std::uint32_t>(base.count(0));
  const std::uint32_t apex = nv;
  std::vector<std::uint32_t> count(n);
  for (int k = 0; k < n; ++k) count[k] = static_cast<std::uint32_t>(base.count(k));
  // Ids of rank m in the pyramid: the base's rank-m elements, then the cones over its rank-(m-1)
  // elements, then (m = n) the base solid. Base ids therefore keep their values.
  auto cone_id = [&](int m, std::uint32_t i) { return (m <= n - 1 ? count[m] : 0u) + i; };

  ComplexSoup soup;
  soup.ambient_dim = n + 1;
  soup.positions = Eigen::MatrixXd::Zero(n + 1, nv + 1);
  soup.positions.topLeftCorner(n, nv) = base.positions();
  soup.positions.col(apex).head(n) = base.positions().rowwise().mean();
  soup.positions(n, apex) = height;
  if (n == 1) {
    // A triangle in the plane: edges only.
    for (std::uint32_t v = 0; v < nv; ++v) soup.edges.push_back({v, apex});
    soup.edges.push_back({0, 1});
    return checked(build_complex(soup), "pyramid");
  }
  if (n >= 3)
    for (std::uint32_t f = 0; f < count[2]; ++f) soup.faces.push_back(base.face_cycle(f));
  for (std::uint32_t e = 0; e < count[1]; ++e) {
    const auto ed = base.edge(e);
    soup.faces.push_back({ed[0], ed[1], apex});
  }
  if (n == 2) soup.faces.push_back(polygon_cycle(base));
  for (int m = 3; m <= n; ++m) {
    auto& level = soup.higher.emplace_back();
    if (m <= n - 1)
      for (std::uint32_t i = 0; i < count[m]; ++i) {
        const auto ids = base.boundary(m).ids(i);
        level.emplace_back(ids.begin(), ids.end());
      }
    for (std::uint32_t i = 0; i < count[m - 1]; ++i) {
      std::vector<std::uint32_t> row{i};
      for (std::uint32_t t : base.boundary(m - 1).ids(i)) row.push_back(cone_id(m - 1, t));
      level.push_back(std::move(row));
    }
    if (m == n) {
      std::vector<std::uint32_t> solid(count[n - 1]);
      for (std::uint32_t f = 0; f < count[n - 1]; ++f) solid[f] = f;
      level.push_back(std::move(solid));
    }
  }
  return checked(build_complex(soup), "pyramid");
}

Complex make_prism(const Complex& base, double height) {
  if (!std::isfinite(height) || height <= 0.0)
    throw InputError("prism: height must be positive and finite");
  require_closed(base, "prism");
  return checked(make_product(base, scaled(make_segment(), height / 2.0)), "prism");
}

Complex make_dual(const Complex& p, double radius) {
  if (!std::isfinite(radius) || radius <= 0.0)
    throw InputError("dual: radius must be positive and finite");
  const int n = p.ambient_dim();
  if (n < 2) throw InputError("dual: needs a polytope of dimension >= 2");
  require_closed(p, "dual");
  if (!is_convex(p)) throw InputError("dual: the polytope is not convex");
  const int fr = n - 1;
  const auto nf = static_cast<std::uint32_t>(p.count(fr));
  const Eigen::VectorXd centre = p.positions().rowwise().mean();
  const double eps = tol::planarity_rel * diameter(p);

  ComplexSoup soup;
  soup.ambient_dim = n;
  soup.positions.resize(n, nf);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const Eigen::VectorXd normal = facet_normal(p, f);
    const double d = normal.dot(p.position(p.first_vertex(fr, f)) - centre);
    if (d <= eps) throw InputError("dual: the vertex centroid lies on a facet hyperplane");
    soup.positions.col(f) = centre + (radius * radius / d) * normal;
  }
  // cofaces[k][i]: the elements of rank k + 1 that contain element i of rank k.
  std::vector<std::vector<std::vector<std::uint32_t>>> cofaces(n - 1);
  for (int k = 0; k <= n - 2; ++k) {
    cofaces[k].resize(p.count(k));
    const Incidence& table = p.boundary(k + 1);
    for (std::uint32_t parent = 0; parent < table.size(); ++parent)
      for (std::uint32_t child : table.ids(parent)) cofaces[k][child].push_back(parent);
  }
  if (n == 2) {
    for (std::uint32_t v = 0; v < p.count(0); ++v) {
      const auto& edges = cofaces[0][v];
      if (edges.size() != 2) throw TopologyError(0, {v}, "dual: vertex not in two edges");
      soup.edges.push_back({edges[0], edges[1]});
    }
    return checked(build_complex(soup), "dual");
  }
  // Dual faces: the facets around each element t of rank n - 3, in the cyclic order in which
  // consecutive facets share a ridge containing t (each such ridge lies in exactly two facets).
  const auto& ridge_facets = cofaces[n - 2];
  for (std::uint32_t t = 0; t < p.count(n - 3); ++t) {
    const auto& ridges = cofaces[n - 3][t];
    if (ridges.size() < 3) throw TopologyError(n - 3, {t}, "dual: element in fewer than 3 ridges");
    std::vector<std::uint32_t> cycle;
    const std::uint32_t first = ridge_facets[ridges[0]][0];
    std::uint32_t cur = ridge_facets[ridges[0]][1];
    std::uint32_t prev_ridge = ridges[0];
    cycle.push_back(first);
    while (cur != first) {
      if (cycle.size() >= ridges.size())
        throw TopologyError(n - 3, {t}, "dual: facets around an element do not form one cycle");
      cycle.push_back(cur);
      std::uint32_t next_ridge = prev_ridge;
      for (std::uint32_t r : ridges) {
        const auto& fs = ridge_facets[r];
        if (r != prev_ridge && (fs[0] == cur || fs[1] == cur)) {
          next_ridge = r;
          break;
        }
      }
      if (next_ridge == prev_ridge)
        throw TopologyError(n - 3, {t}, "dual: facets around an element do not form one cycle");
      const auto& fs = ridge_facets[next_ridge];
      cur = fs[0] == cur ? fs[1] : fs[0];
      prev_ridge = next_ridge;
    }
    if (cycle.size() != ridges.size())
      throw TopologyError(n - 3, {t}, "dual: facets around an element form several cycles");
    soup.faces.push_back(std::move(cycle));
  }
  // Dual rank j >= 3 <-> primal rank n - 1 - j; its boundary is the primal cofaces.
  for (int j = 3; j <= n - 1; ++j) soup.higher.push_back(cofaces[n - 1 - j]);
  return checked(build_complex(soup), "dual");
}

Complex make_dual_same_size(const Complex& p) {
  const int fr = p.facet_rank();
  if (fr < 1 || p.top_rank() < fr || p.count(fr) == 0)
    throw InputError("dual: needs a closed polytope of dimension >= 2");
  const Eigen::VectorXd centre = p.positions().rowwise().mean();
  const double r = (p.positions().colwise() - centre).colwise().norm().maxCoeff();
  double d_min = r;
  for (std::uint32_t f = 0; f < p.count(fr); ++f)
    d_min = std::min(d_min, facet_normal(p, f).dot(p.position(p.first_vertex(fr, f)) - centre));
  // d_min <= 0 (not convex, or degenerate) is rejected by make_dual with a better message.
  return make_dual(p, d_min > 0.0 ? std::sqrt(r * d_min) : 1.0);
}

Complex make_antiprism(int n) {
  // 8 N + 1 elements: at most 2e6, built in about 2.5 s (antiprism:10^6 took 10 s and 765 MB).
  if (n < 3 || n > 250000)
    throw InputError("antiprism needs N = 3..250000, got " + std::to_string(n));
  const double a = std::numbers::pi / n;
  const double r = 1.0 / std::sin(a);  // edge 2 between neighbours of one N-gon
  // Lateral edge 2: 2 r^2 (1 - cos a) + h^2 = 4, and r^2 (1 - cos a) = 1 / (2 cos^2(a/2)).
  const double c = std::cos(a / 2.0);
  const double h = std::sqrt(4.0 - 1.0 / (c * c));
  ComplexSoup soup;
  soup.ambient_dim = 3;
  soup.positions.resize(3, 2 * n);
  const auto un = static_cast<std::uint32_t>(n);
  std::vector<std::uint32_t> top, bottom;
  for (std::uint32_t k = 0; k < un; ++k) {
    soup.positions.col(k) << r * std::cos(2 * a * k), r * std::sin(2 * a * k), h / 2;
    soup.positions.col(un + k) << r * std::cos(2 * a * k + a), r * std::sin(2 * a * k + a), -h / 2;
    top.push_back(k);
    bottom.push_back(un + k);
  }
  soup.faces.push_back(top);
  soup.faces.push_back(bottom);
  for (std::uint32_t k = 0; k < un; ++k) {
    const std::uint32_t k1 = (k + 1) % un;
    soup.faces.push_back({k, k1, un + k});
    soup.faces.push_back({un + k, un + k1, k1});
  }
  return checked(build_complex(soup), "antiprism");
}

Complex make_round_polygon(double r, int n) {
  check_round("polygon", r, n);
  return scaled(make_polygon(n), r);
}

Complex make_uv_sphere(double r, int n) {
  check_round("sphere", r, n);
  const int m = std::max(2, n / 2);
  const auto un = static_cast<std::uint32_t>(n);
  const auto rings = static_cast<std::uint32_t>(m - 1);
  ComplexSoup soup;
  soup.ambient_dim = 3;
  soup.positions.resize(3, rings * un + 2);
  const std::uint32_t north = rings * un, south = north + 1;
  auto vid = [&](std::uint32_t ring, std::uint32_t k) { return ring * un + k % un; };
  for (std::uint32_t j = 0; j < rings; ++j) {
    const double theta = std::numbers::pi * (j + 1) / m;
    for (std::uint32_t k = 0; k < un; ++k) {
      const double phi = 2.0 * std::numbers::pi * k / n;
      soup.positions.col(vid(j, k)) << r * std::sin(theta) * std::cos(phi),
          r * std::sin(theta) * std::sin(phi), r * std::cos(theta);
    }
  }
  soup.positions.col(north) << 0, 0, r;
  soup.positions.col(south) << 0, 0, -r;
  for (std::uint32_t k = 0; k < un; ++k) {
    soup.faces.push_back({north, vid(0, k), vid(0, k + 1)});
    for (std::uint32_t j = 0; j + 1 < rings; ++j)
      soup.faces.push_back({vid(j, k), vid(j + 1, k), vid(j + 1, k + 1), vid(j, k + 1)});
    soup.faces.push_back({vid(rings - 1, k), south, vid(rings - 1, k + 1)});
  }
  return checked(build_complex(soup), "sphere");
}

Complex make_cylinder(double r, int n) {
  check_round("cylinder", r, n);
  return make_prism(make_round_polygon(r, n), 2.0 * r);
}

Complex make_duocylinder(double r, int n) {
  check_round("duocylinder", r, n);
  const Complex polygon = make_round_polygon(r, n);
  return checked(make_product(polygon, polygon), "duocylinder");
}

Complex make_cubinder(double r, int n) {
  check_round("cubinder", r, n);
  return checked(make_product(make_round_polygon(r, n), scaled(make_cube(2), r)), "cubinder");
}

Complex make_spherinder(double r, int n) {
  check_round("spherinder", r, n);
  return make_prism(make_uv_sphere(r, n), 2.0 * r);
}

Complex make_cone(const Complex& base) {
  const Bounds b = bounds(base);
  const double h = 0.5 * (b.max - b.min).maxCoeff();
  return make_pyramid(base, h);
}

Complex make_spin(const Complex& p, int steps) {
  if (p.ambient_dim() != 3) throw InputError("spin: needs a polyhedron in R^3");
  if (steps < 3 || steps > 100000)
    throw InputError("spin: steps must be 3..100000, got " + std::to_string(steps));
  require_closed(p, "spin");
  const double eps = tol::planarity_rel * diameter(p);
  const auto nv = static_cast<std::uint32_t>(p.count(0));
  const auto us = static_cast<std::uint32_t>(steps);
  // Vertices on the axis plane x = 0 are fixed by the rotation: one copy instead of `steps`.
  std::vector<bool> on_axis(nv);
  std::vector<std::uint32_t> first(nv);
  std::uint32_t total = 0;
  for (std::uint32_t v = 0; v < nv; ++v) {
    const double x = p.position(v)(0);
    if (x < -eps) throw InputError("spin: the polyhedron must lie in x >= 0");
    on_axis[v] = x <= eps;
    first[v] = total;
    total += on_axis[v] ? 1 : us;
  }
  auto vid = [&](std::uint32_t v, std::uint32_t k) {
    return on_axis[v] ? first[v] : first[v] + k % us;
  };
  ComplexSoup soup;
  soup.ambient_dim = 4;
  soup.positions.resize(4, total);
  for (std::uint32_t v = 0; v < nv; ++v) {
    const auto x = p.position(v);
    for (std::uint32_t k = 0; k < (on_axis[v] ? 1u : us); ++k) {
      const double t = 2.0 * std::numbers::pi * k / steps;
      const double r = on_axis[v] ? 0.0 : x(0);
      soup.positions.col(vid(v, k)) << r * std::cos(t), x(1), x(2), r * std::sin(t);
    }
  }
  auto all_on_axis = [&](const std::vector<std::uint32_t>& vs) {
    return std::all_of(vs.begin(), vs.end(), [&](std::uint32_t v) { return on_axis[v]; });
  };
  // Face ids: the copies of each swept face of P (steps per face), then the trapezoids swept by
  // its edges (steps per edge). Faces and edges inside the axis plane sweep nothing.
  std::vector<std::uint32_t> face_block(p.count(2), no_index), edge_block(p.count(1), no_index);
  for (std::uint32_t f = 0; f < p.count(2); ++f) {
    const auto cycle = p.face_cycle(f);
    if (all_on_axis(cycle)) continue;
    face_block[f] = static_cast<std::uint32_t>(soup.faces.size());
    for (std::uint32_t k = 0; k < us; ++k) {
      std::vector<std::uint32_t> copy;
      for (auto v : cycle) copy.push_back(vid(v, k));
      soup.faces.push_back(std::move(copy));
    }
  }
  for (std::uint32_t e = 0; e < p.count(1); ++e) {
    const auto [a, b] = p.edge(e);
    if (on_axis[a] && on_axis[b]) continue;
    edge_block[e] = static_cast<std::uint32_t>(soup.faces.size());
    for (std::uint32_t k = 0; k < us; ++k) {
      // Trapezoid a_k a_k+1 b_k+1 b_k; an end on the axis collapses it to a triangle.
      std::vector<std::uint32_t> quad{vid(a, k), vid(a, k + 1), vid(b, k + 1), vid(b, k)};
      quad.erase(std::unique(quad.begin(), quad.end()), quad.end());
      if (quad.size() > 1 && quad.front() == quad.back()) quad.pop_back();
      soup.faces.push_back(std::move(quad));
    }
  }
  auto& cells = soup.higher.emplace_back();
  for (std::uint32_t f = 0; f < p.count(2); ++f) {
    if (face_block[f] == no_index) continue;
    for (std::uint32_t k = 0; k < us; ++k) {
      std::vector<std::uint32_t> row{face_block[f] + k, face_block[f] + (k + 1) % us};
      for (std::uint32_t e : p.boundary(2).ids(f))
        if (edge_block[e] != no_index) row.push_back(edge_block[e] + k);
      cells.push_back(std::move(row));
    }
  }
  return checked(build_complex(soup), "spin");
}

}  // namespace cw4d
