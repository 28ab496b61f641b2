// Every model family that `cw4d list` offers, through at least one concrete spec: it builds,
// validates (closed, coherent, outward, planar facets), its facet normals point outward, and it
// survives a 4OFF round trip. A family added without an example here makes the test fail.
#include <catch2/catch.hpp>

#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"

using namespace cw4d;

namespace {

// Concrete specs, at least one per family (convex ones flagged for the outward-normal check).
struct Example {
  std::string spec;
  bool convex;
};

const std::vector<Example>& examples() {
  static const std::vector<Example> list = {
      {"5-cell", true},
      {"pentachoron", true},
      {"tesseract", true},
      {"8-cell", true},
      {"16-cell", true},
      {"24-cell", true},
      {"120-cell", true},
      {"600-cell", true},
      {"truncated tesseract", true},
      {"rectified 5-cell", true},
      {"omnitruncated 24-cell", true},
      {"simplex:3", true},
      {"simplex:5", true},
      {"cube:3", true},
      {"cube:5", true},
      {"orthoplex:3", true},
      {"orthoplex:5", true},
      {"polygon:7", true},
      {"duoprism:5,7", true},
      {"duoprism:3,12", true},
      {"prism:simplex:3", true},
      {"prism:wythoff:x3x3o", true},
      {"wythoff:x4o3x", true},
      {"wythoff:o3x3x3o", true},
      {"wythoff:x5o", true},
      {"pyramid:cube:3", true},
      {"pyramid:tesseract", true},
      {"cone:sphere:1,8", true},
      {"cone:cylinder:1,8", true},
      {"dual:tesseract", true},
      {"dual:120-cell", true},
      {"antiprism:5", true},
      {"prism:antiprism:7", true},
      {"cylinder:1,8", true},
      {"sphere:1.5,8", true},
      {"duocylinder:1,12", true},
      {"cubinder:1,8", true},
      {"spherinder:1,8", true},
      {"extrude:" + std::string(CW4D_TEST_DATA_DIR) + "/cube.obj", true},
      {"spin:" + std::string(CW4D_TEST_DATA_DIR) + "/offset_cube.off,12", false},
      {"spheritorus:2,0.7,8", false},
      {"torisphere:2,0.7,8", false},
      {"ditorus:3,1.2,0.5,6", false},
      {"tiger:2,2,0.7,6", false},
      {"snub cube", true},
      {"snub dodecahedron", true},
      {"prism:snub dodecahedron", true},
      {"snub 24-cell", true},
      {"product:polygon:5*polygon:3", true},
      {"product:cube:3*polygon:4", true},
      {"wythoff:s3s4o3o", true},
      {"wythoff:s5s3s", true},
      {"grand antiprism", true},
      {"great grand stellated 120-cell", false},
      {"quasitruncated tesseract", false},
      {"glome:1,4", true},
      {"hull:" + std::string(CW4D_TEST_DATA_DIR) + "/cube_points.txt", true},
  };
  return list;
}

}  // namespace

TEST_CASE("every model family has an example that builds, validates and round-trips") {
  std::set<std::string> covered;
  for (const Example& ex : examples()) {
    INFO(ex.spec);
    const auto family = model_family(ex.spec, default_catalogue());
    REQUIRE(family.has_value());
    covered.insert(*family);
    const Complex c = load_model(ex.spec, default_catalogue());
    const ValidationReport report = validate(c);
    INFO(report.summary());
    REQUIRE(report.ok());
    REQUIRE(signed_volume(c) > 0.0);
    if (ex.convex && c.ambient_dim() >= 2) {
      // Outward: every vertex lies on the inner side of every facet's hyperplane.
      const int fr = c.facet_rank();
      for (std::uint32_t f = 0; f < c.count(fr); ++f) {
        const Eigen::VectorXd n = c.facet_normals().col(f);
        const double level = n.dot(c.position(c.first_vertex(fr, f)));
        const double tol = 1e-9 * (1.0 + max_radius(c));
        for (std::uint32_t v = 0; v < c.count(0); ++v) REQUIRE(n.dot(c.position(v)) <= level + tol);
      }
    }
    if (c.ambient_dim() >= 3) {
      std::stringstream text;
      write_off(text, c);
      const Complex back = read_off(text, ex.spec);
      CHECK(back.fvector() == c.fvector());
      CHECK(back.positions() == c.positions());
      CHECK(validate(back).ok());
    }
  }
  for (const BuiltinInfo& info : builtin_list(default_catalogue())) {
    if (info.spec.rfind("FILE", 0) == 0) continue;
    INFO("family without an example: " << info.spec);
    CHECK(covered.count(info.spec) == 1);
  }
}

