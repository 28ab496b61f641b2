#include "cw4d/render/wireframe4d.hpp"

#include <Eigen/LU>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/render/color.hpp"
#include "cw4d/render/section_view.hpp"
#include "cw4d/render/tolerances.hpp"

namespace cw4d::render {

namespace {

// The parameter interval of a-b inside every half-space, as Liang-Barsky: nullopt when empty.
std::optional<std::pair<double, double>> inside_interval(const Eigen::VectorXd& a,
                                                         const Eigen::VectorXd& b,
                                                         const std::vector<HalfSpace>& planes) {
  double t0 = 0.0, t1 = 1.0;
  for (const HalfSpace& h : planes) {
    const double fa = h.value(a), fb = h.value(b);
    if (fa > 0.0 && fb > 0.0) return std::nullopt;
    if (fa > 0.0)
      t0 = std::max(t0, fa / (fa - fb));
    else if (fb > 0.0)
      t1 = std::min(t1, fa / (fa - fb));
  }
  if (!(t0 < t1)) return std::nullopt;
  return std::make_pair(t0, t1);
}

Intervals intersect(const Intervals& in, double lo, double hi) {
  Intervals out;
  for (const auto& [a, b] : in) {
    const double x = std::max(a, lo), y = std::min(b, hi);
    if (x < y) out.emplace_back(x, y);
  }
  return out;
}

Intervals subtract(const Intervals& in, double lo, double hi) {
  Intervals out;
  for (const auto& [a, b] : in) {
    if (hi <= a || lo >= b) {
      out.emplace_back(a, b);
      continue;
    }
    if (a < lo) out.emplace_back(a, lo);
    if (hi < b) out.emplace_back(hi, b);
  }
  return out;
}

HalfSpace normalized(Eigen::VectorXd n, double d) {
  const double len = n.norm();
  return {n / len, d / len};
}

struct Ball {
  Eigen::VectorXd centre;
  double radius = 0.0;
};

Ball scene_ball(const Scene& scene) {
  const int dim = scene.dim();
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(dim, std::numeric_limits<double>::infinity());
  Eigen::VectorXd hi = -lo;
  std::vector<Eigen::MatrixXd> worlds;
  for (const SceneObject& obj : scene.objects) {
    worlds.push_back((obj.transform.linear() * obj.complex->positions()).colwise() +
                     obj.transform.translation());
    if (worlds.back().cols() == 0) continue;
    lo = lo.cwiseMin(worlds.back().rowwise().minCoeff());
    hi = hi.cwiseMax(worlds.back().rowwise().maxCoeff());
  }
  Ball b;
  if (!lo.allFinite()) {
    b.centre = Eigen::VectorXd::Zero(dim);
    return b;
  }
  b.centre = 0.5 * (lo + hi);
  for (const auto& w : worlds)
    if (w.cols() > 0)
      b.radius = std::max(b.radius, (w.colwise() - b.centre).colwise().norm().maxCoeff());
  return b;
}

glm::vec3 to_glm3(const Eigen::VectorXd& v) {
  return {static_cast<float>(v(0)), static_cast<float>(v(1)), static_cast<float>(v(2))};
}

}  // namespace

Intervals clip_to_halfspaces(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                             const std::vector<HalfSpace>& halfspaces) {
  const auto r = inside_interval(a, b, halfspaces);
  if (!r) return {};
  return {*r};
}

ConvexOccluder ConvexOccluder::from(const Complex& world) {
  const int n = world.ambient_dim();
  const int facet_rank = n - 1;
  if (n < 2 || world.top_rank() < facet_rank || world.count(facet_rank) == 0)
    throw InputError("occluder: the complex has no facets");
  ConvexOccluder occ;
  const auto& p = world.positions();
  occ.centre_ = 0.5 * (p.rowwise().minCoeff() + p.rowwise().maxCoeff());
  occ.radius_ = (p.colwise() - occ.centre_).colwise().norm().maxCoeff();
  const double tol = tol::occluder_convex_rel * (occ.radius_ + occ.centre_.norm());
  const std::size_t nf = world.count(facet_rank);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const Eigen::VectorXd area = facet_area_vector(world, f);
    if (!(area.norm() > 0.0)) throw InputError("occluder: facet " + std::to_string(f) + " is flat");
    const Eigen::VectorXd normal = area.normalized();
    const double offset = normal.dot(p.col(world.first_vertex(facet_rank, f)));
    occ.facets_.push_back({normal, offset});
  }
  for (std::uint32_t f = 0; f < nf; ++f) {
    const HalfSpace& h = occ.facets_[f];
    const double worst = ((h.normal.transpose() * p).array() - h.offset).maxCoeff();
    if (worst > tol)
      throw InputError("occluder: not convex (a vertex lies outside facet " + std::to_string(f) +
                       ")");
  }
  // Ridges: the boundary entries of the facets; each must be shared by exactly two facets.
  const std::size_t nr = facet_rank >= 1 ? world.count(facet_rank - 1) : 0;
  std::vector<std::vector<std::uint32_t>> ridge_of(nr);
  const Incidence& inc = world.boundary(facet_rank);
  for (std::uint32_t f = 0; f < nf; ++f)
    for (auto r : inc.ids(f)) ridge_of[r].push_back(f);
  for (std::uint32_t r = 0; r < nr; ++r) {
    if (ridge_of[r].empty()) continue;
    if (ridge_of[r].size() != 2)
      throw InputError("occluder: ridge " + std::to_string(r) + " bounds " +
                       std::to_string(ridge_of[r].size()) + " facets, not 2");
    occ.ridge_facets_.emplace_back(ridge_of[r][0], ridge_of[r][1]);
  }
  return occ;
}

