// `cw4d render`: every mode writes a PNG of the requested size with something drawn on it, for
// built-ins and the example scene; bad requests exit with the documented codes and write nothing.
#include <catch2/catch.hpp>

#include <sys/stat.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cw4d/render/image.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using cw4d::test::Result;

struct TempDir : cw4d::test::TempDir {
  TempDir() : cw4d::test::TempDir("cw4d_test_render_cli") {}
};

Result run(const TempDir& dir, const std::vector<std::string>& args) {
  return cw4d::test::run_program(dir, CW4D_EXE, args);
}

// Fraction of pixels that differ from the white background.
double drawn_fraction(const cw4d::render::Image8& img) {
  std::size_t drawn = 0;
  for (std::size_t i = 0; i < img.bytes.size(); i += img.channels)
    if (img.bytes[i] < 250 || img.bytes[i + 1] < 250 || img.bytes[i + 2] < 250) ++drawn;
  return static_cast<double>(drawn) / (static_cast<double>(img.width) * img.height);
}

const std::string kScene = std::string(CW4D_SOURCE_DIR) + "/data/example-scene.json";

}  // namespace

TEST_CASE("cw4d render writes each kind of picture", "[render][cli]") {
  TempDir dir;
  struct Case {
    std::vector<std::string> args;
    int width, height;
    double min_drawn;
  };
  const std::vector<Case> cases = {
      {{"24-cell", "--normal", "1,1,1,1", "--offset", "0.3", "--edges"}, 200, 150, 0.2},
      {{"--scene", kScene, "--normal", "0,0,0,1", "--offset", "0.1"}, 200, 150, 0.05},
      {{"tesseract", "--mode", "cloud", "--normal", "0,0,1,1", "--layers", "12"}, 160, 120, 0.1},
      {{"--scene", kScene, "--mode", "cloud", "--normal", "0,0,0,1", "--layers", "8"},
       160,
       120,
       0.05},
      {{"120-cell", "--mode", "wireframe"}, 200, 150, 0.05},
      {{"5-cell", "--mode", "wireframe", "--no-occlusion", "--eye4", "1,0,0,0"}, 200, 150, 0.01},
      {{"tesseract", "--mode", "stereographic"}, 200, 150, 0.03},
      {{"24-cell", "--mode", "stereographic", "--lines", "--rotate", "xw:10"}, 200, 150, 0.01},
      {{"24-cell", "--mode", "stereo", "--normal", "0,0,0,1"}, 400, 150, 0.1},
      {{"tesseract", "--mode", "sheet", "--normal", "1,1,0,1", "--layers", "6", "--columns", "3"},
       3 * 100 + 4 * 4,
       2 * 100 + 3 * 4,
       0.1},
  };
  int k = 0;
  for (const auto& c : cases) {
    const std::string out = "pic" + std::to_string(k++) + ".png";
    std::vector<std::string> args = {"render"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const bool sheet = c.args.size() > 2 && c.args[2] == "sheet";
    const bool stereo = c.args.size() > 2 && c.args[2] == "stereo";
    const int w = sheet ? 100 : (stereo ? c.width / 2 : c.width), h = sheet ? 100 : c.height;
    args.insert(args.end(), {"--size", std::to_string(w) + "x" + std::to_string(h), "--samples",
                             "2", "-o", out});
    const Result r = run(dir, args);
    CAPTURE(c.args, r.err);
    REQUIRE(r.code == 0);
    const cw4d::render::Image8 img = cw4d::render::read_png((dir / out).string());
    CHECK(img.width == c.width);
    CHECK(img.height == c.height);
    CHECK(drawn_fraction(img) > c.min_drawn);
  }
}

// Fraction of covered pixels whose color differs between two pictures of the same size.
double differing_fraction(const cw4d::render::Image8& a, const cw4d::render::Image8& b) {
  std::size_t differ = 0, covered = 0;
  for (std::size_t i = 0; i + 2 < a.bytes.size(); i += a.channels) {
    const bool drawn = a.bytes[i] < 250 || a.bytes[i + 1] < 250 || a.bytes[i + 2] < 250;
    if (!drawn) continue;
    ++covered;
    int d = 0;
    for (int c = 0; c < 3; ++c) d += std::abs(int(a.bytes[i + c]) - int(b.bytes[i + c]));
    if (d > 12) ++differ;
  }
  return covered ? static_cast<double>(differ) / covered : 0.0;
}

TEST_CASE("cw4d render textures sections and lights them in 4D", "[render][cli]") {
  TempDir dir;
  const std::vector<std::string> base = {"render",   "tesseract", "--normal",  "0,0,0,1",
                                         "--offset", "0.1",       "--rotate",  "xy:20",
                                         "--size",   "160x120",   "--samples", "1"};
  auto render = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    args.insert(args.end(), {"-o", out});
    const Result r = run(dir, args);
    CAPTURE(extra, r.err);
    REQUIRE(r.code == 0);
    return cw4d::render::read_png((dir / out).string());
  };
  const auto plain = render("plain.png", {});
  const auto checker = render("checker.png", {"--texture", "checker:4"});
  const auto tet = render("tet.png", {"--texture", "checker:4", "--method", "tet"});
  CHECK(differing_fraction(plain, checker) > 0.2);
  CHECK(differing_fraction(checker, tet) < 0.02);  // both paths texture alike
  CHECK(differing_fraction(plain, render("obj.png", {"--texture", "object=0:wood"})) > 0.01);
  // A section on a checker's wall (w = 0: checker:8 has p_w = 4 on every face) shows the side
  // above the wall on every pixel, as a section just above it does (the same cube), not a
  // per-pixel mix of the two sides.
  auto wall = [&](const std::string& out, const std::string& offset) {
    const Result r = run(dir, {"render", "tesseract", "--normal", "0,0,0,1", "--offset", offset,
                               "--texture", "checker:8", "--size", "160x120", "-o", out});
    CAPTURE(offset, r.err);
    REQUIRE(r.code == 0);
    return cw4d::render::read_png((dir / out).string());
  };
  CHECK(differing_fraction(wall("wall.png", "0"), wall("above.png", "0.0001")) == 0.0);
  // 4D light: turning the model in xw changes the picture of the same section (w-cells lit
  // differently), while the 3D studio light sees only the section's shape.
  const auto l20 = render("l20.png", {"--light-mode", "4d", "--rotate", "xw:20"});
  const auto l35 = render("l35.png", {"--light4", "0,0,0.3,1", "--rotate", "xw:35"});
  const auto p20 = render("p20.png", {"--light4", "point:0,0,0,3:3", "--rotate", "xw:20"});
  CHECK(differing_fraction(l20, l35) > 0.2);
  CHECK(drawn_fraction(p20) > 0.1);
  // Bad texture and light specs exit 1 and write nothing.
  TempDir bad;
  CHECK(
      run(bad, {"render", "tesseract", "--normal", "0,0,0,1", "--texture", "plaid", "-o", "a.png"})
          .code == 1);
  CHECK(run(bad, {"render", "tesseract", "--normal", "0,0,0,1", "--light4", "1,2,3", "-o", "a.png"})
            .code == 1);
  CHECK(run(bad, {"render", "tesseract", "--normal", "0,0,0,1", "--method", "tet", "--mode",
                  "stereo", "-o", "a.png"})
            .code == 1);
  CHECK(bad.entries() == 0);
}

