// End-to-end tests of the cw4d command line: each test runs the real binary in a fresh
// temporary directory and checks exit codes, messages, and that outputs agree with the library.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/export/svg.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/scene_section.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/vectors.hpp"

namespace {

namespace fs = std::filesystem;

struct TempDir : cw4d::test::TempDir {
  TempDir() : cw4d::test::TempDir("cw4d_test_cli") {}
};

using cw4d::test::read_text;

using cw4d::test::Result;

// Runs cw4d with the given arguments inside dir; stdout and stderr are captured.
Result run(const TempDir& dir, const std::vector<std::string>& args) {
  return cw4d::test::run_program(dir, CW4D_EXE, args);
}

// Errors are one line "cw4d: error: ..." on stderr.
void check_one_error_line(const Result& r) {
  INFO("stderr: " << r.err);
  CHECK(r.err.rfind("cw4d: error: ", 0) == 0);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK(r.err.back() == '\n');
}

std::vector<std::size_t> fvector_of(const nlohmann::json& j) {
  return j.at("fvector").get<std::vector<std::size_t>>();
}

struct Obj {
  std::vector<Eigen::Vector3d> v;
  std::vector<std::vector<int>> f;  // 1-based vertex indices
};

Obj read_obj(const fs::path& p) {
  Obj obj;
  std::istringstream in(read_text(p));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      Eigen::Vector3d x;
      ls >> x(0) >> x(1) >> x(2);
      obj.v.push_back(x);
    } else if (tag == "f") {
      std::vector<int> face;
      std::string corner;
      while (ls >> corner) face.push_back(std::stoi(corner.substr(0, corner.find('/'))));
      obj.f.push_back(face);
    }
  }
  return obj;
}

using cw4d::test::radians;
using cw4d::test::vec;

// A tetrahedron's boundary missing one face, as a 4D cell: it parses, but is not closed.
const char* kOpenCell =
    "4OFF\n"
    "4 3 6 1\n"
    "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n"
    "3 0 1 2\n3 0 1 3\n3 0 2 3\n"
    "3 0 1 2\n";

}  // namespace

TEST_CASE("list names every built-in", "[cli]") {
  TempDir dir;
  const Result r = run(dir, {"list"});
  REQUIRE(r.code == 0);
  CHECK(r.err.empty());
  for (const auto& b : cw4d::builtin_list(cw4d::default_catalogue())) {
    INFO(b.spec);
    CHECK(r.out.find(b.spec) != std::string::npos);
    CHECK(r.out.find(b.description) != std::string::npos);
  }
}

TEST_CASE("info --json reports f-vectors, validity, bounds and volume", "[cli]") {
  TempDir dir;
  struct Case {
    const char* model;
    std::vector<std::size_t> fvector;
    double volume;
  };
  const double pentagon = 2.5 * std::sin(2 * std::numbers::pi / 5);
  const double heptagon = 3.5 * std::sin(2 * std::numbers::pi / 7);
  const std::vector<Case> cases = {
      {"5-cell", {5, 10, 10, 5}, -1},
      {"tesseract", {16, 32, 24, 8}, 16.0},
      {"16-cell", {8, 24, 32, 16}, 16.0 / 24.0},
      {"duoprism:5,7", {35, 70, 47, 12}, pentagon * heptagon},
  };
  for (const auto& c : cases) {
    INFO(c.model);
    const Result r = run(dir, {"info", c.model, "--json"});
    REQUIRE(r.code == 0);
    const auto j = nlohmann::json::parse(r.out);
    CHECK(j.at("model") == c.model);
    CHECK(j.at("dimension") == 4);
    CHECK(fvector_of(j) == c.fvector);
    CHECK(j.at("valid") == true);
    CHECK(j.at("issues").empty());
    REQUIRE(j.at("bounds").at("min").size() == 4);
    REQUIRE(j.at("bounds").at("max").size() == 4);
    for (int i = 0; i < 4; ++i)
      CHECK(j["bounds"]["min"][i].get<double>() < j["bounds"]["max"][i].get<double>());
    if (c.volume > 0) CHECK(j.at("volume").get<double>() == Approx(c.volume).epsilon(1e-12));
    CHECK(j.at("volume").get<double>() > 0);
  }
  const auto j = nlohmann::json::parse(run(dir, {"info", "tesseract", "--json"}).out);
  CHECK(j["bounds"]["min"] == nlohmann::json({-1.0, -1.0, -1.0, -1.0}));
  CHECK(j["bounds"]["max"] == nlohmann::json({1.0, 1.0, 1.0, 1.0}));

  const Result text = run(dir, {"info", "tesseract"});
  CHECK(text.code == 0);
  CHECK(text.out.find("16, 32, 24, 8") != std::string::npos);
}

