// Hostile input, end to end: a catalogue of malformed model files, scenes, special files and
// contradictory command lines. Each one, run through the real cw4d binary, must give exactly one
// "cw4d: error: ..." line that names file:line (files) or the offending option (command lines),
// the documented exit code, and no output file. The library side of the same inputs is checked
// too: the reader throws ParseError with the same line, or validate() names an element whose
// line OffLines reports. (test_off_io.cpp has the reader's per-message catalogue; this one is
// about what a user of the CLI sees.)
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/input_file.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/complex/wythoff.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using cw4d::test::read_text;

// The documented exit codes (cw4d --help).
enum Exit : int { usage = 1, bad_input = 2, invalid_complex = 3 };

struct TempDir : cw4d::test::TempDir {
  TempDir() : cw4d::test::TempDir("cw4d_test_hostile") {}
};

std::string quote(const std::string& s) {
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

struct Result {
  int code = -1;
  std::string out, err;
};

Result run(const TempDir& dir, const std::vector<std::string>& args) {
  const std::string out = (dir / ".stdout").string(), err = (dir / ".stderr").string();
  std::string cmd = "cd " + quote(dir.path().string()) + " && " + quote(CW4D_EXE);
  for (const auto& a : args) cmd += ' ' + quote(a);
  cmd += " >" + quote(out) + " 2>" + quote(err) + " </dev/null";
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

// Exactly one line, "cw4d: error: " then the message, printable ASCII only (a message quoting
// non-UTF-8 bytes of the input escapes them).
void check_one_printable_error_line(const Result& r) {
  INFO("stderr: " << r.err);
  REQUIRE(!r.err.empty());
  CHECK(r.err.rfind("cw4d: error: ", 0) == 0);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK(r.err.back() == '\n');
  CHECK(std::all_of(r.err.begin(), r.err.end() - 1, [](char ch) {
    return static_cast<unsigned char>(ch) >= 0x20 && static_cast<unsigned char>(ch) < 0x7f;
  }));
}

// Files in a directory, the hidden capture files excluded.
std::vector<std::string> listing(const TempDir& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir.path()))
    names.push_back(fs::relative(e.path(), dir.path()).string());
  std::sort(names.begin(), names.end());
  return names;
}

// --- the model-file catalogue -------------------------------------------------------------------

// The regular 5-cell as 4OFF, one element per line: line 1 header, 2 counts, 3-7 vertices,
// 8-17 faces, 18-22 cells.
std::vector<std::string> five_cell_lines() {
  return {"4OFF",
          "5 10 10 5",
          "1 0 0 0",
          "0 1 0 0",
          "0 0 1 0",
          "0 0 0 1",
          "-0.6 -0.6 -0.6 -0.6",
          "3 0 1 2",
          "3 0 1 3",
          "3 0 2 3",
          "3 1 2 3",
          "3 0 1 4",
          "3 0 2 4",
          "3 1 2 4",
          "3 0 3 4",
          "3 1 3 4",
          "3 2 3 4",
          "4 0 1 2 3",
          "4 0 4 5 6",
          "4 1 4 7 8",
          "4 2 5 7 9",
          "4 3 6 8 9"};
}

std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

std::string five_cell_with(std::size_t line, const std::string& replacement) {
  auto lines = five_cell_lines();
  lines.at(line - 1) = replacement;
  return join(lines);
}

struct HostileFile {
  std::string label;
  std::string content;
  int exit;            // documented exit code of `cw4d slice`
  std::size_t line;    // the line the message names
  std::string needle;  // part of the message
};

std::vector<HostileFile> hostile_files() {
  const std::string ok = join(five_cell_lines());
  std::string nul = five_cell_with(4, "0 1 0 0");
  nul[nul.find("0 1 0 0") + 1] = '\0';
  return {
      // truncated files and wrong counts
      {"empty file", "", bad_input, 1, "unexpected end of file"},
      {"header only", "4OFF\n", bad_input, 2, "expected the element counts"},
      {"cut in the vertex list", ok.substr(0, ok.find("0 0 1 0")), bad_input, 2,
       "counts announce 20 element lines but the file has only 2"},
      {"cut in the middle of the last line", ok.substr(0, ok.size() - 4), bad_input, 22,
       "cell 4 announces 4 entries but the line has 2"},
      {"three counts for 4OFF", five_cell_with(2, "5 10 10"), bad_input, 2, "expected 4 counts"},
      // (read as the body stands, with a warning, without --strict: test_off_io, test_check)
      {"more faces announced than present", five_cell_with(2, "5 11 10 5"), bad_input, 2,
       "header counts 5 11 10 5 disagree with the body, which holds 5 vertices, 10 faces, 5 "
       "cells (refused: strict reading)"},
      {"fewer cells announced than present", five_cell_with(2, "5 10 10 4"), bad_input, 2,
       "disagree with the body"},
      {"negative count", five_cell_with(2, "-5 10 10 5"), bad_input, 2, "is not a non-negative"},
      // huge counts that would exhaust memory if they drove allocation
      // (the body is a whole 5-cell: --strict refuses the counts; without it, it is read)
      {"4e9 vertices", five_cell_with(2, "4000000000 10 10 5"), bad_input, 2,
       "disagree with the body"},
      {"2^64-1 faces", five_cell_with(2, "5 18446744073709551615 10 5"), bad_input, 2,
       "disagree with the body"},
      {"count beyond 64 bits", five_cell_with(2, "5 10 10 99999999999999999999999"), bad_input, 2,
       "is not a non-negative integer"},
      {"face of 4e9 vertices", five_cell_with(8, "4000000000 0 1 2"), bad_input, 8,
       "face 0 announces 4000000000 entries but the line has 3"},
      // bad headers and bytes
      {"unknown header", five_cell_with(1, "4OFFF"), bad_input, 1, "header '4OFFF'"},
      {"binary garbage header", five_cell_with(1, "\x89PNG\r"), bad_input, 1, "header '\\x89PNG'"},
      {"non-UTF-8 bytes in a coordinate", five_cell_with(5, "0 0 \xff\xfe 0"), bad_input, 5,
       "'\\xff\\xfe' is not a number"},
      {"NUL byte in a coordinate", nul, bad_input, 4, "vertex 1 has 3 coordinates"},
      // coordinates
      {"NaN coordinate", five_cell_with(6, "0 0 0 nan"), bad_input, 6, "'nan' is not finite"},
      {"infinite coordinate", five_cell_with(3, "-inf 0 0 0"), bad_input, 3, "is not finite"},
      {"overflowing coordinate", five_cell_with(7, "1e999 0 0 0"), bad_input, 7, "out of range"},
      {"vertex with 3 coordinates", five_cell_with(4, "0 1 0"), bad_input, 4,
       "vertex 1 has 3 coordinates, expected 4"},
      // indices
      {"face vertex out of range", five_cell_with(9, "3 0 1 5"), bad_input, 9,
       "face 1 refers to vertex 5, but there are only 5"},
      {"face vertex beyond 32 bits", five_cell_with(9, "3 0 1 4294967296"), bad_input, 9,
       "face 1 refers to vertex 4294967296"},
      {"cell face out of range", five_cell_with(20, "4 1 4 6 10"), bad_input, 20,
       "cell 2 refers to face 10, but there are only 10"},
      // faces that are not cycles, cells that are not closed
      {"face repeating a vertex (not a cycle)", five_cell_with(10, "3 0 2 0"), bad_input, 10,
       "face 2 lists vertex 0 twice"},
      {"face of two vertices", five_cell_with(10, "2 0 2"), bad_input, 10, "at least 3 needed"},
      {"cell listing a face twice", five_cell_with(19, "4 0 4 5 5"), bad_input, 19,
       "cell 1 lists face 5 twice"},
      {"open cell (a face missing)", five_cell_with(22, "3 3 6 8"), invalid_complex, 22,
       "is not a valid complex"},
      {"cell of two faces", five_cell_with(21, "2 2 5"), invalid_complex, 21,
       "is not a valid complex"},
      {"cell made of another cell's faces", five_cell_with(22, "4 0 1 2 3"), invalid_complex, 8,
       "is not a valid complex"},
      {"duplicate vertex (two vertices at one point)", five_cell_with(7, "1 0 0 0"),
       invalid_complex, 19, "degenerate (zero volume)"},
      // colors
      {"color out of range", five_cell_with(8, "3 0 1 2 256 0 0"), bad_input, 8, "out of range"},
      {"junk after the indices", five_cell_with(18, "4 0 1 2 3 junk"), bad_input, 18,
       "cell 0 has 1 values after its indices"},
  };
}

}  // namespace