TEST_CASE("cw4d render: view-aligned clouds, stereo pairs, sections in wireframes, eye inside",
          "[render][cli]") {
  TempDir dir;
  struct Case {
    std::vector<std::string> args;
    int width;
    std::string says;
  };
  const std::vector<Case> cases = {
      {{"tesseract", "--mode", "cloud", "--normal", "0,0,1,1", "--view", "1,0,0.05"},
       120,
       "stacked along u"},
      {{"tesseract", "--mode", "cloud", "--normal", "0,0,1,1", "--stack", "s"},
       120,
       "stacked along s"},
      {{"tesseract", "--mode", "cloud", "--normal", "0,0,1,1", "--stereo"}, 240, "stereo pair"},
      {{"24-cell", "--mode", "wireframe", "--stereo"}, 240, "stereo pair"},
      {{"24-cell", "--mode", "wireframe", "--section", "--offset", "0.3"}, 120, "its section"},
      {{"tesseract", "--mode", "wireframe", "--eye4-at", "0.2,0.1,0,0", "--look4", "0,0,0,1",
        "--fov4", "120"},
       120,
       "4D wireframe"},
  };
  int k = 0;
  for (const auto& c : cases) {
    const std::string out = "v" + std::to_string(k++) + ".png";
    std::vector<std::string> args = {"render"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    args.insert(args.end(), {"--size", "120x90", "--samples", "1", "--layers", "12", "-o", out});
    const Result r = run(dir, args);
    CAPTURE(c.args, r.err, r.out);
    REQUIRE(r.code == 0);
    CHECK(r.out.find(c.says) != std::string::npos);
    const auto img = cw4d::render::read_png((dir / out).string());
    CHECK(img.width == c.width);
    CHECK(drawn_fraction(img) > 0.02);
  }
  TempDir bad;
  CHECK(run(bad, {"render", "tesseract", "--normal", "0,0,0,1", "--stereo", "-o", "a.png"}).code ==
        1);
  CHECK(run(bad, {"render", "tesseract", "--mode", "wireframe", "--eye4-at", "0,0,0,1", "--look4",
                  "0,0,0,1", "-o", "a.png"})
            .code == 1);
  CHECK(run(bad, {"render", "tesseract", "--mode", "cloud", "--normal", "0,0,0,1", "--stack", "w",
                  "-o", "a.png"})
            .code == 1);
  CHECK(bad.entries() == 0);
}

TEST_CASE("cw4d render --animate writes an animated WebP", "[render][cli]") {
  TempDir dir;
  for (const std::string kind : {"sweep", "rotate:xw", "orbit"}) {
    // (A normal with changing sections: libwebp folds identical frames into one.)
    const Result r =
        run(dir, {"render", "tesseract", "--normal", "1,1,1,1", "--offset", "0.2", "--animate",
                  kind, "--frames", "5", "--size", "64x48", "-o", "a.webp"});
    CAPTURE(kind, r.err);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("5 frames") != std::string::npos);
    const std::string bytes = cw4d::test::read_text(dir / "a.webp");
    // RIFF....WEBP with the animation chunk of the extended format.
    REQUIRE(bytes.size() > 40);
    CHECK(bytes.compare(0, 4, "RIFF") == 0);
    CHECK(bytes.compare(8, 4, "WEBP") == 0);
    CHECK(bytes.find("ANIM") != std::string::npos);
    CHECK(bytes.find("ANMF") != std::string::npos);
  }
  CHECK(dir.entries() == 1);  // no temporary file left
  TempDir bad;
  CHECK(
      run(bad, {"render", "tesseract", "--normal", "0,0,0,1", "--animate", "spin", "-o", "a.webp"})
          .code == 1);
  CHECK(run(bad, {"render", "tesseract", "--normal", "0,0,0,1", "--animate", "rotate:xx", "-o",
                  "a.webp"})
            .code == 1);
  CHECK(
      run(bad, {"render", "tesseract", "--normal", "0,0,0,1", "--animate", "sweep", "-o", "a.png"})
          .code == 1);
  CHECK(run(bad, {"render", "tesseract", "--normal", "0,0,0,1", "--offset", "7", "--animate",
                  "orbit", "-o", "a.webp"})
            .code == 5);
  CHECK(bad.entries() == 0);
}

