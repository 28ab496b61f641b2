// Schlegel diagrams: the front cell frames the diagram and the other cells tile it.
#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/render/schlegel.hpp"

using namespace cw4d;

namespace {

// 3-volume of the image of cell c: a fan of tetrahedra from the image of its vertex centroid
// over the fan triangles of its faces (the images of convex cells are convex).
double image_volume(const Complex& m, const render::SchlegelProjection& sp, std::uint32_t c) {
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  const auto vs = m.vertices_of(3, c);
  for (auto v : vs) g += sp.project(m.position(v));
  g /= static_cast<double>(vs.size());
  double vol = 0.0;
  for (const auto f : m.boundary(3).ids(c)) {
    const auto cyc = m.face_cycle(f);
    const Eigen::Vector3d a = sp.project(m.position(cyc[0])) - g;
    for (std::size_t k = 1; k + 1 < cyc.size(); ++k) {
      const Eigen::Vector3d b = sp.project(m.position(cyc[k])) - g;
      const Eigen::Vector3d d = sp.project(m.position(cyc[k + 1])) - g;
      vol += std::abs(a.dot(b.cross(d))) / 6.0;
    }
  }
  return vol;
}

void check_diagram(const Complex& m, long long cell) {
  const render::SchlegelProjection sp = render::schlegel_projection(m, cell);
  if (cell >= 0) CHECK(sp.cell == cell);
  const double scale = max_radius(m);
  // The eye is outside the front cell only.
  for (std::uint32_t c = 0; c < m.count(3); ++c) {
    const Eigen::Vector4d n = facet_area_vector(m, c).normalized();
    const Eigen::Vector4d x = m.position(m.first_vertex(3, c));
    CHECK((n.dot(sp.eye() - x) > 0.0) == (c == sp.cell));
  }
  // The front cell's vertices are fixed: their image is their position in the cell's frame.
  for (const auto v : m.vertices_of(3, sp.cell)) {
    const Eigen::Vector3d y = sp.basis.transpose() * (Eigen::Vector4d(m.position(v)) - sp.centre);
    CHECK((sp.project(m.position(v)) - y).norm() < 1e-12 * scale);
  }
  // Every vertex's image lies in the front cell's image: inside each of its faces' planes.
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  const auto fv = m.vertices_of(3, sp.cell);
  for (auto v : fv) g += sp.project(m.position(v));
  g /= static_cast<double>(fv.size());
  for (const auto f : m.boundary(3).ids(sp.cell)) {
    const auto cyc = m.face_cycle(f);
    const Eigen::Vector3d a = sp.project(m.position(cyc[0]));
    Eigen::Vector3d n =
        (sp.project(m.position(cyc[1])) - a).cross(sp.project(m.position(cyc[2])) - a).normalized();
    if (n.dot(g - a) > 0.0) n = -n;  // outward
    for (Eigen::Index v = 0; v < m.positions().cols(); ++v)
      CHECK(n.dot(sp.project(m.positions().col(v)) - a) <= 1e-9 * scale);
  }
  // The other cells' images tile the front cell's image: their volumes add up to it.
  double others = 0.0;
  for (std::uint32_t c = 0; c < m.count(3); ++c)
    if (c != sp.cell) others += image_volume(m, sp, c);
  CHECK(others == Approx(image_volume(m, sp, sp.cell)).epsilon(1e-9));
  CHECK(render::schlegel_edges(m, sp).size() == m.count(1));
}

}  // namespace

TEST_CASE("Schlegel diagrams: the front cell holds the diagram, the others tile it",
          "[render][schlegel]") {
  check_diagram(make_cube(4), -1);
  check_diagram(make_cube(4), 3);
  check_diagram(load_model("24-cell"), -1);
  check_diagram(load_model("120-cell"), 17);
  check_diagram(load_model("5-cell"), -1);
  check_diagram(load_model("duoprism:3,5"), 2);
}

TEST_CASE("Schlegel pictures: the front cell's outline bounds the drawing", "[render][schlegel]") {
  const Complex m = load_model("120-cell");
  const render::SchlegelProjection sp = render::schlegel_projection(m, 0);
  render::SchlegelOptions o;
  o.raster.width = 300;
  o.raster.height = 240;
  o.raster.samples_per_axis = 1;
  o.view_from = glm::vec3(0.3f, 0.2f, 1.0f);
  const render::Image img = render::render_schlegel(m, sp, o);
  REQUIRE(img.width == 300);
  REQUIRE(img.height == 240);
  // Screen bounds of the front cell's vertices, by the same camera.
  const render::Camera cam = render::schlegel_camera(m, sp, o);
  const render::View view = cam.view(300.0f / 240.0f);
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const auto v : m.vertices_of(3, sp.cell)) {
    const Eigen::Vector3d y = sp.project(m.position(v));
    const glm::vec4 c = view.clip_from_world * glm::vec4(y.x(), y.y(), y.z(), 1.0);
    const double px = (c.x / c.w * 0.5 + 0.5) * 300.0, py = (0.5 - c.y / c.w * 0.5) * 240.0;
    x0 = std::min(x0, px);
    x1 = std::max(x1, px);
    y0 = std::min(y0, py);
    y1 = std::max(y1, py);
  }
  // The drawn pixels' bounds: those of the front cell, up to the line width.
  double d0 = 1e9, d1 = -1e9, e0 = 1e9, e1 = -1e9;
  std::size_t drawn = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::vec4 p = img.at(x, y);
      if (p.r > 0.97f && p.g > 0.97f && p.b > 0.97f) continue;
      ++drawn;
      d0 = std::min(d0, x + 0.5);
      d1 = std::max(d1, x + 0.5);
      e0 = std::min(e0, y + 0.5);
      e1 = std::max(e1, y + 0.5);
    }
  CHECK(drawn > 2000);
  CHECK(std::abs(d0 - x0) < 2.5);
  CHECK(std::abs(d1 - x1) < 2.5);
  CHECK(std::abs(e0 - y0) < 2.5);
  CHECK(std::abs(e1 - y1) < 2.5);
}

TEST_CASE("Schlegel diagrams refuse what they cannot draw", "[render][schlegel]") {
  CHECK_THROWS_AS(render::schlegel_projection(make_cube(3)), InputError);
  CHECK_THROWS_AS(render::schlegel_projection(make_cube(4), 8), InputError);
  CHECK_THROWS_AS(render::schlegel_projection(make_cube(4), -2), InputError);
}
