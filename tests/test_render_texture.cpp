// 3D textures through UVW and 4D light (render/texture.hpp, section_view.hpp): golden-free.
// The checker's cells and edges on an axis-aligned cut of the tesseract against their analytic
// places; the CW slicer and the tetrahedral slicer texture the same picture (two algorithms);
// trilinear filtering of an image volume against hand-computed mixtures; the Lambert term of
// directional and inverse-cube point lights against the analytic 4D normal of a turned cell;
// layer stripes of voxel clouds at grazing views; animated WebP read back by libwebp's demuxer.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <gif_lib.h>
#include <webp/demux.h>
#include <Eigen/Geometry>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/render/animation.hpp"
#include "cw4d/render/color.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/raster.hpp"
#include "cw4d/render/section_view.hpp"
#include "cw4d/render/texture.hpp"
#include "cw4d/render/voxel_cloud.hpp"
#include "cw4d/render/wireframe4d.hpp"
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

namespace {

// A section of the tesseract through `normal` at `offset`, textured with `spec` (empty: none),
// from the section camera of the offset-0 section (every picture of one case shares it).
Image textured_tesseract(const Eigen::VectorXd& normal, double offset, const std::string& spec) {
  const Complex tesseract = make_cube(4);
  const Scene scene = scene_of(tesseract, AffineTransform(4));
  SectionViewOptions o;
  o.raster.width = 240;
  o.raster.height = 180;
  o.raster.samples_per_axis = 2;
  o.source = &scene;
  if (!spec.empty()) add_texture(o.textures, spec);
  const Camera cam = section_camera(section(tesseract, Hyperplane::from(normal, 0.0)), o);
  return render_section(section(tesseract, Hyperplane::from(normal, offset)), o, cam, nullptr,
                        false);
}

// Which side of a checker each fully covered pixel shows, from its luminance over the
// untextured picture's: 1 light (a ratio within 0.1 of 1), 0 dark (within 0.1 of the dark
// factor), -1 neither (a blend of both sides, or of two faces, in an anti-aliased pixel) or
// not fully covered.
std::vector<int> check_classes(const Image& textured, const Image& plain, float dark) {
  std::vector<int> out(textured.pixels.size(), -1);
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (textured.pixels[i].a < 0.999f || plain.pixels[i].a < 0.999f) continue;
    const float ratio = luminance(textured.pixels[i]) / std::max(luminance(plain.pixels[i]), 1e-6f);
    if (std::abs(ratio - 1.0f) < 0.1f) out[i] = 1;
    if (std::abs(ratio - dark) < 0.1f) out[i] = 0;
  }
  return out;
}

struct Speckle {
  std::size_t interior = 0;  // classed pixels whose 4 neighbours are classed
  std::size_t isolated = 0;  // of those, the ones whose class differs from all 4 neighbours
};

Speckle speckle(const std::vector<int>& cls, int width, int height) {
  Speckle s;
  for (int y = 1; y + 1 < height; ++y)
    for (int x = 1; x + 1 < width; ++x) {
      const int c = cls[static_cast<std::size_t>(y) * width + x];
      const int n[4] = {cls[static_cast<std::size_t>(y - 1) * width + x],
                        cls[static_cast<std::size_t>(y + 1) * width + x],
                        cls[static_cast<std::size_t>(y) * width + x - 1],
                        cls[static_cast<std::size_t>(y) * width + x + 1]};
      if (c < 0 || n[0] < 0 || n[1] < 0 || n[2] < 0 || n[3] < 0) continue;
      ++s.interior;
      if (n[0] != c && n[1] != c && n[2] != c && n[3] != c) ++s.isolated;
    }
  return s;
}

}  // namespace

