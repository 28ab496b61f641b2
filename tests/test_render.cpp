// The thin rasterizer (render/): golden-free checks against independent oracles. Silhouette
// areas against the analytic area of a cube and Cauchy's projection formula, depth order of
// overlapping objects, the top-left fill rule (no sample drawn twice, none missed), near-plane
// clipping, occlusion culling of 4D edges against analytic shadows and a ray-casting oracle,
// stereographic arcs against circles, identical pictures for every thread count, and the
// 8-bit sRGB output against the float frame encoded with the transfer function.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/render/color.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/raster.hpp"
#include "cw4d/render/section_view.hpp"
#include "cw4d/render/stereographic.hpp"
#include "cw4d/render/voxel_cloud.hpp"
#include "cw4d/render/wireframe4d.hpp"
#include "cw4d/section/scene_section.hpp"
#include "cw4d/section/section.hpp"
#include "support/temp_dir.hpp"
#include "support/vectors.hpp"

using namespace cw4d;
using namespace cw4d::render;
using cw4d::test::vec;

namespace {

SceneObject object(std::shared_ptr<const Complex> model, const AffineTransform& t, Rgba color) {
  SceneObject o;
  o.model = "test";
  o.complex = std::move(model);
  o.transform = t;
  o.color = color;
  return o;
}

SectionViewOptions ortho_options(glm::vec3 from, int w = 400, int h = 300) {
  SectionViewOptions o;
  o.raster.width = w;
  o.raster.height = h;
  o.raster.samples_per_axis = 4;
  o.projection = Projection::Orthographic;
  o.view_from = from;
  return o;
}

// Cauchy: the orthographic shadow of a convex body has area 1/2 sum_f area_f |n_f . v|.
double projected_area(const Section& s, const Eigen::Vector3d& v) {
  const Complex& c = s.complex;
  double sum = 0.0;
  for (std::uint32_t f = 0; f < c.count(2); ++f) {
    const auto cyc = c.face_cycle(f);
    Eigen::Vector3d area = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < cyc.size(); ++i)
      area += 0.5 * Eigen::Vector3d(c.position(cyc[i]))
                        .cross(Eigen::Vector3d(c.position(cyc[(i + 1) % cyc.size()])));
    sum += std::abs(area.dot(v));
  }
  return 0.5 * sum;
}

bool same_pixels(const Image& a, const Image& b) {
  if (a.width != b.width || a.height != b.height) return false;
  for (std::size_t i = 0; i < a.pixels.size(); ++i)
    if (a.pixels[i] != b.pixels[i]) return false;
  return true;
}

// Pixel of a world point seen by `cam` in a w x h image.
glm::ivec2 pixel_of(const Camera& cam, glm::vec3 p, int w, int h) {
  const View v = cam.view(static_cast<float>(w) / h);
  const glm::vec4 c = v.clip_from_world * glm::vec4(p, 1.0f);
  return {static_cast<int>((c.x / c.w * 0.5f + 0.5f) * w),
          static_cast<int>((0.5f - c.y / c.w * 0.5f) * h)};
}

}  // namespace

TEST_CASE("a lit cube section covers the analytic silhouette area (orthographic)", "[render]") {
  const Complex tesseract = make_cube(4);
  const Section cube = section(tesseract, Hyperplane::from(vec({0, 0, 0, 1}), 0.0));
  for (glm::vec3 from :
       {glm::vec3(2.0f, 1.3f, 1.0f), glm::vec3(0.0f, 0.0f, 1.0f), glm::vec3(-1.0f, 0.4f, -2.5f)}) {
    const SectionViewOptions o = ortho_options(from);
    const Camera cam = section_camera(cube, o);
    const Image img = render_section(cube, o, cam, nullptr, false);
    const glm::vec3 v = glm::normalize(from);
    const double analytic = 4.0 * (std::abs(v.x) + std::abs(v.y) + std::abs(v.z));  // side 2
    const double px_per_unit = o.raster.height / cam.ortho_height;
    const double expected = analytic * px_per_unit * px_per_unit;
    CAPTURE(from.x, from.y, from.z, expected, img.coverage());
    CHECK(std::abs(img.coverage() - expected) < 0.01 * expected);
  }
}

TEST_CASE("a cube section seen face-on in perspective covers its front square", "[render]") {
  const Section cube = section(make_cube(4), Hyperplane::from(vec({0, 0, 0, 1}), 0.0));
  SectionViewOptions o;
  o.raster.width = 320;
  o.raster.height = 320;
  o.raster.samples_per_axis = 4;
  o.view_from = glm::vec3(1.0f, 0.0f, 0.0f);
  o.cull_back_faces = true;
  const Camera cam = section_camera(cube, o);
  const Image img = render_section(cube, o, cam, nullptr, false);
  const double dist = glm::length(cam.eye) - 1.0;  // to the face x = 1
  const double half_px = 1.0 / (dist * std::tan(0.5 * glm::radians(cam.fov_y_degrees))) * 160.0;
  const double expected = 4.0 * half_px * half_px;
  CAPTURE(expected, img.coverage());
  CHECK(std::abs(img.coverage() - expected) < 0.01 * expected);
}