TEST_CASE("hostile model files: one message with file:line, the documented exit code, no output",
          "[hostile][cli]") {
  const std::vector<HostileFile> catalogue = hostile_files();
  CHECK(catalogue.size() >= 30);
  for (const HostileFile& h : catalogue) {
    DYNAMIC_SECTION(h.label) {
      TempDir dir;
      dir.write("bad.4off", h.content);
      const auto before = listing(dir);
      for (const std::vector<std::string>& args :
           {std::vector<std::string>{"--strict", "slice", "bad.4off", "--normal", "0,0,0,1",
                                     "--offset", "0.1", "-o", "out/section.obj"},
            std::vector<std::string>{"--strict", "convert", "bad.4off", "-o", "copy.4off"}}) {
        INFO(args[1]);
        const Result r = run(dir, args);
        CHECK(r.code == h.exit);
        check_one_printable_error_line(r);
        CHECK(r.err.find("cw4d: error: bad.4off:" + std::to_string(h.line) + ": ") == 0);
        CHECK(r.err.find(h.needle) != std::string::npos);
        CHECK(r.out.empty());
        CHECK(listing(dir) == before);  // no output file, no directory, no temporary left
      }
      // The library reports the same line (reading strictly, as the commands above).
      const std::string path = (dir / "bad.4off").string();
      cw4d::OffReadOptions strict;
      strict.strict = true;
      const cw4d::ScopedOffReadOptions scoped(strict);
      if (h.exit == bad_input) {
        try {
          (void)cw4d::read_off_file(path);
          FAIL("read_off_file accepted it");
        } catch (const cw4d::ParseError& e) {
          CHECK(e.file() == path);
          CHECK(e.line() == h.line);
          CHECK(std::string(e.what()).find(h.needle) != std::string::npos);
        }
      } else {
        cw4d::OffLines lines;
        const cw4d::Complex c = cw4d::read_off_file(path, &lines);
        const cw4d::ValidationReport report = cw4d::validate(c);
        REQUIRE_FALSE(report.ok());
        const auto& first = report.issues.front();
        CHECK(lines.line_of(first.rank, first.id) == h.line);
      }
    }
  }
}

// --- special files ------------------------------------------------------------------------------

TEST_CASE("special files as models: directories, devices, FIFOs, missing files", "[hostile][cli]") {
  struct Special {
    std::string label, path, needle;
  };
  TempDir dir;
  fs::create_directory(dir / "dir.4off");
  REQUIRE(::mkfifo((dir / "fifo.4off").c_str(), 0600) == 0);
  const std::vector<Special> specials = {
      {"a directory", "dir.4off", "is a directory"},
      {"a FIFO (would block forever)", "fifo.4off", "not a regular file"},
      {"/dev/zero (endless)", "/dev/zero", "not a regular file"},
      {"a missing file", "missing.4off", "cannot open"},
  };
  const auto before = listing(dir);
  for (const Special& sp : specials) {
    DYNAMIC_SECTION(sp.label) {
      const Result r = run(dir, {"convert", sp.path, "-o", "copy.4off"});
      CHECK(r.code == bad_input);
      check_one_printable_error_line(r);
      CHECK(r.err.find("cw4d: error: " + sp.path + ":0: ") == 0);
      CHECK(r.err.find(sp.needle) != std::string::npos);
      CHECK(listing(dir) == before);
      const std::string path = sp.path.front() == '/' ? sp.path : (dir / sp.path).string();
      try {
        (void)cw4d::read_input_file(path);
        FAIL("read_input_file accepted it");
      } catch (const cw4d::ParseError& e) {
        CHECK(e.line() == 0);
        CHECK(std::string(e.what()).find(sp.needle) != std::string::npos);
      }
    }
  }
}

// --- scenes -------------------------------------------------------------------------------------