TEST_CASE("a texture's lattice walls are tie-broken to their upper side", "[render][texture]") {
  // The rule of texture.hpp on single samples: UVW a few float ulps either side of a wall
  // (what interpolation rounding makes of a wall the section lies on) gives one answer, that of
  // the cell above the wall.
  auto around = [](float x, int ulps) {
    std::vector<float> out{x};
    float lo = x, hi = x;
    for (int i = 0; i < ulps; ++i) {
      lo = std::nextafter(lo, -1e9f);
      hi = std::nextafter(hi, 1e9f);
      out.push_back(lo);
      out.push_back(hi);
    }
    return out;
  };
  // checker:8: the wall p.z = 4 at w = 0.5; above it (p.z = 4.5) the factor of cell (0, 0, 4).
  const Texture3D checker = parse_texture("checker:8");
  const float above = checker.factor({0.01f, 0.01f, 4.5f / 8.0f});
  REQUIRE(above == 1.0f);
  REQUIRE(checker.factor({0.01f, 0.01f, 3.5f / 8.0f}) == checker.dark);
  for (const float w : around(0.5f, 16)) CHECK(checker.factor({0.01f, 0.01f, w}) == above);
  // grid:4 (line half-width 0.04 of a period): on the line x = 0, the edge p.z = 1 + 0.04 of
  // the line z = 1 gives the gap above it, the edge p.z = 1 - 0.04 the line above it.
  const Texture3D grid = parse_texture("grid:4");
  const float h = 0.5f * grid.line_width;
  REQUIRE(grid.factor({0.0f, 0.3f, 1.0f / 4.0f}) == grid.dark);
  REQUIRE(grid.factor({0.0f, 0.3f, 1.5f / 4.0f}) == 1.0f);
  for (const float w : around((1.0f + h) / 4.0f, 16)) CHECK(grid.factor({0.0f, 0.3f, w}) == 1.0f);
  for (const float w : around((1.0f - h) / 4.0f, 16))
    CHECK(grid.factor({0.0f, 0.3f, w}) == grid.dark);
  // An image volume repeated twice: at the repeat's wall w = 1/2 the first slice (the start of
  // the next repeat), not the last.
  Texture3D volume;
  volume.kind = Texture3D::Kind::Volume;
  volume.scale = 2.0f;
  auto slices = std::make_shared<ImageVolume>();
  slices->width = slices->height = 1;
  slices->depth = 2;
  slices->texels = {glm::vec3(0.0f), glm::vec3(1.0f)};
  volume.volume = slices;
  for (const float w : around(0.5f, 16))
    CHECK(volume.apply(glm::vec3(0.5f), {0.5f, 0.5f, w}).r == 0.0f);
}

TEST_CASE("a section on a checker's wall shows one side of it, without speckle",
          "[render][texture]") {
  // The tesseract cut at w = d is the same cube for every |d| < 1; on its faces the UVW's w is
  // (d + 1) / 2, so checker:8 has p.z = 4 + 4 d: d = 0 lies exactly on a wall, d = 1e-4 is
  // 4e-4 of a period above it (a hundred times the interpolation rounding of ~1e-6 |p|),
  // where floor() is unambiguous and the faces show the cells above the wall. The same
  // geometry and camera: the two pictures must be the same, pixel for pixel, anti-aliased
  // outline included (no pixel differs by more than rounding in the last bit of a color).
  const Eigen::VectorXd n = vec({0, 0, 0, 1});
  const Image on = textured_tesseract(n, 0.0, "checker:8");
  const Image above = textured_tesseract(n, 1e-4, "checker:8");
  const Image below = textured_tesseract(n, -0.01, "checker:8");  // p.z = 3.96: cells below
  const Image plain = textured_tesseract(n, 0.0, "");
  const float dark = parse_texture("checker:8").dark;
  std::size_t covered = 0, differ = 0, differ_below = 0;
  for (std::size_t i = 0; i < on.pixels.size(); ++i) {
    if (on.pixels[i].a <= 0.0f && above.pixels[i].a <= 0.0f) continue;
    ++covered;
    if (glm::length(on.pixels[i] - above.pixels[i]) > 1e-5f) ++differ;
    if (glm::length(on.pixels[i] - below.pixels[i]) > 0.02f) ++differ_below;
  }
  const std::vector<int> cls = check_classes(on, plain, dark);
  const Speckle sp = speckle(cls, on.width, on.height);
  const Speckle sp_above = speckle(check_classes(above, plain, dark), on.width, on.height);
  const auto light = static_cast<std::size_t>(std::count(cls.begin(), cls.end(), 1));
  const auto shaded = static_cast<std::size_t>(std::count(cls.begin(), cls.end(), 0));
  CAPTURE(covered, differ, differ_below, sp.interior, sp.isolated, sp_above.isolated, light,
          shaded);
  REQUIRE(covered > 10000);
  CHECK(differ == 0);
  // The oracle sees the side: just below the wall every check swaps its colour.
  CHECK(differ_below > covered / 2);
  // No salt and pepper: no more pixels of one side surrounded by the other than off the wall
  // (a few, where the narrow checks of the face seen at a grazing angle meet at a corner),
  // where random sides would isolate about one pixel in sixteen; both check colours show.
  CHECK(sp.interior > covered / 2);
  CHECK(sp.isolated <= sp_above.isolated);
  CHECK(sp_above.isolated <= sp_above.interior / 1000);
  CHECK(light > covered / 5);
  CHECK(shaded > covered / 5);
}