TEST_CASE("slice of the tesseract by x+y+z+w = 0 is an octahedron", "[cli]") {
  TempDir dir;
  const Result r =
      run(dir, {"slice", "tesseract", "--normal", "1,1,1,1", "--offset", "0", "-o", "out/oct.obj"});
  REQUIRE(r.code == 0);
  CHECK(r.err.empty());
  CHECK(r.out.find("wrote out/oct.obj: 6 vertices, 12 edges, 8 faces") == 0);
  const Obj obj = read_obj(dir / "out/oct.obj");
  CHECK(obj.v.size() == 6);
  REQUIRE(obj.f.size() == 8);
  for (const auto& f : obj.f) CHECK(f.size() == 3);
  // Regular octahedron: every vertex at the same distance from the centre.
  for (const auto& v : obj.v) CHECK(v.norm() == Approx(obj.v[0].norm()).epsilon(1e-12));
}

TEST_CASE("slice writes the library's section, with rotations applied in the order given",
          "[cli]") {
  TempDir dir;
  struct Case {
    const char* model;
    std::vector<std::string> args;
    Eigen::VectorXd normal;
    double offset;
    cw4d::AffineTransform xf;
    bool triangulate;
  };
  using cw4d::AffineTransform;
  // xw then xy: the two rotations share the x axis and do not commute.
  const AffineTransform xw_then_xy = AffineTransform::rotation(4, 0, 1, radians(20)) *
                                     AffineTransform::rotation(4, 0, 3, radians(30));
  const std::vector<Case> cases = {
      {"tesseract",
       {"--normal", "0,0,0,1", "--offset", "0.3", "--rotate", "xw:30", "--rotate", "xy:20"},
       vec({0, 0, 0, 1}),
       0.3,
       xw_then_xy,
       false},
      {"tesseract",
       {"--normal", "0,0,0,1", "--offset", "0.3", "--rotate", "xw:30", "--rotate", "xy:20",
        "--triangulate"},
       vec({0, 0, 0, 1}),
       0.3,
       xw_then_xy,
       true},
      {"5-cell",
       {"--normal=-1,2,0.5,1", "--offset", "-0.1", "--translate", "0.1,0,0,-0.2"},
       vec({-1, 2, 0.5, 1}),
       -0.1,
       AffineTransform::translation(vec({0.1, 0, 0, -0.2})),
       false},
      {"16-cell",
       {"--normal", "1,0,0,1", "--offset", "0.25", "--rotate", "yz:45", "--translate", "0,0,0,0.1"},
       vec({1, 0, 0, 1}),
       0.25,
       AffineTransform::translation(vec({0, 0, 0, 0.1})) *
           AffineTransform::rotation(4, 1, 2, radians(45)),
       false},
      {"duoprism:5,7",
       {"--normal", "0.3,1,0,0.2", "--offset", "0.1", "--rotate", "zw:10"},
       vec({0.3, 1, 0, 0.2}),
       0.1,
       AffineTransform::rotation(4, 2, 3, radians(10)),
       true},
  };
  int k = 0;
  for (const auto& c : cases) {
    const std::string out = std::to_string(k++) + ".obj";
    INFO(c.model << " -> " << out);
    std::vector<std::string> args = {"slice", c.model};
    args.insert(args.end(), c.args.begin(), c.args.end());
    if (c.triangulate) args.push_back("--triangulate");
    args.insert(args.end(), {"-o", out});
    const Result r = run(dir, args);
    INFO("stderr: " << r.err);
    REQUIRE(r.code == 0);

    const cw4d::Section expected =
        cw4d::section(cw4d::load_model(c.model, cw4d::default_catalogue()),
                      cw4d::Hyperplane::from(c.normal, c.offset), c.xf);
    REQUIRE(!expected.empty());
    const Obj obj = read_obj(dir / out);
    const auto& sc = expected.complex;
    REQUIRE(obj.v.size() == sc.count(0));
    std::size_t faces = 0;
    for (std::uint32_t f = 0; f < sc.count(2); ++f)
      faces += c.triangulate ? sc.face_cycle(f).size() - 2 : 1;
    CHECK(obj.f.size() == faces);
    for (std::uint32_t v = 0; v < sc.count(0); ++v)
      CHECK((obj.v[v] - sc.position(v)).norm() < 1e-12);
    for (const auto& f : obj.f)
      for (int id : f) CHECK((id >= 1 && id <= static_cast<int>(obj.v.size())));
  }
}

