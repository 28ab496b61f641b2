// 3D textures through UVW and 4D light (render/texture.hpp, section_view.hpp): golden-free.
// The checker's cells and edges on an axis-aligned cut of the tesseract against their analytic
// places; the CW slicer and the tetrahedral slicer texture the same picture (two algorithms);
// trilinear filtering of an image volume against hand-computed mixtures; the Lambert term of
// directional and inverse-cube point lights against the analytic 4D normal of a turned cell.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/render/color.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/raster.hpp"
#include "cw4d/render/section_view.hpp"
#include "cw4d/render/texture.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"
#include "support/temp_dir.hpp"
#include "support/vectors.hpp"

using namespace cw4d;
using namespace cw4d::render;
using cw4d::test::vec;

namespace {

Scene scene_of(const Complex& model, const AffineTransform& t) {
  Scene s;
  SceneObject o;
  o.model = "test";
  o.complex = std::make_shared<const Complex>(model);
  o.transform = t;
  s.objects.push_back(o);
  return s;
}

glm::vec3 to_glm(const Eigen::VectorXd& v) {
  return {static_cast<float>(v(0)), static_cast<float>(v(1)), static_cast<float>(v(2))};
}

// An orthographic camera looking at the section from the direction `from_world` (a 4D
// direction inside the hyperplane), `up_world` up, showing `height` section units.
Camera ortho_camera(const Section& s, const Eigen::VectorXd& from_world,
                    const Eigen::VectorXd& up_world, float height) {
  Camera c;
  c.projection = Projection::Orthographic;
  c.eye = 5.0f * to_glm(s.frame.basis.transpose() * from_world);
  c.target = glm::vec3(0.0f);
  c.up = to_glm(s.frame.basis.transpose() * up_world);
  c.ortho_height = height;
  c.near_plane = 0.1f;
  c.far_plane = 20.0f;
  return c;
}

// Screen x (pixels) of a section point.
double screen_x(const View& view, glm::vec3 p, int width) {
  const glm::vec4 c = view.clip_from_world * glm::vec4(p, 1.0f);
  return (c.x / c.w * 0.5 + 0.5) * width;
}

float luminance(const glm::vec4& p) {
  return p.r + p.g + p.b;
}

// Indices where a row of pixels switches between the light and the dark class (threshold: the
// geometric mean of the brightest and darkest covered pixel), over covered pixels only.
std::vector<int> transitions(const std::vector<glm::vec4>& row) {
  float lo = 1e9f, hi = 0.0f;
  for (const auto& p : row)
    if (p.a > 0.99f) {
      lo = std::min(lo, luminance(p));
      hi = std::max(hi, luminance(p));
    }
  const float threshold = std::sqrt(lo * hi);
  std::vector<int> out;
  int prev = -1;
  for (int i = 0; i < static_cast<int>(row.size()); ++i) {
    if (row[i].a < 0.99f) {
      prev = -1;
      continue;
    }
    const int cls = luminance(row[i]) > threshold ? 1 : 0;
    if (prev >= 0 && cls != prev) out.push_back(i);
    prev = cls;
  }
  return out;
}

}  // namespace