TEST_CASE("a section crossing a checker's walls keeps them", "[render][texture]") {
  // Tilted by 0.3 in z, the hyperplane 0.3 z + w = 0.05 |n| crosses the checker:8 walls of
  // the w layers, p_w = 4 (w + 1) = 4, 5, on the cube's faces as well as the walls of y and z:
  // both colours show, nothing speckles, and down the face x = 1 (seen face-on, the column
  // y = 0.13) the colour changes exactly where the analytic parity
  // floor(4 (y + 1)) + floor(4 (z + 1)) + floor(4 (w + 1)) does, w walls included.
  const Eigen::VectorXd n = vec({0, 0, 0.3, 1}).normalized();
  const double d = 0.05;
  const Image img = textured_tesseract(n, d, "checker:8");
  const Image plain = textured_tesseract(n, d, "");
  const std::vector<int> cls = check_classes(img, plain, parse_texture("checker:8").dark);
  const Speckle sp = speckle(cls, img.width, img.height);
  const auto light = static_cast<std::size_t>(std::count(cls.begin(), cls.end(), 1));
  const auto shaded = static_cast<std::size_t>(std::count(cls.begin(), cls.end(), 0));
  CAPTURE(light, shaded, sp.interior, sp.isolated);
  REQUIRE(sp.interior > 10000);
  CHECK(light > sp.interior / 5);
  CHECK(shaded > sp.interior / 5);
  CHECK(sp.isolated <= sp.interior / 1000);  // grazing narrow checks meet at corners, as above

  const Complex tesseract = make_cube(4);
  const Scene scene = scene_of(tesseract, AffineTransform(4));
  const Section s = section(tesseract, Hyperplane::from(n, d));
  SectionViewOptions o;
  o.raster.width = o.raster.height = 480;
  o.raster.samples_per_axis = 1;
  o.source = &scene;
  add_texture(o.textures, "checker:8");
  const Camera cam = ortho_camera(s, vec({1, 0, 0, 0}), vec({0, 0, 1, 0}), 2.4f);
  const View view = cam.view(1.0f);
  const Image face = render_section(s, o, cam, nullptr, false);
  const double y = 0.13;
  auto w_at = [&](double z) { return (d - n(2) * z) / n(3); };
  auto screen = [&](double z) {
    const glm::vec4 c =
        view.clip_from_world * glm::vec4(to_glm(s.frame.to_plane(vec({1, y, z, w_at(z)}))), 1.0f);
    return glm::vec2((c.x / c.w * 0.5 + 0.5) * face.width, (0.5 - 0.5 * c.y / c.w) * face.height);
  };
  const int column = static_cast<int>(screen(0.0).x);
  std::vector<glm::vec4> pixels;
  for (int r = 0; r < face.height; ++r) pixels.push_back(face.at(column, r));
  const std::vector<int> found = transitions(pixels);
  // The analytic changes of parity along z, to 1e-6.
  auto parity = [&](double z) {
    return static_cast<long>(std::floor(4 * (y + 1)) + std::floor(4 * (z + 1)) +
                             std::floor(4 * (w_at(z) + 1))) &
           1;
  };
  std::vector<double> expected;
  int w_walls = 0;
  const int steps = 2000000;
  for (int k = 1; k < steps; ++k) {
    const double z0 = -1.0 + 2.0 * (k - 1) / steps, z1 = -1.0 + 2.0 * k / steps;
    if (parity(z0) == parity(z1)) continue;
    expected.push_back(screen(0.5 * (z0 + z1)).y);
    if (std::floor(4 * (w_at(z0) + 1)) != std::floor(4 * (w_at(z1) + 1))) ++w_walls;
  }
  std::sort(expected.begin(), expected.end());
  CAPTURE(column, found, expected, w_walls);
  REQUIRE(w_walls == 2);  // p_w = 4 and 5 (z = 0.174 and -0.659), apart from the z walls
  REQUIRE(found.size() == expected.size());
  for (std::size_t k = 0; k < found.size(); ++k) CHECK(std::abs(found[k] - expected[k]) <= 1.0);
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

namespace {

// Mean |second difference| of the luminance over white, along y (vertical = true) or x, inside
// the box where `mask` is well covered (shrunk by 3 pixels): the energy of stripes across that
// direction, gaps between layers included.
double stripe_energy(const Image& img, const Image& mask, bool vertical) {
  int x0 = img.width, x1 = -1, y0 = img.height, y1 = -1;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (mask.at(x, y).a > 0.3f) {
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
        y0 = std::min(y0, y);
        y1 = std::max(y1, y);
      }
  auto lum = [&](int x, int y) {
    const glm::vec4 p = img.at(x, y);
    return luminance(p) + 3.0f * (1.0f - p.a);
  };
  double sum = 0.0;
  std::size_t n = 0;
  for (int y = y0 + 3; y <= y1 - 3; ++y)
    for (int x = x0 + 3; x <= x1 - 3; ++x) {
      const float a = vertical ? lum(x, y - 1) : lum(x - 1, y);
      const float c = vertical ? lum(x, y + 1) : lum(x + 1, y);
      sum += std::abs(a - 2.0f * lum(x, y) + c);
      ++n;
    }
  return n ? sum / static_cast<double>(n) : 0.0;
}

}  // namespace

TEST_CASE("a voxel cloud seen at a grazing angle shows no layer stripes", "[render][cloud]") {
  // Seen from (1, 0, 0.05) the s layers are edge-on: stacked along s they make horizontal
  // stripes (s is the picture's vertical); stacked along u, the axis the view follows, none.
  Scene scene = scene_of(make_cube(4), AffineTransform::rotation(4, 0, 3, 0.35) *
                                           AffineTransform::rotation(4, 1, 2, 0.3));
  scene.objects[0].color = Rgba{0.3f, 0.6f, 0.9f, 0.6f};
  CloudOptions o;
  o.raster.width = 240;
  o.raster.height = 200;
  o.raster.samples_per_axis = 1;
  o.layers = 24;
  o.view_from = glm::vec3(1.0f, 0.0f, 0.05f);
  o.flatten = false;
  const Eigen::VectorXd n = vec({0, 0, 1, 1}).normalized();
  CHECK(cloud_stack_axis(o.view_from) == 0);
  const Image follow = render_voxel_cloud(scene, n, o);
  o.stack_axis = 2;
  const Image fixed = render_voxel_cloud(scene, n, o);
  const double follow_v = stripe_energy(follow, follow, true);
  const double follow_h = stripe_energy(follow, follow, false);
  const double fixed_v = stripe_energy(fixed, follow, true);
  CAPTURE(follow_v, follow_h, fixed_v);
  CHECK(fixed_v > 4.0 * follow_v);          // the metric sees the edge-on layers
  CHECK(follow_v < 2.0 * follow_h + 1e-3);  // no direction of stripes stands out
  // The opacity follows the actual spacing: four times the layers, the same cloud.
  o.stack_axis = -1;
  o.layers = 96;
  const Image fine = render_voxel_cloud(scene, n, o);
  CHECK(fine.coverage() == Approx(follow.coverage()).epsilon(0.03));
}

TEST_CASE("stereo pairs of clouds and wireframes: two views, the same with no angle",
          "[render][stereo]") {
  Scene scene = scene_of(make_orthoplex(4), AffineTransform::rotation(4, 0, 3, 0.3));
  scene.objects[0].color = Rgba{0.8f, 0.4f, 0.2f, 0.7f};
  CloudOptions co;
  co.raster.width = 96;
  co.raster.height = 72;
  co.raster.samples_per_axis = 1;
  co.layers = 12;
  const Eigen::VectorXd n = vec({0, 0, 0, 1});
  const Image single = render_voxel_cloud(scene, n, co);
  WireframeOptions wo;
  wo.raster = co.raster;
  const Camera4 cam = frame_scene(scene, vec({0.3, 0.2, 0.1, -1}));
  const Image wire = render_wireframe(scene, cam, wo);
  auto half = [](const Image& pair, int side) {
    Image h(pair.width / 2, pair.height);
    for (int y = 0; y < h.height; ++y)
      for (int x = 0; x < h.width; ++x) h.at(x, y) = pair.at(x + side * h.width, y);
    return h;
  };
  auto same = [](const Image& a, const Image& b) { return a.pixels == b.pixels; };
  const Image c0 = render_cloud_stereo_pair(scene, n, co, 0.0f);
  const Image w0 = render_wireframe_stereo_pair(scene, cam, wo, 0.0f);
  REQUIRE(c0.width == 2 * co.raster.width);
  CHECK(same(half(c0, 0), single));
  CHECK(same(half(c0, 1), single));
  CHECK(same(half(w0, 0), wire));
  CHECK(same(half(w0, 1), wire));
  const Image c6 = render_cloud_stereo_pair(scene, n, co, 6.0f);
  const Image w6 = render_wireframe_stereo_pair(scene, cam, wo, 6.0f);
  CHECK_FALSE(same(half(c6, 0), half(c6, 1)));
  CHECK_FALSE(same(half(w6, 0), half(w6, 1)));
}

TEST_CASE("a wireframe with its section draws the section where its corners project",
          "[render][wireframe]") {
  const Complex model = make_orthoplex(4);
  const Scene scene = scene_of(model, AffineTransform::rotation(4, 1, 3, 0.4));
  const Section s =
      section(model, Hyperplane::from(vec({0, 0, 0, 1}), 0.2), scene.objects[0].transform);
  REQUIRE_FALSE(s.empty());
  const Camera4 cam = frame_scene(scene, vec({0.3, 0.2, 0.1, -1}));
  WireframeOptions wo;
  wo.raster.width = 200;
  wo.raster.height = 160;
  wo.raster.samples_per_axis = 1;
  const Image plain = render_wireframe(scene, cam, wo);
  wo.section = &s;
  const Image with = render_wireframe(scene, cam, wo);
  // The screen box of the section's corners, through the 4D camera and the retina's 3D camera.
  const Camera cam3 = Camera::framing(glm::vec3(0.0f), std::sqrt(3.0f), wo.view_from, 200.0f / 160,
                                      wo.projection, 30.0f, 1.02f, glm::vec3(0, 1, 0));
  const View view = cam3.view(200.0f / 160);
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (std::uint32_t v = 0; v < s.complex.count(0); ++v) {
    const Eigen::VectorXd r = cam.project(s.world_position(v));
    const glm::vec4 c = view.clip_from_world * glm::vec4(r(0), r(1), r(2), 1.0f);
    const double px = (c.x / c.w * 0.5 + 0.5) * 200, py = (0.5 - 0.5 * c.y / c.w) * 160;
    x0 = std::min(x0, px), x1 = std::max(x1, px), y0 = std::min(y0, py), y1 = std::max(y1, py);
  }
  std::size_t changed = 0, outside = 0;
  for (int y = 0; y < 160; ++y)
    for (int x = 0; x < 200; ++x) {
      if (glm::length(with.at(x, y) - plain.at(x, y)) < 1e-4f) continue;
      ++changed;
      if (x + 1 < x0 || x > x1 + 1 || y + 1 < y0 || y > y1 + 1) ++outside;
    }
  CAPTURE(changed, outside, x0, x1, y0, y1);
  CHECK(changed > 0.3 * (x1 - x0) * (y1 - y0));
  CHECK(outside == 0);
}

TEST_CASE("animated WebP: libwebp's decoder reads back every frame", "[render][animation]") {
  // Three lossless frames of distinct patterns; the demux library (a separate decoder) must
  // return them exactly, with the frame times.
  std::vector<Image8> frames;
  for (int f = 0; f < 3; ++f) {
    Image8 img;
    img.width = 17;
    img.height = 11;
    img.channels = 3;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x)
        for (int c = 0; c < 3; ++c)
          img.bytes.push_back(static_cast<std::uint8_t>((x * 13 + y * 7 + c * 50 + f * 90) % 256));
    frames.push_back(img);
  }
  AnimationOptions ao;
  ao.lossless = true;
  ao.frame_ms = 120;
  const std::string bytes = encode_webp_animation(frames, ao);
  WebPData data{reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()};
  WebPAnimDecoderOptions dopt;
  REQUIRE(WebPAnimDecoderOptionsInit(&dopt));
  dopt.color_mode = MODE_RGBA;
  WebPAnimDecoder* dec = WebPAnimDecoderNew(&data, &dopt);
  REQUIRE(dec != nullptr);
  WebPAnimInfo info;
  REQUIRE(WebPAnimDecoderGetInfo(dec, &info));
  CHECK(info.canvas_width == 17);
  CHECK(info.canvas_height == 11);
  CHECK(info.frame_count == 3);
  int f = 0;
  while (WebPAnimDecoderHasMoreFrames(dec)) {
    std::uint8_t* rgba = nullptr;
    int timestamp = 0;
    REQUIRE(WebPAnimDecoderGetNext(dec, &rgba, &timestamp));
    REQUIRE(f < 3);
    CHECK(timestamp == 120 * (f + 1));
    std::size_t wrong = 0;
    for (int i = 0; i < 17 * 11; ++i)
      for (int c = 0; c < 3; ++c)
        if (rgba[4 * i + c] != frames[f].bytes[3 * i + c]) ++wrong;
    CHECK(wrong == 0);
    ++f;
  }
  CHECK(f == 3);
  WebPAnimDecoderDelete(dec);
  // Bad input is refused before anything is encoded.
  CHECK_THROWS_AS(encode_webp_animation({}), InputError);
  frames[1].width = 16;
  CHECK_THROWS_AS(encode_webp_animation(frames), InputError);
}