TEST_CASE("cw4d render --animate writes an animated GIF", "[render][cli]") {
  TempDir dir;
  const Result r =
      run(dir, {"render", "tesseract", "--normal", "1,1,1,1", "--offset", "0.2", "--animate",
                "sweep", "--frames", "4", "--frame-ms", "50", "--size", "64x48", "-o", "a.gif"});
  CAPTURE(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out.find("4 frames") != std::string::npos);
  const std::string bytes = cw4d::test::read_text(dir / "a.gif");
  REQUIRE(bytes.size() > 13);
  CHECK(bytes.compare(0, 6, "GIF89a") == 0);
  CHECK((static_cast<unsigned char>(bytes[6]) | static_cast<unsigned char>(bytes[7]) << 8) == 64);
  CHECK((static_cast<unsigned char>(bytes[8]) | static_cast<unsigned char>(bytes[9]) << 8) == 48);
  CHECK(bytes.find("NETSCAPE2.0") != std::string::npos);
  // One image descriptor (0x2c) after each graphic control extension (0x21 0xf9), 4 frames.
  std::size_t gce = 0;
  for (std::size_t at = bytes.find("\x21\xf9"); at != std::string::npos;
       at = bytes.find("\x21\xf9", at + 1))
    gce += at + 8 < bytes.size() && bytes[at + 8] == '\x2c';
  CHECK(gce == 4);
  CHECK(bytes.back() == '\x3b');  // the trailer
  CHECK(dir.entries() == 1);      // no temporary file left
}