TEST_CASE("a checker on the tesseract's cut shows its cells at the analytic edges",
          "[render][texture]") {
  // The cut w = 0.1 of [-1, 1]^4 is the cube [-1, 1]^3; the face x = 1 is the cut of the cell
  // x = 1, whose UVW box spans y, z, w in [-1, 1]: checker:S has S cells along y and z there,
  // edges at y = -1 + 2k/S, and the w layer (0.1 + 1)/2 * S away from any edge.
  const Complex tesseract = make_cube(4);
  const Scene scene = scene_of(tesseract, AffineTransform(4));
  const Section s = section(tesseract, Hyperplane::from(vec({0, 0, 0, 1}), 0.1));
  for (const int cells : {4, 8, 10}) {
    SectionViewOptions o;
    o.raster.width = o.raster.height = 480;
    o.raster.samples_per_axis = 1;
    o.source = &scene;
    add_texture(o.textures, "checker:" + std::to_string(cells));
    const Camera cam = ortho_camera(s, vec({1, 0, 0, 0}), vec({0, 0, 1, 0}), 2.4f);
    const View view = cam.view(1.0f);
    const Image img = render_section(s, o, cam, nullptr, false);
    // Rows at z = 0.13 and z = -0.61 (inside a checker row), across y.
    for (const double z : {0.13, -0.61}) {
      const glm::vec3 pz = to_glm(s.frame.to_plane(vec({1, 0, z, 0})));
      const glm::vec4 c = view.clip_from_world * glm::vec4(pz, 1.0f);
      const int row_index = static_cast<int>((0.5 - 0.5 * c.y / c.w) * img.height);
      std::vector<glm::vec4> row(img.pixels.begin() + row_index * img.width,
                                 img.pixels.begin() + (row_index + 1) * img.width);
      const std::vector<int> found = transitions(row);
      CAPTURE(cells, z, found);
      REQUIRE(found.size() == static_cast<std::size_t>(cells - 1));  // `cells` runs
      std::vector<double> expected;
      for (int k = 1; k < cells; ++k) {
        const double y = -1.0 + 2.0 * k / cells;
        expected.push_back(screen_x(view, to_glm(s.frame.to_plane(vec({1, y, z, 0}))), img.width));
      }
      std::sort(expected.begin(), expected.end());
      for (std::size_t k = 0; k < found.size(); ++k) CHECK(std::abs(found[k] - expected[k]) <= 1.0);
    }
  }
}

TEST_CASE("the CW slicer and the tetrahedral slicer texture a section identically",
          "[render][texture]") {
  struct Case {
    Complex model;
    AffineTransform place;
    std::vector<double> normal;
    double offset;
  };
  const AffineTransform turn =
      AffineTransform::rotation(4, 0, 1, 0.3) * AffineTransform::rotation(4, 2, 3, 0.45);
  std::vector<Case> cases;
  cases.push_back({make_cube(4), turn, {0, 0, 0, 1}, 0.1});
  cases.push_back({make_orthoplex(4), turn, {1, 1, 0, 1}, 0.15});
  cases.push_back({make_duoprism(5, 6), AffineTransform(4), {0.3, 0, 0.2, 1}, 0.05});
  for (const char* spec : {"checker:6", "grid:3", "marble:2", "wood:4"}) {
    for (const Case& c : cases) {
      const Scene scene = scene_of(c.model, c.place);
      Eigen::VectorXd n = Eigen::Map<const Eigen::VectorXd>(c.normal.data(), 4).normalized();
      const Hyperplane plane = Hyperplane::from(n, c.offset);
      const Section s = section(c.model, plane, c.place);
      const TetSection ts = slice_tets(tetrahedralize(c.model), plane, c.place);
      SectionViewOptions o;
      o.raster.width = 240;
      o.raster.height = 180;
      o.raster.samples_per_axis = 1;
      o.source = &scene;
      add_texture(o.textures, spec);
      const Camera cam = section_camera(s, o);
      const Image a = render_section(s, o, cam, nullptr, false);
      const TriangleMesh soup =
          soup_mesh(ts.positions, ts.normals, ts.uvw, ts.cell, scene.objects[0], &o.textures);
      const Image b = render_mesh(soup, {}, ts.frame, o, cam, false);
      std::size_t covered = 0, differ = 0;
      for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        if (a.pixels[i].a < 1.0f && b.pixels[i].a < 1.0f) continue;
        ++covered;
        if (glm::length(a.pixels[i] - b.pixels[i]) > 0.02f) ++differ;
      }
      // The texture shows: the untextured picture differs in many pixels.
      SectionViewOptions plain = o;
      plain.textures = {};
      const Image u = render_section(s, plain, cam, nullptr, false);
      std::size_t textured = 0;
      for (std::size_t i = 0; i < a.pixels.size(); ++i)
        if (glm::length(a.pixels[i] - u.pixels[i]) > 0.02f) ++textured;
      CAPTURE(spec, c.normal, covered, differ, textured);
      REQUIRE(covered > 2000);
      CHECK(textured > covered / 100);  // grid lines cover a few per cent
      // Pixels on texture edges and silhouettes may fall either way by rounding.
      CHECK(differ < covered / 50);
    }
  }
}