namespace {

struct GifReader {
  const std::string& bytes;
  std::size_t at = 0;
};

int read_gif_bytes(GifFileType* gif, GifByteType* out, int n) {
  auto* r = static_cast<GifReader*>(gif->UserData);
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(n), r->bytes.size() - r->at);
  std::memcpy(out, r->bytes.data() + r->at, k);
  r->at += k;
  return static_cast<int>(k);
}

}  // namespace

TEST_CASE("animated GIF: giflib's decoder reads back every frame", "[render][animation]") {
  // Three frames of a few colors each whose channels are multiples of 8 (what the median cut
  // keeps exactly): the decoder must return every pixel, the frame time (in hundredths of a
  // second) and the NETSCAPE2.0 loop block (0: forever).
  const std::uint8_t levels[] = {0, 64, 128, 192, 248};
  std::vector<Image8> frames;
  for (int f = 0; f < 3; ++f) {
    Image8 img;
    img.width = 17;
    img.height = 11;
    img.channels = f == 2 ? 4 : 3;  // alpha is dropped
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        for (int c = 0; c < 3; ++c) img.bytes.push_back(levels[(x / 3 + y / 2 + c + f) % 5]);
        if (img.channels == 4) img.bytes.push_back(static_cast<std::uint8_t>(x * 15));
      }
    frames.push_back(img);
  }
  AnimationOptions ao;
  ao.frame_ms = 120;
  const std::string bytes = encode_gif_animation(frames, ao);
  REQUIRE(bytes.substr(0, 6) == "GIF89a");
  GifReader reader{bytes};
  int error = 0;
  GifFileType* gif = DGifOpen(&reader, read_gif_bytes, &error);
  REQUIRE(gif != nullptr);
  REQUIRE(DGifSlurp(gif) == GIF_OK);
  CHECK(gif->SWidth == 17);
  CHECK(gif->SHeight == 11);
  REQUIRE(gif->ImageCount == 3);
  bool loop_forever = false;
  for (int f = 0; f < 3; ++f) {
    const SavedImage& im = gif->SavedImages[f];
    REQUIRE(im.ImageDesc.Width == 17);
    REQUIRE(im.ImageDesc.Height == 11);
    const ColorMapObject* map = im.ImageDesc.ColorMap ? im.ImageDesc.ColorMap : gif->SColorMap;
    REQUIRE(map != nullptr);
    GraphicsControlBlock gcb;
    REQUIRE(DGifSavedExtensionToGCB(gif, f, &gcb) == GIF_OK);
    CHECK(gcb.DelayTime == 12);
    for (int e = 0; e + 1 < im.ExtensionBlockCount; ++e)
      if (im.ExtensionBlocks[e].Function == APPLICATION_EXT_FUNC_CODE &&
          im.ExtensionBlocks[e].ByteCount == 11 &&
          std::memcmp(im.ExtensionBlocks[e].Bytes, "NETSCAPE2.0", 11) == 0) {
        const ExtensionBlock& next = im.ExtensionBlocks[e + 1];
        loop_forever =
            next.ByteCount == 3 && next.Bytes[0] == 1 && next.Bytes[1] == 0 && next.Bytes[2] == 0;
      }
    std::size_t wrong = 0;
    const Image8& want = frames[static_cast<std::size_t>(f)];
    for (int i = 0; i < 17 * 11; ++i) {
      const GifColorType c = map->Colors[im.RasterBits[i]];
      const std::uint8_t* p = &want.bytes[static_cast<std::size_t>(i) * want.channels];
      wrong += c.Red != p[0] || c.Green != p[1] || c.Blue != p[2];
    }
    CHECK(wrong == 0);
  }
  CHECK(loop_forever);
  DGifCloseFile(gif, &error);
  CHECK_THROWS_AS(encode_gif_animation({}), InputError);
  frames[1].width = 16;
  CHECK_THROWS_AS(encode_gif_animation(frames), InputError);
}

