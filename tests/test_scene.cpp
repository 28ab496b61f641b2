// Scenes: reading JSON scene files (with file:line errors), cutting every object with one plane
// and merging the pieces, and the colors that follow the faces into OBJ+MTL, SVG and nOFF.
#include <unistd.h>
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/export/obj.hpp"
#include "cw4d/export/svg.hpp"
#include "cw4d/section/scene_section.hpp"
#include "cw4d/section/section.hpp"
#include "support/temp_dir.hpp"
#include "support/vectors.hpp"

using namespace cw4d;

namespace {

namespace fs = std::filesystem;

struct TempDir : cw4d::test::TempDir {
  TempDir() : cw4d::test::TempDir("cw4d_test_scene") {}
};

using cw4d::test::read_text;

Scene parse(const std::string& text, const std::string& base = {}) {
  std::istringstream in(text);
  return read_scene(in, "test.json", base);
}

using cw4d::test::radians;
using cw4d::test::vec;

bool same_transform(const AffineTransform& a, const AffineTransform& b) {
  return (a.linear() - b.linear()).norm() < 1e-12 &&
         (a.translation() - b.translation()).norm() < 1e-12;
}

Rgba rgb(float r, float g, float b, float a = 1.0f) {
  return {r, g, b, a};
}

// Two tesseracts (one model) placed apart, one with cell colors, and a 5-cell.
const char* kScene = R"({
  "objects": [
    {"model": "tesseract", "name": "left", "scale": 0.5,
     "rotate": [["xw", 30], ["yz", 15]], "translate": [-3, 0, 0, 0],
     "color": "#ff8000", "opacity": 0.5,
     "cell_colors": {"0": "#00ff00", "6": [0, 0, 1]}},
    {"model": "tesseract", "name": "right", "rotate": [["zw", -20]], "translate": [3, 0, 0, 0.2],
     "color": [0.25, 0.5, 1]},
    // comments are allowed
    {"model": "5-cell", "scale": [1, 2, 1, 1], "translate": [0, 4, 0, 0]}
  ]
})";

}  // namespace

TEST_CASE("a scene places, colors and shares its models", "[scene]") {
  const Scene scene = parse(kScene);
  REQUIRE(scene.objects.size() == 3);
  CHECK(scene.dim() == 4);
  const SceneObject& left = scene.objects[0];
  const SceneObject& right = scene.objects[1];
  const SceneObject& simplex = scene.objects[2];
  // The two tesseracts are one Complex.
  CHECK(left.complex.get() == right.complex.get());
  CHECK(left.complex.get() != simplex.complex.get());
  CHECK(left.complex->fvector() == std::vector<std::size_t>{16, 32, 24, 8});
  CHECK(left.name == "left");
  CHECK(simplex.name.empty());
  CHECK(left.model == "tesseract");

  // scale, then the rotations in order, then the translation
  const AffineTransform expect_left = AffineTransform::translation(vec({-3, 0, 0, 0})) *
                                      AffineTransform::rotation(4, 1, 2, radians(15)) *
                                      AffineTransform::rotation(4, 0, 3, radians(30)) *
                                      AffineTransform::scale(4, 0.5);
  CHECK(same_transform(left.transform, expect_left));
  CHECK(same_transform(simplex.transform, AffineTransform::translation(vec({0, 4, 0, 0})) *
                                              AffineTransform::scale(vec({1, 2, 1, 1}))));

  CHECK(left.color == rgb(1.0f, 128 / 255.0f, 0.0f, 0.5f));
  REQUIRE(left.cell_colors.size() == 2);
  CHECK(left.cell_colors.at(0) == rgb(0, 1, 0, 0.5f));
  CHECK(left.cell_colors.at(6) == rgb(0, 0, 1, 0.5f));
  CHECK(left.color_of_cell(6) == rgb(0, 0, 1, 0.5f));
  CHECK(left.color_of_cell(3) == left.color);
  CHECK(right.color == rgb(0.25f, 0.5f, 1.0f, 1.0f));
  CHECK(simplex.color == Rgba{});  // white, opaque
}