TEST_CASE("silhouettes of tilted sections match Cauchy's projection formula", "[render]") {
  std::mt19937 rng(20261122);
  std::normal_distribution<double> g;
  const std::vector<Complex> models = {make_cube(4), make_orthoplex(4), load_model("24-cell"),
                                       make_duoprism(5, 7)};
  for (const Complex& m : models)
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::VectorXd n(4);
      for (int i = 0; i < 4; ++i) n(i) = g(rng);
      const Section s = section(m, Hyperplane::from(n, 0.1 * g(rng)));
      REQUIRE_FALSE(s.empty());
      const glm::vec3 from(static_cast<float>(g(rng)), static_cast<float>(g(rng)),
                           static_cast<float>(g(rng)));
      const SectionViewOptions o = ortho_options(from, 300, 300);
      const Camera cam = section_camera(s, o);
      const Image img = render_section(s, o, cam, nullptr, false);
      const glm::vec3 v = glm::normalize(from);
      const double px = o.raster.height / cam.ortho_height;
      const double expected = projected_area(s, Eigen::Vector3d(v.x, v.y, v.z)) * px * px;
      CAPTURE(trial, expected, img.coverage());
      CHECK(std::abs(img.coverage() - expected) < 0.01 * expected);
    }
}

TEST_CASE("the nearer of two overlapping objects wins, whatever the drawing order", "[render]") {
  auto tesseract = std::make_shared<const Complex>(make_cube(4));
  const Rgba red{1, 0, 0, 1}, blue{0, 0, 1, 1};
  for (bool perspective : {false, true})
    for (bool reversed : {false, true}) {
      Scene scene;
      // Section coordinates are x, y, z (normal e_w); the blue cube is higher in z.
      scene.objects.push_back(object(tesseract, AffineTransform(4), red));
      scene.objects.push_back(
          object(tesseract, AffineTransform::translation(vec({0.8, 0.8, 1.5, 0.0})), blue));
      if (reversed) std::swap(scene.objects[0], scene.objects[1]);
      const Section s = section_scene(scene, Hyperplane::from(vec({0, 0, 0, 1}), 0.0));
      SectionViewOptions o = ortho_options(glm::vec3(0.0f, 0.0f, 1.0f));
      if (perspective) o.projection = Projection::Perspective;
      const Camera cam = section_camera(s, o);
      const Image img = render_section(s, o, cam);
      // Covered by both (blue in front): blue; covered by red only: red.
      const glm::ivec2 both = pixel_of(cam, {0.4f, 0.4f, 2.5f}, o.raster.width, o.raster.height);
      const glm::ivec2 red_only =
          pixel_of(cam, {-0.6f, -0.6f, 1.0f}, o.raster.width, o.raster.height);
      const glm::vec4 pb = img.at(both.x, both.y), pr = img.at(red_only.x, red_only.y);
      CAPTURE(perspective, reversed, pb.r, pb.b, pr.r, pr.b);
      CHECK(pb.b > 4 * pb.r);
      CHECK(pr.r > 4 * pr.b);
    }
}

TEST_CASE("top-left rule: triangles sharing edges cover every sample exactly once", "[render]") {
  // A fan of triangles around an off-grid centre, drawn half transparent: a sample drawn twice
  // would reach alpha 0.75, a gap inside the polygon would leave 0.
  for (int spp : {1, 2}) {
    RasterOptions ro;
    ro.width = 97;
    ro.height = 83;
    ro.samples_per_axis = spp;
    ro.threads = 2;
    Rasterizer r(ro);
    Camera cam;
    cam.projection = Projection::Orthographic;
    cam.eye = {0, 0, 5};
    cam.ortho_height = 2.0f;
    TriangleMesh fan;
    const glm::vec4 color(1.0f, 1.0f, 1.0f, 0.5f);
    fan.vertices.push_back({{0.0317f, -0.0213f, 0.0f}, {}, color});
    const int k = 13;
    for (int i = 0; i < k; ++i) {
      const float a = 2.0f * std::numbers::pi_v<float> * i / k + 0.1f;
      fan.vertices.push_back({{0.8f * std::cos(a), 0.8f * std::sin(a), 0.0f}, {}, color});
    }
    for (int i = 0; i < k; ++i)
      fan.triangles.push_back(
          {0, static_cast<std::uint32_t>(1 + i), static_cast<std::uint32_t>(1 + (i + 1) % k)});
    DrawOptions d;
    d.shading = Shading::Unlit;
    d.blend = Blend::Over;
    r.draw(fan, cam.view(r.aspect()), Lighting{}, d);
    const Image img = r.render();
    int inside = 0;
    for (const auto& p : img.pixels) {
      // Pixel alpha = 0.5 * covered samples / spp: never above 0.5.
      CHECK(p.a <= 0.5f + 1e-6f);
      if (p.a > 0.4999f) ++inside;
    }
    // The interior pixels are all full: a 13-gon of circumradius 0.8 (of 2 units = 83 px).
    const double px = 83.0 / 2.0;
    const double area = 0.5 * k * 0.64 * std::sin(2 * std::numbers::pi / k) * px * px;
    CHECK(inside > 0.9 * area);
    CHECK(std::abs(img.coverage() / 0.5 - area) < 0.01 * area);
  }
}