TEST_CASE("slice and convert write nOFF", "[cli]") {
  TempDir dir;
  const Result s =
      run(dir, {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0.5", "-o", "cube.off"});
  REQUIRE(s.code == 0);
  const cw4d::Complex cube = cw4d::read_off_file((dir / "cube.off").string());
  CHECK(cube.ambient_dim() == 3);
  CHECK(cube.fvector() == std::vector<std::size_t>{8, 12, 6});
  CHECK(cw4d::validate(cube).ok());

  // 5D models slice to 4D complexes, which only nOFF holds.
  const Result s5 =
      run(dir, {"slice", "cube:5", "--normal", "1,0,0,0,1", "--offset", "0.5", "-o", "five.4off"});
  REQUIRE(s5.code == 0);
  CHECK(cw4d::read_off_file((dir / "five.4off").string()).ambient_dim() == 4);
}

TEST_CASE("convert round trip keeps the f-vector", "[cli]") {
  TempDir dir;
  for (const char* model : {"5-cell", "tesseract", "16-cell", "duoprism:5,7"}) {
    INFO(model);
    const std::string out = std::string("rt/") + model + ".4off";
    const Result c = run(dir, {"convert", model, "-o", out});
    REQUIRE(c.code == 0);
    const auto a = nlohmann::json::parse(run(dir, {"info", model, "--json"}).out);
    const Result i = run(dir, {"info", out, "--json"});
    REQUIRE(i.code == 0);
    const auto b = nlohmann::json::parse(i.out);
    CHECK(fvector_of(a) == fvector_of(b));
    CHECK(b.at("valid") == true);
    CHECK(b.at("volume").get<double>() == Approx(a.at("volume").get<double>()).epsilon(1e-12));
  }
}

TEST_CASE("malformed 4OFF files exit 2 naming file:line, and write nothing", "[cli]") {
  TempDir dir;
  struct Bad {
    const char* name;
    std::string text;
    int line;
  };
  const std::string tetra_vertices = "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n";
  const std::vector<Bad> files = {
      // The counts promise more lines than the file holds: reported at the counts line.
      {"truncated.4off", "4OFF\n4 4 6 1\n" + tetra_vertices + "3 0 1 2\n3 0 1 3\n", 2},
      // Cut in the middle of the last face line.
      {"cut.4off",
       "4OFF\n4 4 6 1\n" + tetra_vertices + "3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1\n4 0 1 2 3\n", 10},
      {"index.4off",
       "4OFF\n4 4 6 1\n" + tetra_vertices + "3 0 1 2\n3 0 1 7\n3 0 2 3\n3 1 2 3\n" + "4 0 1 2 3\n",
       8},
      {"nan.4off",
       "4OFF\n# vertices follow\n4 4 6 1\n0 0 0 0\n1 nan 0 0\n0 1 0 0\n0 0 1 0\n"
       "3 0 1 2\n3 0 1 3\n3 0 2 3\n3 1 2 3\n4 0 1 2 3\n",
       5},
      {"header.4off", "# a comment first\n4FFO\n4 4 6 1\n" + tetra_vertices, 2},
      {"coords.4off",
       "4OFF\n4 4 6 1\n0 0 0 0\n1 0 0\n0 1 0 0\n0 0 1 0\n3 0 1 2\n3 0 1 3\n"
       "3 0 2 3\n3 1 2 3\n4 0 1 2 3\n",
       4},
  };
  for (const auto& bad : files) {
    INFO(bad.name);
    dir.write(bad.name, bad.text);
    const std::string where = std::string(bad.name) + ":" + std::to_string(bad.line) + ":";
    const std::vector<std::vector<std::string>> commands = {
        {"info", bad.name},
        {"convert", bad.name, "-o", "out.4off"},
        {"slice", bad.name, "--normal", "1,0,0,0", "--offset", "0.1", "-o", "out.obj"},
    };
    for (const auto& cmd : commands) {
      INFO(cmd[0]);
      const Result r = run(dir, cmd);
      CHECK(r.code == 2);
      check_one_error_line(r);
      CHECK(r.err.find(where) != std::string::npos);
      CHECK(!dir.exists("out.4off"));
      CHECK(!dir.exists("out.obj"));
    }
  }
  const Result missing = run(dir, {"info", "no-such-file.4off"});
  CHECK(missing.code == 2);
  check_one_error_line(missing);
  // A directory opens as a stream but cannot be read.
  const Result directory = run(dir, {"info", "."});
  CHECK(directory.code == 2);
  check_one_error_line(directory);
}

TEST_CASE("a parseable but invalid complex: info reports it, slice and convert exit 3", "[cli]") {
  TempDir dir;
  dir.write("open.4off", kOpenCell);
  // The reader builds it; only validation objects.
  const cw4d::Complex open = cw4d::read_off_file((dir / "open.4off").string());
  REQUIRE(!cw4d::validate(open).ok());

  const Result info = run(dir, {"info", "open.4off", "--json"});
  REQUIRE(info.code == 0);
  const auto j = nlohmann::json::parse(info.out);
  CHECK(j.at("valid") == false);
  CHECK(!j.at("issues").empty());
  CHECK(fvector_of(j) == std::vector<std::size_t>{4, 6, 3, 1});

  const Result slice =
      run(dir, {"slice", "open.4off", "--normal", "1,0,0,0", "--offset", "0.1", "-o", "o.obj"});
  CHECK(slice.code == 3);
  check_one_error_line(slice);
  CHECK(slice.err.find("not closed") != std::string::npos);
  CHECK(!dir.exists("o.obj"));

  const Result convert = run(dir, {"convert", "open.4off", "-o", "o.4off"});
  CHECK(convert.code == 3);
  check_one_error_line(convert);
  CHECK(!dir.exists("o.4off"));
}

TEST_CASE("usage errors exit 1 and write nothing", "[cli]") {
  TempDir dir;
  const std::vector<std::vector<std::string>> commands = {
      {},
      {"frobnicate"},
      {"info"},
      {"info", "no-such-model"},
      {"info", "cube:99"},
      {"slice", "no-such-model", "--normal", "1,0,0,0", "--offset", "0", "-o", "x.obj"},
      {"slice", "tesseract", "--normal", "0,0,0,0", "--offset", "0", "-o", "x.obj"},
      {"slice", "tesseract", "--normal", "0,0,1", "--offset", "0", "-o", "x.obj"},
      {"slice", "tesseract", "--normal", "0,0,0,1,0", "--offset", "0", "-o", "x.obj"},
      {"slice", "tesseract", "--normal", "0,a,0,1", "--offset", "0", "-o", "x.obj"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "abc", "-o", "x.obj"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "-o", "x.obj"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "-o", "x.dae"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "--format", "dae", "-o",
       "x.obj"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "--triangulate", "-o",
       "x.stl"},
      {"sweep", "tesseract", "--normal", "0,0,0,1", "--from", "0", "--to", "0", "--layers", "4",
       "-o", "x.glb"},
      {"sweep", "tesseract", "--normal", "0,0,0,1", "--from", "-1", "--to", "1", "--layers", "0",
       "-o", "x.glb"},
      {"sweep", "tesseract", "--normal", "0,0,0,1", "--from", "nan", "--to", "1", "--layers", "3",
       "-o", "x.glb"},
      {"sweep", "cube:3", "--normal", "0,0,1", "--from", "-1", "--to", "1", "--layers", "3", "-o",
       "x.glb"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "--triangulate", "-o",
       "x.4off"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "--rotate", "xq:10", "-o",
       "x.obj"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "--rotate", "xy", "-o",
       "x.obj"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "--translate", "1,2", "-o",
       "x.obj"},
      {"slice", "cube:3", "--normal", "1,0,0", "--offset", "0", "--rotate", "xw:10", "-o", "x.obj"},
      {"convert", "tesseract", "-o", "x.obj"},
      {"info", "tesseract", "--bogus"},
  };
  for (const auto& cmd : commands) {
    std::string line;
    for (const auto& a : cmd) line += a + " ";
    INFO("cw4d " << line);
    const Result r = run(dir, cmd);
    CHECK(r.code == 1);
    check_one_error_line(r);
    CHECK(!dir.exists("x.obj"));
    CHECK(!dir.exists("x.4off"));
    CHECK(!dir.exists("x.stl"));
    CHECK(!dir.exists("x.dae"));
    CHECK(!dir.exists("x.glb"));
  }
  const Result help = run(dir, {"--help"});
  CHECK(help.code == 0);
  CHECK(help.out.find("Exit codes") != std::string::npos);
}

TEST_CASE("an unwritable output exits 4 and leaves nothing", "[cli]") {
  TempDir dir;
  dir.write("blocker", "a regular file\n");
  const std::vector<std::vector<std::string>> commands = {
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "-o", "blocker/x.obj"},
      {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "-o", "blocker/sub/x.obj"},
      {"convert", "tesseract", "-o", "blocker/x.4off"},
  };
  for (const auto& cmd : commands) {
    INFO(cmd.back());
    const Result r = run(dir, cmd);
    CHECK(r.code == 4);
    check_one_error_line(r);
    CHECK(fs::is_regular_file(dir / "blocker"));
    CHECK(read_text(dir / "blocker") == "a regular file\n");
  }
  // Only the blocker and nothing else (no temporary files) in the directory.
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path())) ++entries;
  CHECK(entries == 1);
}

