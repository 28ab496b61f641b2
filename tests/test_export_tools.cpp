// The files `cw4d slice` and `cw4d sweep` write, opened by the tools users open them with:
// the Khronos glTF-Validator must report no errors and no warnings, and assimp must load every
// OBJ/glTF/PLY/STL with the counts the section has (computed here from the library).
#include <catch2/catch.hpp>

#include <regex>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/section/section.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/vectors.hpp"

namespace {

using cw4d::test::Result;
using cw4d::test::vec;

struct TempDir : cw4d::test::TempDir {
  TempDir() : cw4d::test::TempDir("cw4d_test_export_tools") {}
};

Result cw4d_run(const TempDir& dir, const std::vector<std::string>& args) {
  Result r = cw4d::test::run_program(dir, CW4D_EXE, args);
  INFO("cw4d stderr: " << r.err);
  REQUIRE(r.code == 0);
  return r;
}

// The glTF-Validator's verdict on the files; its report lines go to the test log.
void validate(const TempDir& dir, const std::vector<std::string>& files) {
  std::vector<std::string> args{CW4D_GLTF_VALIDATOR_SCRIPT, CW4D_NODE_MODULES};
  args.insert(args.end(), files.begin(), files.end());
  const Result r = cw4d::test::run_program(dir, CW4D_NODE, args);
  INFO("glTF-Validator:\n" << r.out << r.err);
  REQUIRE(r.code != 2);  // the validator itself could not run (see ./setup.sh test)
  CHECK(r.code == 0);
  for (const auto& f : files) CHECK(r.out.find(f + ": errors 0 warnings 0") != std::string::npos);
}

struct AssimpCounts {
  long meshes = -1, vertices = -1, faces = -1;
};

// `assimp info` loads the file (triangulating, as its default post-processing does) and
// prints the scene's totals.
AssimpCounts assimp_info(const TempDir& dir, const std::string& file) {
  const Result r = cw4d::test::run_program(dir, CW4D_ASSIMP, {"info", file});
  INFO("assimp info " << file << ":\n" << r.out << r.err);
  REQUIRE(r.code == 0);
  AssimpCounts c;
  const auto number = [&](const char* label) {
    std::smatch m;
    const std::regex re(std::string("\\n") + label + ":\\s+(\\d+)");
    REQUIRE(std::regex_search(r.out, m, re));
    return std::stol(m[1]);
  };
  c.meshes = number("Meshes");
  c.vertices = number("Vertices");
  c.faces = number("Faces");
  return c;
}

long triangles_of(const cw4d::Section& s) {
  long n = 0;
  for (std::uint32_t f = 0; f < s.complex.count(2); ++f)
    n += static_cast<long>(s.complex.face_cycle(f).size()) - 2;
  return n;
}

long corners_of(const cw4d::Section& s) {
  long n = 0;
  for (std::uint32_t f = 0; f < s.complex.count(2); ++f)
    n += static_cast<long>(s.complex.face_cycle(f).size());
  return n;
}

}  // namespace

TEST_CASE(
    "slice: glTF, GLB, OBJ, PLY and STL open in the validator and assimp with the "
    "section's counts",
    "[export][tools]") {
  TempDir dir;
  for (const char* spec : {"tesseract", "24-cell", "120-cell"}) {
    INFO(spec);
    const std::vector<std::string> cut{"--rotate", "xw:30",   "--rotate", "yw:20",
                                       "--normal", "0,0,0,1", "--offset", "0.3"};
    const cw4d::Complex model = cw4d::load_model(spec);
    const cw4d::AffineTransform xf =
        cw4d::AffineTransform::rotation(4, 1, 3, cw4d::test::radians(20)) *
        cw4d::AffineTransform::rotation(4, 0, 3, cw4d::test::radians(30));
    const cw4d::Section sec =
        cw4d::section(model, cw4d::Hyperplane::from(vec({0, 0, 0, 1}), 0.3), xf);
    REQUIRE(!sec.empty());
    const long tris = triangles_of(sec), corners = corners_of(sec);
    for (const char* ext : {"glb", "gltf", "obj", "ply", "stl"}) {
      std::vector<std::string> args{"slice", spec};
      args.insert(args.end(), cut.begin(), cut.end());
      args.push_back("-o");
      args.push_back(std::string("s.") + ext);
      cw4d_run(dir, args);
    }
    validate(dir, {"s.glb", "s.gltf"});
    for (const char* f : {"s.glb", "s.gltf"}) {
      const AssimpCounts c = assimp_info(dir, f);
      CHECK(c.meshes == 1);
      CHECK(c.vertices == corners);  // corners are split: flat normals per polygon
      CHECK(c.faces == tris);
    }
    const AssimpCounts obj = assimp_info(dir, "s.obj");
    CHECK(obj.meshes == static_cast<long>(sec.complex.count(2)));  // a `g` group per cell
    CHECK(obj.faces == tris);
    const AssimpCounts ply = assimp_info(dir, "s.ply");
    CHECK(ply.meshes == 1);
    CHECK(ply.vertices == static_cast<long>(sec.complex.count(0)));  // welded
    CHECK(ply.faces == tris);
    const AssimpCounts stl = assimp_info(dir, "s.stl");
    CHECK(stl.meshes == 1);
    CHECK(stl.faces == tris);
  }
}