TEST_CASE("near-plane clipping: a ground plane through the eye covers the lower half", "[render]") {
  RasterOptions ro;
  ro.width = 200;
  ro.height = 120;
  Rasterizer r(ro);
  Camera cam;
  cam.eye = {0, 0, 0};
  cam.target = {0, 0, -1};
  cam.near_plane = 0.01f;
  cam.far_plane = 1e5f;
  // y = -1: a fan of 7 triangles around a point ahead, reaching far behind the eye and far
  // ahead, drawn half transparent: the clipped shared edges must neither crack nor overlap.
  TriangleMesh ground;
  const glm::vec4 c(1.0f, 1.0f, 1.0f, 0.5f);
  ground.vertices.push_back({{0.3f, -1.0f, -2.0f}, {}, c});
  const int k = 7;
  for (int i = 0; i < k; ++i) {
    const float a = 2.0f * std::numbers::pi_v<float> * i / k + 0.2f;
    ground.vertices.push_back({{4e4f * std::cos(a), -1.0f, 4e4f * std::sin(a)}, {}, c});
  }
  for (int i = 0; i < k; ++i)
    ground.triangles.push_back(
        {0, static_cast<std::uint32_t>(1 + (i + 1) % k), static_cast<std::uint32_t>(1 + i)});
  DrawOptions d;
  d.shading = Shading::Unlit;
  d.blend = Blend::Over;
  r.draw(ground, cam.view(r.aspect()), Lighting{}, d);
  const Image img = r.render();
  // The horizon is the middle row (the far edges are 4e4 away: within a pixel of it).
  double lower = 0, upper = 0;
  float most = 0;
  for (int y = 0; y < ro.height; ++y)
    for (int x = 20; x < ro.width - 20; ++x) {
      (y < ro.height / 2 ? upper : lower) += img.at(x, y).a;
      most = std::max(most, img.at(x, y).a);
    }
  const double half = (ro.width - 40) * ro.height / 2.0;
  CHECK(most <= 0.5f + 1e-6f);
  CHECK(lower > 0.98 * 0.5 * half);
  CHECK(upper < 0.02 * 0.5 * half);
}

TEST_CASE("pictures are identical for every thread count", "[render]") {
  const Complex m = load_model("24-cell");
  const Section s = section(m, Hyperplane::from(vec({0.3, -0.2, 0.5, 1.0}), 0.2));
  SectionViewOptions o;
  o.raster.width = 333;
  o.raster.height = 211;
  o.edges = true;
  std::vector<Image> pics;
  for (int threads : {1, 2, 3, 7}) {
    o.raster.threads = threads;
    pics.push_back(render_section(s, o));
  }
  for (std::size_t i = 1; i < pics.size(); ++i) CHECK(same_pixels(pics[0], pics[i]));

  Scene scene;
  scene.objects.push_back(
      object(std::make_shared<const Complex>(m), AffineTransform(4), Rgba{0.9f, 0.6f, 0.2f, 0.7f}));
  CloudOptions co;
  co.raster.width = 160;
  co.raster.height = 120;
  co.layers = 12;
  WireframeOptions wo;
  wo.raster.width = 160;
  wo.raster.height = 120;
  const Camera4 cam4 = frame_scene(scene, vec({0.3, 0.2, 0.1, -1.0}));
  std::vector<Image> clouds, wires;
  for (int threads : {1, 3}) {
    co.raster.threads = wo.raster.threads = threads;
    clouds.push_back(render_voxel_cloud(scene, vec({0, 0, 0, 1}), co));
    wires.push_back(render_wireframe(scene, cam4, wo));
  }
  CHECK(same_pixels(clouds[0], clouds[1]));
  CHECK(same_pixels(wires[0], wires[1]));
}

TEST_CASE("occlusion culling removes exactly the analytic shadow of a tesseract",
          "[render][occlusion]") {
  const ConvexOccluder occ = ConvexOccluder::from(make_cube(4));
  const double margin = 1e-9;
  SECTION("eye outside: an edge behind the tesseract loses its middle") {
    const auto sh = occ.shadow(vec({0, 0, 0, -5}), margin);
    REQUIRE_FALSE(sh.eye_inside);
    // The front cell w = -1 is 4 away; at w = 3 (8 away) its shadow spans |x| <= 2.
    const Eigen::VectorXd a = vec({-4, 0, 0, 3}), b = vec({4, 0, 0, 3});
    const Intervals v = occ.cull(a, b, {{0.0, 1.0}}, sh);
    REQUIRE(v.size() == 2);
    CHECK(v[0].first == 0.0);
    CHECK(v[0].second == Approx(0.25).margin(1e-8));
    CHECK(v[1].first == Approx(0.75).margin(1e-8));
    CHECK(v[1].second == 1.0);
  }
  SECTION("eye outside: an edge entering the shadow through the front cell") {
    const auto sh = occ.shadow(vec({0, 0, 0, -5}), margin);
    // x = 0.5 from w = -3 to 3: hidden from the front cell w = -1 on (t = 1/3).
    const Intervals v = occ.cull(vec({0.5, 0, 0, -3}), vec({0.5, 0, 0, 3}), {{0.0, 1.0}}, sh);
    REQUIRE(v.size() == 1);
    CHECK(v[0].first == 0.0);
    CHECK(v[0].second == Approx(1.0 / 3.0).margin(1e-8));
  }
  SECTION("eye outside, off axis: the silhouette cone bounds the shadow") {
    // Eye at (3, 0, 0, -5): front cells x = 1 and w = -1; the far silhouette ridge is
    // x = -1, w = -1. At w = 3 the shadow spans x from 3 + (-1 - 3) * 8/4 = -5 to
    // 3 + (1 - 3) * 8/6 = 1/3 (the near ridge x = 1, w = 1).
    const auto sh = occ.shadow(vec({3, 0, 0, -5}), margin);
    const Intervals v = occ.cull(vec({-8, 0, 0, 3}), vec({8, 0, 0, 3}), {{0.0, 1.0}}, sh);
    REQUIRE(v.size() == 2);
    CHECK(v[0].second == Approx((-5.0 + 8.0) / 16.0).margin(1e-8));
    CHECK(v[1].first == Approx((1.0 / 3.0 + 8.0) / 16.0).margin(1e-8));
  }
  SECTION("eye inside: only the part inside the polytope stays") {
    const auto sh = occ.shadow(vec({0.2, 0.1, 0, 0}), margin);
    REQUIRE(sh.eye_inside);
    const Intervals v = occ.cull(vec({-5, 0, 0, 0.5}), vec({5, 0, 0, 0.5}), {{0.0, 1.0}}, sh);
    REQUIRE(v.size() == 1);
    CHECK(v[0].first == Approx(0.4).margin(1e-8));
    CHECK(v[0].second == Approx(0.6).margin(1e-8));
  }
  SECTION("the tesseract's own front edges stay, its back edges go") {
    Scene scene;
    scene.objects.push_back(
        object(std::make_shared<const Complex>(make_cube(4)), AffineTransform(4), {}));
    const Camera4 cam = Camera4::look_at(vec({0, 0, 0, -5}), vec({0, 0, 0, 0}), 60.0);
    const auto vis = visible_edges(scene, cam);
    // Seen along w, the front cell w = -1 hides everything behind it: exactly its 12 edges
    // remain, whole (the 4 edges along w lie on the silhouette cone, hidden beyond w = -1).
    double front_length = 0, other_length = 0;
    for (const auto& s : vis) {
      const bool front = std::abs(s.a(3) + 1) < 1e-9 && std::abs(s.b(3) + 1) < 1e-9;
      (front ? front_length : other_length) += (s.b - s.a).norm();
    }
    CHECK(front_length == Approx(12 * 2.0).epsilon(1e-9));
    // (The 8 edges along w stay visible for the shrink margin, 2e-6, times 4 / cos: 7e-5.)
    CHECK(other_length < 1e-4);
  }
}