TEST_CASE("hostile scenes: one message with file:line, exit 2 (3 for an invalid model), no output",
          "[hostile][cli][scene]") {
  struct HostileScene {
    std::string label, json;
    std::string file;  // the file the message names
    std::size_t line;
    std::string needle;
  };
  const std::vector<HostileScene> scenes = {
      {"JSON cut short", "{\"objects\": [\n  {\"model\": \"tesseract\"}\n", "scene.json", 2, ""},
      {"not JSON at all", "objects:\n  - tesseract\n", "scene.json", 1, ""},
      {"non-UTF-8 bytes in a string", "{\"objects\": [\n{\"model\": \"tess\xff\xferact\"}]}",
       "scene.json", 2, "ill-formed UTF-8"},
      {"unknown key (a typo)",
       "{\"objects\": [\n{\"model\": \"tesseract\",\n \"colour\": \"#fff\"}]}", "scene.json", 3,
       "colour"},
      {"no objects", "{\"objects\": []}", "scene.json", 1, "object"},
      {"opacity above 1", "{\"objects\": [\n{\"model\": \"tesseract\",\n\n \"opacity\": 2}]}",
       "scene.json", 4, "opacity"},
      {"cell color id out of range",
       "{\"objects\": [{\"model\": \"5-cell\",\n \"cell_colors\": {\"5\": \"#ff0000\"}}]}",
       "scene.json", 2, "5"},
      {"translation of the wrong dimension",
       "{\"objects\": [{\"model\": \"tesseract\",\n\"translate\": [1, 2, 3]}]}", "scene.json", 2,
       "translate"},
      {"a number too large for a double",
       "{\"objects\": [{\"model\": \"tesseract\",\n\"translate\": [1e999, 0, 0, 0]}]}",
       "scene.json", 2, ""},
      {"unknown built-in", "{\"objects\": [\n{\"model\": \"tesseract:7\"}]}", "scene.json", 2,
       "tesseract:7"},
      {"a malformed model file", "{\"objects\": [{\"model\": \"bad.4off\"}]}", "bad.4off", 5,
       "is not finite"},
      {"a model file with an open cell", "{\"objects\": [{\"model\": \"open.4off\"}]}", "open.4off",
       22, "is not a valid complex"},
  };
  for (const HostileScene& sc : scenes) {
    DYNAMIC_SECTION(sc.label) {
      TempDir dir;
      dir.write("scene.json", sc.json);
      dir.write("bad.4off", five_cell_with(5, "0 0 inf 0"));
      dir.write("open.4off", five_cell_with(22, "3 3 6 8"));
      const auto before = listing(dir);
      const Result r = run(dir, {"slice", "--scene", "scene.json", "--normal", "0,0,0,1",
                                 "--offset", "0", "-o", "section.obj"});
      CHECK(r.code == (sc.file == "open.4off" ? invalid_complex : bad_input));
      check_one_printable_error_line(r);
      CHECK(r.err.find("cw4d: error: " + sc.file + ":" + std::to_string(sc.line) + ": ") !=
            std::string::npos);
      CHECK(r.err.find(sc.needle) != std::string::npos);
      CHECK(listing(dir) == before);
      if (sc.file == "open.4off") {
        // The reader accepts what parses; validation (which the CLI runs) rejects it.
        const cw4d::Scene scene = cw4d::read_scene_file((dir / "scene.json").string());
        CHECK_FALSE(cw4d::validate(*scene.objects.at(0).complex).ok());
      } else {
        try {
          (void)cw4d::read_scene_file((dir / "scene.json").string());
          FAIL("read_scene_file accepted it");
        } catch (const cw4d::ParseError& e) {
          CHECK(fs::path(e.file()).filename() == sc.file);
          CHECK(e.line() == sc.line);
        }
      }
    }
  }
}

// --- contradictory and malformed command lines ----------------------------------------------

TEST_CASE("contradictory command lines: exit 1 naming the options, nothing read or written",
          "[hostile][cli]") {
  struct BadLine {
    std::string label;
    std::vector<std::string> args;
    std::string needle;
  };
  const std::vector<BadLine> lines = {
      {"a model and a scene",
       {"slice", "tesseract", "--scene", "s.json", "--normal", "0,0,0,1", "--offset", "0", "-o",
        "a.obj"},
       "--scene"},
      {"--rotate with --scene",
       {"slice", "--scene", "s.json", "--rotate", "xw:30", "--normal", "0,0,0,1", "--offset", "0",
        "-o", "a.obj"},
       "--rotate"},
      {"--triangulate for SVG output",
       {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "--triangulate", "-o",
        "a.svg"},
       "--triangulate"},
      {"zero normal",
       {"slice", "tesseract", "--normal", "0,0,0,0", "--offset", "0", "-o", "a.obj"},
       "--normal"},
      {"normal of the wrong dimension",
       {"slice", "tesseract", "--normal", "0,0,1", "--offset", "0", "-o", "a.obj"},
       "normal"},
      {"NaN offset",
       {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "nan", "-o", "a.obj"},
       "offset"},
      {"unknown output format",
       {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "-o", "a.xyz"},
       "a.xyz"},
      {"convert to OBJ", {"convert", "tesseract", "-o", "a.obj"}, "a.obj"},
      {"no subcommand", {}, "subcommand"},
  };
  for (const BadLine& b : lines) {
    DYNAMIC_SECTION(b.label) {
      TempDir dir;
      const Result r = run(dir, b.args);
      CHECK(r.code == usage);
      check_one_printable_error_line(r);
      CHECK(r.err.find(b.needle) != std::string::npos);
      CHECK(listing(dir).empty());
    }
  }
}

// --- resource limits: what would crash, hang or take the machine ---------------------------------

namespace {

// Runs with a wall-clock guard: a hang becomes a killed process (a failure) instead of a stuck
// suite.
Result run_guarded(const TempDir& dir, const std::vector<std::string>& args) {
  const std::string out = (dir / ".stdout").string(), err = (dir / ".stderr").string();
  std::string cmd =
      "cd " + quote(dir.path().string()) + " && timeout --signal=KILL 60 " + quote(CW4D_EXE);
  for (const auto& a : args) cmd += ' ' + quote(a);
  cmd += " >" + quote(out) + " 2>" + quote(err) + " </dev/null";
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  fs::remove(out);
  fs::remove(err);
  return r;
}

// The first number after `key` in a JSON text.
long long number_after(const std::string& text, const std::string& key) {
  std::size_t at = text.find(key);
  if (at == std::string::npos) return -1;
  at = text.find_first_of("-0123456789", at + key.size());
  return at == std::string::npos ? -1 : std::stoll(text.substr(at));
}

std::string repeat(const std::string& s, int n) {
  std::string out;
  for (int i = 0; i < n; ++i) out += s;
  return out;
}

}  // namespace