TEST_CASE("snub diagrams name the snub polytopes (published f-vectors)") {
  CHECK(load_model("wythoff:s3s4o3o", default_catalogue()).fvector() ==
        std::vector<std::size_t>{96, 432, 480, 144});
  CHECK(load_model("wythoff:s4s3s", default_catalogue()).fvector() ==
        std::vector<std::size_t>{24, 60, 38});
  CHECK(load_model("wythoff:s5s3s", default_catalogue()).fvector() ==
        std::vector<std::size_t>{60, 150, 92});
  CHECK(load_model("grand antiprism", default_catalogue()).fvector() ==
        std::vector<std::size_t>{100, 500, 720, 320});
  // Other diagrams with snub nodes are not built (yet): a clear error, not a wrong model.
  CHECK_THROWS_AS(load_model("wythoff:s3s3s3s", default_catalogue()), InputError);
}

TEST_CASE("product:A*B is the Cartesian product (f-vector of the product of the faces)") {
  // duoprism:5,3 = pentagon x triangle: V = 15, E = 5*3 + 5*3, F = 15 + 3 + 5, C = 3 + 5.
  CHECK(load_model("product:polygon:5*polygon:3", default_catalogue()).fvector() ==
        std::vector<std::size_t>{15, 30, 23, 8});
  CHECK(load_model("product:polygon:5*polygon:3", default_catalogue()).positions().cols() ==
        load_model("duoprism:5,3", default_catalogue()).positions().cols());
  CHECK_THROWS_AS(load_model("product:polygon:5", default_catalogue()), InputError);
  CHECK_THROWS_AS(load_model("product:*polygon:5", default_catalogue()), InputError);
}

TEST_CASE("catalogues are explicit values: core, default, extended", "[catalogue]") {
  using FVector = std::vector<std::size_t>;
  const Catalogue& core = core_catalogue();
  const Catalogue& all = default_catalogue();
  // The core catalogue has no hull or mesh-file family; the default one has them and every core
  // family, under the same usage, in the same order.
  for (const char* spec : {"glome:1,3", "snub cube", "grand antiprism", "hull:x.txt",
                           "extrude:x.obj", "spin:x.obj,8"}) {
    INFO(spec);
    CHECK(core.find(spec) == nullptr);
    CHECK(all.find(spec) != nullptr);
  }
  REQUIRE(all.families().size() > core.families().size());
  for (std::size_t i = 0; i < core.families().size(); ++i)
    CHECK(all.families()[i].usage == core.families()[i].usage);
  CHECK_THROWS_AS(load_model("glome:1,3"), InputError);  // the default argument is the core
  CHECK(validate(load_model("glome:1,3", all)).ok());
  // Operators load their operands from the catalogue the spec is loaded with.
  // Prism over (V, E, F) of the snub cube (24, 60, 38): (2V, 2E + V, 2F + E, F + 2).
  CHECK(load_model("prism:snub cube", all).fvector() == FVector{48, 144, 136, 40});
  CHECK_THROWS_AS(load_model("prism:snub cube", core), InputError);
  CHECK_THROWS_AS(load_model("dual:gap"), InputError);
  // The scene reader takes the catalogue too; an unknown model is the scene's ParseError.
  const std::string scene = R"({"objects": [{"model": "grand antiprism"}]})";
  std::istringstream in(scene);
  CHECK(read_scene(in, "gap.json", {}, all).objects.at(0).complex->fvector() ==
        FVector{100, 500, 720, 320});
  std::istringstream again(scene);
  CHECK_THROWS_AS(read_scene(again, "gap.json"), ParseError);

  // An empty catalogue loads only files; an extended one adds or replaces by usage and leaves
  // the original as it was.
  CHECK_THROWS_AS(Catalogue().load("tesseract"), InputError);
  const Catalogue mine =
      Catalogue().extended({named_family({"my-cell"}, "a tesseract", [] { return make_cube(4); })});
  CHECK(mine.load("My-Cell").fvector() == FVector{16, 32, 24, 8});
  CHECK_THROWS_AS(mine.load("prism:my-cell"), InputError);
  CHECK(mine.list().size() == 3);  // my-cell, then the file entries (nOFF, G4MF)
  const Catalogue swapped = core.extended(
      {named_family({"tesseract", "8-cell"}, "a 16-cell", [] { return make_orthoplex(4); })});
  CHECK(swapped.families().size() == core.families().size());
  CHECK(swapped.load("8-cell").fvector() == FVector{8, 24, 32, 16});
  CHECK(swapped.load("prism:tesseract").fvector() == FVector{16, 56, 88, 64, 18});
  CHECK(core.load("8-cell").fvector() == FVector{16, 32, 24, 8});
  ModelFamily broken;
  broken.usage = "broken";
  CHECK_THROWS_AS(Catalogue({broken}), InputError);
}