ConvexOccluder::Shadow ConvexOccluder::shadow(const Eigen::VectorXd& eye, double margin) const {
  Shadow s;
  std::vector<double> dist(facets_.size());
  // Eye-to-facet signed distances; "front" (facing the eye) only beyond a rounding-size band.
  const double band = tol::eye_facet_band_rel * (radius_ + eye.norm() + centre_.norm());
  bool inside = true;
  for (std::size_t f = 0; f < facets_.size(); ++f) {
    dist[f] = facets_[f].value(eye);
    if (dist[f] > band) inside = false;
  }
  s.eye_inside = inside;
  if (inside) {  // visible = the polytope, grown by the margin
    for (const HalfSpace& h : facets_) s.planes.push_back({h.normal, h.offset + margin});
    return s;
  }
  for (std::size_t f = 0; f < facets_.size(); ++f)
    if (dist[f] > band) s.planes.push_back({facets_[f].normal, facets_[f].offset - margin});
  for (const auto& [f1, f2] : ridge_facets_) {
    const bool front1 = dist[f1] > band, front2 = dist[f2] > band;
    if (front1 == front2) continue;
    const std::uint32_t F = front1 ? f1 : f2, K = front1 ? f2 : f1;
    // The pencil of hyperplanes through the ridge: s_F (n_K.x - d_K) - s_K (n_F.x - d_F) = 0
    // passes through the eye; the polytope lies on its negative side.
    const double sF = dist[F], sK = dist[K];
    const Eigen::VectorXd normal = sF * facets_[K].normal - sK * facets_[F].normal;
    const double offset = sF * facets_[K].offset - sK * facets_[F].offset;
    if (!(normal.norm() > 0.0)) continue;
    HalfSpace h = normalized(normal, offset);
    h.offset -= margin;
    s.planes.push_back(h);
  }
  return s;
}

Intervals ConvexOccluder::cull(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                               const Intervals& visible, const Shadow& shadow) const {
  if (visible.empty()) return visible;
  const auto r = inside_interval(a, b, shadow.planes);
  if (shadow.eye_inside) {  // only the inside is visible
    if (!r) return {};
    return intersect(visible, r->first, r->second);
  }
  if (!r) return visible;  // nothing of the segment is in the shadow
  return subtract(visible, r->first, r->second);
}