TEST_CASE("bounding-sphere pre-tests leave the visible edges of a crowded scene unchanged",
          "[render][occlusion]") {
  // 120 small polytopes scattered in a box (seeded), seen from outside and from inside one:
  // the pre-tests only skip occluders that cannot hide anything, so the segments are the same
  // as with every occluder tried.
  std::mt19937 rng(1234);
  std::uniform_real_distribution<double> pos(-6.0, 6.0), size(0.2, 0.7), angle(0.0, 3.0);
  auto cube = std::make_shared<const Complex>(make_cube(4));
  auto cross = std::make_shared<const Complex>(make_orthoplex(4));
  Scene scene;
  for (int i = 0; i < 120; ++i) {
    SceneObject o;
    o.model = "test";
    o.complex = i % 2 ? cube : cross;
    o.transform = AffineTransform::translation(vec({pos(rng), pos(rng), pos(rng), pos(rng)})) *
                  AffineTransform::rotation(4, i % 4, (i + 1) % 4, angle(rng)) *
                  AffineTransform::scale(4, size(rng));
    scene.objects.push_back(o);
  }
  const Eigen::VectorXd inside = scene.objects[0].transform.translation();
  for (const Camera4& cam : {frame_scene(scene, vec({0.3, 0.2, 0.1, -1})),
                             Camera4::look_at(inside, inside + vec({0, 0, 0, 1}), 120.0)}) {
    const auto fast = visible_edges(scene, cam, true, render::tol::shadow_margin_rel, true);
    const auto full = visible_edges(scene, cam, true, render::tol::shadow_margin_rel, false);
    REQUIRE(fast.size() == full.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < fast.size(); ++i) {
      CHECK(fast[i].object == full[i].object);
      CHECK(fast[i].edge == full[i].edge);
      worst =
          std::max(worst, std::max((fast[i].a - full[i].a).norm(), (fast[i].b - full[i].b).norm()));
    }
    CHECK(worst < 1e-12);
    // Something is hidden, something is shown: the scene does exercise the culling.
    const auto none = visible_edges(scene, cam, false);
    double shown = 0.0, all = 0.0;
    for (const auto& s : fast) shown += (s.b - s.a).norm();
    for (const auto& s : none) all += (s.b - s.a).norm();
    CAPTURE(shown, all);
    CHECK(shown > 0.0);
    CHECK(shown < 0.99 * all);
  }
}