TEST_CASE("a scene's section is the union of its objects' sections, colored per object and cell",
          "[scene]") {
  const Scene scene = parse(kScene);
  for (const Hyperplane& plane :
       {Hyperplane::from(vec({0, 0, 0, 1}), 0.1), Hyperplane::from(vec({0.2, 0.1, -0.3, 1}), -0.5),
        Hyperplane::from(vec({0, 0, 0, 1}), 0.0)}) {
    INFO("plane " << plane.normal.transpose() << " d=" << plane.offset);
    const Section merged = section_scene(scene, plane);
    std::size_t faces = 0, vertices = 0, edges = 0;
    double volume = 0.0;
    std::vector<Section> separate;
    for (const SceneObject& obj : scene.objects) {
      separate.push_back(section(*obj.complex, plane, obj.transform));
      faces += separate.back().complex.count(2);
      edges += separate.back().complex.count(1);
      vertices += separate.back().complex.count(0);
      if (!separate.back().empty()) volume += signed_volume(separate.back().complex);
    }
    REQUIRE(faces > 0);
    CHECK(merged.complex.ambient_dim() == 3);
    CHECK(merged.complex.count(0) == vertices);
    CHECK(merged.complex.count(1) == edges);
    REQUIRE(merged.complex.count(2) == faces);
    CHECK(signed_volume(merged.complex) == Approx(volume).epsilon(1e-12));
    CHECK(validate(merged.complex).ok());  // disjoint closed surfaces
    REQUIRE(merged.object_of_face.size() == faces);
    REQUIRE(merged.source.size() > 2);
    REQUIRE(merged.source[2].size() == faces);
    REQUIRE(merged.vertex_source.size() == vertices);
    REQUIRE(merged.complex.has_facet_normals());
    REQUIRE(merged.complex.colors(2).size() == faces);

    // Face by face, the pieces appear in object order with their provenance, positions and
    // normals, and the color of their object or cell.
    std::uint32_t f = 0, v0 = 0;
    std::size_t cell_colored = 0;
    for (std::uint32_t i = 0; i < separate.size(); ++i) {
      const Complex& c = separate[i].complex;
      for (std::uint32_t v = 0; v < c.count(0); ++v)
        CHECK((merged.complex.position(v0 + v) - c.position(v)).norm() == 0.0);
      for (std::uint32_t g = 0; g < c.count(2); ++g, ++f) {
        CHECK(merged.object_of_face[f] == i);
        const std::uint32_t cell = separate[i].source[2][g];
        CHECK(merged.source[2][f] == cell);
        CHECK((merged.complex.facet_normals().col(f) - c.facet_normals().col(g)).norm() == 0.0);
        // Same cycle, shifted by the vertices of the earlier pieces.
        auto cycle = c.face_cycle(g);
        for (auto& x : cycle) x += v0;
        CHECK(merged.complex.face_cycle(f) == cycle);
        const SceneObject& obj = scene.objects[i];
        const Rgba expect = obj.cell_colors.count(cell) ? obj.cell_colors.at(cell) : obj.color;
        CHECK(merged.complex.colors(2)[f] == expect);
        cell_colored += obj.cell_colors.count(cell);
      }
      v0 += static_cast<std::uint32_t>(c.count(0));
    }
    CHECK(cell_colored > 0);  // the cells with their own colors are cut
  }
}

TEST_CASE("objects the plane cannot reach are skipped", "[scene]") {
  const Scene scene = parse(R"({"objects": [
    {"model": "tesseract", "color": "#ff0000"},
    {"model": "tesseract", "translate": [0, 0, 0, 10], "color": "#0000ff"},
    {"model": "16-cell", "translate": [0, 0, 0, 1.25], "color": "#00ff00"}
  ]})");
  const Hyperplane plane = Hyperplane::from(vec({0, 0, 0, 1}), 0.5);
  const std::vector<Section> pieces = section_objects(scene, plane);
  REQUIRE(pieces.size() == 3);
  CHECK(pieces[0].complex.fvector() == std::vector<std::size_t>{8, 12, 6});
  CHECK(pieces[1].empty());
  CHECK(pieces[1].complex.ambient_dim() == 3);
  CHECK(!pieces[2].empty());  // reached: the 16-cell spans w in [0.25, 2.25]
  const Section merged = merge_sections(scene, pieces);
  CHECK(merged.complex.count(2) == 6 + pieces[2].complex.count(2));
  for (std::uint32_t f = 0; f < merged.complex.count(2); ++f) {
    CHECK(merged.object_of_face[f] != 1);
    CHECK(merged.complex.colors(2)[f] == (f < 6 ? rgb(1, 0, 0) : rgb(0, 1, 0)));
  }
  // A plane that misses everything gives an empty section.
  CHECK(section_scene(scene, Hyperplane::from(vec({0, 0, 0, 1}), -5)).empty());
  // A plane of the wrong dimension is an input error.
  CHECK_THROWS_AS(section_objects(scene, Hyperplane::from(vec({0, 0, 1}), 0)), InputError);
}