TEST_CASE("missing parent directories of the output are created", "[cli]") {
  TempDir dir;
  const Result r = run(dir, {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "-o",
                             "a/b/c/section.obj"});
  CHECK(r.code == 0);
  CHECK(fs::is_regular_file(dir / "a/b/c/section.obj"));
}

TEST_CASE("an empty section exits 5 and writes nothing", "[cli]") {
  TempDir dir;
  for (const char* out : {"out/empty.obj", "empty.4off"}) {
    INFO(out);
    const Result r =
        run(dir, {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "10", "-o", out});
    CHECK(r.code == 5);
    check_one_error_line(r);
    CHECK(!dir.exists(out));
    CHECK(!dir.exists("out"));
  }
  // Far away after the translation: the plane w = 0 misses a tesseract moved to w = 5.
  const Result moved = run(dir, {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0",
                                 "--translate", "0,0,0,5", "-o", "moved.obj"});
  CHECK(moved.code == 5);
  CHECK(!dir.exists("moved.obj"));
}

TEST_CASE("slice of a 3D model writes its polygon outline as OBJ line elements", "[cli]") {
  TempDir dir;
  const Result r =
      run(dir, {"slice", "cube:3", "--normal", "0,1,1", "--offset", "0.5", "-o", "outline.obj"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string text = read_text(dir / "outline.obj");
  const cw4d::Section expect = cw4d::section(cw4d::load_model("cube:3", cw4d::default_catalogue()),
                                             cw4d::Hyperplane::from(vec({0, 1, 1}), 0.5));
  std::size_t v = 0, l = 0, f = 0;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    v += line.rfind("v ", 0) == 0;
    l += line.rfind("l ", 0) == 0;
    f += line.rfind("f ", 0) == 0;
  }
  CHECK(v == expect.complex.count(0));
  CHECK(l == expect.complex.count(1));
  CHECK(l == 4);  // the cut of a cube by this plane is a rectangle
  CHECK(f == 0);
}

TEST_CASE("slice to .svg draws exactly the faces that face the viewer", "[cli]") {
  TempDir dir;
  const Result r = run(dir, {"slice", "tesseract", "--normal", "1,1,1,1", "--offset", "0.5",
                             "--rotate", "xy:15", "-o", "pic.svg"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  const std::string text = read_text(dir / "pic.svg");
  CHECK(text.rfind("<svg", 0) == 0);
  std::size_t polygons = 0;
  for (std::size_t at = text.find("<polygon"); at != std::string::npos;
       at = text.find("<polygon", at + 1))
    ++polygons;
  const cw4d::Complex model = cw4d::load_model("tesseract", cw4d::default_catalogue());
  const cw4d::AffineTransform xf =
      cw4d::AffineTransform::rotation(4, 0, 1, 15 * std::numbers::pi / 180);
  const cw4d::Section s = cw4d::section(model, cw4d::Hyperplane::from(vec({1, 1, 1, 1}), 0.5), xf);
  std::size_t front = 0;
  const Eigen::Vector3d view = cw4d::SvgOptions{}.view_from.normalized();
  for (std::uint32_t face = 0; face < s.complex.count(2); ++face)
    front += Eigen::Vector3d(s.complex.facet_normals().col(face)).dot(view) > 0.0;
  CHECK(front > 0);
  CHECK(polygons == front);
  // A 3D model has no 3D section to draw.
  const Result bad =
      run(dir, {"slice", "cube:3", "--normal", "0,0,1", "--offset", "0", "-o", "x.svg"});
  CHECK(bad.code == 1);
  CHECK(!dir.exists("x.svg"));
}

// --- scenes --------------------------------------------------------------------------------

namespace {

// Two instances of one model (one with cell colors), a model file next to the scene, and an
// object the plane misses.
const char* kCliScene = R"({
  "objects": [
    {"model": "tesseract", "name": "left", "scale": 0.5, "rotate": [["xw", 30]],
     "translate": [-3, 0, 0, 0], "color": "#ff8000", "opacity": 0.5,
     "cell_colors": {"6": [0, 0, 1]}},
    {"model": "tesseract", "name": "right", "translate": [3, 0, 0, 0.2], "color": [0, 1, 0]},
    {"model": "models/simplex.4off", "translate": [0, 0, 0, 9]}
  ]
})";

// "newmtl" name -> (Kd, d) as written.
std::map<std::string, std::string> read_mtl(const fs::path& p) {
  std::map<std::string, std::string> out;
  std::istringstream in(read_text(p));
  std::string line, current;
  while (std::getline(in, line)) {
    if (line.rfind("newmtl ", 0) == 0) current = line.substr(7);
    if (line.rfind("Kd ", 0) == 0 || line.rfind("d ", 0) == 0) out[current] += line + ";";
  }
  return out;
}

}  // namespace

TEST_CASE("slice --scene writes the objects as one mesh with an MTL of their colors", "[cli]") {
  TempDir dir;
  fs::create_directories(dir / "scenes/models");
  dir.write("scenes/s.json", kCliScene);
  cw4d::write_off_file((dir / "scenes/models/simplex.4off").string(), cw4d::make_simplex(4));
  const Result r = run(dir, {"slice", "--scene", "scenes/s.json", "--normal", "0,0,0,1", "--offset",
                             "0.1", "-o", "out/s.obj"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.err.empty());
  CHECK(r.out.rfind("wrote out/s.obj and out/s.mtl: 16 vertices, 24 edges, 12 faces", 0) == 0);
  CHECK(r.out.find("object 0 'left' (tesseract): 8 vertices, 12 edges, 6 faces") !=
        std::string::npos);
  CHECK(r.out.find("object 1 'right' (tesseract): 8 vertices, 12 edges, 6 faces, volume 8") !=
        std::string::npos);
  CHECK(r.out.find("object 2 (models/simplex.4off): missed by the plane") != std::string::npos);

  // Same geometry as the library's merged section; one material per color, faces under theirs.
  const cw4d::Scene scene = cw4d::read_scene_file((dir / "scenes/s.json").string());
  const cw4d::Section expect =
      cw4d::section_scene(scene, cw4d::Hyperplane::from(vec({0, 0, 0, 1}), 0.1));
  const Obj obj = read_obj(dir / "out/s.obj");
  REQUIRE(obj.v.size() == expect.complex.count(0));
  REQUIRE(obj.f.size() == expect.complex.count(2));
  const auto materials = read_mtl(dir / "out/s.mtl");
  CHECK(materials.size() == 3);  // orange (half transparent), blue cell 6 (too), green
  CHECK(materials.at("color_0") == "Kd 1 0.5019608 0;d 0.5;");
  std::set<std::string> used;
  std::istringstream in(read_text(dir / "out/s.obj"));
  std::string line, current;
  std::uint32_t f = 0;
  CHECK(read_text(dir / "out/s.obj").find("mtllib s.mtl\n") != std::string::npos);
  while (std::getline(in, line)) {
    if (line.rfind("usemtl ", 0) == 0) current = line.substr(7);
    if (line.rfind("f ", 0) != 0) continue;
    const cw4d::Rgba c = expect.complex.colors(2)[f];
    const std::string object = expect.object_of_face[f] == 0 ? "left" : "right";
    INFO("face " << f << " of " << object << ", cell " << expect.source[2][f]);
    REQUIRE(materials.count(current));
    const std::string want = c == cw4d::Rgba{0, 0, 1, 0.5f}   ? "Kd 0 0 1;d 0.5;"
                             : c == cw4d::Rgba{0, 1, 0, 1.0f} ? "Kd 0 1 0;d 1;"
                                                              : "Kd 1 0.5019608 0;d 0.5;";
    CHECK(materials.at(current) == want);
    if (expect.object_of_face[f] == 1) CHECK(want == "Kd 0 1 0;d 1;");
    if (expect.source[2][f] == 6 && expect.object_of_face[f] == 0) CHECK(want == "Kd 0 0 1;d 0.5;");
    used.insert(current);
    ++f;
  }
  CHECK(used.size() == 3);

  // nOFF keeps the colors.
  const Result off = run(dir, {"slice", "--scene", "scenes/s.json", "--normal", "0,0,0,1",
                               "--offset", "0.1", "-o", "s.off"});
  REQUIRE(off.code == 0);
  CHECK(cw4d::read_off_file((dir / "s.off").string()).colors(2).size() == 12);
}

TEST_CASE("a bad scene exits 2 naming file:line and writes nothing", "[cli]") {
  TempDir dir;
  const std::vector<std::pair<std::string, int>> scenes = {
      {"{\"objects\": [\n{\"model\": \"tesseract\"\n{\"model\": \"5-cell\"}]}", 3},
      {"{\"objects\": [{\"model\": \"tesseract\",\n\"colour\": \"#ff0000\"}]}", 2},
      {"{\"objects\": [{\"model\": \"tesseract\",\n\n\"opacity\": 3}]}", 3},
      {"{\"objects\": [{\"model\": \"tesseract\", \"cell_colors\": {\n\"99\": \"#ff0000\"}}]}", 2},
      {"{\"objects\": [\n{\"model\": \"tessaract\"}]}", 2},
  };
  for (const auto& [text, line] : scenes) {
    INFO(text);
    dir.write("bad.json", text);
    for (const char* out : {"x.obj", "x.svg", "x.4off"}) {
      const Result r = run(
          dir, {"slice", "--scene", "bad.json", "--normal", "0,0,0,1", "--offset", "0", "-o", out});
      CHECK(r.code == 2);
      check_one_error_line(r);
      CHECK(r.err.find("bad.json:" + std::to_string(line) + ":") != std::string::npos);
      CHECK(!dir.exists(out));
      CHECK(!dir.exists("x.mtl"));
    }
  }
  const Result missing = run(dir, {"slice", "--scene", "none.json", "--normal", "0,0,0,1",
                                   "--offset", "0", "-o", "x.obj"});
  CHECK(missing.code == 2);
  CHECK(missing.err.find("none.json:0:") != std::string::npos);
}

TEST_CASE("slice rejects a scene together with MODEL, --rotate or --translate", "[cli]") {
  TempDir dir;
  dir.write("s.json", "{\"objects\": [{\"model\": \"tesseract\"}]}");
  const std::vector<std::vector<std::string>> commands = {
      {"slice", "tesseract", "--scene", "s.json", "--normal", "0,0,0,1", "--offset", "0", "-o",
       "x.obj"},
      {"slice", "--scene", "s.json", "--rotate", "xw:30", "--normal", "0,0,0,1", "--offset", "0",
       "-o", "x.obj"},
      {"slice", "--scene", "s.json", "--translate", "0,0,0,1", "--normal", "0,0,0,1", "--offset",
       "0", "-o", "x.obj"},
      {"slice", "--normal", "0,0,0,1", "--offset", "0", "-o", "x.obj"},
      {"slice", "--scene", "s.json", "--normal", "0,0,1", "--offset", "0", "-o", "x.obj"},
  };
  for (const auto& cmd : commands) {
    std::string text;
    for (const auto& a : cmd) text += a + " ";
    INFO("cw4d " << text);
    const Result r = run(dir, cmd);
    CHECK(r.code == 1);
    check_one_error_line(r);
    CHECK(!dir.exists("x.obj"));
    CHECK(!dir.exists("x.mtl"));
  }
  // The scene's plane misses everything: exit 5, as for a model.
  const Result empty = run(
      dir, {"slice", "--scene", "s.json", "--normal", "0,0,0,1", "--offset", "7", "-o", "x.obj"});
  CHECK(empty.code == 5);
  CHECK(!dir.exists("x.obj"));
}

TEST_CASE("bench measures the hot path, the tetrahedral path and a sweep", "[cli]") {
  const TempDir dir;
  const Result r = run(dir, {"bench", "24-cell", "--layers", "16", "--seconds", "0.05"});
  INFO("stdout: " << r.out << "\nstderr: " << r.err);
  REQUIRE(r.code == 0);
  // Triangles per slice: a tetrahedral cut splits every k-gon of the CW cut into at least
  // k - 2 triangles, so it never has fewer.
  const auto number_after = [&](const std::string& label) {
    const auto at = r.out.find(label);
    REQUIRE(at != std::string::npos);
    const auto us = r.out.find("us", at);
    return std::stod(r.out.substr(us + 2));
  };
  const double cw = number_after("hot path (Slicer)");
  const double tet = number_after("tetrahedral path");
  CHECK(cw > 0.0);
  CHECK(tet >= cw);
  CHECK(r.out.find("slices/sweep") != std::string::npos);
  // Bad budgets are usage errors.
  CHECK(run(dir, {"bench", "--seconds", "0"}).code == 1);
  CHECK(run(dir, {"bench", "cube:3"}).code == 1);
}

TEST_CASE("net writes the tesseract's cross and non-overlapping nets", "[cli][net]") {
  TempDir dir;
  const Result r = run(dir, {"net", "tesseract", "--tree", "bfs", "-o", "out/cross.4off"});
  INFO("stdout: " << r.out << "\nstderr: " << r.err);
  REQUIRE(r.code == 0);
  CHECK(r.err.empty());
  CHECK(r.out.find("8 cells") != std::string::npos);
  CHECK(r.out.find("no overlaps") != std::string::npos);
  const cw4d::Complex cross = cw4d::read_off_file((dir / "out/cross.4off").string());
  CHECK(cw4d::validate(cross).ok());
  REQUIRE(cross.ambient_dim() == 3);
  // A 3D OFF file holds the surface: 8 cubes of 6 squares on their own vertices.
  CHECK(cross.count(0) == 64);
  CHECK(cross.count(2) == 48);
  CHECK(cw4d::signed_volume(cross) == Approx(64.0));

  const Result obj = run(dir, {"net", "tesseract", "--tree", "bfs", "-o", "cross.obj"});
  REQUIRE(obj.code == 0);
  const Obj o = read_obj(dir / "cross.obj");
  CHECK(o.v.size() == 64);
  CHECK(o.f.size() == 48);
  // One group per cell.
  const std::string text = read_text(dir / "cross.obj");
  std::set<std::string> groups;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("g ", 0) == 0) groups.insert(line);
  CHECK(groups.size() == 8);

  for (const std::string model : {"24-cell", "120-cell"}) {
    const Result n = run(dir, {"net", model, "-o", model + ".off"});
    INFO(model << ": " << n.out << n.err);
    REQUIRE(n.code == 0);
    CHECK(n.out.find("no overlaps") != std::string::npos);
    const cw4d::Complex net = cw4d::read_off_file((dir / (model + ".off")).string());
    CHECK(cw4d::validate(net).ok());
    const cw4d::Complex m = cw4d::load_model(model);
    double boundary = 0.0;  // the model's cells, measured in place
    for (std::uint32_t c = 0; c < m.count(3); ++c) boundary += cw4d::element_volume(m, 3, c);
    CHECK(cw4d::signed_volume(net) == Approx(boundary).epsilon(1e-9));
  }

  const Result png = run(dir, {"net", "24-cell", "--size", "320x200", "-o", "n.png"});
  REQUIRE(png.code == 0);
  const std::string bytes = read_text(dir / "n.png");
  REQUIRE(bytes.size() > 24);
  CHECK(bytes.substr(1, 3) == "PNG");
  const auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(bytes[at]) << 24) |
           (static_cast<unsigned char>(bytes[at + 1]) << 16) |
           (static_cast<unsigned char>(bytes[at + 2]) << 8) |
           static_cast<unsigned char>(bytes[at + 3]);
  };
  CHECK(be32(16) == 320u);
  CHECK(be32(20) == 200u);

  const Result cube = run(dir, {"net", "cube:3", "-o", "cube.obj"});
  REQUIRE(cube.code == 0);
  CHECK(cube.out.find("6 faces") != std::string::npos);
  CHECK(cube.out.find("area 24") != std::string::npos);
  CHECK(read_obj(dir / "cube.obj").f.size() == 6);

  // A tree that overlaps is written, with a warning.
  const Result dfs = run(dir, {"net", "120-cell", "--tree", "dfs", "-o", "dfs.obj"});
  CHECK(dfs.code == 0);
  CHECK(dfs.err.rfind("cw4d: warning: the net overlaps itself", 0) == 0);
  CHECK(dir.exists("dfs.obj"));
}