Camera4 Camera4::look_at(const Eigen::VectorXd& eye, const Eigen::VectorXd& target, double fov) {
  if (eye.size() != target.size() || eye.size() < 2)
    throw InputError("4D camera: eye and target must have the same dimension (>= 2)");
  const Eigen::VectorXd d = target - eye;
  if (!(d.norm() > 0.0) || !d.allFinite())
    throw InputError("4D camera: the eye and the target coincide");
  if (!(fov > 0.0 && fov < 180.0))
    throw InputError("4D camera: the field of view must lie in (0, 180)");
  const int n = static_cast<int>(eye.size());
  Camera4 c;
  c.eye = eye;
  c.fov_degrees = fov;
  c.frame = Eigen::MatrixXd::Zero(n, n);
  const Eigen::VectorXd f = d.normalized();
  Eigen::Index drop = 0;
  f.cwiseAbs().maxCoeff(&drop);
  int col = 0;
  for (int i = 0; i < n; ++i) {
    if (i == drop) continue;
    Eigen::VectorXd u = Eigen::VectorXd::Unit(n, i);
    u -= u.dot(f) * f;
    for (int k = 0; k < col; ++k) u -= u.dot(c.frame.col(k)) * c.frame.col(k);
    c.frame.col(col++) = u.normalized();
  }
  c.frame.col(n - 1) = f;
  if (c.frame.determinant() < 0.0) c.frame.col(0) = -c.frame.col(0);
  return c;
}

std::vector<HalfSpace> Camera4::frustum() const {
  const int n = dim();
  const double t = std::tan(0.5 * fov_degrees * std::numbers::pi / 180.0);
  const Eigen::VectorXd f = frame.col(n - 1);
  std::vector<HalfSpace> out;
  out.push_back({-f, -f.dot(eye) - near_plane});
  out.push_back({f, f.dot(eye) + far_plane});
  for (int i = 0; i + 1 < n; ++i) {
    const Eigen::VectorXd u = frame.col(i);
    for (double sign : {1.0, -1.0}) {
      const Eigen::VectorXd normal = sign * u - t * f;
      out.push_back(normalized(normal, normal.dot(eye)));
    }
  }
  return out;
}

Eigen::VectorXd Camera4::project(const Eigen::VectorXd& x) const {
  const int n = dim();
  const Eigen::VectorXd q = to_camera(x);
  const double t = std::tan(0.5 * fov_degrees * std::numbers::pi / 180.0);
  return q.head(n - 1) / (q(n - 1) * t);
}

namespace {

// Whether anything in the ball (m, h) can lie in the shadow of the ball (c, r) seen from `eye`:
// the cone of rays from the eye through the ball, beyond its nearest point. Conservative: true
// when unsure (an eye inside either ball).
bool may_be_shadowed(const Eigen::VectorXd& eye, const Eigen::VectorXd& c, double r,
                     const Eigen::VectorXd& m, double h) {
  const Eigen::VectorXd to_c = c - eye, to_m = m - eye;
  const double dc = to_c.norm(), dm = to_m.norm();
  const double slack = 1e-9 * (dc + dm + r + h);
  if (dc <= r + slack || dm <= h + slack) return true;
  if (dm + h < dc - r - slack) return false;  // wholly in front of the occluder
  const double alpha = std::asin(std::min(1.0, r / dc)), beta = std::asin(std::min(1.0, h / dm));
  const double cos_angle = std::clamp(to_c.dot(to_m) / (dc * dm), -1.0, 1.0);
  return std::acos(cos_angle) <= alpha + beta + 1e-9;
}

}  // namespace