TEST_CASE("cw4d render frames writes numbered PNGs", "[render][cli]") {
  TempDir dir;
  const Result r = run(dir, {"render", "16-cell", "--mode", "frames", "--normal", "0,0,0,1",
                             "--layers", "5", "--size", "64x48", "-o", "anim/f.png"});
  INFO(r.err);
  REQUIRE(r.code == 0);
  for (int i = 0; i < 5; ++i) {
    const auto p = dir / ("anim/f_000" + std::to_string(i) + ".png");
    REQUIRE(fs::exists(p));
    CHECK(cw4d::render::read_png(p.string()).width == 64);
  }
  CHECK_FALSE(fs::exists(dir / "anim/f_0005.png"));
}

TEST_CASE("cw4d render rejects bad requests without writing", "[render][cli]") {
  TempDir dir;
  // No --normal for a section, a non-PNG output, a bad size, an unknown mode, a scene for the
  // stereographic mode, a plane that misses the model.
  CHECK(run(dir, {"render", "tesseract", "-o", "a.png"}).code == 1);
  CHECK(run(dir, {"render", "tesseract", "--normal", "0,0,0,1", "-o", "a.svg"}).code == 1);
  CHECK(run(dir, {"render", "tesseract", "--normal", "0,0,0,1", "--size", "0x5", "-o", "a.png"})
            .code == 1);
  CHECK(run(dir, {"render", "tesseract", "--mode", "raytrace", "-o", "a.png"}).code == 1);
  CHECK(run(dir, {"render", "--scene", kScene, "--mode", "stereographic", "-o", "a.png"}).code ==
        1);
  CHECK(run(dir, {"render", "cube:3", "--normal", "0,0,1", "-o", "a.png"}).code == 1);
  const Result miss =
      run(dir, {"render", "tesseract", "--normal", "0,0,0,1", "--offset", "5", "-o", "a.png"});
  CHECK(miss.code == 5);
  CHECK(miss.err.rfind("cw4d: error: ", 0) == 0);
  CHECK(dir.entries() == 0);
}