TEST_CASE("deeply nested specs and scenes: refused with a message, no stack overflow",
          "[hostile][cli][limits]") {
  TempDir dir;
  for (const std::string op : {"prism:", "dual:", "cone:"}) {
    DYNAMIC_SECTION(op << " x 20000") {
      const Result r = run_guarded(dir, {"info", repeat(op, 20000) + "nosuch"});
      CHECK(r.code == usage);
      check_one_printable_error_line(r);
      CHECK(r.err.find("nests operators more than 32 deep") != std::string::npos);
    }
  }
  SECTION("product: nested 5000 deep on the left") {
    // (5000 levels: the argument stays below Linux's 128 KiB per argument.)
    const Result r = run_guarded(
        dir, {"info", repeat("product:", 5000) + "polygon:3" + repeat("*polygon:3", 5000)});
    CHECK(r.code == usage);
    CHECK(r.err.find("nests operators") != std::string::npos);
  }
  SECTION("a scene nested 10^5 deep") {
    dir.write("deep.json", "{\"objects\": " + repeat("[", 100000) + repeat("]", 100000) + "}");
    const Result r = run_guarded(dir, {"slice", "--scene", "deep.json", "--normal", "0,0,0,1",
                                       "--offset", "0", "-o", "a.obj"});
    CHECK(r.code == bad_input);
    check_one_printable_error_line(r);
    CHECK(r.err.find("deep.json:1: ") != std::string::npos);
    CHECK(r.err.find("nest more than 64 deep") != std::string::npos);
    CHECK_FALSE(dir.exists("a.obj"));
  }
  SECTION("nesting within the limit still works, left or right") {
    struct Nested {
      std::string spec;
      int dim;
      long long vertices;  // products multiply the vertex counts
    };
    for (const Nested& n : {Nested{"product:product:polygon:3*polygon:4*polygon:5", 6, 60},
                            Nested{"product:polygon:3*product:polygon:4*polygon:5", 6, 60},
                            Nested{"prism:prism:prism:5-cell", 7, 40}}) {
      INFO(n.spec);
      const Result r = run_guarded(dir, {"info", n.spec, "--json"});
      REQUIRE(r.code == 0);
      CHECK(r.out.find("\"valid\": true") != std::string::npos);
      CHECK(number_after(r.out, "\"dimension\"") == n.dim);
      CHECK(number_after(r.out, "\"fvector\"") == n.vertices);
    }
  }
}

TEST_CASE("every input path refuses FIFOs and endless devices", "[hostile][cli][limits]") {
  TempDir dir;
  REQUIRE(::mkfifo((dir / "p").c_str(), 0600) == 0);
  REQUIRE(::mkfifo((dir / "p.off").c_str(), 0600) == 0);
  for (const std::string spec : {"hull:p", "extrude:p.off", "spin:p.off,8", "p.off",
                                 "hull:/dev/zero", "extrude:/dev/zero", "/dev/zero"}) {
    DYNAMIC_SECTION(spec) {
      const Result r = run_guarded(dir, {"info", spec});
      CHECK(r.code == bad_input);
      check_one_printable_error_line(r);
      CHECK(r.err.find("not a regular file") != std::string::npos);
    }
  }
  SECTION("--scene FIFO") {
    const Result r = run_guarded(
        dir, {"slice", "--scene", "p", "--normal", "0,0,0,1", "--offset", "0", "-o", "a.obj"});
    CHECK(r.code == bad_input);
    CHECK(r.err.find("not a regular file") != std::string::npos);
  }
}