TEST_CASE("slice --scene: one glTF node per object the plane meets, validated", "[export][tools]") {
  TempDir dir;
  cw4d_run(dir, {"slice", "--scene", CW4D_SOURCE_DIR "/data/example-scene.json", "--normal",
                 "0,0,0,1", "--offset", "0.1", "-o", "scene.glb"});
  validate(dir, {"scene.glb"});
  const AssimpCounts c = assimp_info(dir, "scene.glb");
  CHECK(c.meshes == 3);
  // The OBJ keeps the scene's objects apart: assimp (like Blender) makes a node per `o` line.
  cw4d_run(dir, {"slice", "--scene", CW4D_SOURCE_DIR "/data/example-scene.json", "--normal",
                 "0,0,0,1", "--offset", "0.1", "-o", "scene.obj"});
  const Result info = cw4d::test::run_program(dir, CW4D_ASSIMP, {"info", "scene.obj"});
  REQUIRE(info.code == 0);
  for (const char* name : {"centre", "left", "right"}) {
    INFO(name << " in\n" << info.out);
    CHECK(info.out.find(std::string("\u2574") + name + "\n") != std::string::npos);  // "├╴name"
  }
}

TEST_CASE("sweep: 64 layers of the 24-cell as one animated GLB with 64 meshes", "[export][tools]") {
  TempDir dir;
  const Result r = cw4d_run(dir, {"sweep", "24-cell", "--normal", "1,1,1,1", "--from", "-1.9",
                                  "--to", "1.9", "--layers", "64", "-o", "sweep.glb"});
  CHECK(r.out.rfind("wrote sweep.glb: 64 of 64 layers", 0) == 0);
  CHECK(r.err.empty());  // no progress bar when stderr is not a terminal
  validate(dir, {"sweep.glb"});
  const AssimpCounts c = assimp_info(dir, "sweep.glb");
  CHECK(c.meshes == 64);
  const Result info = cw4d::test::run_program(dir, CW4D_ASSIMP, {"info", "sweep.glb"});
  CHECK(info.out.find("Animations:         1") != std::string::npos);
}

TEST_CASE("sweep: numbered files in a folder, empty layers reported and not written",
          "[export][tools]") {
  TempDir dir;
  // The tesseract spans w in [-1, 1]: the first and last of these 6 layers miss it.
  const Result r = cw4d_run(dir, {"sweep", "tesseract", "--normal", "0,0,0,1", "--from", "-1.5",
                                  "--to", "1.5", "--layers", "6", "--format", "ply", "-o", "out"});
  CHECK(r.out.find("4 of 6 layers") != std::string::npos);
  CHECK(r.out.find("empty layers (not written): 0 (d=-1.5) 5 (d=1.5)") != std::string::npos);
  for (int i = 0; i < 6; ++i) {
    const std::string name = "out/layer_00" + std::to_string(i) + ".ply";
    CHECK(dir.exists(name) == (i != 0 && i != 5));
    if (i != 0 && i != 5) CHECK(assimp_info(dir, name).faces == 12);
  }
  // A file name is numbered: s.obj -> s_000.obj ...; OBJ files come with their UVW.
  cw4d_run(dir, {"sweep", "16-cell", "--normal", "1,0,0,0", "--from", "-0.5", "--to", "0.5",
                 "--layers", "3", "-o", "objs/s.obj"});
  for (const char* f : {"objs/s_000.obj", "objs/s_001.obj", "objs/s_002.obj"}) {
    CHECK(assimp_info(dir, f).faces == 8);  // |x| < 1 cuts the 16-cell in an octahedron
  }
  // A layer that cannot be written (its path is a directory): exit 4, and the layers written
  // before it are removed again.
  std::filesystem::create_directories(dir / "fail/layer_002.ply");
  const Result fail =
      cw4d::test::run_program(dir, CW4D_EXE,
                              {"sweep", "tesseract", "--normal", "0,0,0,1", "--from", "-0.5",
                               "--to", "0.5", "--layers", "4", "--format", "ply", "-o", "fail"});
  CHECK(fail.code == 4);
  CHECK(!dir.exists("fail/layer_000.ply"));
  CHECK(!dir.exists("fail/layer_001.ply"));
  CHECK(!dir.exists("fail/layer_003.ply"));
  // Every layer misses: exit 5, nothing written.
  const Result miss =
      cw4d::test::run_program(dir, CW4D_EXE,
                              {"sweep", "tesseract", "--normal", "0,0,0,1", "--from", "2", "--to",
                               "3", "--layers", "4", "-o", "none.glb"});
  CHECK(miss.code == 5);
  CHECK(!dir.exists("none.glb"));
}

TEST_CASE("sweep: a progress bar on a terminal, none with --quiet", "[export][tools]") {
  TempDir dir;
  // script(1) runs the command with its output on a pseudo-terminal.
  const auto on_terminal = [&](const std::string& extra) {
    const std::string cmd = cw4d::test::shell_quote(CW4D_EXE) +
                            " sweep 16-cell --normal 1,1,1,1 --from -0.5 --to 0.5 --layers 8 " +
                            extra + " -o p.glb";
    return cw4d::test::run_program(dir, "script", {"-qec", cmd, "/dev/null"});
  };
  const Result bar = on_terminal("");
  REQUIRE(bar.code == 0);
  CHECK(bar.out.find("\rcw4d: sweep [") != std::string::npos);
  CHECK(bar.out.find("] 8/8 layers") != std::string::npos);
  const Result quiet = on_terminal("--quiet");
  REQUIRE(quiet.code == 0);
  CHECK(quiet.out.find("cw4d: sweep [") == std::string::npos);
  CHECK(quiet.out.find("wrote p.glb: 8 of 8 layers") != std::string::npos);
}