TEST_CASE("net refuses bad requests with one line and writes nothing", "[cli][net]") {
  TempDir dir;
  dir.write("open.4off", kOpenCell);
  dir.write("file", "x");
  const std::vector<std::pair<std::vector<std::string>, int>> cases = {
      {{"net", "tesseract", "--root", "8", "-o", "x.obj"}, 1},
      {{"net", "tesseract", "--tree", "spiral", "-o", "x.obj"}, 1},
      {{"net", "tesseract", "-o", "x.xyz"}, 1},
      {{"net", "tesseract", "--format", "png", "-o", "x.obj"}, 1},
      {{"net", "cube:5", "-o", "x.obj"}, 1},
      {{"net", "cube:3", "-o", "x.png"}, 1},
      {{"net", "cube:3", "-o", "x.svg"}, 1},
      {{"net", "no-such-model", "-o", "x.obj"}, 1},
      {{"net", "open.4off", "-o", "x.obj"}, 3},
      {{"net", "tesseract", "-o", "file/x.obj"}, 4},
  };
  for (const auto& [cmd, code] : cases) {
    const Result r = run(dir, cmd);
    INFO(cmd[1] << " " << cmd.back() << ": " << r.err);
    CHECK(r.code == code);
    check_one_error_line(r);
    CHECK(!dir.exists("x.obj"));
    CHECK(!dir.exists("x.png"));
  }
}

