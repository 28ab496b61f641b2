// Tests of 4OFF / OFF / nOFF reading and writing: round trips of the built-ins, the Miratope
// files against their own headers, a catalogue of malformed inputs with line numbers, colors.
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/validate.hpp"

using namespace cw4d;
namespace fs = std::filesystem;

namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::string to_text(const Complex& c) {
  std::ostringstream out;
  write_off(out, c);
  return out.str();
}

Complex from_text(const std::string& text, const std::string& name = "test.4off") {
  std::istringstream in(text);
  return read_off(in, name);
}

std::vector<std::array<std::uint32_t, 2>> edge_set(const Complex& c) {
  std::vector<std::array<std::uint32_t, 2>> out;
  for (std::uint32_t e = 0; e < c.count(1); ++e) {
    auto [a, b] = c.edge(e);
    out.push_back({std::min(a, b), std::max(a, b)});
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Bit-for-bit equality of two coordinate matrices (distinguishes -0.0 from 0.0).
bool same_bits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index j = 0; j < a.cols(); ++j)
    for (Eigen::Index i = 0; i < a.rows(); ++i)
      if (std::bit_cast<std::uint64_t>(a(i, j)) != std::bit_cast<std::uint64_t>(b(i, j)))
        return false;
  return true;
}

// Same structure as stored: f-vector, coordinates, face cycles, rows of ranks >= 3 with signs.
void require_same_complex(const Complex& a, const Complex& b) {
  REQUIRE(a.ambient_dim() == b.ambient_dim());
  REQUIRE(a.fvector() == b.fvector());
  CHECK(same_bits(a.positions(), b.positions()));
  CHECK(edge_set(a) == edge_set(b));
  for (std::uint32_t f = 0; f < a.count(2); ++f) {
    INFO("face " << f);
    CHECK(a.face_cycle(f) == b.face_cycle(f));
  }
  for (int k = 3; k <= a.top_rank(); ++k) {
    const Incidence& ta = a.boundary(k);
    const Incidence& tb = b.boundary(k);
    for (std::uint32_t x = 0; x < ta.size(); ++x) {
      INFO("rank " << k << " element " << x);
      CHECK(std::vector<std::uint32_t>(ta.ids(x).begin(), ta.ids(x).end()) ==
            std::vector<std::uint32_t>(tb.ids(x).begin(), tb.ids(x).end()));
      CHECK(std::vector<std::int8_t>(ta.signs(x).begin(), ta.signs(x).end()) ==
            std::vector<std::int8_t>(tb.signs(x).begin(), tb.signs(x).end()));
    }
  }
}