TEST_CASE("an image volume is filtered trilinearly", "[render][texture]") {
  cw4d::test::TempDir dir("cw4d_test_render_texture");
  // 2 x 2 x 2 gray texels: value (i + 2 j + 4 k) * 30 (sRGB bytes).
  auto byte = [](int i, int j, int k) {
    return static_cast<std::uint8_t>((i + 2 * j + 4 * k) * 30);
  };
  std::vector<std::string> paths;
  for (int k = 0; k < 2; ++k) {
    Image8 img;
    img.width = img.height = 2;
    img.channels = 3;
    for (int row = 0; row < 2; ++row)
      for (int i = 0; i < 2; ++i) {
        const int j = 1 - row;  // the top row is v = 1
        for (int ch = 0; ch < 3; ++ch) img.bytes.push_back(byte(i, j, k));
      }
    char name[32];
    std::snprintf(name, sizeof name, "z%02d.png", k);
    paths.push_back((dir / name).string());
    write_png(paths.back(), img);
  }
  const ImageVolume v = ImageVolume::from_png_slices(paths);
  REQUIRE(v.width == 2);
  REQUIRE(v.depth == 2);
  auto lin = [&](int i, int j, int k) { return srgb_to_linear(byte(i, j, k) / 255.0f); };
  // Texel centres give the texel; the volume's centre the mean of all eight; (0.25+0.25, ...)
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i)
        CHECK(v.sample({0.25f + 0.5f * i, 0.25f + 0.5f * j, 0.25f + 0.5f * k}).r ==
              Approx(lin(i, j, k)).margin(1e-6));
  float mean = 0.0f;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) mean += lin(i, j, k) / 8.0f;
  CHECK(v.sample({0.5f, 0.5f, 0.5f}).g == Approx(mean).margin(1e-6));
  // At u = 0.375 (a quarter of the way from texel 0 to texel 1), v, w at texel 0.
  CHECK(v.sample({0.375f, 0.25f, 0.25f}).b ==
        Approx(0.75f * lin(0, 0, 0) + 0.25f * lin(1, 0, 0)).margin(1e-6));
  // Clamped outside.
  CHECK(v.sample({-1.0f, 0.0f, 2.0f}).r == Approx(lin(0, 0, 1)).margin(1e-6));
  // The same volume through the spellings the CLI takes.
  const Texture3D from_dir = parse_texture("volume:" + dir.path().string());
  REQUIRE(from_dir.volume);
  CHECK(from_dir.volume->texels == v.texels);
  const Texture3D from_pattern = parse_texture("volume:" + (dir / "z%02d.png").string() + ":2");
  CHECK(from_pattern.scale == 2.0f);
  CHECK(from_pattern.volume->texels == v.texels);
  CHECK(from_pattern.apply(glm::vec3(0.3f), {0.125f, 0.125f, 0.125f}).r ==
        Approx(lin(0, 0, 0)).margin(1e-6));
}

TEST_CASE("texture specs are parsed or rejected", "[render][texture]") {
  CHECK(parse_texture("checker").scale == 8.0f);
  CHECK(parse_texture("grid:2.5").scale == 2.5f);
  CHECK(parse_texture("marble:3").kind == Texture3D::Kind::Marble);
  for (const char* bad : {"checker:0", "checker:-1", "checker:x", "stripes",
                          "wood:", "volume:", "volume:/nonexistent/dir/z%d.png"})
    CHECK_THROWS_AS(parse_texture(bad), InputError);
  TextureAssignment a;
  add_texture(a, "checker:4");
  add_texture(a, "object=2:grid");
  add_texture(a, "cell=5:wood");
  CHECK(a.find(0, 0)->kind == Texture3D::Kind::Checker);
  CHECK(a.find(2, 0)->kind == Texture3D::Kind::Grid);
  CHECK(a.find(2, 5)->kind == Texture3D::Kind::Wood);
  CHECK_THROWS_AS(add_texture(a, "cell=x:wood"), InputError);
  CHECK_THROWS_AS(add_texture(a, "object=1"), InputError);
  // The checker's factor: dark on odd cells.
  const Texture3D c = parse_texture("checker:2");
  CHECK(c.factor({0.1f, 0.1f, 0.1f}) == 1.0f);
  CHECK(c.factor({0.6f, 0.1f, 0.1f}) == c.dark);
  CHECK(c.factor({0.6f, 0.6f, 0.1f}) == 1.0f);
}

