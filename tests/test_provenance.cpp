// A section's provenance against the model a reader is given: ids out of the model's range and
// models of another shape are refused (InputError) before any array is indexed, and the right
// model (or a moved copy of it) is accepted. Run under ASan or valgrind, the refused cases read
// nothing out of bounds.
#include <catch2/catch.hpp>

#include <memory>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/placement.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/export/mesh.hpp"
#include "cw4d/export/obj.hpp"
#include "cw4d/render/color.hpp"
#include "cw4d/render/section_view.hpp"
#include "cw4d/section/provenance.hpp"
#include "cw4d/section/scene_section.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"
#include "cw4d/section/uvw.hpp"

using namespace cw4d;
using Catch::Matchers::Contains;
using Catch::Matchers::Equals;

namespace {

// A generic plane that cuts every model below through many cells.
Hyperplane plane() {
  return Hyperplane::from(Eigen::Vector4d(0.3, -0.2, 0.5, 1.0), 0.1);
}

// The model with a distinct color per 3-cell (what the renderer reads through the provenance).
Complex colored(const std::string& spec) {
  Complex c = load_model(spec);
  auto& colors = c.colors_mut(3);
  colors.assign(c.count(3), Rgba{});
  for (std::size_t i = 0; i < colors.size(); ++i)
    colors[i] = Rgba{static_cast<float>(i % 7) / 7.0f, static_cast<float>(i % 5) / 5.0f,
                     static_cast<float>(i % 3) / 3.0f, 1.0f};
  return c;
}

// The largest cell id of the section's faces: the independent account of what a reader indexes.
std::uint32_t max_cell(const Section& s) {
  std::uint32_t m = 0;
  for (std::uint32_t c : s.source[2]) m = std::max(m, c);
  return m;
}

}  // namespace

TEST_CASE("provenance: ids beyond the model are refused by every reader", "[provenance]") {
  const Complex big = colored("120-cell");
  const Complex small = colored("tesseract");  // 8 cells, 32 edges, 16 vertices
  Section s = section(big, plane());
  REQUIRE(s.complex.count(2) > 0);
  REQUIRE(max_cell(s) >= small.count(3));  // ids a reader would read beyond the small model
  // Without its fingerprint (a section built by hand), the ids alone give it away.
  s.source_fingerprint = 0;
  // (A composed Catch2 v2 matcher kept in a variable would hold dangling references.)
  const auto refused = Contains("the section was not cut from this model (");
  CHECK_THROWS_AS(check_provenance(s, small), InputError);
  CHECK_THROWS_WITH(check_provenance(s, small), refused);
  CHECK_THROWS_WITH(section_uvw(s, {&small}), refused);
  CHECK_THROWS_WITH(render::section_mesh(s, &small), refused);
  render::SectionViewOptions o;
  o.raster.width = 32;
  o.raster.height = 24;
  CHECK_THROWS_WITH(render::render_section(s, o, &small), refused);
  Scene scene;
  scene.objects.push_back({"tesseract",
                           std::make_shared<const Complex>(small),
                           AffineTransform::identity(4),
                           Rgba{},
                           {},
                           ""});
  o.source = &scene;
  o.light_4d = true;
  CHECK_THROWS_WITH(render::render_section(s, o, nullptr), refused);
  // The message names the first id out of range and the model's count of that rank.
  Section cells_only = s;
  cells_only.vertex_source.clear();  // (then not checked: no reader can use them)
  std::uint32_t first = 0;
  for (std::uint32_t c : s.source[2])
    if (c >= small.count(3)) {
      first = c;
      break;
    }
  CHECK_THROWS_WITH(check_provenance(cells_only, small),
                    Equals("the section was not cut from this model (cell id " +
                           std::to_string(first) + " >= 8 cells)"));
  // The right model passes, and the renderer's colors are the model's through the provenance.
  CHECK_NOTHROW(check_provenance(s, big));
  const render::TriangleMesh mesh = render::section_mesh(s, &big);
  std::size_t v = 0;
  for (std::uint32_t f = 0; f < s.complex.count(2); ++f)
    for (std::size_t j = 0; j < s.complex.face_cycle(f).size(); ++j, ++v)
      REQUIRE(mesh.vertices[v].color == render::to_linear(big.colors(3)[s.source[2][f]]));
}