TEST_CASE("occlusion culling agrees with ray casting for random eyes and edges",
          "[render][occlusion]") {
  std::mt19937 rng(4);
  std::normal_distribution<double> g;
  const Complex m = load_model("24-cell");
  const ConvexOccluder occ = ConvexOccluder::from(m);
  // Oracle: the open segment eye -> x meets the polytope (Liang-Barsky against its facets).
  auto hidden = [&](const Eigen::VectorXd& eye, const Eigen::VectorXd& x, bool& ambiguous) {
    double t0 = 0, t1 = 1;
    bool empty = false;
    double slack = 1e300;  // how deep the ray goes inside, for ambiguity
    for (const HalfSpace& h : occ.facets()) {
      const double fa = h.value(eye), fb = h.value(x);
      if (fa > 0 && fb > 0) {
        empty = true;
        slack = std::min(slack, std::min(fa, fb));
        break;
      }
      if (fa > 0)
        t0 = std::max(t0, fa / (fa - fb));
      else if (fb > 0)
        t1 = std::min(t1, fa / (fa - fb));
    }
    const bool inside_eye = [&] {
      for (const HalfSpace& h : occ.facets())
        if (h.value(eye) > 0) return false;
      return true;
    }();
    bool result;
    if (inside_eye) {
      double worst = -1e300;
      for (const HalfSpace& h : occ.facets()) worst = std::max(worst, h.value(x));
      ambiguous = std::abs(worst) < 1e-4;
      result = worst > 0;
    } else {
      result = !empty && t0 < t1 && t0 < 1.0;
      ambiguous = (!empty && std::abs(t1 - t0) < 1e-4) || std::abs(t0 - 1.0) < 1e-4;
    }
    return result;
  };
  int checked = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Eigen::VectorXd eye(4), a(4), b(4);
    for (int i = 0; i < 4; ++i) {
      eye(i) = g(rng) * (trial % 3 == 0 ? 0.4 : 3.0);
      a(i) = g(rng) * 2.5;
      b(i) = g(rng) * 2.5;
    }
    const auto sh = occ.shadow(eye, 1e-12);
    const Intervals vis = occ.cull(a, b, {{0.0, 1.0}}, sh);
    for (int k = 0; k <= 40; ++k) {
      const double t = (k + 0.37) / 41.0;
      bool ambiguous = false;
      const bool oracle = hidden(eye, a + t * (b - a), ambiguous);
      if (ambiguous) continue;
      bool visible = false;
      for (const auto& [t0, t1] : vis) visible = visible || (t0 <= t && t <= t1);
      CAPTURE(trial, k, sh.eye_inside);
      REQUIRE(visible == !oracle);
      ++checked;
    }
  }
  CHECK(checked > 10000);
}

TEST_CASE("the 4D frustum keeps exactly the part of an edge in view", "[render][occlusion]") {
  const Camera4 cam = Camera4::look_at(vec({0, 0, 0, -5}), vec({0, 0, 0, 0}), 90.0);
  // fov 90: |x| <= depth. An edge at depth 2 (w = -3) from x = -4 to 4 keeps |x| <= 2.
  const Intervals v = clip_to_halfspaces(vec({-4, 0, 0, -3}), vec({4, 0, 0, -3}), cam.frustum());
  REQUIRE(v.size() == 1);
  CHECK(v[0].first == Approx(0.25));
  CHECK(v[0].second == Approx(0.75));
  const Eigen::VectorXd r = cam.project(vec({1, -2, 0.5, -1}));  // depth 4
  CHECK(std::abs(r(0)) == Approx(0.25));
  CHECK(std::abs(r(1)) == Approx(0.5));
  CHECK(std::abs(r(2)) == Approx(0.125));
}

