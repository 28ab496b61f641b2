// Hostile input, end to end: a catalogue of malformed model files, scenes, special files and
// contradictory command lines. Each one, run through the real cw4d binary, must give exactly one
// "cw4d: error: ..." line that names file:line (files) or the offending option (command lines),
// the documented exit code, and no output file. The library side of the same inputs is checked
// too: the reader throws ParseError with the same line, or validate() names an element whose
// line OffLines reports. (test_off_io.cpp has the reader's per-message catalogue; this one is
// about what a user of the CLI sees.)
#include <sys/stat.h>
#include <sys/wait.h>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/input_file.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/validate.hpp"
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
  return {"4OFF",        "5 10 10 5",
          "1 0 0 0",     "0 1 0 0",   "0 0 1 0",   "0 0 0 1",   "-0.6 -0.6 -0.6 -0.6",
          "3 0 1 2",     "3 0 1 3",   "3 0 2 3",   "3 1 2 3",   "3 0 1 4",
          "3 0 2 4",     "3 1 2 4",   "3 0 3 4",   "3 1 3 4",   "3 2 3 4",
          "4 0 1 2 3",   "4 0 4 5 6", "4 1 4 7 8", "4 2 5 7 9", "4 3 6 8 9"};
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
  int exit;              // documented exit code of `cw4d slice`
  std::size_t line;      // the line the message names
  std::string needle;    // part of the message
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
      {"more faces announced than present", five_cell_with(2, "5 11 10 5"), bad_input, 2,
       "counts announce 21 element lines but the file has only 20"},
      {"fewer cells announced than present", five_cell_with(2, "5 10 10 4"), bad_input, 22,
       "unexpected data after the last element"},
      {"negative count", five_cell_with(2, "-5 10 10 5"), bad_input, 2, "is not a non-negative"},
      // huge counts that would exhaust memory if they drove allocation
      {"4e9 vertices", five_cell_with(2, "4000000000 10 10 5"), bad_input, 2, "counts announce"},
      {"2^64-1 faces", five_cell_with(2, "5 18446744073709551615 10 5"), bad_input, 2,
       "counts announce"},
      {"count beyond 64 bits", five_cell_with(2, "5 10 10 99999999999999999999999"), bad_input, 2,
       "is not a non-negative integer"},
      {"face of 4e9 vertices", five_cell_with(8, "4000000000 0 1 2"), bad_input, 8,
       "face 0 announces 4000000000 entries but the line has 3"},
      // bad headers and bytes
      {"unknown header", five_cell_with(1, "4OFFF"), bad_input, 1, "header '4OFFF'"},
      {"binary garbage header", five_cell_with(1, "\x89PNG\r"), bad_input, 1,
       "header '\\x89PNG'"},
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
           {std::vector<std::string>{"slice", "bad.4off", "--normal", "0,0,0,1", "--offset", "0.1",
                                     "-o", "out/section.obj"},
            std::vector<std::string>{"convert", "bad.4off", "-o", "copy.4off"}}) {
        INFO(args.front());
        const Result r = run(dir, args);
        CHECK(r.code == h.exit);
        check_one_printable_error_line(r);
        CHECK(r.err.find("cw4d: error: bad.4off:" + std::to_string(h.line) + ": ") == 0);
        CHECK(r.err.find(h.needle) != std::string::npos);
        CHECK(r.out.empty());
        CHECK(listing(dir) == before);  // no output file, no directory, no temporary left
      }
      // The library reports the same line.
      const std::string path = (dir / "bad.4off").string();
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
      {"unknown key (a typo)", "{\"objects\": [\n{\"model\": \"tesseract\",\n \"colour\": \"#fff\"}]}",
       "scene.json", 3, "colour"},
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
      {"a model file with an open cell", "{\"objects\": [{\"model\": \"open.4off\"}]}",
       "open.4off", 22, "is not a valid complex"},
  };
  for (const HostileScene& sc : scenes) {
    DYNAMIC_SECTION(sc.label) {
      TempDir dir;
      dir.write("scene.json", sc.json);
      dir.write("bad.4off", five_cell_with(5, "0 0 inf 0"));
      dir.write("open.4off", five_cell_with(22, "3 3 6 8"));
      const auto before = listing(dir);
      const Result r = run(dir, {"slice", "--scene", "scene.json", "--normal", "0,0,0,1", "--offset",
                                 "0", "-o", "section.obj"});
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
      {"a model and a scene", {"slice", "tesseract", "--scene", "s.json", "--normal", "0,0,0,1",
                               "--offset", "0", "-o", "a.obj"}, "--scene"},
      {"--rotate with --scene", {"slice", "--scene", "s.json", "--rotate", "xw:30", "--normal",
                                 "0,0,0,1", "--offset", "0", "-o", "a.obj"}, "--rotate"},
      {"--triangulate for SVG output", {"slice", "tesseract", "--normal", "0,0,0,1", "--offset",
                                        "0", "--triangulate", "-o", "a.svg"}, "--triangulate"},
      {"zero normal", {"slice", "tesseract", "--normal", "0,0,0,0", "--offset", "0", "-o",
                       "a.obj"}, "--normal"},
      {"normal of the wrong dimension", {"slice", "tesseract", "--normal", "0,0,1", "--offset",
                                         "0", "-o", "a.obj"}, "normal"},
      {"NaN offset", {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "nan", "-o",
                      "a.obj"}, "offset"},
      {"unknown output format", {"slice", "tesseract", "--normal", "0,0,0,1", "--offset", "0",
                                 "-o", "a.xyz"}, "a.xyz"},
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