TEST_CASE("info reports the mass properties, atlas the critical offsets", "[cli]") {
  TempDir dir;
  // [-1,1]^4: hypervolume 16, eight cubes of 8, centroid 0, int x^2 = 2^3 * 2/3 = 16/3.
  const auto j = nlohmann::json::parse(run(dir, {"info", "tesseract", "--json"}).out);
  const auto& m = j.at("mass");
  CHECK(m.at("hypervolume").get<double>() == Approx(16.0).epsilon(1e-14));
  CHECK(m.at("boundary_volume").get<double>() == Approx(64.0).epsilon(1e-14));
  REQUIRE(m.at("centroid").size() == 4);
  REQUIRE(m.at("second_moment").size() == 4);
  for (int i = 0; i < 4; ++i) {
    CHECK(std::abs(m["centroid"][i].get<double>()) < 1e-14);
    for (int k = 0; k < 4; ++k)
      CHECK(m["second_moment"][i][k].get<double>() ==
            Approx(i == k ? 16.0 / 3.0 : 0.0).margin(1e-13));
  }
  CHECK(m.at("winding_weighted") == false);
  const Result text = run(dir, {"info", "tesseract"});
  CHECK(text.out.find("boundary   64") != std::string::npos);
  const auto star = nlohmann::json::parse(run(dir, {"info", "great 120-cell", "--json"}).out);
  CHECK(star.at("mass").at("winding_weighted") == true);
  CHECK(run(dir, {"info", "great 120-cell"}).out.find("winding number") != std::string::npos);

  dir.write("open.4off", kOpenCell);
  const auto open = nlohmann::json::parse(run(dir, {"info", "open.4off", "--json"}).out);
  CHECK(open.at("mass").is_null());
  CHECK(!open.at("mass_reason").get<std::string>().empty());

  // The tesseract along (1,1,1,1): heights -2..2; tetrahedron, truncated tetrahedron twice,
  // tetrahedron.
  const Result atlas = run(dir, {"atlas", "tesseract", "--normal", "1,1,1,1", "--json"});
  REQUIRE(atlas.code == 0);
  const auto a = nlohmann::json::parse(atlas.out);
  CHECK(a.at("critical_offsets") == nlohmann::json({-2.0, -1.0, 0.0, 1.0, 2.0}));
  REQUIRE(a.at("intervals").size() == 4);
  CHECK(a["intervals"][0]["f_vector"] == nlohmann::json({4, 6, 4}));
  CHECK(a["intervals"][1]["f_vector"] == nlohmann::json({12, 18, 8}));
  CHECK(a["intervals"][1]["from"] == -1.0);
  CHECK(a["intervals"][1]["to"] == 0.0);
  CHECK(a["critical_sections"][2]["f_vector"] == nlohmann::json({6, 12, 8}));
  CHECK(a["critical_sections"][2]["degenerate"] == true);

  const Result sheet =
      run(dir, {"atlas", "tesseract", "--normal", "1,0,0,0", "-o", "out/sheet.png"});
  CHECK(sheet.code == 0);
  CHECK(dir.exists("out/sheet.png"));
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"atlas", "tesseract", "--normal", "0,0,0,0"},
           {"atlas", "tesseract", "--normal", "1,0,0"},
           {"atlas", "tesseract"},
           {"atlas", "no-such-model", "--normal", "1,0,0,0"},
           {"atlas", "tesseract", "--normal", "1,0,0,0", "-o", "x.obj"}}) {
    const Result bad = run(dir, args);
    CHECK(bad.code == 1);
    check_one_error_line(bad);
  }
  const Result invalid = run(dir, {"atlas", "open.4off", "--normal", "1,0,0,0"});
  CHECK(invalid.code == 3);
  check_one_error_line(invalid);
}