// The counts of a Miratope file read independently of the library: the first non-comment line
// is the header, the counts follow on it or on the next non-comment line, in the order V F E C.
std::vector<std::size_t> header_counts(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> tokens;
  bool seen_header = false;
  while (std::getline(in, line)) {
    if (auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream words(line);
    std::string w;
    std::vector<std::string> here;
    while (words >> w) here.push_back(w);
    if (here.empty()) continue;
    if (!seen_header) {
      seen_header = true;
      tokens.assign(here.begin() + 1, here.end());
      if (!tokens.empty()) break;
      continue;
    }
    tokens = here;
    break;
  }
  std::vector<std::size_t> counts;
  for (const auto& t : tokens) counts.push_back(std::stoull(t));
  return counts;
}

std::vector<fs::path> off_files(const std::string& dir) {
  std::vector<fs::path> out;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".off") out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

const std::string miratope = std::string(CW4D_TEST_DATA_DIR) + "/miratope/";

// Facet normals point away from the vertex centroid (convex polytopes only).
void check_outward_normals(const Complex& c) {
  REQUIRE(c.has_facet_normals());
  const int fr = c.facet_rank();
  const Eigen::VectorXd centroid = c.positions().rowwise().mean();
  std::size_t bad = 0;
  for (std::uint32_t f = 0; f < c.count(fr); ++f)
    for (auto v : c.vertices_of(fr, f))
      if (!(c.facet_normals().col(f).dot(c.position(v) - centroid) > 1e-9)) ++bad;
  CHECK(bad == 0);
}

// A 4-simplex with unit-vector vertices: 22 lines, the faces on lines 8..17, cells 18..22.
std::vector<std::string> simplex_lines() {
  return {"4OFF",      "5 10 10 5", "0 0 0 0",   "1 0 0 0",  "0 1 0 0", "0 0 1 0",
          "0 0 0 1",   "3 0 1 2",   "3 0 1 3",   "3 0 1 4",  "3 0 2 3", "3 0 2 4",
          "3 0 3 4",   "3 1 2 3",   "3 1 2 4",   "3 1 3 4",  "3 2 3 4", "4 0 1 3 6",
          "4 0 2 4 7", "4 1 2 5 8", "4 3 4 5 9", "4 6 7 8 9"};
}

std::string join(const std::vector<std::string>& lines, const char* eol = "\n") {
  std::string out;
  for (const auto& l : lines) out += l + eol;
  return out;
}

// The simplex file with 1-based line `line` replaced.
std::string simplex_with(std::size_t line, const std::string& replacement) {
  auto lines = simplex_lines();
  lines.at(line - 1) = replacement;
  return join(lines);
}

struct Malformed {
  std::string label;
  std::string text;
  std::size_t line;    // expected ParseError::line()
  std::string needle;  // expected part of ParseError::message()
};

std::vector<Malformed> malformed_catalogue() {
  const std::vector<std::string> base = simplex_lines();
  const std::string s = join(base);
  std::vector<std::string> crlf = base;
  crlf[15] = "3 1 3 9";  // face 8
  std::vector<Malformed> m = {
      {"empty input", "", 1, "unexpected end of file"},
      {"only comments", "# nothing here\n\n   # still nothing\n", 1, "expected a header"},
      {"bad header word", simplex_with(1, "4OFX"), 1, "header '4OFX'"},
      {"header dimension 2", simplex_with(1, "2OFF"), 1, "header '2OFF'"},
      {"header dimension 10", simplex_with(1, "10OFF"), 1, "header '10OFF'"},
      {"header suffix", simplex_with(1, "OFF4"), 1, "header 'OFF4'"},
      {"missing counts", "4OFF\n", 2, "expected the element counts"},
      {"missing counts after comments", "# a\n4OFF\n# b\n\n", 3, "expected the element counts"},
      {"three counts for 4OFF", simplex_with(2, "5 10 10"), 2, "expected 4 counts"},
      {"five counts for 4OFF", simplex_with(2, "5 10 10 5 1"), 2, "expected 4 counts"},
      {"two counts for OFF", "OFF\n4 4\n", 2, "expected 3 counts"},
      {"counts on the header line", "4OFF 5 10 10\n0 0 0 0\n", 1, "expected 4 counts"},
      {"negative count", simplex_with(2, "5 -10 10 5"), 2, "'-10' is not a non-negative integer"},
      {"non-numeric count", simplex_with(2, "5 ten 10 5"), 2, "'ten' is not a non-negative"},
      {"count beyond 64 bits", simplex_with(2, "5 10 99999999999999999999 5"), 2,
       "is not a non-negative integer"},
      {"truncated vertex list", join({"4OFF", "5 10 10 5", "0 0 0 0", "1 0 0 0"}), 2,
       "counts announce 20 element lines but the file has only 2"},
      {"truncated vertex list with its faces",
       join({"4OFF", "5 10 10 5", "0 0 0 0", "1 0 0 0", "0 1 0 0", "3 0 1 2"}), 2,
       "counts announce 20 element lines but the file has only 4"},
      {"vertex with 3 coordinates", simplex_with(5, "0 1 0"), 5,
       "vertex 2 has 3 coordinates, expected 4"},
      {"vertex with 5 coordinates", simplex_with(3, "0 0 0 0 0"), 3,
       "vertex 0 has 5 coordinates, expected 4"},
      {"non-number coordinate", simplex_with(6, "0 0 one 0"), 6, "'one' is not a number"},
      {"coordinate with trailing letters", simplex_with(4, "1.5x 0 0 0"), 4,
       "'1.5x' is not a number"},
      {"nan coordinate", simplex_with(4, "nan 0 0 0"), 4, "'nan' is not finite"},
      {"NaN coordinate", simplex_with(7, "0 0 0 NaN"), 7, "is not finite"},
      {"inf coordinate", simplex_with(7, "0 0 0 inf"), 7, "'inf' is not finite"},
      {"-infinity coordinate", simplex_with(3, "-infinity 0 0 0"), 3, "is not finite"},
      {"coordinate overflow", simplex_with(5, "0 1e400 0 0"), 5, "'1e400' is out of range"},
      {"non-UTF-8 bytes in a number", simplex_with(5, "0 1\xff\xfe 0 0"), 5, "is not a number"},
      {"non-UTF-8 lone byte", simplex_with(6, "0 0 \xc3 0"), 6, "is not a number"},
      {"face index out of range", simplex_with(12, "3 0 2 5"), 12,
       "face 4 refers to vertex 5, but there are only 5"},
      {"face index negative", simplex_with(8, "3 0 -1 2"), 8, "'-1' is not a non-negative"},
      {"face with 2 vertices", simplex_with(9, "2 0 1"), 9,
       "face 1 has 2 entries, at least 3 needed"},
      {"face with 0 vertices", simplex_with(9, "0"), 9, "face 1 has 0 entries"},
      {"face repeating a vertex", simplex_with(10, "3 0 1 0"), 10, "face 2 lists vertex 0 twice"},
      {"face size not a number", simplex_with(8, "three 0 1 2"), 8, "face 0 size 'three'"},
      {"face shorter than announced", simplex_with(11, "4 0 2 3"), 11,
       "face 3 announces 4 entries but the line has 3"},
      {"cell face out of range", simplex_with(20, "4 1 2 5 10"), 20,
       "cell 2 refers to face 10, but there are only 10"},
      {"cell listing a face twice", simplex_with(22, "4 6 7 6 9"), 22, "cell 4 lists face 6 twice"},
      {"cell with one face", simplex_with(18, "1 0"), 18, "cell 0 has 1 entries"},
      {"color with 2 components", simplex_with(8, "3 0 1 2 255 0"), 8,
       "face 0 has 2 values after its indices"},
      {"color with 5 components", simplex_with(21, "4 3 4 5 9 1 1 1 1 1"), 21,
       "cell 3 has 5 values after its indices"},
      {"color component above 255", simplex_with(13, "3 0 3 4 256 0 0"), 13, "out of range"},
      {"negative color component", simplex_with(13, "3 0 3 4 0 -1 0"), 13, "out of range"},
      {"color mixing scales", simplex_with(13, "3 0 3 4 0.5 128 0"), 13, "mixes"},
      {"color not a number", simplex_with(13, "3 0 3 4 red 0 0"), 13, "is not a number"},
      {"trailing garbage line", s + "garbage\n", 23, "unexpected data after the last element"},
      {"4000000000 vertices in a 5-line file", "4OFF\n4000000000 1 0 1\n0 0 0 0\n3 0 0 0\n1 0\n", 2,
       "counts announce"},
      {"2^64-1 vertices", "4OFF\n18446744073709551615 1 3 1\n0 0 0 0\n3 0 1 2\n2 0 0\n", 2,
       "counts announce"},
      {"line numbers count comments and blank lines",
       "# comment\n\n4OFF\n# counts next\n5 10 10 5\n\n" + join({"0 0 0 0", "1 0 0 0", "x"}) +
           join(std::vector<std::string>(base.begin() + 5, base.end())),
       9, "vertex 2 has 1 coordinates"},
      {"CRLF line endings", join(crlf, "\r\n"), 16, "face 8 refers to vertex 9"},
  };
  return m;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// (a) round trips

TEST_CASE("write_off then read_off reproduces every built-in", "[off][roundtrip]") {
  const std::vector<std::string> specs = {
      // 3D
      "cube:3", "simplex:3", "orthoplex:3", "prism:polygon:5", "prism:polygon:3",
      // 4D
      "5-cell", "tesseract", "16-cell", "duoprism:3,4", "duoprism:5,7", "prism:cube:3",
      "prism:simplex:3", "prism:orthoplex:3", "cube:4", "simplex:4", "orthoplex:4",
      // 5D and up
      "cube:5", "simplex:5", "orthoplex:5", "prism:5-cell", "prism:duoprism:3,4", "prism:tesseract",
      "cube:6", "simplex:8", "simplex:9"};
  for (const auto& spec : specs) {
    INFO(spec);
    const Complex c = load_model(spec);
    const std::string text = to_text(c);
    const Complex d = from_text(text, spec);
    require_same_complex(c, d);
    const ValidationReport r = validate(d);
    INFO(r.summary());
    CHECK(r.ok());
    CHECK(signed_volume(d) == Approx(signed_volume(c)).epsilon(1e-12));
    // Writing the result again gives the same text.
    CHECK(to_text(d) == text);
    CHECK(d.colors(2).empty());
  }
}

TEST_CASE("round trip keeps coordinates that need all 17 digits", "[off][roundtrip]") {
  Complex c = load_model("tesseract");
  Eigen::MatrixXd p = c.positions();
  // Rotation-like perturbations give full-precision coordinates; -0.0 must survive too.
  for (Eigen::Index j = 0; j < p.cols(); ++j)
    for (Eigen::Index i = 0; i < p.rows(); ++i) p(i, j) *= 1.0 + 1e-3 * std::sin(1.0 + i + 7 * j);
  p(0, 0) = 0.1 + 0.2;
  c.set_positions(p);
  const Complex d = from_text(to_text(c));
  CHECK(same_bits(c.positions(), d.positions()));
  Complex z = load_model("cube:3");
  Eigen::MatrixXd q = z.positions();
  q(1, 2) = 5e-324;  // smallest subnormal
  q(2, 3) = 1.7976931348623157e308;
  z.set_positions(q);
  CHECK(same_bits(z.positions(), from_text(to_text(z)).positions()));
}

TEST_CASE("write_off_file and read_off_file", "[off][roundtrip]") {
  const fs::path dir = fs::temp_directory_path() / "cw4d_test_off_io";
  fs::create_directories(dir);
  const std::string path = (dir / "duoprism.4off").string();
  const Complex c = load_model("duoprism:4,6");
  write_off_file(path, c);
  const Complex d = read_off_file(path);
  require_same_complex(c, d);
  CHECK(validate(d).ok());
  // load_model takes paths too.
  CHECK(load_model(path).fvector() == c.fvector());
  fs::remove_all(dir);
}

TEST_CASE("write_off rejects complexes outside R^3..R^9", "[off]") {
  std::ostringstream out;
  CHECK_THROWS_AS(write_off(out, make_polygon(5)), InputError);
  CHECK_THROWS_AS(write_off(out, make_cube(2)), InputError);
}

// ---------------------------------------------------------------------------------------------
// (b) Miratope files

TEST_CASE("header_counts helper reads V F E C", "[off][miratope]") {
  CHECK(header_counts(miratope + "regular/Pentachoron.off") ==
        std::vector<std::size_t>{5, 10, 10, 5});
  CHECK(header_counts(miratope + "regular/Tesseract.off") ==
        std::vector<std::size_t>{16, 24, 32, 8});
}

TEST_CASE("Miratope convex regular polychora load, match their headers and validate",
          "[off][miratope]") {
  const std::vector<std::string> convex = {"Pentachoron",        "Tesseract",
                                           "Hexadecachoron",     "Icositetrachoron",
                                           "Hecatonicosachoron", "Hexacosichoron"};
  for (const auto& name : convex) {
    const std::string path = miratope + "regular/" + name + ".off";
    INFO(path);
    const auto h = header_counts(path);
    REQUIRE(h.size() == 4);
    Complex c(4);
    REQUIRE_NOTHROW(c = read_off_file(path));
    CHECK(c.ambient_dim() == 4);
    CHECK(c.fvector() == std::vector<std::size_t>{h[0], h[2], h[1], h[3]});
    const ValidationReport r = validate(c);
    INFO(r.summary());
    CHECK(r.ok());
    check_outward_normals(c);
  }
}

TEST_CASE("Miratope star regular polychora load", "[off][miratope]") {
  const std::vector<std::string> convex = {"Pentachoron",        "Tesseract",
                                           "Hexadecachoron",     "Icositetrachoron",
                                           "Hecatonicosachoron", "Hexacosichoron"};
  const auto files = off_files(miratope + "regular");
  REQUIRE(files.size() == 16);
  std::size_t star = 0;
  for (const auto& path : files) {
    if (std::find(convex.begin(), convex.end(), path.stem().string()) != convex.end()) continue;
    ++star;
    INFO(path.string());
    const auto h = header_counts(path);
    REQUIRE(h.size() == 4);
    Complex c(4);
    REQUIRE_NOTHROW(c = read_off_file(path.string()));
    CHECK(c.count(0) == h[0]);
    CHECK(c.count(2) == h[1]);
    CHECK(c.count(1) == h[2]);
    CHECK(c.count(3) == h[3]);
  }
  CHECK(star == 10);
}

TEST_CASE("Miratope convex uniform polychora load, match their headers and validate",
          "[off][miratope]") {
  const auto files = off_files(miratope + "convex uniform");
  REQUIRE(files.size() == 41);
  for (const auto& path : files) {
    INFO(path.string());
    const auto h = header_counts(path);
    REQUIRE(h.size() == 4);
    Complex c(4);
    REQUIRE_NOTHROW(c = read_off_file(path.string()));
    CHECK(c.fvector() == std::vector<std::size_t>{h[0], h[2], h[1], h[3]});
    const ValidationReport r = validate(c);
    INFO(r.summary());
    CHECK(r.ok());
    check_outward_normals(c);
  }
}

TEST_CASE("Miratope nonconvex uniform polychora load and match their headers", "[off][miratope]") {
  // Self-intersecting cells and faces: only the structure is checked, not validity.
  const auto files = off_files(miratope + "nonconvex uniform");
  REQUIRE_FALSE(files.empty());
  for (const auto& path : files) {
    INFO(path.string());
    const auto h = header_counts(path);
    REQUIRE(h.size() == 4);
    Complex c(4);
    REQUIRE_NOTHROW(c = read_off_file(path.string()));
    CHECK(c.fvector() == std::vector<std::size_t>{h[0], h[2], h[1], h[3]});
  }
}

// ---------------------------------------------------------------------------------------------
// (c) plain OFF

TEST_CASE("a plain 3D OFF cube", "[off]") {
  const std::string text =
      "OFF\n"
      "8 6 12\n"
      "-1 -1 -1\n 1 -1 -1\n 1 1 -1\n -1 1 -1\n"
      "-1 -1 1\n 1 -1 1\n 1 1 1\n -1 1 1\n"
      "4 0 3 2 1\n"
      "4 4 5 6 7\n"
      "4 0 1 5 4\n"
      "4 2 3 7 6\n"
      "4 1 2 6 5\n"
      "4 0 4 7 3\n";
  const Complex c = from_text(text, "cube.off");
  CHECK(c.ambient_dim() == 3);
  CHECK(c.fvector() == std::vector<std::size_t>{8, 12, 6});
  CHECK(validate(c).ok());
  CHECK(signed_volume(c) == Approx(8.0));
  // Same cube with every face listed clockwise, comments and counts on the header line: the
  // reader orients it outward all the same.
  const std::string flipped =
      "OFF 8 6 12  # counts on the header line\n"
      "-1 -1 -1\n 1 -1 -1\n 1 1 -1\n -1 1 -1\n"
      "-1 -1 1\n 1 -1 1\n 1 1 1\n -1 1 1\n"
      "4 1 2 3 0\n4 7 6 5 4\n4 4 5 1 0\n4 6 7 3 2\n4 5 6 2 1\n4 3 7 4 0\n";
  const Complex d = from_text(flipped, "flipped.off");
  CHECK(d.fvector() == std::vector<std::size_t>{8, 12, 6});
  CHECK(validate(d).ok());
  CHECK(signed_volume(d) == Approx(8.0));
}

// ---------------------------------------------------------------------------------------------
// (d) malformed inputs

TEST_CASE("the simplex used by the catalogue is itself valid", "[off][malformed]") {
  const Complex c = from_text(join(simplex_lines()));
  CHECK(c.fvector() == std::vector<std::size_t>{5, 10, 10, 5});
  CHECK(validate(c).ok());
}

TEST_CASE("malformed inputs throw ParseError with the right line", "[off][malformed]") {
  const auto catalogue = malformed_catalogue();
  REQUIRE(catalogue.size() >= 15);
  for (const auto& bad : catalogue) {
    DYNAMIC_SECTION(bad.label) {
      std::istringstream in(bad.text);
      REQUIRE_THROWS_AS(read_off(in, bad.label), ParseError);
      try {
        std::istringstream again(bad.text);
        read_off(again, bad.label);
      } catch (const ParseError& e) {
        INFO("message: " << e.what());
        CHECK(e.line() == bad.line);
        CHECK(contains(e.message(), bad.needle));
        CHECK(e.file() == bad.label);
        CHECK(std::string(e.what()) ==
              bad.label + ":" + std::to_string(bad.line) + ": " + e.message());
      }
    }
  }
}

TEST_CASE("huge announced counts fail fast", "[off][malformed]") {
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < 100; ++i) {
    std::istringstream in("4OFF\n4000000000 4000000000 0 4000000000\n0 0 0 0\n0 0 0 0\n0\n");
    REQUIRE_THROWS_AS(read_off(in, "huge"), ParseError);
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  CHECK(seconds < 1.0);
}

TEST_CASE("regression: announced counts whose sum wraps around 2^64 are rejected",
          "[off][malformed]") {
  // V + F + C = 3 + 1 + (2^64 - 2) wraps to 2, which passes the "announced lines" check.
  const std::string wrap3 =
      "4OFF\n3 1 3 18446744073709551614\n0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 2\n";
  {
    std::istringstream in(wrap3);
    CHECK_THROWS_AS(read_off(in, "wrap"), ParseError);
  }
  // 5OFF: the two higher counts wrap to 0 together.
  const std::string wrap5 =
      "5OFF\n3 1 3 9223372036854775808 9223372036854775808\n"
      "0 0 0 0 0\n1 0 0 0 0\n0 1 0 0 0\n3 0 1 2\n";
  {
    std::istringstream in(wrap5);
    CHECK_THROWS_AS(read_off(in, "wrap5"), ParseError);
  }
}

TEST_CASE("read_off_file on a missing path", "[off][malformed]") {
  const std::string path = "/nonexistent/cw4d/no_such_file.4off";
  REQUIRE_THROWS_AS(read_off_file(path), ParseError);
  try {
    read_off_file(path);
  } catch (const ParseError& e) {
    CHECK(e.line() == 0);
    CHECK(e.file() == path);
  }
  // Through load_model as well (a path, not a built-in).
  CHECK_THROWS_AS(load_model(path), ParseError);
}

// ---------------------------------------------------------------------------------------------
// (e) colors

TEST_CASE("face and cell colors are read and survive a round trip", "[off][color]") {
  auto lines = simplex_lines();
  lines[7] += " 255 0 0";      // face 0: 0..255 integers
  lines[9] += " 0 0 255 128";  // face 2: with alpha
  lines[16] += " 0.25 0.5 1";  // face 9: 0..1 floats
  for (std::size_t i = 17; i < 22; ++i) lines[i] += " 0.5 0.5 0.5 1";
  const Complex c = from_text(join(lines));
  REQUIRE(validate(c).ok());
  REQUIRE(c.colors(2).size() == 10);
  REQUIRE(c.colors(3).size() == 5);
  CHECK(c.colors(2)[0] == Rgba{1.0f, 0.0f, 0.0f, 1.0f});
  CHECK(c.colors(2)[1] == Rgba{});  // uncolored faces are opaque white
  CHECK(c.colors(2)[2] == Rgba{0.0f, 0.0f, 1.0f, static_cast<float>(128 / 255.0)});
  CHECK(c.colors(2)[9] == Rgba{0.25f, 0.5f, 1.0f, 1.0f});
  for (const auto& col : c.colors(3)) CHECK(col == Rgba{0.5f, 0.5f, 0.5f, 1.0f});

  const Complex d = from_text(to_text(c));
  require_same_complex(c, d);
  CHECK(d.colors(2) == c.colors(2));
  CHECK(d.colors(3) == c.colors(3));
  CHECK(to_text(d) == to_text(c));
}

TEST_CASE("colors of a 3D OFF", "[off][color]") {
  const std::string text =
      "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
      "3 0 2 1 0 255 0\n3 0 1 3\n3 0 3 2\n3 1 2 3 0.1 0.2 0.3 0.4\n";
  const Complex c = from_text(text, "tet.off");
  REQUIRE(validate(c).ok());
  REQUIRE(c.colors(2).size() == 4);
  CHECK(c.colors(2)[0] == Rgba{0.0f, 1.0f, 0.0f, 1.0f});
  CHECK(c.colors(2)[1] == Rgba{});
  CHECK(c.colors(2)[3] == Rgba{0.1f, 0.2f, 0.3f, 0.4f});
  const Complex d = from_text(to_text(c));
  CHECK(d.colors(2) == c.colors(2));
}

// ---------------------------------------------------------------------------------------------
// (f) files as they are shared: counts that disagree with the body, colors, comments

namespace {

// Reads `text` with the given strictness, collecting the warnings.
Complex read_quirky(const std::string& text, bool strict, std::vector<std::string>* warnings) {
  OffReadOptions options;
  options.strict = strict;
  options.warn = [warnings](const std::string& w) { warnings->push_back(w); };
  ScopedOffReadOptions scoped(options);
  std::istringstream in(text);
  return read_off(in, "quirky.4off");
}

}  // namespace

TEST_CASE("header counts that disagree with the body: read as the body stands, one warning",
          "[off][quirks]") {
  const std::string s = join(simplex_lines());
  const std::vector<std::size_t> simplex_f{5, 10, 10, 5};
  struct Case {
    std::string label, text;
    std::vector<std::size_t> fvector;  // what the body holds
  };
  auto with_counts = [&](const std::string& counts) { return simplex_with(2, counts); };
  const std::vector<Case> cases = {
      {"too many vertices", with_counts("6 10 10 5"), simplex_f},
      {"too few vertices", with_counts("4 10 10 5"), simplex_f},
      {"too many faces", with_counts("5 12 10 5"), simplex_f},
      {"too many cells", with_counts("5 10 10 7"), simplex_f},
      {"too few cells", with_counts("5 10 10 3"), simplex_f},
      {"all counts zero", with_counts("0 0 0 0"), simplex_f},
      {"counts on the header line, wrong", "4OFF 9 9 9 9\n" + s.substr(s.find("0 0 0 0")),
       simplex_f},
      {"a cell more than announced", s + "4 6 7 8 9\n", {5, 10, 10, 6}},
      {"cells missing", s.substr(0, s.rfind("4 3 4 5 9")), {5, 10, 10, 3}},
      {"3D OFF with a face count too high",
       "OFF\n4 9 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
       "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
       {4, 6, 4}},
  };
  for (const auto& c : cases) {
    DYNAMIC_SECTION(c.label) {
      std::vector<std::string> warnings;
      const Complex m = read_quirky(c.text, false, &warnings);
      std::vector<std::size_t> f = m.fvector();
      f.resize(c.fvector.size());
      CHECK(f == c.fvector);
      REQUIRE(warnings.size() == 1);
      CHECK(contains(warnings[0], "disagree with the body"));
      CHECK(warnings[0].rfind("quirky.4off:", 0) == 0);
      // Strict reading refuses the same file with one line naming the counts.
      warnings.clear();
      try {
        read_quirky(c.text, true, &warnings);
        FAIL("strict reading accepted " << c.label);
      } catch (const ParseError& e) {
        CHECK(contains(e.message(), "disagree with the body"));
        CHECK(contains(e.message(), "strict"));
        CHECK(std::string(e.what()).find('\n') == std::string::npos);
      }
      CHECK(warnings.empty());
    }
  }
  SECTION("the right counts give no warning") {
    std::vector<std::string> warnings;
    const Complex m = read_quirky(s, true, &warnings);
    CHECK(validate(m).ok());
    CHECK(warnings.empty());
  }
  SECTION("a body that splits no way keeps the header's error") {
    std::vector<std::string> warnings;
    CHECK_THROWS_WITH(read_quirky(s + "garbage\n", false, &warnings),
                      Catch::Contains("unexpected data after the last element"));
    CHECK(warnings.empty());
  }
}

TEST_CASE("colors: integers are bytes, decimals 0..1; vertex colors and end-of-line comments",
          "[off][quirks][color]") {
  auto lines = simplex_lines();
  lines[2] += " 255 255 255";  // vertex colors are read and ignored
  lines[3] += " 0.5 0.5 0.5 1.0  # a vertex with a color and a comment";
  lines[7] += " 0 0 1";         // integers: bytes, even when all are 0 or 1
  lines[8] += " 1.0 0.5 0";     // decimals: 0..1
  lines[9] += " 1e0 0 0 5e-1";  // an exponent makes it a decimal too
  lines[10] += "#comment right after the indices";
  for (std::size_t i = 17; i < 22; ++i) lines[i] += " 10 20 30 255 # cell " + std::to_string(i);
  std::vector<std::string> warnings;
  const Complex c = read_quirky(join(lines), true, &warnings);
  CHECK(warnings.empty());
  REQUIRE(validate(c).ok());
  REQUIRE(c.colors(2).size() == 10);
  CHECK(c.colors(2)[0] == Rgba{0.0f, 0.0f, static_cast<float>(1 / 255.0), 1.0f});
  CHECK(c.colors(2)[1] == Rgba{1.0f, 0.5f, 0.0f, 1.0f});
  CHECK(c.colors(2)[2] == Rgba{1.0f, 0.0f, 0.0f, 0.5f});
  CHECK(c.colors(2)[3] == Rgba{});
  REQUIRE(c.colors(3).size() == 5);
  for (const auto& col : c.colors(3))
    CHECK(col == Rgba{static_cast<float>(10 / 255.0), static_cast<float>(20 / 255.0),
                      static_cast<float>(30 / 255.0), 1.0f});
  // Written as decimals, so they read back the same.
  const std::string text = to_text(c);
  const Complex d = from_text(text);
  CHECK(d.colors(2) == c.colors(2));
  CHECK(d.colors(3) == c.colors(3));
  // A model without colors stays without.
  CHECK(from_text(join(simplex_lines())).colors(2).empty());
}