TEST_CASE("one catalogue serves many threads", "[catalogue][threads]") {
  // One const catalogue read by four threads at once (operators recurse into it): every thread
  // gets the published f-vectors.
  const std::vector<std::pair<std::string, std::vector<std::size_t>>> cases = {
      {"snub 24-cell", {96, 432, 480, 144}},
      {"prism:snub cube", {48, 144, 136, 40}},
      {"24-cell", {24, 96, 96, 24}},
      {"dual:tesseract", {8, 24, 32, 16}}};
  std::vector<int> wrong(4, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int round = 0; round < 2; ++round)
        for (std::size_t k = 0; k < cases.size(); ++k) {
          const auto& [spec, f] = cases[(k + t) % cases.size()];
          wrong[t] += load_model(spec, default_catalogue()).fvector() != f;
        }
    });
  for (auto& thread : threads) thread.join();
  CHECK(wrong == std::vector<int>(4, 0));
}

TEST_CASE("families beyond what builds in seconds are refused from the spec",
          "[builtins][limits]") {
  // Each message names the bound; the counts in it are checked against closed forms.
  auto refusal = [](const std::string& spec) {
    try {
      (void)load_model(spec);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    FAIL("accepted " << spec);
    return std::string();
  };
  // A product of P and Q has (sum_i f_i(P)) (sum_j f_j(Q)) elements: (2N + 1)^2 for two N-gons.
  CHECK_THAT(refusal("duocylinder:1,707"),
             Catch::Contains(std::to_string(1415 * 1415) + " elements, at most 2000000"));
  CHECK_THAT(refusal("duoprism:707,707"),
             Catch::Contains(std::to_string(1415 * 1415) + " elements, at most 2000000"));
  // sphere:R,578 has V = 288 * 578 + 2, F = 289 * 578 faces, E = V + F - 2, and its solid; the
  // spherinder (its prism) 3 times that.
  {
    const long long v = 288LL * 578 + 2, f = 289LL * 578, total = 2 * v + 2 * f - 1;
    CHECK_THAT(refusal("spherinder:1,578"),
               Catch::Contains(std::to_string(3 * total) + " elements"));
  }
  CHECK_THAT(refusal("antiprism:250001"), Catch::Contains("3..250000"));
  CHECK_THAT(refusal("prism:antiprism:250000"), Catch::Contains("at most 2000000"));
  // Just inside, where building is quick: the counts are the closed forms.
  const Complex s = load_model("sphere:1,8");
  CHECK(s.fvector() == std::vector<std::size_t>{3 * 8 + 2, 3 * 8 + 4 * 8, 4 * 8});
  const Complex a = load_model("antiprism:9");
  CHECK(a.fvector() == std::vector<std::size_t>{2 * 9, 4 * 9, 2 * 9 + 2});
}
