#include "cw4d/render/stereographic.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "cw4d/complex/error.hpp"
#include "cw4d/render/color.hpp"
#include "cw4d/render/tolerances.hpp"

namespace cw4d::render {

namespace {

constexpr double kPoleGap = tol::pole_gap;
constexpr int kMaxDepth = 16;

struct SpherePoint {
  Eigen::Vector4d x;  // on the unit sphere
  Eigen::Vector3d s;  // projected
  bool finite;        // projected inside the clip radius
};

glm::vec3 to_glm(const Eigen::Vector3d& v) {
  return {static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z())};
}

// Color along w: the southern hemisphere (near the origin of the image) warm, the north cool.
glm::vec4 w_color(double w) {
  return glm::vec4(depth_cue_color(static_cast<float>(0.5 * (w + 1.0))), 1.0f);
}

// Any unit vector perpendicular to t.
Eigen::Vector3d perpendicular(const Eigen::Vector3d& t) {
  const Eigen::Vector3d axis =
      std::abs(t.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return t.cross(axis).normalized();
}

void add_ring(TriangleMesh& mesh, const Eigen::Vector3d& c, const Eigen::Vector3d& u,
              const Eigen::Vector3d& v, double radius, int sides, glm::vec4 color) {
  for (int k = 0; k < sides; ++k) {
    const double a = 2.0 * std::numbers::pi * k / sides;
    const Eigen::Vector3d n = std::cos(a) * u + std::sin(a) * v;
    mesh.vertices.push_back({to_glm(c + radius * n), to_glm(n), color});
  }
}

void add_ball(TriangleMesh& mesh, const Eigen::Vector3d& c, double radius, glm::vec4 color) {
  constexpr int kRings = 8, kSegments = 12;
  const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
  for (int i = 0; i <= kRings; ++i) {
    const double phi = std::numbers::pi * i / kRings;
    for (int j = 0; j < kSegments; ++j) {
      const double th = 2.0 * std::numbers::pi * j / kSegments;
      const Eigen::Vector3d n(std::sin(phi) * std::cos(th), std::sin(phi) * std::sin(th),
                              std::cos(phi));
      mesh.vertices.push_back({to_glm(c + radius * n), to_glm(n), color});
    }
  }
  for (int i = 0; i < kRings; ++i)
    for (int j = 0; j < kSegments; ++j) {
      const std::uint32_t a = first + i * kSegments + j,
                          b = first + i * kSegments + (j + 1) % kSegments;
      const std::uint32_t c2 = a + kSegments, d = b + kSegments;
      mesh.triangles.push_back({a, c2, d});
      mesh.triangles.push_back({a, d, b});
    }
}

}  // namespace

std::vector<ProjectedCurve> stereographic_curves(const Complex& model,
                                                 const StereographicOptions& o) {
  if (model.ambient_dim() != 4) throw InputError("stereographic projection needs a 4D model");
  std::vector<ProjectedCurve> curves;
  const auto& p = model.positions();
  if (p.cols() == 0 || model.top_rank() < 1) return curves;
  const Eigen::Vector4d centre = 0.5 * (p.rowwise().minCoeff() + p.rowwise().maxCoeff());
  Eigen::Matrix4d turn = o.rotation;
  if (o.facet_at_south_pole && model.top_rank() >= 3 && model.count(3) > 0) {
    // A rotation taking the direction of facet 0's centroid to -e_w: the reflection swapping
    // the two, then a reflection fixing e_w (x -> -x), so that orientation is kept.
    Eigen::Vector4d c = Eigen::Vector4d::Zero();
    const auto verts = model.vertices_of(3, 0);
    for (auto v : verts) c += p.col(v);
    c = c / static_cast<double>(verts.size()) - centre;
    if (c.norm() > 0.0) {
      const Eigen::Vector4d target(0, 0, 0, -1);
      Eigen::Vector4d u = c.normalized() - target;
      Eigen::Matrix4d h = Eigen::Matrix4d::Identity();
      if (u.norm() > 1e-12) {
        u.normalize();
        h -= 2.0 * u * u.transpose();
        h.row(0) *= -1.0;
      }
      turn = o.rotation * h;
    }
  }
  auto on_sphere = [&](const Eigen::Vector4d& x) -> SpherePoint {
    Eigen::Vector4d q = turn * (x - centre);
    const double len = q.norm();
    q = len > 0.0 ? Eigen::Vector4d(q / len) : Eigen::Vector4d(0, 0, 0, -1);
    SpherePoint sp{q, Eigen::Vector3d::Zero(), false};
    const double gap = 1.0 - q.w();
    if (gap > kPoleGap) {
      sp.s = q.head<3>() / gap;
      sp.finite = sp.s.norm() <= o.clip_radius;
    }
    return sp;
  };
  for (std::uint32_t e = 0; e < model.count(1); ++e) {
    const auto [ta, hb] = model.edge(e);
    const Eigen::Vector4d a = p.col(ta), b = p.col(hb);
    // Adaptive subdivision in the edge parameter: split while the projected chord is long.
    std::vector<std::pair<double, SpherePoint>> pts;
    std::function<void(double, const SpherePoint&, double, const SpherePoint&, int)> split =
        [&](double t0, const SpherePoint& p0, double t1, const SpherePoint& p1, int depth) {
          const bool long_chord = !(p0.finite && p1.finite) || (p0.s - p1.s).norm() > o.max_chord;
          if (depth < kMaxDepth && long_chord) {
            const double tm = 0.5 * (t0 + t1);
            const SpherePoint pm = on_sphere(a + tm * (b - a));
            split(t0, p0, tm, pm, depth + 1);
            split(tm, pm, t1, p1, depth + 1);
            return;
          }
          pts.emplace_back(t1, p1);
        };
    const SpherePoint pa = on_sphere(a);
    pts.emplace_back(0.0, pa);
    split(0.0, pa, 1.0, on_sphere(b), 0);
    // Break the polyline at points that did not project inside the clip radius.
    ProjectedCurve cur;
    cur.edge = e;
    double last_t = 0.0;
    auto flush = [&] {
      cur.ends_at_vertex = last_t == 1.0;
      if (cur.points.size() >= 2) curves.push_back(cur);
      cur.points.clear();
      cur.w.clear();
    };
    for (const auto& [t, sp] : pts) {
      if (!sp.finite) {
        flush();
        continue;
      }
      if (cur.points.empty()) cur.starts_at_vertex = t == 0.0;
      last_t = t;
      cur.points.push_back(sp.s);
      cur.w.push_back(sp.x.w());
    }
    flush();
  }
  return curves;
}

TriangleMesh tube_mesh(const std::vector<ProjectedCurve>& curves, const StereographicOptions& o) {
  TriangleMesh mesh;
  const int sides = std::max(3, o.tube_sides);
  for (const auto& c : curves) {
    const std::size_t n = c.points.size();
    Eigen::Vector3d u_prev;
    for (std::size_t i = 0; i < n; ++i) {
      const Eigen::Vector3d t =
          (c.points[std::min(i + 1, n - 1)] - c.points[i == 0 ? 0 : i - 1]).normalized();
      // Parallel transport of the ring frame keeps the tube from twisting.
      Eigen::Vector3d u = i == 0 ? perpendicular(t) : Eigen::Vector3d(u_prev - u_prev.dot(t) * t);
      if (!(u.norm() > 1e-9)) u = perpendicular(t);
      u.normalize();
      u_prev = u;
      const Eigen::Vector3d v = t.cross(u);
      const double radius = o.tube_radius / std::max(1.0 - c.w[i], kPoleGap);
      add_ring(mesh, c.points[i], u, v, radius, sides, w_color(c.w[i]));
      if (i == 0) continue;
      const auto cur = static_cast<std::uint32_t>(mesh.vertices.size() - sides);
      const auto prev = cur - static_cast<std::uint32_t>(sides);
      for (int k = 0; k < sides; ++k) {
        const std::uint32_t a = prev + k, b = prev + (k + 1) % sides;
        const std::uint32_t c2 = cur + k, d = cur + (k + 1) % sides;
        mesh.triangles.push_back({a, b, d});
        mesh.triangles.push_back({a, d, c2});
      }
    }
  }
  return mesh;
}

Image render_stereographic(const Complex& model, const StereographicOptions& o) {
  const auto curves = stereographic_curves(model, o);
  RasterOptions ro = o.raster;
  ro.background = glm::vec4(0.0f);
  Rasterizer r(ro);
  const Camera cam = Camera::framing(glm::vec3(0.0f), o.view_radius, o.view_from, r.aspect(),
                                     o.projection, 30.0f, 1.0f);
  const View view = cam.view(r.aspect());
  if (o.tubes) {
    TriangleMesh mesh = tube_mesh(curves, o);
    if (o.vertex_balls && model.count(0) > 0) {
      // Vertices: the curve ends that are polytope vertices (parameter 0 and 1).
      std::vector<bool> done(model.count(0), false);
      for (const auto& c : curves) {
        const auto ends = model.edge(c.edge);
        for (int k = 0; k < 2; ++k) {
          const std::size_t idx = k == 0 ? 0 : c.points.size() - 1;
          const auto vtx = ends[k];
          // Only real vertices: a broken curve's end is not one.
          if (done[vtx] || !(k == 0 ? c.starts_at_vertex : c.ends_at_vertex)) continue;
          done[vtx] = true;
          const double radius = 1.7 * o.tube_radius / std::max(1.0 - c.w[idx], kPoleGap);
          add_ball(mesh, c.points[idx], radius, glm::vec4(0.9f, 0.9f, 0.92f, 1.0f));
        }
      }
    }
    r.draw(mesh, view, Lighting::studio(cam));
  } else {
    std::vector<LineSegment> lines;
    for (const auto& c : curves)
      for (std::size_t i = 1; i < c.points.size(); ++i)
        lines.push_back(
            {to_glm(c.points[i - 1]), to_glm(c.points[i]), w_color(c.w[i - 1]), w_color(c.w[i])});
    DrawOptions d;
    d.line_width = o.line_width;
    r.draw_lines(lines, view, d);
  }
  Image img = r.render();
  img.flatten(o.background);
  return img;
}

}  // namespace cw4d::render