TEST_CASE("4D light: the Lambert term follows the cell's 4D normal", "[render][light4]") {
  // The tesseract turned by theta in the xw plane (e_x towards e_w) and cut at w = 0: the cell
  // x = 1 has the 4D normal (cos theta, 0, 0, sin theta) and cuts the face x = 1 / cos theta.
  // A light along +w gives N.L = sin theta there (zero in 3D: the face's 3D normal is +x); a
  // point light at (0, 0, 0, 4) gives (R / r)^3 N.(P - p)/r at the face's centre (R = 4).
  const Complex tesseract = make_cube(4);
  for (const double theta_deg : {20.0, 30.0, 40.0}) {  // below 45: the cell x = 1 meets w = 0
    const double theta = theta_deg * std::numbers::pi / 180.0;
    const AffineTransform turn = AffineTransform::rotation(4, 0, 3, theta);
    const Scene scene = scene_of(tesseract, turn);
    const Section s = section(tesseract, Hyperplane::from(vec({0, 0, 0, 1}), 0.0), turn);
    SectionViewOptions o;
    o.source = &scene;
    o.light_4d = true;
    const TriangleMesh mesh = section_mesh(s, nullptr, scene, nullptr);
    const Camera cam = ortho_camera(s, vec({1, 0, 0, 0}), vec({0, 0, 1, 0}), 3.0f);
    const double xf = 1.0 / std::cos(theta);
    for (const bool point : {false, true}) {
      Lighting l = section_lighting(cam, s.frame, o);
      REQUIRE(l.four_d);
      l.ambient = glm::vec3(0.0f);
      l.specular = 0.0f;
      Light4 light;
      light.kind = point ? Light4::Kind::Point : Light4::Kind::Directional;
      light.vector = point ? glm::vec4(0, 0, 0, 4) : glm::vec4(0, 0, 0, 1);
      light.reference = 4.0f;
      l.lights4 = {light};
      RasterOptions ro;
      ro.width = ro.height = 101;  // odd: the middle pixel's centre is on the axis
      ro.samples_per_axis = 1;
      Rasterizer r(ro);
      r.draw(mesh, cam.view(1.0f), l);
      const Image img = r.render();
      const glm::vec4 p = img.at(50, 50);
      REQUIRE(p.a == 1.0f);
      // The face's base color: the mesh vertex of the face seen there (the cell x = 1).
      glm::vec3 base(0.0f);
      for (const auto& v : mesh.vertices)
        if (std::abs(glm::dot(v.normal4, glm::vec4(1, 0, 0, 0)) - std::cos(theta)) < 1e-5 &&
            std::abs(v.normal4.w - std::sin(theta)) < 1e-5)
          base = glm::vec3(v.color);
      REQUIRE(base != glm::vec3(0.0f));
      double expected = std::sin(theta);
      if (point) {
        const Eigen::Vector4d to_light(-xf, 0.0, 0.0, 4.0);
        const double rr = to_light.norm();
        expected =
            std::max(0.0,
                     Eigen::Vector4d(std::cos(theta), 0, 0, std::sin(theta)).dot(to_light / rr)) /
            (rr * rr * rr) * 64.0;  // (R / r)^3 with R = 4
      }
      CAPTURE(theta_deg, point, expected, p.r, base.r);
      REQUIRE(expected > 0.01);
      CHECK(p.r == Approx(base.r * expected).epsilon(2e-3));
      CHECK(p.g == Approx(base.g * expected).epsilon(2e-3));
    }
  }
}

TEST_CASE("4D light needs the section's source", "[render][light4]") {
  const Section s = section(make_cube(4), Hyperplane::from(vec({0, 0, 0, 1}), 0.0));
  SectionViewOptions o;
  o.raster.width = o.raster.height = 32;
  o.light_4d = true;
  CHECK_THROWS_AS(render_section(s, o), InputError);
  o.light_4d = false;
  add_texture(o.textures, "checker");
  CHECK_THROWS_AS(render_section(s, o), InputError);
}