std::vector<VisibleSegment> visible_edges(const Scene& scene, const Camera4& camera, bool occlusion,
                                          double margin_rel, bool bounding_pretests) {
  if (camera.dim() != scene.dim())
    throw InputError("the camera lives in R^" + std::to_string(camera.dim()) + ", the scene in R^" +
                     std::to_string(scene.dim()));
  std::vector<Complex> worlds;
  std::vector<std::optional<ConvexOccluder>> occluders;
  for (const SceneObject& obj : scene.objects) {
    worlds.push_back(transformed(*obj.complex, obj.transform));
    std::optional<ConvexOccluder> occ;
    if (occlusion) {
      try {
        occ = ConvexOccluder::from(worlds.back());
      } catch (const InputError&) {
        // Non-convex (or open) objects are drawn but hide nothing.
      }
    }
    occluders.push_back(std::move(occ));
  }
  std::vector<ConvexOccluder::Shadow> shadows;
  for (const auto& occ : occluders)
    shadows.push_back(occ ? occ->shadow(camera.eye, margin_rel * occ->radius())
                          : ConvexOccluder::Shadow{});
  const auto frustum = camera.frustum();
  std::vector<VisibleSegment> out;
  std::vector<std::uint32_t> candidates;  // occluders that may hide part of object i
  for (std::uint32_t i = 0; i < worlds.size(); ++i) {
    const Complex& w = worlds[i];
    if (w.top_rank() < 1) continue;
    // Bounding-sphere pre-tests: an occluder whose shadow cone misses the object's ball (or an
    // edge's ball) cannot hide it, so the exact culling runs only where it may matter.
    candidates.clear();
    Eigen::VectorXd centre = Eigen::VectorXd::Zero(camera.dim());
    double radius = 0.0;
    if (bounding_pretests && w.count(0) > 0) {
      const auto& p = w.positions();
      centre = 0.5 * (p.rowwise().minCoeff() + p.rowwise().maxCoeff());
      radius = (p.colwise() - centre).colwise().norm().maxCoeff();
    }
    for (std::uint32_t j = 0; j < occluders.size(); ++j) {
      if (!occluders[j]) continue;
      if (bounding_pretests && !shadows[j].eye_inside && j != i &&
          !may_be_shadowed(camera.eye, occluders[j]->centre(), occluders[j]->radius(), centre,
                           radius))
        continue;
      candidates.push_back(j);
    }
    for (std::uint32_t e = 0; e < w.count(1); ++e) {
      const auto [ta, hb] = w.edge(e);
      const Eigen::VectorXd a = w.position(ta), b = w.position(hb);
      Intervals vis = clip_to_halfspaces(a, b, frustum);
      if (vis.empty()) continue;
      const Eigen::VectorXd mid = 0.5 * (a + b);
      const double half = 0.5 * (b - a).norm();
      for (std::size_t k = 0; k < candidates.size() && !vis.empty(); ++k) {
        const std::uint32_t j = candidates[k];
        if (bounding_pretests && !shadows[j].eye_inside &&
            !may_be_shadowed(camera.eye, occluders[j]->centre(), occluders[j]->radius(), mid, half))
          continue;
        vis = occluders[j]->cull(a, b, vis, shadows[j]);
      }
      for (const auto& [t0, t1] : vis) out.push_back({a + t0 * (b - a), a + t1 * (b - a), i, e});
    }
  }
  return out;
}

Camera4 frame_scene(const Scene& scene, const Eigen::VectorXd& from, double fov_degrees) {
  if (scene.objects.empty()) throw InputError("the scene has no objects");
  if (from.size() != scene.dim() || !(from.norm() > 0.0))
    throw InputError("the 4D view direction must have " + std::to_string(scene.dim()) +
                     " components, not all zero");
  const Ball ball = scene_ball(scene);
  const double half = 0.5 * fov_degrees * std::numbers::pi / 180.0;
  const double dist = std::max(ball.radius, 1e-9) * 1.05 / std::sin(half);
  return Camera4::look_at(ball.centre + dist * from.normalized(), ball.centre, fov_degrees);
}