TEST_CASE("outputs that are not regular files are written through, never replaced",
          "[hostile][cli][output]") {
  TempDir dir;
  const std::vector<std::string> slice = {"slice", "tesseract", "--normal", "0,0,0,1", "--offset",
                                          "0.5",   "--format",  "obj",      "-o"};
  auto with = [&](const std::string& out) {
    auto a = slice;
    a.push_back(out);
    return a;
  };
  // Copies of /dev/null and /dev/full as device nodes (root only), else the real ones (only
  // written through, which is what is checked).
  const bool nodes = ::mknod((dir / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0 &&
                     ::mknod((dir / "full").c_str(), S_IFCHR | 0666, makedev(1, 7)) == 0;
  const std::string null = nodes ? "null" : "/dev/null", full = nodes ? "full" : "/dev/full";
  const auto is_char_device = [&](const std::string& name) {
    struct stat st {};
    return ::stat((name[0] == '/' ? fs::path(name) : dir / name).c_str(), &st) == 0 &&
           S_ISCHR(st.st_mode);
  };
  SECTION("a null device stays a device; the section goes into it") {
    const Result r = run_guarded(dir, with(null));
    CHECK(r.code == 0);
    CHECK(is_char_device(null));
  }
  SECTION("a full device: no space left, exit 4, still a device") {
    const Result r = run_guarded(dir, with(full));
    CHECK(r.code == 4);
    check_one_printable_error_line(r);
    CHECK(r.err.find("no space left") != std::string::npos);
    CHECK(is_char_device(full));
  }
  SECTION("a FIFO nobody reads: refused with exit 4, not waited on, still a FIFO") {
    REQUIRE(::mkfifo((dir / "fifo.obj").c_str(), 0600) == 0);
    const Result r = run_guarded(dir, with("fifo.obj"));
    CHECK(r.code == 4);
    check_one_printable_error_line(r);
    CHECK(r.err.find("no process is reading it") != std::string::npos);
    struct stat st {};
    REQUIRE(::stat((dir / "fifo.obj").c_str(), &st) == 0);
    CHECK(S_ISFIFO(st.st_mode));
  }
  SECTION("a symbolic link keeps pointing at the file it names, which gets the section") {
    dir.write("real.obj", "old\n");
    fs::create_symlink("real.obj", dir / "link.obj");
    const Result r = run_guarded(dir, with("link.obj"));
    CHECK(r.code == 0);
    CHECK(fs::is_symlink(dir / "link.obj"));
    CHECK(read_text((dir / "real.obj").string()).rfind("# cw4d", 0) == 0);
  }
}

TEST_CASE("inputs that announce more than they hold: exit 2 before allocating",
          "[hostile][cli][limits]") {
  TempDir dir;
  // OpenMesh reserves what the header announces: 2e9 vertices in a 60-byte file.
  dir.write("huge.off", "OFF\n2000000000 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  dir.write("huge.ply",
            "ply\nformat ascii 1.0\nelement vertex 2000000000\nproperty float x\nproperty float "
            "y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n");
  for (const std::string spec : {"extrude:huge.off", "spin:huge.ply,8"}) {
    DYNAMIC_SECTION(spec) {
      const Result r = run_guarded(dir, {"info", spec});
      CHECK(r.code == bad_input);
      check_one_printable_error_line(r);
      CHECK(r.err.find("announces 2000000000 vertices") != std::string::npos);
    }
  }
  SECTION("a render that would hold 2 * 64 images of 4096 x 4096 pixels") {
    const Result r =
        run_guarded(dir, {"render", "tesseract", "--normal", "0,0,0,1", "--mode", "sheet",
                          "--layers", "64", "--size", "4096x4096", "-o", "a.png"});
    CHECK(r.code == usage);
    check_one_printable_error_line(r);
    CHECK(r.err.find("pixels in memory") != std::string::npos);
    CHECK_FALSE(dir.exists("a.png"));
  }
  SECTION("a net drawn at 16384 x 16384 pixels shares the renderer's budget") {
    // 2.7e8 pixels, beyond the 1.5e8 a picture may hold; 12000 x 12000 (1.44e8) is within it,
    // refused here only for the model the test gives (the budget is checked first).
    const Result r = run_guarded(dir, {"net", "tesseract", "--size", "16384x16384", "-o", "n.png"});
    CHECK(r.code == usage);
    check_one_printable_error_line(r);
    CHECK(r.err.find("pixels in memory") != std::string::npos);
    CHECK_FALSE(dir.exists("n.png"));
    const Result within =
        run_guarded(dir, {"net", "no-such-model", "--size", "12000x12000", "-o", "n.png"});
    CHECK(within.code == usage);
    CHECK(within.err.find("pixels in memory") == std::string::npos);
  }
}

TEST_CASE("orientation_work counts what orienting walks, and bounds it up front",
          "[hostile][limits]") {
  // The oracle: walk the simplices for_each_simplex emits over the facets.
  for (const std::string spec : {"tesseract", "24-cell", "cube:6", "simplex:5", "duoprism:5,7",
                                 "prism:16-cell", "orthoplex:5"}) {
    INFO(spec);
    const cw4d::Complex c = cw4d::load_model(spec);
    const int n = c.ambient_dim();
    double walked = 0;
    for (std::uint32_t f = 0; f < c.count(n - 1); ++f)
      cw4d::for_each_simplex(c, n - 1, f, [&](std::span<const std::uint32_t>, int) { ++walked; });
    CHECK(cw4d::orientation_work(c) == Approx(walked * n * n * n / 64.0));
  }
  // A model beyond the budget is refused before it is oriented, with the CLI's exit 1.
  TempDir dir;
  for (const std::string spec :
       {"product:polygon:3500*polygon:3500", "prism:prism:prism:prism:prism:prism:prism:5-cell"}) {
    DYNAMIC_SECTION(spec) {
      const Result r = run_guarded(dir, {"info", spec});
      CHECK(r.code == usage);
      check_one_printable_error_line(r);
      CHECK(r.err.find("too large") != std::string::npos);
    }
  }
}

namespace {

// What the containment tests of for_each_simplex's walk over every facet read at most,
// counted on a built complex by walking it: at each element of rank >= 3 the walk visits
// (apex: its first vertex), each boundary element is searched for the apex, a face by reading
// its edges, a higher element by reading, at every element of rank >= 3 of its closure, its
// boundary ids (and at a cell its faces' edges); the walk goes on into those that miss it.
double walked_containment_reads(const cw4d::Complex& c) {
  const auto face_size = [&](std::uint32_t f) {
    return static_cast<double>(c.boundary(2).ids(f).size());
  };
  std::vector<std::vector<double>> closure(static_cast<std::size_t>(c.top_rank()) + 1);
  const auto searched = [&](int rank, std::uint32_t x) {
    auto& memo = closure[static_cast<std::size_t>(rank)];
    if (memo.empty()) memo.assign(c.count(rank), -1.0);
    if (memo[x] >= 0.0) return memo[x];
    // The distinct elements of rank >= 3 below x (x included), rank by rank.
    double reads = 0.0;
    std::vector<std::uint32_t> level{x};
    for (int r = rank; r >= 3; --r) {
      std::vector<std::uint32_t> next;
      for (auto y : level) {
        reads += static_cast<double>(c.boundary(r).ids(y).size());
        for (auto z : c.boundary(r).ids(y)) {
          if (r == 3) reads += face_size(z);
          next.push_back(z);
        }
      }
      std::sort(next.begin(), next.end());
      next.erase(std::unique(next.begin(), next.end()), next.end());
      level = std::move(next);
    }
    return memo[x] = reads;
  };
  std::function<double(int, std::uint32_t)> walk = [&](int rank, std::uint32_t x) {
    if (rank <= 2) return 0.0;
    const std::uint32_t apex = c.first_vertex(rank, x);
    double reads = 0.0;
    for (auto j : c.boundary(rank).ids(x)) {
      reads += rank - 1 == 2 ? face_size(j) : searched(rank - 1, j);
      const auto v = c.vertices_of(rank - 1, j);
      if (!std::binary_search(v.begin(), v.end(), apex)) reads += walk(rank - 1, j);
    }
    return reads;
  };
  const int fr = c.ambient_dim() - 1;
  double total = 0.0;
  for (std::uint32_t f = 0; f < c.count(fr); ++f) total += walk(fr, f);
  return total;
}

}  // namespace

TEST_CASE("wythoff: the size is known from the group before anything is built",
          "[hostile][limits][wythoff]") {
  // The oracle: published f-vectors (vertices, edges, faces, cells, ...) of uniform polytopes,
  // e.g. H. S. M. Coxeter, "Regular Polytopes" (1973), table I, and N. W. Johnson, "Geometries
  // and Transformations" (2018), for the polychora; a permutohedron of order 6 for x3x3x3x3x.
  const std::vector<std::pair<std::string, std::vector<double>>> known = {
      {"x5o2x", {10, 15, 7}},                     // pentagonal prism
      {"o5x3x", {60, 90, 32}},                    // truncated icosahedron
      {"x5x3x", {120, 180, 62}},                  // great rhombicosidodecahedron
      {"x4o3o3o", {16, 32, 24, 8}},               // tesseract
      {"x5o3o3o", {600, 1200, 720, 120}},         // 120-cell
      {"o3x3o5o", {720, 3600, 3600, 720}},        // rectified 600-cell
      {"x5x3o3o", {2400, 4800, 3120, 720}},       // truncated 120-cell
      {"x3x3x3x", {120, 240, 150, 30}},           // omnitruncated 5-cell
      {"x4x3x3x", {384, 768, 464, 80}},           // omnitruncated tesseract
      {"x3x4x3x", {1152, 2304, 1392, 240}},       // omnitruncated 24-cell
      {"x5x3x3x", {14400, 28800, 17040, 2640}},   // omnitruncated 120-cell
      {"x5/2o5o3o", {120, 1200, 720, 120}},       // small stellated 120-cell {5/2,5,3}
      {"x3x3x3x3x", {720, 1800, 1560, 540, 62}},  // omnitruncated 5-simplex
  };
  for (const auto& [diagram, f] : known) {
    INFO(diagram);
    const auto size = cw4d::wythoff_size(cw4d::parse_coxeter_diagram(diagram));
    REQUIRE(size);
    CHECK(size->f == f);
    // The same polytope built: its counts, and the work build_complex measured on it.
    const cw4d::Complex c = cw4d::make_wythoff(diagram);
    for (int k = 0; k < c.ambient_dim(); ++k) CHECK(static_cast<double>(c.count(k)) == f[k]);
    CHECK(size->orientation_work == Approx(cw4d::orientation_work(c)).epsilon(1e-12));
    CHECK(size->containment_reads == Approx(walked_containment_reads(c)).epsilon(1e-12));
  }
  // Beyond the limits: refused by the estimate, with the CLI's exit 1 and one line. The
  // permutohedron of order 8 (x3x3x3x3x3x3x) has 8! vertices, far below the vertex limit, but
  // its facets exceed the orientation budget; the omnitruncated 10-orthoplex has 2^10 10!.
  const auto big = cw4d::wythoff_size(cw4d::parse_coxeter_diagram("x3x3x3x3x3x3x"));
  REQUIRE(big);
  CHECK(big->f[0] == 40320);
  CHECK(big->f[6] == 254);  // 2^8 - 2 facets
  CHECK(big->orientation_work > cw4d::max_orientation_work);
  TempDir dir;
  for (const auto& [spec, says] : std::vector<std::pair<std::string, std::string>>{
           {"wythoff:x3x3x3x3x3x3x", "too large"},
           // The expanded 10-simplex: 110 vertices and orientation_work 2.9e6, within the
           // budget, but the containment tests of its rank-9 facets read 2.6e8 ids (seconds).
           {"wythoff:x3o3o3o3o3o3o3o3o3x", "too large"},
           {"wythoff:x4x3x3x3x3x3x3x3x3x", "more than 2000000 vertices"},
           {"wythoff:x5x3x3x2x3x3x3x3x3x", "more than 2000000 vertices"}}) {
    DYNAMIC_SECTION(spec) {
      const Result r = run_guarded(dir, {"info", spec});
      CHECK(r.code == usage);
      check_one_printable_error_line(r);
      CHECK(r.err.find(says) != std::string::npos);
    }
  }
}

TEST_CASE("volumes beyond a double's range and coinciding vertices are said so",
          "[hostile][cli][messages]") {
  TempDir dir;
  const std::string faces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  // A tetrahedron of edge ~1e308: valid (decided on rescaled positions), volume ~1e924.
  dir.write("huge.off", "OFF\n4 4 0\n-1e308 0 0\n1e308 0 0\n0 1e308 0\n0 0 1e308\n" + faces);
  // The same scaled by 1e-308: volume ~1e-924.
  dir.write("tiny.off", "OFF\n4 4 0\n-1e-300 0 0\n1e-300 0 0\n0 1e-300 0\n0 0 1e-300\n" + faces);
  dir.write("same.off", "OFF\n4 4 0\n1 2 3\n1 2 3\n1 2 3\n1 2 3\n" + faces);
  const Result huge = run_guarded(dir, {"info", "huge.off"});
  CHECK(huge.code == 0);
  CHECK(huge.out.find("valid      yes") != std::string::npos);
  CHECK(huge.out.find("volume     beyond the range of a double") != std::string::npos);
  CHECK(huge.out.find("nan") == std::string::npos);
  const Result tiny = run_guarded(dir, {"info", "tiny.off"});
  CHECK(tiny.code == 0);
  CHECK(tiny.out.find("volume     below the range of a double") != std::string::npos);
  const Result same = run_guarded(dir, {"convert", "same.off", "-o", "out.off"});
  CHECK(same.code == invalid_complex);
  check_one_printable_error_line(same);
  CHECK(same.err.find("all its vertices coincide") != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "out.off"));
}

TEST_CASE("temporaries are removed when SIGTERM or SIGINT ends the process",
          "[hostile][output][signals]") {
  TempDir dir;
  for (const int sig : {SIGTERM, SIGINT}) {
    for (const bool folder : {false, true}) {
      DYNAMIC_SECTION("signal " << sig << (folder ? ", a staging folder" : ", a file")) {
        const fs::path tmp = dir / (folder ? ".staging" : ".out.tmp");
        const pid_t child = ::fork();
        REQUIRE(child >= 0);
        if (child == 0) {
          // The test framework catches these signals; the program under test does not.
          ::signal(SIGTERM, SIG_DFL);
          ::signal(SIGINT, SIG_DFL);
          if (folder) {
            fs::create_directory(tmp);
            std::ofstream(tmp / "layer_000.obj") << "v 0 0 0\n";
            std::ofstream(tmp / "layer_001.obj") << "v 0 0 0\n";
          } else {
            std::ofstream(tmp) << "partial";
          }
          cw4d::TemporaryGuard guard(tmp.string(), folder);
          ::raise(sig);
          ::_exit(0);  // not reached: the signal ends the process
        }
        int status = 0;
        REQUIRE(::waitpid(child, &status, 0) == child);
        CHECK(WIFSIGNALED(status));
        CHECK(WTERMSIG(status) == sig);
        CHECK_FALSE(fs::exists(tmp));
      }
    }
  }
  SECTION("a released guard leaves its file to its owner") {
    const fs::path kept = dir / "kept";
    const pid_t child = ::fork();
    REQUIRE(child >= 0);
    if (child == 0) {
      ::signal(SIGTERM, SIG_DFL);
      std::ofstream(kept) << "done";
      cw4d::TemporaryGuard guard(kept.string(), false);
      guard.release();
      ::raise(SIGTERM);
      ::_exit(0);
    }
    int status = 0;
    REQUIRE(::waitpid(child, &status, 0) == child);
    CHECK(fs::exists(kept));
  }
}

TEST_CASE("a sweep into a folder appears whole or not at all", "[hostile][cli][output]") {
  TempDir dir;
  SECTION("success: the folder holds every layer and nothing else") {
    // (with or without trailing separators: the same folder)
    for (const std::string target : {"out/layers", "out/layers/", "out/layers//"}) {
      INFO(target);
      fs::remove_all(dir / "out");
      const Result r = run_guarded(dir, {"sweep", "tesseract", "--normal", "0,0,0,1", "--from",
                                         "-0.5", "--to", "0.5", "--layers", "3", "-o", target});
      REQUIRE(r.code == 0);
      std::vector<std::string> names;
      for (const auto& e : fs::directory_iterator(dir / "out/layers"))
        names.push_back(e.path().filename().string());
      std::sort(names.begin(), names.end());
      CHECK(names == std::vector<std::string>{"layer_000.obj", "layer_001.obj", "layer_002.obj"});
      for (const auto& e : fs::directory_iterator(dir / "out"))
        CHECK(e.path().filename() == "layers");  // no staging folder left
    }
  }
  SECTION("failure: an unwritable layer leaves no folder and no staging") {
    // Layer 1 cannot be written (a directory is in its place): nothing may remain.
    fs::create_directories(dir / "out/layer_001.obj");
    const Result r = run_guarded(dir, {"sweep", "tesseract", "--normal", "0,0,0,1", "--from",
                                       "-0.5", "--to", "0.5", "--layers", "3", "-o", "out"});
    CHECK(r.code == 4);
    std::vector<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir / "out"))
      names.push_back(fs::relative(e.path(), dir / "out").string());
    CHECK(names == std::vector<std::string>{"layer_001.obj"});
  }
}