TEST_CASE("model files resolve against the scene's directory and are loaded once", "[scene]") {
  TempDir dir;
  fs::create_directories(dir / "models");
  write_off_file((dir / "models/simplex.4off").string(), make_simplex(4));
  dir.write("scenes/a.json", R"({"objects": [
    {"model": "../models/simplex.4off"},
    {"model": "../models/./simplex.4off", "translate": [3, 0, 0, 0]},
    {"model": "tesseract"},
    {"model": "8-cell"}
  ]})");
  const Scene scene = read_scene_file((dir / "scenes/a.json").string());
  REQUIRE(scene.objects.size() == 4);
  CHECK(scene.objects[0].complex.get() == scene.objects[1].complex.get());
  CHECK(scene.objects[0].complex->fvector() == std::vector<std::size_t>{5, 10, 10, 5});
  // Different specs are different models, even when they name the same polytope.
  CHECK(scene.objects[2].complex.get() != scene.objects[3].complex.get());
  // The model file's own errors name that file and its line.
  dir.write("models/bad.4off",
            "4OFF\n4 4 6 1\n0 0 0 0\n1 0 0 x\n0 1 0 0\n0 0 1 0\n"
            "3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 3\n4 0 1 2 3\n");
  dir.write("scenes/b.json", "{\"objects\": [{\"model\": \"../models/bad.4off\"}]}");
  try {
    read_scene_file((dir / "scenes/b.json").string());
    FAIL("no error");
  } catch (const ParseError& e) {
    CHECK(fs::path(e.file()).filename() == "bad.4off");
    CHECK(e.line() == 4);
  }
  dir.write("scenes/c.json", "{\"objects\": [{\"model\": \"missing.4off\"}]}");
  CHECK_THROWS_AS(read_scene_file((dir / "scenes/c.json").string()), ParseError);
  try {
    read_scene_file((dir / "scenes/none.json").string());
    FAIL("no error");
  } catch (const ParseError& e) {
    CHECK(e.line() == 0);
  }
}