TEST_CASE("stereographic edges are circular arcs", "[render]") {
  StereographicOptions o;
  // Some rotation so that no edge passes through the pole exactly.
  const AffineTransform rot =
      AffineTransform::rotation(4, 0, 3, 0.3) * AffineTransform::rotation(4, 1, 2, 0.7);
  o.rotation = rot.linear();
  const auto curves = stereographic_curves(load_model("24-cell"), o);
  REQUIRE(curves.size() >= 96);
  for (const auto& c : curves) {
    REQUIRE(c.points.size() >= 3);
    // The circle through the first, middle and last points: every point lies on it.
    const Eigen::Vector3d p0 = c.points.front(), p1 = c.points[c.points.size() / 2],
                          p2 = c.points.back();
    const Eigen::Vector3d u = p1 - p0, v = p2 - p0, n = u.cross(v);
    if (n.norm() < 1e-9 * u.norm() * v.norm())
      continue;  // a straight line through the pole's image
    const Eigen::Vector3d centre =
        p0 +
        (u.squaredNorm() * v.cross(n) + v.squaredNorm() * n.cross(u)) / (2.0 * n.squaredNorm());
    const double radius = (p0 - centre).norm();
    for (std::size_t i = 0; i < c.points.size(); ++i) {
      CHECK(std::abs((c.points[i] - centre).norm() - radius) < 1e-9 * (1 + radius));
      CHECK(std::abs((c.points[i] - centre).dot(n.normalized())) < 1e-9 * (1 + radius));
      if (i > 0) CHECK((c.points[i] - c.points[i - 1]).norm() <= o.max_chord * (1 + 1e-12));
    }
  }
}

TEST_CASE("opacity correction keeps the cloud's total opacity for any layer count", "[render]") {
  for (int n : {1, 4, 33, 200}) {
    const float a = corrected_opacity(0.7f, 1.0 / n, 1.0);
    CHECK(1.0 - std::pow(1.0 - a, n) == Approx(0.7).epsilon(1e-5));
  }
  CHECK(corrected_opacity(1.0f, 0.01, 1.0) == 1.0f);
  CHECK(corrected_opacity(0.5f, 2.0, 1.0) == Approx(0.75f));
}

TEST_CASE("PNG files are sRGB and written whole", "[render]") {
  cw4d::test::TempDir dir("cw4d_test_render");
  Image img(3, 2, glm::vec4(0.0f));
  img.at(0, 0) = glm::vec4(0.5f, 0.0f, 1.0f, 1.0f);
  img.at(2, 1) = glm::vec4(0.21586f, 0.21586f, 0.21586f, 1.0f);  // sRGB 128
  const std::string path = (dir / "a.png").string();
  write_png(path, img, glm::vec3(0.0f));
  const Image8 back = read_png(path);
  REQUIRE(back.width == 3);
  REQUIRE(back.height == 2);
  REQUIRE(back.channels == 3);
  CHECK(int(back.bytes[0]) == 188);  // linear 0.5 -> sRGB 188
  CHECK(int(back.bytes[2]) == 255);
  CHECK(int(back.bytes[(1 * 3 + 2) * 3]) == 128);
  CHECK(dir.entries() == 1);  // no temporary file left
  CHECK_THROWS_AS(write_png((dir / "missing" / "x" / "a.png").string(), img), IoError);
  CHECK(linear_to_srgb(srgb_to_linear(0.3f)) == Approx(0.3f));
}

TEST_CASE("bad render input is rejected with typed errors", "[render]") {
  RasterOptions ro;
  ro.samples_per_axis = 5;
  CHECK_THROWS_AS(Rasterizer(ro), InputError);
  ro.samples_per_axis = 1;
  ro.width = 0;
  CHECK_THROWS_AS(Rasterizer(ro), InputError);
  Camera cam;
  cam.target = cam.eye;
  CHECK_THROWS_AS(cam.view(1.0f), InputError);
  CHECK_THROWS_AS(Camera4::look_at(vec({0, 0, 0, 1}), vec({0, 0, 0, 1})), InputError);
  const Section s3 = section(make_cube(5), Hyperplane::from(vec({0, 0, 0, 0, 1}), 0.0));
  CHECK_THROWS_AS(section_mesh(s3), InputError);
  CHECK_THROWS_AS(ConvexOccluder::from(Complex(4)), InputError);
  Scene scene;
  scene.objects.push_back(
      object(std::make_shared<const Complex>(make_cube(4)), AffineTransform(4), {}));
  CloudOptions co;
  co.layers = 0;
  CHECK_THROWS_AS(render_voxel_cloud(scene, vec({0, 0, 0, 1}), co), InputError);
  CHECK_THROWS_AS(render_voxel_cloud(scene, vec({0, 0, 0, 0}), CloudOptions{}), InputError);
}

TEST_CASE("a voxel cloud seen face-on has the object's opacity for any layer count", "[render]") {
  // Every layer of a tesseract cut along w is the same cube; looking straight down the layer
  // axis, the corrected layers add up to the cloud opacity whatever their number.
  Scene scene;
  scene.objects.push_back(object(std::make_shared<const Complex>(make_cube(4)), AffineTransform(4),
                                 Rgba{0.2f, 0.6f, 0.9f, 0.8f}));
  for (int layers : {5, 17, 60}) {
    CloudOptions o;
    o.raster.width = 64;
    o.raster.height = 64;
    o.layers = layers;
    o.opacity = 0.9f;
    o.view_from = glm::vec3(0.0f, 0.0f, 1.0f);
    o.flatten = false;
    const Image img = render_voxel_cloud(scene, vec({0, 0, 0, 1}), o);
    CAPTURE(layers);
    CHECK(img.at(32, 32).a == Approx(0.9 * 0.8).epsilon(1e-4));
    CHECK(img.at(1, 1).a == 0.0f);  // outside the cube's shadow
  }
}