TEST_CASE("cw4d render --mode schlegel draws every edge from outside one cell", "[render][cli]") {
  TempDir dir;
  const Result r =
      run(dir, {"render", "120-cell", "--mode", "schlegel", "--size", "200x150", "-o", "s.png"});
  INFO(r.out << r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out.find("1200 edges") != std::string::npos);
  const auto img = cw4d::render::read_png((dir / "s.png").string());
  CHECK(img.width == 200);
  CHECK(img.height == 150);
  CHECK(drawn_fraction(img) > 0.05);
  const Result faces = run(
      dir, {"render", "tesseract", "--mode", "schlegel", "--faces", "--cell", "3", "-o", "t.png"});
  REQUIRE(faces.code == 0);
  CHECK(faces.out.find("32 edges and 24 faces, seen from outside cell 3") != std::string::npos);
  const Result bad =
      run(dir, {"render", "tesseract", "--mode", "schlegel", "--cell", "8", "-o", "bad.png"});
  CHECK(bad.code == 1);
  CHECK(!fs::exists(dir / "bad.png"));
  const Result flat = run(dir, {"render", "cube:3", "--mode", "schlegel", "-o", "c.png"});
  CHECK(flat.code == 1);
  CHECK(!fs::exists(dir / "c.png"));
}

TEST_CASE("cw4d render refuses hostile texture patterns, slices and sizes", "[render][cli]") {
  TempDir dir;
  auto one_line = [](const Result& r) {
    return r.err.rfind("cw4d: error: ", 0) == 0 && r.err.find('\n') == r.err.size() - 1;
  };
  // A printf conversion in the pattern is a usage error, not a crash.
  for (const std::string pattern : {"%nd", "%s%d", "z%d%d.png"}) {
    const Result r = run(dir, {"render", "tesseract", "--normal", "0,0,0,1", "--texture",
                               "volume:" + pattern, "-o", "t.png"});
    CAPTURE(pattern, r.err);
    CHECK(r.code == 1);
    CHECK(one_line(r));
    CHECK(r.err.find("'" + pattern + "'") != std::string::npos);
  }
  // A FIFO slice and /dev/zero: exit 2 at once.
  REQUIRE(::mkfifo((dir / "f0.png").c_str(), 0600) == 0);
  fs::create_symlink("/dev/zero", dir / "z0.png");
  for (const std::string pattern : {"f%d.png", "z%d.png"}) {
    const Result r = run(dir, {"render", "tesseract", "--normal", "0,0,0,1", "--texture",
                               "volume:" + pattern, "-o", "t.png"});
    CAPTURE(pattern, r.err);
    CHECK(r.code == 2);
    CHECK(one_line(r));
    CHECK(r.err.find("not a regular file") != std::string::npos);
  }
  // A side beyond int is not wrapped around into a small one.
  const Result big = run(dir, {"render", "tesseract", "--normal", "0,0,0,1", "--size",
                               "4294967297x600", "-o", "t.png"});
  CHECK(big.code == 1);
  CHECK(big.err.find("--size") != std::string::npos);
  // Schlegel mode on a 2D model blames the model's dimension, not a --normal never given.
  const Result sch = run(dir, {"render", "polygon:5", "--mode", "schlegel", "-o", "t.png"});
  CHECK(sch.code == 1);
  CHECK(sch.err.find("--normal") == std::string::npos);
  CHECK(sch.err.find("R^2") != std::string::npos);
  CHECK(!fs::exists(dir / "t.png"));
}

TEST_CASE("cw4d render --animate refuses more work than it draws in reasonable time",
          "[render][cli]") {
  TempDir dir;
  // 1000 frames of 16384 x 4000: within the pixels held at once (one frame), beyond the
  // pixels drawn over all frames: refused up front, nothing written.
  const Result r = run(dir, {"render", "tesseract", "--normal", "0,0,0,1", "--animate", "sweep",
                             "--frames", "1000", "--size", "16384x4000", "-o", "a.webp"});
  CHECK(r.code == 1);
  CHECK(r.err.find("--frames") != std::string::npos);
  CHECK(dir.entries() == 0);
}