TEST_CASE("malformed scenes are parse errors naming the line", "[scene]") {
  struct Bad {
    const char* what;
    std::string text;
    std::size_t line;
    const char* message;  // a piece of the message
  };
  const std::vector<Bad> cases = {
      {"missing comma",
       "{\"objects\": [\n  {\"model\": \"tesseract\"}\n  {\"model\": \"5-cell\"}\n]}", 3,
       "invalid JSON"},
      {"trailing garbage", "{\"objects\": [{\"model\": \"tesseract\"}]}\n\nx\n", 3, "invalid JSON"},
      {"unterminated", "{\"objects\": [\n{\"model\": \"tesseract\"}\n", 2, "invalid JSON"},
      {"not an object", "\n[1, 2]\n", 2, "a scene is a JSON object"},
      {"unknown top-level key", "{\n\"objects\": [{\"model\": \"tesseract\"}],\n\"camera\": 1\n}",
       3, "unknown key \"camera\""},
      {"no objects key", "{\n}\n", 1, "no \"objects\""},
      {"empty objects", "{\n\"objects\": [\n]\n}", 2, "no objects"},
      {"unknown object key",
       "{\"objects\": [\n{\"model\": \"tesseract\",\n \"colour\": \"#ff0000\"}]}", 3,
       "allowed: model, name, scale, rotate, translate, color, opacity, cell_colors"},
      {"missing model", "{\"objects\": [\n{\"model\": \"tesseract\"},\n{\"name\": \"x\"}]}", 3,
       "has no \"model\""},
      {"model of wrong type", "{\"objects\": [\n{\"model\": 4}]}", 2, "\"model\" must be"},
      {"unknown model", "{\"objects\": [\n\n{\"model\": \"tessaract\"}]}", 3, "unknown model"},
      {"translate as a string",
       "{\"objects\": [{\"model\": \"tesseract\",\n\"translate\": \"1,2,3,4\"}]}", 2,
       "\"translate\" must be an array of 4 numbers"},
      {"translate too short",
       "{\"objects\": [{\"model\": \"tesseract\",\n\"translate\": [1, 2, 3]}]}", 2,
       "\"translate\" must be an array of 4 numbers"},
      {"translate component",
       "{\"objects\": [{\"model\": \"tesseract\", \"translate\": [\n1,\n2,\n"
       "\"3\",\n4]}]}",
       4, "component 3 must be a number"},
      {"bad hex color", "{\"objects\": [{\"model\": \"tesseract\",\n\n\"color\": \"#ff00\"}]}", 3,
       "bad color \"#ff00\""},
      {"color component out of range",
       "{\"objects\": [{\"model\": \"tesseract\", \"color\": [\n0.5,\n1.5,\n0]}]}", 3,
       "component 2 is outside 0..1"},
      {"color of wrong type", "{\"objects\": [{\"model\": \"tesseract\",\n\"color\": true}]}", 2,
       "bad color"},
      {"opacity above 1", "{\"objects\": [{\"model\": \"tesseract\",\n\"opacity\": 2\n}]}", 2,
       "\"opacity\" must lie in [0, 1]"},
      {"negative opacity", "{\"objects\": [{\"model\": \"tesseract\",\n\"opacity\": -0.1}]}", 2,
       "\"opacity\" must lie in [0, 1]"},
      {"cell id out of range",
       "{\"objects\": [{\"model\": \"tesseract\", \"cell_colors\": {\n\"1\": \"#ff0000\",\n"
       "\"8\": \"#00ff00\"}}]}",
       3, "cell id \"8\" is not in 0..7"},
      {"cell id not a number",
       "{\"objects\": [{\"model\": \"tesseract\", \"cell_colors\": {\n\"first\": \"#ff0000\"}}]}",
       2, "cell id \"first\""},
      {"bad cell color",
       "{\"objects\": [{\"model\": \"tesseract\", \"cell_colors\": {\n\"1\": \"red\"}}]}", 2,
       "bad color of cell 1"},
      {"rotation plane",
       "{\"objects\": [{\"model\": \"tesseract\", \"rotate\": [\n[\"xy\", 10],\n"
       "[\"xq\", 10]]}]}",
       3, "xq"},
      {"rotation not a pair",
       "{\"objects\": [{\"model\": \"tesseract\", \"rotate\": [\n[\"xy\", 10, 3]]}]}", 2,
       "rotation 1 is not [plane, degrees]"},
      {"rotation angle",
       "{\"objects\": [{\"model\": \"tesseract\", \"rotate\": [\n[\"xy\",\n"
       "\"ten\"]]}]}",
       3, "angle of rotation 1 must be a number"},
      {"rotation axis beyond the model",
       "{\"objects\": [{\"model\": \"cube:3\", \"rotate\": [\n"
       "[\"xw\", 10]]}]}",
       2, "does not have"},
      {"zero scale", "{\"objects\": [{\"model\": \"tesseract\",\n\"scale\": 0}]}", 2,
       "\"scale\" must not be zero"},
      {"scale per axis", "{\"objects\": [{\"model\": \"tesseract\", \"scale\": [1,\n1,\n0, 1]}]}",
       3, "\"scale\" must not be zero"},
      {"duplicate key", "{\"objects\": [{\"model\": \"tesseract\",\n\"model\": \"5-cell\"}]}", 2,
       "duplicate key \"model\""},
      {"mixed dimensions", "{\"objects\": [{\"model\": \"tesseract\"},\n{\"model\": \"cube:3\"}]}",
       2, "a scene has one dimension"},
      {"name of wrong type", "{\"objects\": [{\"model\": \"tesseract\",\n\"name\": [1]}]}", 2,
       "\"name\" must be a string"},
      {"object not an object", "{\"objects\": [\n\"tesseract\"]}", 2, "must be an object"},
  };
  for (const Bad& bad : cases) {
    INFO(bad.what << ":\n" << bad.text);
    try {
      parse(bad.text);
      FAIL("no error");
    } catch (const ParseError& e) {
      INFO(e.what());
      CHECK(e.file() == "test.json");
      CHECK(e.line() == bad.line);
      CHECK(e.message().find(bad.message) != std::string::npos);
      CHECK(std::string(e.what()).rfind("test.json:" + std::to_string(bad.line) + ": ", 0) == 0);
    }
  }
}