TEST_CASE("messages in the user's terms", "[hostile][cli][messages]") {
  TempDir dir;
  struct Case {
    std::string label;
    std::vector<std::string> args;
    int code;
    std::string needle;
  };
  dir.write("flat.txt", "0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n1 1 0 0\n");
  dir.write("same.txt", "1 1 1 1\n1 1 1 1\n1 1 1 1\n1 1 1 1\n1 1 1 1\n");
  const std::vector<Case> cases = {
      {"typo'd subcommand",
       {"slcie", "tesseract"},
       usage,
       "unknown subcommand 'slcie'; did you mean 'slice'?"},
      {"unknown model, close to a name", {"info", "24cell"}, usage, "did you mean '24-cell'?"},
      {"unknown model, two letters swapped",
       {"info", "grand-antiprsim"},
       usage,
       "did you mean 'grand antiprism'?"},
      {"unknown operator head",
       {"info", "prsim:tesseract"},
       usage,
       "did you mean 'prism:tesseract'?"},
      {"a missing mesh file",
       {"info", "extrude:nothere.off"},
       bad_input,
       "nothere.off:0: cannot open: file not found"},
      {"points in a hyperplane",
       {"info", "hull:flat.txt"},
       usage,
       "flat.txt: no convex hull: the points lie in a lower-dimensional flat"},
      {"coincident points",
       {"info", "hull:same.txt"},
       usage,
       "same.txt: no convex hull: all points coincide"},
      {"a format the extension contradicts",
       {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0", "--format", "stl", "-o",
        "a.obj"},
       usage,
       "--format stl contradicts the extension of 'a.obj'"},
      {"a plane that misses names the range",
       {"slice", "tesseract", "--normal", "0,0,0,2", "--offset", "3", "-o", "a.obj"},
       5,
       "it meets d from -1 to 1 along the unit normal (0,0,0,1)"},
      {"a scene scale of 1e155",
       {"slice", "--scene", "big.json", "--normal", "0,0,0,1", "--offset", "0", "-o", "a.obj"},
       usage,
       "has coordinates up to 1e+155"},
      {"a Miratope polygon", {"info", "poly.off"}, bad_input, "is Miratope's file of a polygon"},
  };
  dir.write("big.json", "{\"objects\": [{\"model\": \"tesseract\", \"scale\": 1e155}]}");
  dir.write("poly.off", "2OFF\n3 1\n0 0\n1 0\n0 1\n3 0 1 2\n");
  for (const Case& c : cases) {
    DYNAMIC_SECTION(c.label) {
      const Result r = run_guarded(dir, c.args);
      CHECK(r.code == c.code);
      check_one_printable_error_line(r);
      CHECK(r.err.find(c.needle) != std::string::npos);
      CHECK_FALSE(dir.exists("a.obj"));
    }
  }
  SECTION("--version, help, help COMMAND") {
    Result r = run_guarded(dir, {"--version"});
    CHECK(r.code == 0);
    CHECK(r.out.rfind("cw4d ", 0) == 0);
    r = run_guarded(dir, {"help"});
    CHECK(r.code == 0);
    CHECK(r.out.find("Exit codes:") != std::string::npos);
    r = run_guarded(dir, {"help", "slice"});
    CHECK(r.code == 0);
    CHECK(r.out.find("--offset") != std::string::npos);
  }
  SECTION("info --normal prints the offsets that meet the model") {
    // The 24-cell (x3o4o3o, edge 2) has vertices (+-2, 0, 0, 0) and permutations... along w
    // its vertices reach +-2 (its circumradius is 2, the edge).
    const Result r = run_guarded(dir, {"info", "24-cell", "--normal", "0,0,0,5"});
    REQUIRE(r.code == 0);
    CHECK(r.out.find("offsets    d from -") != std::string::npos);
    const Result t = run_guarded(dir, {"info", "tesseract", "--normal", "1,1,1,1", "--json"});
    REQUIRE(t.code == 0);
    // Along (1,1,1,1)/2 the tesseract [-1,1]^4 spans -2 .. 2.
    CHECK(t.out.find("\"min\": -2.0") != std::string::npos);
    CHECK(t.out.find("\"max\": 2.0") != std::string::npos);
  }
}