TEST_CASE("a polytope behind another is hidden, one beside it is not", "[render][occlusion]") {
  auto tesseract = std::make_shared<const Complex>(make_cube(4));
  Scene scene;
  scene.objects.push_back(object(tesseract, AffineTransform(4), {}));
  // Half size, 4 units behind the first along w: inside its shadow cone from w = -6.
  scene.objects.push_back(
      object(tesseract,
             AffineTransform::translation(vec({0, 0, 0, 4})) * AffineTransform::scale(4, 0.5), {}));
  // Beside it: nothing in between.
  scene.objects.push_back(object(tesseract, AffineTransform::translation(vec({5, 0, 0, 0})), {}));
  const Camera4 cam = Camera4::look_at(vec({0, 0, 0, -6}), vec({0, 0, 0, 0}), 120.0);
  std::vector<double> length(3, 0.0);
  for (const auto& s : visible_edges(scene, cam)) length[s.object] += (s.b - s.a).norm();
  CHECK(length[0] > 0.0);
  CHECK(length[1] == 0.0);
  // The side tesseract shows every edge of its own front: at least its 12 edges facing -w...
  CHECK(length[2] >= 24.0 - 1e-9);
  // ...and without occlusion all 32 edges of length 2 are drawn.
  std::vector<double> all(3, 0.0);
  for (const auto& s : visible_edges(scene, cam, false)) all[s.object] += (s.b - s.a).norm();
  CHECK(all[2] == Approx(64.0));
  CHECK(all[1] == Approx(32.0));
}

TEST_CASE("colors are interpolated perspective-correctly", "[render]") {
  // A floor receding from the eye, its red channel linear in world z: at every pixel the color
  // must equal that function at the floor point the pixel's ray hits (screen-linear
  // interpolation would be far off).
  RasterOptions ro;
  ro.width = 64;
  ro.height = 64;
  ro.samples_per_axis = 1;
  Rasterizer r(ro);
  Camera cam;
  cam.eye = {0, 0, 0};
  cam.target = {0, -0.5f, -1};
  cam.fov_y_degrees = 60.0f;
  const float z0 = -1.0f, z1 = -40.0f;
  auto red = [&](float z) { return (z - z0) / (z1 - z0); };
  TriangleMesh floor;
  floor.vertices = {{{-30, -1, z0}, {}, {red(z0), 0, 0, 1}},
                    {{30, -1, z0}, {}, {red(z0), 0, 0, 1}},
                    {{0, -1, z1}, {}, {red(z1), 0, 0, 1}}};
  floor.triangles = {{0, 1, 2}};
  DrawOptions d;
  d.shading = Shading::Unlit;
  const View view = cam.view(r.aspect());
  r.draw(floor, view, Lighting{}, d);
  const Image img = r.render();
  const glm::mat4 inv = glm::inverse(view.clip_from_world);
  int checked = 0;
  double worst_affine_gap = 0.0;
  for (int y = 0; y < ro.height; ++y)
    for (int x = 0; x < ro.width; ++x) {
      if (img.at(x, y).a < 1.0f) continue;
      // The ray through the pixel centre, intersected with y = -1.
      const float nx = (x + 0.5f) / ro.width * 2 - 1, ny = 1 - (y + 0.5f) / ro.height * 2;
      glm::vec4 p = inv * glm::vec4(nx, ny, 1.0f, 1.0f);
      const glm::vec3 dir = glm::normalize(glm::vec3(p) / p.w - cam.eye);
      const float t = (-1.0f - cam.eye.y) / dir.y;
      const float z = cam.eye.z + t * dir.z;
      CHECK(img.at(x, y).r == Approx(red(z)).margin(2e-3));
      // What screen-linear interpolation would give, for the record.
      const glm::vec4 c = view.clip_from_world * glm::vec4(0, -1, z, 1);
      const glm::vec4 c0 = view.clip_from_world * glm::vec4(0, -1, z0, 1);
      const glm::vec4 c1 = view.clip_from_world * glm::vec4(0, -1, z1, 1);
      const float s = (c.y / c.w - c0.y / c0.w) / (c1.y / c1.w - c0.y / c0.w);
      worst_affine_gap = std::max(worst_affine_gap, static_cast<double>(std::abs(s - red(z))));
      ++checked;
    }
  CHECK(checked > 300);
  CHECK(worst_affine_gap > 0.2);  // the test can tell the two apart
}