Image render_wireframe(const Scene& scene, const Camera4& camera, const WireframeOptions& o) {
  if (scene.dim() != 4 || camera.dim() != 4)
    throw InputError("4D wireframes need a 4D scene and camera");
  const auto segments = visible_edges(scene, camera, o.occlusion);
  // Depth cue over the depth range of what is visible.
  double near = std::numeric_limits<double>::infinity(), far = -near;
  for (const auto& s : segments)
    for (const Eigen::VectorXd* x : {&s.a, &s.b}) {
      const double depth = (*x - camera.eye).dot(camera.frame.col(3));
      near = std::min(near, depth);
      far = std::max(far, depth);
    }
  auto cue = [&](const Eigen::VectorXd& x) {
    const double depth = (x - camera.eye).dot(camera.frame.col(3));
    const double t = far > near ? (depth - near) / (far - near) : 0.5;
    return glm::vec4(depth_cue_color(static_cast<float>(t)), 1.0f);
  };
  std::vector<LineSegment> lines;
  lines.reserve(segments.size());
  for (const auto& s : segments)
    lines.push_back(
        {to_glm3(camera.project(s.a)), to_glm3(camera.project(s.b)), cue(s.a), cue(s.b)});

  RasterOptions ro = o.raster;
  ro.background = glm::vec4(0.0f);
  Rasterizer r(ro);
  const Camera cam3 = Camera::framing(glm::vec3(0.0f), std::sqrt(3.0f), o.view_from, r.aspect(),
                                      o.projection, 30.0f, 1.02f, glm::vec3(0, 1, 0));
  const View view = cam3.view(r.aspect());
  DrawOptions d;
  d.line_width = o.line_width;
  r.draw_lines(lines, view, d);
  if (o.retina_box) {
    std::vector<LineSegment> box;
    const glm::vec4 grey(0.55f, 0.55f, 0.58f, 1.0f);
    for (int axis = 0; axis < 3; ++axis)
      for (int k = 0; k < 4; ++k) {
        glm::vec3 a(0.0f);
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        a[u] = (k & 1) ? 1.0f : -1.0f;
        a[v] = (k & 2) ? 1.0f : -1.0f;
        glm::vec3 b = a;
        a[axis] = -1.0f;
        b[axis] = 1.0f;
        box.push_back({a, b, grey, grey});
      }
    DrawOptions bd;
    bd.line_width = 1.0f;
    r.draw_lines(box, view, bd);
  }
  if (o.section && !o.section->empty()) {
    // The section's faces in 4D, through the 4D camera to the retina.
    const Section& sec = *o.section;
    const TriangleMesh flat = section_mesh(sec);
    TriangleMesh mesh;
    const double near_depth = camera.near_plane;
    auto depth_of = [&](const Eigen::VectorXd& x) {
      return (x - camera.eye).dot(camera.frame.col(camera.dim() - 1));
    };
    for (const auto& t : flat.triangles) {
      Vertex v[3];
      bool inside = true;
      for (int k = 0; k < 3; ++k) {
        const glm::vec3 p = flat.vertices[t[k]].position;
        const Eigen::VectorXd x = sec.frame.lift(Eigen::Vector3d(p.x, p.y, p.z));
        if (!(depth_of(x) > near_depth)) {
          inside = false;
          break;
        }
        v[k].position = to_glm3(camera.project(x));
        v[k].color = flat.vertices[t[k]].color;
        v[k].color.a *= o.section_opacity;
      }
      if (!inside) continue;
      const glm::vec3 n = glm::cross(v[1].position - v[0].position, v[2].position - v[0].position);
      const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
      for (auto& vk : v) {
        vk.normal = n;
        mesh.vertices.push_back(vk);
      }
      mesh.triangles.push_back({first, first + 1, first + 2});
    }
    DrawOptions sd;
    sd.blend = Blend::Over;
    r.draw(mesh, view, Lighting::studio(cam3), sd);
  }
  Image img = r.render();
  img.flatten(o.background);
  return img;
}

Image render_wireframe_stereo_pair(const Scene& scene, const Camera4& camera,
                                   const WireframeOptions& o, float angle_degrees) {
  Image pair(2 * o.raster.width, o.raster.height, glm::vec4(o.background, 1.0f));
  for (int side = 0; side < 2; ++side) {
    const float a = glm::radians((side == 0 ? -0.5f : 0.5f) * angle_degrees);
    WireframeOptions one = o;
    // About the retina's up axis (y), as the eyes of a viewer standing upright.
    one.view_from = glm::vec3(glm::rotate(glm::mat4(1.0f), a, glm::vec3(0.0f, 1.0f, 0.0f)) *
                              glm::vec4(o.view_from, 0.0f));
    pair.blit(render_wireframe(scene, camera, one), side * o.raster.width, 0);
  }
  return pair;
}

}  // namespace cw4d::render