TEST_CASE("OBJ of a scene's section comes with an MTL of its colors", "[scene][export]") {
  TempDir dir;
  const Scene scene = parse(kScene);
  const Section merged = section_scene(scene, Hyperplane::from(vec({0, 0, 0, 1}), 0.1));
  const auto& colors = merged.complex.colors(2);
  REQUIRE(colors.size() == merged.complex.count(2));
  write_obj_file((dir / "s.obj").string(), merged);
  const std::string obj = read_text(dir / "s.obj");
  const std::string mtl = read_text(dir / "s.mtl");
  CHECK(obj.find("mtllib s.mtl\n") != std::string::npos);
  CHECK(mtl == mtl_text(merged.complex));

  // Materials: name -> color.
  std::map<std::string, Rgba> materials;
  {
    std::istringstream in(mtl);
    std::string line, current;
    while (std::getline(in, line)) {
      std::istringstream ls(line);
      std::string tag;
      ls >> tag;
      if (tag == "newmtl") {
        ls >> current;
        materials[current] = Rgba{};
      } else if (tag == "Kd") {
        ls >> materials[current].r >> materials[current].g >> materials[current].b;
      } else if (tag == "d") {
        ls >> materials[current].a;
      }
    }
  }
  std::set<std::tuple<float, float, float, float>> distinct;
  for (const Rgba& c : colors) distinct.insert({c.r, c.g, c.b, c.a});
  CHECK(materials.size() == distinct.size());
  CHECK(materials.size() >= 3);
  // Each face is written under the material of its color; groups name object and cell.
  std::istringstream in(obj);
  std::string line, current;
  std::uint32_t f = 0;
  bool object_groups = false;
  while (std::getline(in, line)) {
    if (line.rfind("usemtl ", 0) == 0) current = line.substr(7);
    if (line.rfind("g object_", 0) == 0) object_groups = true;
    if (line.rfind("f ", 0) != 0) continue;
    REQUIRE(f < colors.size());
    INFO("face " << f << " material " << current);
    REQUIRE(materials.count(current));
    CHECK(materials[current] == colors[f]);
    ++f;
  }
  CHECK(f == merged.complex.count(2));
  CHECK(object_groups);

  // A section without colors gets no MTL, as before.
  const Section plain = section(load_model("tesseract"), Hyperplane::from(vec({0, 0, 0, 1}), 0.1));
  write_obj_file((dir / "plain.obj").string(), plain);
  CHECK(!fs::exists(dir / "plain.mtl"));
  CHECK(read_text(dir / "plain.obj").find("mtllib") == std::string::npos);
  CHECK(read_text(dir / "plain.obj").find("usemtl") == std::string::npos);

  // When the OBJ cannot be written the MTL is taken back: nothing is left behind.
  TempDir blocked;
  fs::create_directory(blocked / "x.obj");  // a directory where the file should go
  CHECK_THROWS_AS(write_obj_file((blocked / "x.obj").string(), merged), IoError);
  CHECK(!fs::exists(blocked / "x.mtl"));
  CHECK(blocked.entries() == 1);
}

TEST_CASE("nOFF and SVG keep a scene's face colors", "[scene][export]") {
  TempDir dir;
  const Scene scene = parse(kScene);
  const Section merged = section_scene(scene, Hyperplane::from(vec({0, 0, 0, 1}), 0.1));
  write_off_file((dir / "s.off").string(), merged.complex);
  const Complex back = read_off_file((dir / "s.off").string());
  REQUIRE(back.count(2) == merged.complex.count(2));
  REQUIRE(back.colors(2).size() == back.count(2));
  for (std::uint32_t f = 0; f < back.count(2); ++f) {
    const Rgba a = back.colors(2)[f], b = merged.complex.colors(2)[f];
    CHECK(std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b) + std::abs(a.a - b.a) <
          1e-6);
  }

  // The half-transparent orange object shows as fill-opacity; the per-cell hues are gone.
  const std::string svg = svg_text(merged);
  CHECK(svg.find("fill-opacity=\"0.500\"") != std::string::npos);
  const std::string plain =
      svg_text(section(load_model("tesseract"), Hyperplane::from(vec({0, 0, 0, 1}), 0.1)));
  CHECK(plain.find("fill-opacity") == std::string::npos);
  // One object colored pure red: every polygon is a shade of red.
  const Scene red = parse(R"({"objects": [{"model": "tesseract", "color": "#ff0000",
                                           "rotate": [["xw", 20]]}]})");
  const std::string red_svg = svg_text(section_scene(red, Hyperplane::from(vec({0, 0, 0, 1}), 0)));
  std::size_t polygons = 0;
  for (std::size_t at = red_svg.find("<polygon fill=\"#"); at != std::string::npos;
       at = red_svg.find("<polygon fill=\"#", at + 1)) {
    ++polygons;
    CHECK(red_svg.substr(at + 18, 4) == "0000");  // #rr0000
  }
  CHECK(polygons > 0);
}