TEST_CASE("Blinn-Phong at every pixel matches the formula evaluated in double", "[render][light]") {
  // A square in z = 0 facing +z, lit by a directional and a point light, seen orthographically
  // (the viewer's direction constant) and in perspective (varying per pixel): at each pixel the
  // shade must be ambient * base + sum_l c_l i_l (base N.L + s max(N.H, 0)^k), evaluated here in
  // double at the point the pixel's ray hits, for a whole and a fractional shininess k (the two
  // ways the rasterizer raises the highlight).
  const glm::vec3 base(0.6f, 0.5f, 0.4f);
  TriangleMesh square;
  for (const auto& p :
       {glm::vec3(-2, -2, 0), glm::vec3(2, -2, 0), glm::vec3(2, 2, 0), glm::vec3(-2, 2, 0)})
    square.vertices.push_back({p, {0, 0, 1}, glm::vec4(base, 1.0f)});
  square.triangles = {{0, 1, 2}, {0, 2, 3}};
  int checked = 0, highlighted = 0;
  for (const bool ortho : {true, false})
    for (const float shininess : {20.0f, 20.5f}) {
      Camera cam;
      cam.eye = {0.2f, -0.1f, 2.0f};
      cam.target = {0.2f, -0.1f, 0.0f};
      cam.projection = ortho ? Projection::Orthographic : Projection::Perspective;
      cam.ortho_height = 1.5f;
      cam.fov_y_degrees = 40.0f;
      Lighting lit;
      lit.ambient = glm::vec3(0.1f);
      lit.specular = 0.5f;
      lit.shininess = shininess;
      lit.lights.push_back({Light::Kind::Directional, glm::normalize(glm::vec3(0.1f, 0.05f, 1.0f)),
                            glm::vec3(0.8f, 0.7f, 0.6f), 0.0f});
      lit.lights.push_back(
          {Light::Kind::Point, glm::vec3(-0.5f, 0.4f, 1.0f), glm::vec3(0.3f), 0.7f});
      RasterOptions ro;
      ro.width = 48;
      ro.height = 40;
      ro.samples_per_axis = 1;
      Rasterizer r(ro);
      const View view = cam.view(r.aspect());
      r.draw(square, view, lit);
      const Image img = r.render();
      const glm::mat4 inv = glm::inverse(view.clip_from_world);
      for (int y = 0; y < ro.height; ++y)
        for (int x = 0; x < ro.width; ++x) {
          REQUIRE(img.at(x, y).a == 1.0f);  // the square fills the view
          // The pixel centre's ray, intersected with z = 0 (double).
          const double nx = (x + 0.5) / ro.width * 2 - 1, ny = 1 - (y + 0.5) / ro.height * 2;
          const glm::vec4 a = inv * glm::vec4(nx, ny, -1.0f, 1.0f);
          const glm::vec4 b = inv * glm::vec4(nx, ny, 1.0f, 1.0f);
          const Eigen::Vector3d pa(a.x / a.w, a.y / a.w, a.z / a.w);
          const Eigen::Vector3d pb(b.x / b.w, b.y / b.w, b.z / b.w);
          const Eigen::Vector3d p = pa + (pb - pa) * (pa.z() / (pa.z() - pb.z()));
          const Eigen::Vector3d eye(cam.eye.x, cam.eye.y, cam.eye.z);
          const Eigen::Vector3d v = ortho ? Eigen::Vector3d(0, 0, 1) : (eye - p).normalized();
          const Eigen::Vector3d n(0, 0, 1);
          Eigen::Vector3d expect = 0.1 * Eigen::Vector3d(base.r, base.g, base.b);
          for (const Light& light : lit.lights) {
            const Eigen::Vector3d lv(light.vector.x, light.vector.y, light.vector.z);
            Eigen::Vector3d l = lv;
            double intensity = 1.0;
            if (light.kind == Light::Kind::Point) {
              l = lv - p;
              intensity = 1.0 / (1.0 + light.attenuation * l.squaredNorm());
            }
            l.normalize();
            const double nl = n.dot(l);
            if (nl <= 0.0) continue;
            const double nh = n.dot((l + v).normalized());
            // The rasterizer skips highlights under 1e-3 (N.H below 1e-3^(1/k)).
            const double spec =
                nh > std::pow(1e-3, 1.0 / shininess) ? 0.5 * std::pow(nh, shininess) : 0.0;
            highlighted += spec > 0.01;
            for (int c = 0; c < 3; ++c)
              expect(c) += intensity * light.color[c] * (base[c] * nl + spec);
          }
          const glm::vec4 got = img.at(x, y);
          CAPTURE(ortho, shininess, x, y);
          for (int c = 0; c < 3; ++c) CHECK(got[c] == Approx(expect(c)).epsilon(1e-4));
          ++checked;
        }
    }
  CHECK(checked == 4 * 48 * 40);
  CHECK(highlighted > 100);  // the highlights are in the picture, not only the diffuse term
}

TEST_CASE("the table sRGB encoder gives linear_to_srgb8's byte for every float", "[render]") {
  // Oracle: linear_to_srgb8 (the transfer function's power) at every float in [0, 1] with a
  // stride, at every float within 4096 of each analytic step (where sRGB(c) * 255 is k - 1/2,
  // solved in double from IEC 61966-2-1) and at the special values.
  const Srgb8Encoder& e = Srgb8Encoder::instance();
  CHECK(e.exact);
  CHECK(e.max_steps >= 1);
  long mismatches = 0, tested = 0;
  auto check_bits = [&](std::uint32_t bits) {
    const float c = std::bit_cast<float>(bits);
    mismatches += e(c) != linear_to_srgb8(c);
    ++tested;
  };
  for (std::uint32_t bits = 0; bits <= 0x3F800000u; bits += 97) check_bits(bits);
  for (int k = 1; k <= 255; ++k) {
    const double s = (k - 0.5) / 255.0;
    const double c = s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
    const auto mid = std::bit_cast<std::uint32_t>(static_cast<float>(c));
    for (std::uint32_t b = mid - 4096; b <= mid + 4096; ++b) check_bits(b);
  }
  CHECK(tested > 12'000'000);
  CHECK(mismatches == 0);
  for (const float c :
       {0.0f, -0.0f, -1.0f, 1.0f, 1.5f, 1e-45f, 1e-38f, 0.0031308f,
        std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
        std::numeric_limits<float>::quiet_NaN()}) {
    CAPTURE(c);
    CHECK(e(c) == linear_to_srgb8(c));
  }
}