TEST_CASE("decisions do not depend on units: huge, tiny and extreme values",
          "[hostile][cli][scale]") {
  TempDir dir;
  std::string big, tiny;
  for (int m = 0; m < 16; ++m) {
    std::string line, small;
    for (int i = 0; i < 4; ++i) {
      line += std::string(i ? " " : "") + ((m >> i) & 1 ? "1e200" : "-1e200");
      small += std::string(i ? " " : "") + ((m >> i) & 1 ? "1e-200" : "-1e-200");
    }
    big += line + "\n";
    tiny += small + "\n";
  }
  dir.write("big.txt", big);
  dir.write("tiny.txt", tiny);
  for (const std::string spec : {"hull:big.txt", "hull:tiny.txt"}) {
    DYNAMIC_SECTION(spec) {
      // The hull of the tesseract's vertices, in any unit, is a tesseract: 16 8 cells.
      const Result r = run_guarded(dir, {"info", spec, "--json"});
      REQUIRE(r.code == 0);
      CHECK(r.out.find("\"valid\": true") != std::string::npos);
      CHECK(number_after(r.out, "\"fvector\"") == 16);
      CHECK(r.out.find("8\n  ]") != std::string::npos);
    }
  }
  // Normals and rotations of extreme magnitude are directions like any other: the section of
  // the tesseract by w = 0 (a cube of volume 8) whatever their length.
  for (const std::vector<std::string>& extra :
       {std::vector<std::string>{"--normal", "0,0,0,1e-320"},
        std::vector<std::string>{"--normal", "0,0,0,1e308"},
        std::vector<std::string>{"--normal", "0,0,0,1", "--rotate", "xy:1e308"}}) {
    DYNAMIC_SECTION(extra[1] << (extra.size() > 2 ? " " + extra[3] : std::string())) {
      std::vector<std::string> args = {"slice", "tesseract", "--offset", "0", "-o", "a.obj"};
      args.insert(args.end(), extra.begin(), extra.end());
      const Result r = run_guarded(dir, args);
      REQUIRE(r.code == 0);
      CHECK(r.out.find("volume 8") != std::string::npos);
    }
  }
}