namespace {

// The CRC-32 of PNG chunks (ISO 3309), bit by bit: independent of the reader under test.
std::uint32_t crc32_of(const std::string& bytes) {
  std::uint32_t c = 0xffffffffu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
  }
  return c ^ 0xffffffffu;
}

std::string be32(std::uint32_t v) {
  return {static_cast<char>(v >> 24), static_cast<char>(v >> 16), static_cast<char>(v >> 8),
          static_cast<char>(v)};
}

std::string chunk(const std::string& type, const std::string& data) {
  return be32(static_cast<std::uint32_t>(data.size())) + type + data + be32(crc32_of(type + data));
}

// A valid PNG header declaring width x height gray pixels, with one small IDAT (a zlib stream
// of a few stored zero bytes) and IEND: a "bomb" of a few dozen bytes.
std::string png_bomb(std::uint32_t width, std::uint32_t height) {
  const std::string sig = "\x89PNG\r\n\x1a\n";
  const std::string ihdr = be32(width) + be32(height) + std::string("\x08\x00\x00\x00\x00", 5);
  // zlib: header 78 01, one final stored block of 6 zero bytes (a 2 x 2 picture's rows with
  // their filter bytes), their Adler-32 (6 << 16 | 1).
  const std::string idat("\x78\x01\x01\x06\x00\xf9\xff\x00\x00\x00\x00\x00\x00\x00\x06\x00\x01",
                         17);
  return sig + chunk("IHDR", ihdr) + chunk("IDAT", idat) + chunk("IEND", "");
}

}  // namespace