TEST_CASE("the 8-bit frame is the float frame encoded as to_srgb8, byte for byte", "[render]") {
  // Oracle: the float picture of the same rasterizer, encoded here pixel by pixel with
  // linear_to_srgb8 (straight alpha, or flattened on the background), for one and several
  // samples per pixel, a partly transparent raster background, blended draws (fractional alpha)
  // and a size that is no multiple of the tile or of eight pixels.
  const Complex m = load_model("120-cell");
  const Section s = section(m, Hyperplane::from(vec({1.0, 0.7, 0.4, 0.2}), 0.3));
  TriangleMesh mesh = section_mesh(s, &m);
  TriangleMesh glass = mesh;
  for (auto& v : glass.vertices) {
    v.position = 0.9f * v.position + glm::vec3(0.05f, 0.02f, 0.2f);
    v.color.a = 0.45f;
  }
  SectionViewOptions so;
  so.raster.width = 203;
  so.raster.height = 141;
  const Camera cam = section_camera(s, so);
  long compared = 0, partial = 0;
  for (const int samples : {1, 2, 3})
    for (const bool blended : {false, true}) {
      RasterOptions ro;
      ro.width = 203;
      ro.height = 141;
      ro.samples_per_axis = samples;
      ro.background = blended ? glm::vec4(0.1f, 0.05f, 0.2f, 0.4f) : glm::vec4(0.0f);
      Rasterizer r(ro);
      const View view = cam.view(r.aspect());
      const Lighting lit = Lighting::studio(cam);
      r.draw(mesh, view, lit);
      if (blended) {
        DrawOptions d;
        d.blend = Blend::Over;
        r.draw(glass, view, lit, d);
      }
      const Image img = r.render();
      for (const bool alpha : {false, true}) {
        const glm::vec3 bg(0.9f, 0.3f, 0.6f);
        Image8 fast;
        r.render(fast, bg, alpha);
        CAPTURE(samples, blended, alpha);
        REQUIRE(fast.width == 203);
        REQUIRE(fast.height == 141);
        REQUIRE(fast.channels == (alpha ? 4 : 3));
        REQUIRE(fast.bytes.size() == img.pixels.size() * fast.channels);
        long wrong = 0;
        for (std::size_t i = 0; i < img.pixels.size(); ++i) {
          const glm::vec4 p = img.pixels[i];
          const float a = std::clamp(p.a, 0.0f, 1.0f);
          partial += a > 0.0f && a < 1.0f;
          std::uint8_t expect[4];
          if (alpha) {
            for (int c = 0; c < 3; ++c) expect[c] = linear_to_srgb8(a > 0.0f ? p[c] / a : 0.0f);
            expect[3] = static_cast<std::uint8_t>(std::lround(a * 255.0f));
          } else {
            for (int c = 0; c < 3; ++c) expect[c] = linear_to_srgb8(p[c] + (1.0f - a) * bg[c]);
          }
          for (int c = 0; c < fast.channels; ++c)
            wrong += fast.bytes[i * fast.channels + c] != expect[c];
          ++compared;
        }
        CHECK(wrong == 0);
        // And to_srgb8 of the float frame says the same.
        const Image8 slow = to_srgb8(img, bg, alpha);
        CHECK(slow.bytes == fast.bytes);
      }
    }
  CHECK(compared == 12L * 203 * 141);
  CHECK(partial > 1000);  // fractional alpha was exercised
}

TEST_CASE("a mesh drawn in parts, or again after clear(), gives the same picture", "[render]") {
  // Oracle: the same triangles in the same order must give the same picture however they are
  // queued — one draw (several geometry blocks), three draws, or after clear() on a rasterizer
  // that drew something else before.
  const Complex m = load_model("spherinder:1,100");
  const Section s = section(m, Hyperplane::from(vec({0.3, 0.0, 0.0, 1.0}), 0.1));
  const TriangleMesh mesh = section_mesh(s, &m);
  REQUIRE(mesh.triangles.size() > 4096);  // more than two geometry work items
  SectionViewOptions so;
  so.raster.width = 160;
  so.raster.height = 120;
  const Camera cam = section_camera(s, so);
  RasterOptions ro;
  ro.width = 160;
  ro.height = 120;
  ro.samples_per_axis = 2;
  const Lighting lit = Lighting::studio(cam);
  Rasterizer whole(ro);
  const View view = cam.view(whole.aspect());
  whole.draw(mesh, view, lit);
  const Image expect = whole.render();
  CHECK(expect.coverage() > 1000.0);

  Rasterizer parts(ro);
  TriangleMesh other = mesh;
  for (auto& v : other.vertices) v.position *= 0.5f;
  parts.draw(other, view, lit);  // something else first, then dropped
  parts.clear();
  CHECK(parts.queued_triangles() == 0);
  const std::size_t n = mesh.triangles.size();
  for (const auto& [from, to] :
       {std::pair<std::size_t, std::size_t>{0, n / 3}, {n / 3, n / 3 + 7}, {n / 3 + 7, n}}) {
    TriangleMesh part;
    part.vertices = mesh.vertices;
    part.triangles.assign(mesh.triangles.begin() + static_cast<std::ptrdiff_t>(from),
                          mesh.triangles.begin() + static_cast<std::ptrdiff_t>(to));
    parts.draw(part, view, lit);
  }
  CHECK(parts.queued_triangles() == whole.queued_triangles());
  CHECK(same_pixels(parts.render(), expect));
}