TEST_CASE("files from the wild: a byte-order mark, zero-volume polyhedra decided exactly",
          "[hostile][wild]") {
  TempDir dir;
  SECTION("a UTF-8 byte-order mark before the header is accepted") {
    dir.write("bom.4off", "\xEF\xBB\xBF" + join(five_cell_lines()));
    const Result r = run_guarded(dir, {"convert", "bom.4off", "-o", "copy.4off"});
    CHECK(r.code == 0);
    CHECK(r.out.find("5 vertices, 10 edges, 10 faces, 5 cells") != std::string::npos);
  }
  SECTION("the octahemioctahedron (zero volume) is refused as given, mirrored and scaled") {
    // Vertices: the cuboctahedron's 12, the permutations of (+-1, +-1, 0). Faces: its 8
    // triangles and the 4 hexagons through the centre normal to the body diagonals.
    std::vector<Eigen::Vector3d> v;
    for (int zero = 0; zero < 3; ++zero)
      for (int s = 0; s < 4; ++s) {
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        p((zero + 1) % 3) = s & 1 ? 1 : -1;
        p((zero + 2) % 3) = s & 2 ? 1 : -1;
        v.push_back(p);
      }
    std::vector<std::vector<int>> faces;
    for (int s = 0; s < 8; ++s) {
      const Eigen::Vector3d d(s & 1 ? 1 : -1, s & 2 ? 1 : -1, s & 4 ? 1 : -1);
      std::vector<int> tri;  // the triangle around the vertex d of the cube: v . d = 2
      for (int i = 0; i < 12; ++i)
        if (v[i].dot(d) == 2) tri.push_back(i);
      faces.push_back(tri);
    }
    for (int s = 0; s < 4; ++s) {
      const Eigen::Vector3d d(1, s & 1 ? 1 : -1, s & 2 ? 1 : -1);
      const Eigen::Vector3d a = d.unitOrthogonal(), b = d.normalized().cross(a);
      std::vector<std::pair<double, int>> ring;
      for (int i = 0; i < 12; ++i)
        if (v[i].dot(d) == 0) ring.push_back({std::atan2(v[i].dot(b), v[i].dot(a)), i});
      std::sort(ring.begin(), ring.end());
      std::vector<int> hex;
      for (const auto& [angle, i] : ring) hex.push_back(i);
      faces.push_back(hex);
    }
    REQUIRE(faces.size() == 12);
    auto off = [&](double sx, double scale) {
      std::string out = "OFF\n12 12 24\n";
      for (const auto& p : v) {
        char line[128];
        std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", sx * scale * p.x(), scale * p.y(),
                      scale * p.z());
        out += line;
      }
      for (const auto& f : faces) {
        out += std::to_string(f.size());
        for (int i : f) out += " " + std::to_string(i);
        out += "\n";
      }
      return out;
    };
    std::vector<std::string> verdicts;
    for (const auto& [label, sx, scale] :
         {std::tuple{"as given", 1.0, 1.0}, std::tuple{"mirrored", -1.0, 1.0},
          std::tuple{"scaled x3", 1.0, 3.0}, std::tuple{"scaled x1e-7", 1.0, 1e-7},
          std::tuple{"mirrored, scaled x0.3", -1.0, 0.3}}) {
      INFO(label);
      dir.write("ohoh.off", off(sx, scale));
      const cw4d::ValidationReport report =
          cw4d::validate(cw4d::read_off_file((dir / "ohoh.off").string()));
      CHECK_FALSE(report.ok());
      verdicts.push_back(report.summary());
    }
    for (const auto& verdict : verdicts) {
      CHECK(verdict == verdicts.front());
      CHECK(verdict.find("encloses no volume") != std::string::npos);
    }
  }
}

TEST_CASE("an interrupted sweep leaves nothing behind", "[hostile][cli][signals]") {
  for (const std::string sig : {"TERM", "INT"}) {
    DYNAMIC_SECTION("SIG" << sig) {
      TempDir dir;
      // 5000 layers of the 120-cell take far more than a second: the signal lands mid-sweep.
      const std::string cmd = "cd " + quote(dir.path().string()) + " && timeout -s " + sig + " 1 " +
                              quote(CW4D_EXE) +
                              " sweep 120-cell --normal 1,2,3,4 --from -3 --to 3 --layers 5000"
                              " -q -o out/layers >/dev/null 2>&1";
      const int status = std::system(cmd.c_str());
      REQUIRE(WIFEXITED(status));
      REQUIRE(WEXITSTATUS(status) == 124);  // interrupted, not finished
      // At most the (empty) parent folder the sweep created: no layer, no staging folder.
      const auto left = listing(dir);
      CHECK((left.empty() || left == std::vector<std::string>{"out"}));
    }
  }
}