TEST_CASE("slice patterns are parsed, never handed to printf", "[render][texture]") {
  const SlicePattern a = parse_slice_pattern("slices/z%03d.png");
  CHECK(a.path(7) == "slices/z007.png");
  CHECK(a.path(1234) == "slices/z1234.png");
  CHECK(parse_slice_pattern("%d").path(42) == "42");
  CHECK(parse_slice_pattern("100%%/s%d_%%.png").path(3) == "100%/s3_%.png");
  CHECK(parse_slice_pattern("a%09db").path(5) == "a000000005b");
  for (const char* bad : {"%nd", "%s%d", "a%d%d", "%x", "%", "a%", "%0d", "%010d", "%00d", "%5d",
                          "%ld", "no number", "%%d", "%-3d", "%*d"}) {
    CAPTURE(bad);
    try {
      parse_slice_pattern(bad);
      FAIL("accepted");
    } catch (const InputError& e) {
      const std::string what = e.what();
      CHECK(what.find(std::string("'") + bad + "'") != std::string::npos);
      CHECK(what.find('\n') == std::string::npos);
    }
  }
  // Through the texture spec: a pattern that printf would crash on is a usage error.
  CHECK_THROWS_AS(parse_texture("volume:%nd"), InputError);
  CHECK_THROWS_AS(parse_texture("volume:%s%s%s%s%d"), InputError);
}