TEST_CASE("provenance: a model of another shape is refused by its fingerprint", "[provenance]") {
  const Complex tesseract = colored("tesseract");
  const Complex cell24 = colored("24-cell");
  const Section s = section(tesseract, plane());
  REQUIRE(s.complex.count(2) > 0);
  // Every id of this section is in range for the 24-cell (24 vertices, 96 edges, 96 faces, 24
  // cells against the tesseract's 16, 32, 24, 8): only the fingerprint tells them apart.
  Section unmarked = s;
  unmarked.source_fingerprint = 0;
  CHECK_NOTHROW(check_provenance(unmarked, cell24));
  REQUIRE(s.source_fingerprint == model_fingerprint(tesseract));
  const auto refused = Equals(
      "the section was not cut from this model (its f-vector (24, 96, 96, 24) is not the one "
      "of the section's source)");
  CHECK_THROWS_WITH(check_provenance(s, cell24), refused);
  CHECK_THROWS_WITH(section_uvw(s, {&cell24}), refused);
  CHECK_THROWS_WITH(render::section_mesh(s, &cell24), refused);
  // The model itself and a moved copy (same shape) are accepted, by every path that cuts.
  const Complex moved = transformed(tesseract, AffineTransform::rotation(4, 0, 3, 0.4));
  CHECK_NOTHROW(check_provenance(s, tesseract));
  CHECK_NOTHROW(check_provenance(s, moved));
  CHECK_NOTHROW(section_uvw(s, {&tesseract}));
  CHECK(section_general(tesseract, plane(), AffineTransform::identity(4)).source_fingerprint ==
        model_fingerprint(tesseract));
  const SliceModel sm(cell24);
  Slicer slicer;
  SliceBuffers b;
  slicer.slice(sm, plane(), b);
  CHECK(to_section(b).source_fingerprint == model_fingerprint(cell24));
  std::vector<SliceBuffers> layers;
  slicer.sweep(sm, plane().normal, std::vector<double>{-0.5, 0.0, 0.5},
               AffineTransform::identity(4), layers);
  for (const SliceBuffers& layer : layers)
    CHECK(to_section(layer).source_fingerprint == model_fingerprint(cell24));
  CHECK_THROWS_WITH(section_uvw(to_section(layers[1]), {&tesseract}),
                    Contains("the section was not cut from this model"));
}

TEST_CASE("provenance: a scene section needs the models of its scene, in order", "[provenance]") {
  Scene scene;
  const auto add = [&](const std::string& spec, double x) {
    scene.objects.push_back({spec,
                             std::make_shared<const Complex>(load_model(spec)),
                             AffineTransform::translation(Eigen::Vector4d(x, 0, 0, 0)),
                             Rgba{},
                             {},
                             ""});
  };
  add("24-cell", -2.0);
  add("tesseract", 2.0);
  const Section s = section_scene(scene, plane());
  REQUIRE(s.object_of_face.size() == s.complex.count(2));
  const std::vector<const Complex*> right{scene.objects[0].complex.get(),
                                          scene.objects[1].complex.get()};
  const std::vector<const Complex*> swapped{right[1], right[0]};
  CHECK_NOTHROW(check_provenance(s, right));
  CHECK_NOTHROW(section_uvw(s, right));
  CHECK_THROWS_WITH(section_uvw(s, swapped), Contains("the section was not cut from these 2"));
  // Without the fingerprint: the 24-cell's ids checked against the tesseract, object by object.
  Section unmarked = s;
  unmarked.source_fingerprint = 0;
  CHECK_THROWS_WITH(check_provenance(unmarked, swapped),
                    Contains("the section was not cut from this scene (object 0: "));
  CHECK_THROWS_WITH(check_provenance(unmarked, {right[0]}),
                    Equals("the section was not cut from this scene (object id 1 >= 1 objects)"));
  // The per-object sections carry their own model's fingerprint.
  const std::vector<Section> pieces = section_objects(scene, plane());
  CHECK_NOTHROW(check_provenance(pieces[1], *right[1]));
  CHECK_THROWS(check_provenance(pieces[1], *right[0]));
}

TEST_CASE("placement: the one check of where a model is cut", "[provenance][placement]") {
  const Complex m = load_model("tesseract");
  const AffineTransform id = AffineTransform::identity(4);
  CHECK_NOTHROW(check_placement(m, id, "model 'tesseract'"));
  CHECK_NOTHROW(check_placement(m, AffineTransform::scale(4, 1e99), "m"));
  CHECK_NOTHROW(check_placement(m, AffineTransform::scale(4, 1e-99), "m"));
  CHECK_THROWS_WITH(check_placement(m, AffineTransform::scale(4, 1e300), "model 'tesseract'"),
                    Equals("model 'tesseract' has coordinates up to 1e+300 once placed: cw4d cuts "
                           "models within 1e100 of the origin (scale it down)"));
  CHECK_THROWS_WITH(check_placement(m, AffineTransform::scale(4, 0.0), "m"),
                    Equals("m spans only 0 once placed: cw4d cuts models at least 1e-100 across "
                           "(scale it up)"));
  CHECK_THROWS_WITH(
      check_placement(m, AffineTransform::translation(Eigen::Vector4d(0, 1e101, 0, 0)), "m"),
      Contains("has coordinates up to 1e+101"));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (double bad : {nan, inf, -inf}) {
    Eigen::Matrix4d a = Eigen::Matrix4d::Identity();
    a(1, 2) = bad;
    CHECK_THROWS_WITH(check_placement(m, AffineTransform(a, Eigen::Vector4d::Zero()), "m"),
                      Equals("m is placed by a transform with an entry that is not finite"));
    CHECK_THROWS_WITH(
        check_placement(m, AffineTransform::translation(Eigen::Vector4d(0, 0, bad, 0)), "m"),
        Equals("m is placed by a transform with an entry that is not finite"));
  }
  CHECK_THROWS_AS(check_placement(m, AffineTransform::identity(3), "m"), InputError);
  // Accepted placements are remembered by revision: a changed model is checked afresh.
  Complex c = m;
  const AffineTransform big = AffineTransform::scale(4, 1e98);
  CHECK_NOTHROW(check_placement(c, big, "c"));
  c.positions_mut() *= 1000.0;
  CHECK_THROWS_WITH(check_placement(c, big, "c"), Contains("c has coordinates up to 1e+101"));
}