TEST_CASE("PNG reads are bounded: regular files, bytes and texels", "[render][texture]") {
  cw4d::test::TempDir dir("cw4d_test_render_png");
  // A FIFO nobody writes to: refused at once, not waited on.
  const std::string fifo = (dir / "fifo.png").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_THROWS_AS(read_png(fifo), ParseError);
  // /dev/zero through a link: not a regular file, nothing read.
  std::filesystem::create_symlink("/dev/zero", dir / "zero.png");
  CHECK_THROWS_AS(read_png((dir / "zero.png").string()), ParseError);
  // A sparse file beyond the byte budget: refused from its size, before reading.
  { std::ofstream(dir / "big.png").put('x'); }
  std::filesystem::resize_file(dir / "big.png", max_png_file_bytes + 1);
  CHECK_THROWS_AS(read_png((dir / "big.png").string()), ParseError);
  // Bombs: a few dozen bytes declaring 100000 x 100000 (and 20000 x 20000, which stb_image's
  // own limit lets through) are refused from the header, naming the dimensions.
  for (const std::uint32_t side : {100000u, 20000u}) {
    const std::string bomb = png_bomb(side, side);
    CHECK(bomb.size() < 100);
    const auto header =
        png_header({reinterpret_cast<const unsigned char*>(bomb.data()), bomb.size()});
    REQUIRE(header);
    CHECK(header->width == static_cast<int>(side));
    CHECK(header->channels == 1);
    dir.write("bomb.png", bomb);
    try {
      read_png((dir / "bomb.png").string());
      FAIL("decoded");
    } catch (const ParseError& e) {
      CHECK(std::string(e.what()).find(std::to_string(side) + "x" + std::to_string(side)) !=
            std::string::npos);
    }
  }
  // The same construction at a small size is a readable PNG (the test's bytes are valid).
  const std::string small = png_bomb(2, 2);
  const Image8 img =
      decode_png({reinterpret_cast<const unsigned char*>(small.data()), small.size()});
  CHECK(img.width == 2);
  CHECK(img.height == 2);
  CHECK(img.bytes == std::vector<std::uint8_t>(4, 0));
  // An empty IDAT chunk is legal and changes nothing (stb_image alone would copy its zero
  // bytes from a null buffer: the sanitizer build reports that).
  const std::size_t idat = small.find("IDAT") - 4;
  const std::string with_empty = small.substr(0, idat) + chunk("IDAT", "") + small.substr(idat);
  const Image8 same =
      decode_png({reinterpret_cast<const unsigned char*>(with_empty.data()), with_empty.size()});
  CHECK(same.width == 2);
  CHECK(same.bytes == img.bytes);
  // Cut short after an empty IDAT's header (its CRC incomplete): refused as unreadable.
  const std::string cut = small.substr(0, idat) + chunk("IDAT", "").substr(0, 11);
  CHECK_THROWS_AS(decode_png({reinterpret_cast<const unsigned char*>(cut.data()), cut.size()}),
                  ParseError);
  // An image volume: a FIFO slice is refused (not a hang, not the volume's end).
  std::filesystem::rename(fifo, dir / "f0.png");
  CHECK_THROWS_AS(parse_texture("volume:" + (dir / "f%d.png").string()), ParseError);
  // 6000 x 6000 is within one PNG's budget (2^26) but beyond the volume's (2^25): refused
  // from the header, where decoding would fail (the stream holds too few bytes).
  const std::string slice = png_bomb(6000, 6000);
  for (int k = 0; k < 3; ++k) dir.write("v" + std::to_string(k) + ".png", slice);
  try {
    parse_texture("volume:" + (dir / "v%d.png").string());
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("v0.png") != std::string::npos);
    CHECK(std::string(e.what()).find("6000x6000") != std::string::npos);
  }
}

TEST_CASE("an animation is encoded frame by frame", "[render][animation]") {
  // The streaming encoder gives the same file as the one taking all frames, in both formats.
  std::vector<Image8> frames;
  for (int f = 0; f < 3; ++f) {
    Image8 img;
    img.width = 9;
    img.height = 5;
    for (int i = 0; i < 9 * 5 * 3; ++i) img.bytes.push_back(static_cast<std::uint8_t>(i * 7 + f));
    frames.push_back(img);
  }
  for (const auto format : {AnimationEncoder::Format::WebP, AnimationEncoder::Format::Gif}) {
    AnimationEncoder enc(format, 9, 5);
    for (const auto& f : frames) enc.add(f);
    CHECK(enc.frames() == 3);
    const std::string streamed = enc.finish();
    CHECK(streamed == (format == AnimationEncoder::Format::Gif ? encode_gif_animation(frames)
                                                               : encode_webp_animation(frames)));
    AnimationEncoder other(format, 8, 5);
    CHECK_THROWS_AS(other.add(frames[0]), InputError);
    CHECK_THROWS_AS(other.finish(), InputError);
  }
}
