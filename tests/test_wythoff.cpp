// Tests of the Wythoff construction: f-vectors of every ringing of A4, B4, F4, H4 against the
// published tables of convex uniform polychora, the Miratope 4OFF files as an independent oracle
// (counts and circumradius / edge), uniformity and validity of every result, 3D and 2D families,
// bad diagrams and the named built-ins.
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/complex/wythoff.hpp"

using namespace cw4d;
using FVector = std::vector<std::size_t>;

namespace {

// A ringing ("xxoo") applied to a family's labels ("433") gives the diagram "x4x3o3o".
std::string diagram(const std::string& rings, const std::string& labels) {
  std::string out;
  for (std::size_t i = 0; i < rings.size(); ++i) {
    if (i > 0) out += labels[i - 1];
    out += rings[i];
  }
  return out;
}

struct Ringing {
  const char* rings;
  FVector f;  // V, E, F, C (or V, E, F in 3D)
};

struct Family {
  const char* name;
  const char* labels;
  std::vector<Ringing> ringings;
};

// Published f-vectors of the convex uniform polychora (Coxeter, Johnson; Klitzing's tables).
const std::vector<Family>& families_4d() {
  static const std::vector<Family> families = {
      {"A4",
       "333",
       {{"xooo", {5, 10, 10, 5}},
        {"oxoo", {10, 30, 30, 10}},
        {"ooxo", {10, 30, 30, 10}},
        {"ooox", {5, 10, 10, 5}},
        {"xxoo", {20, 40, 30, 10}},
        {"xoxo", {30, 90, 80, 20}},
        {"xoox", {20, 60, 70, 30}},
        {"oxxo", {30, 60, 40, 10}},
        {"oxox", {30, 90, 80, 20}},
        {"ooxx", {20, 40, 30, 10}},
        {"xxxo", {60, 120, 80, 20}},
        {"xxox", {60, 150, 120, 30}},
        {"xoxx", {60, 150, 120, 30}},
        {"oxxx", {60, 120, 80, 20}},
        {"xxxx", {120, 240, 150, 30}}}},
      {"B4",
       "433",
       {{"xooo", {16, 32, 24, 8}},
        {"oxoo", {32, 96, 88, 24}},
        {"ooxo", {24, 96, 96, 24}},
        {"ooox", {8, 24, 32, 16}},
        {"xxoo", {64, 128, 88, 24}},
        {"xoxo", {96, 288, 248, 56}},
        {"xoox", {64, 192, 208, 80}},
        {"oxxo", {96, 192, 120, 24}},
        {"oxox", {96, 288, 240, 48}},
        {"ooxx", {48, 120, 96, 24}},
        {"xxxo", {192, 384, 248, 56}},
        {"xxox", {192, 480, 368, 80}},
        {"xoxx", {192, 480, 368, 80}},
        {"oxxx", {192, 384, 240, 48}},
        {"xxxx", {384, 768, 464, 80}}}},
      {"F4",
       "343",
       {{"xooo", {24, 96, 96, 24}},
        {"oxoo", {96, 288, 240, 48}},
        {"ooxo", {96, 288, 240, 48}},
        {"ooox", {24, 96, 96, 24}},
        {"xxoo", {192, 384, 240, 48}},
        {"xoxo", {288, 864, 720, 144}},
        {"xoox", {144, 576, 672, 240}},
        {"oxxo", {288, 576, 336, 48}},
        {"oxox", {288, 864, 720, 144}},
        {"ooxx", {192, 384, 240, 48}},
        {"xxxo", {576, 1152, 720, 144}},
        {"xxox", {576, 1440, 1104, 240}},
        {"xoxx", {576, 1440, 1104, 240}},
        {"oxxx", {576, 1152, 720, 144}},
        {"xxxx", {1152, 2304, 1392, 240}}}},
      {"H4",
       "533",
       {{"xooo", {600, 1200, 720, 120}},
        {"oxoo", {1200, 3600, 3120, 720}},
        {"ooxo", {720, 3600, 3600, 720}},
        {"ooox", {120, 720, 1200, 600}},
        {"xxoo", {2400, 4800, 3120, 720}},
        {"xoxo", {3600, 10800, 9120, 1920}},
        {"xoox", {2400, 7200, 7440, 2640}},
        {"oxxo", {3600, 7200, 4320, 720}},
        {"oxox", {3600, 10800, 8640, 1440}},
        {"ooxx", {1440, 4320, 3600, 720}},
        {"xxxo", {7200, 14400, 9120, 1920}},
        {"xxox", {7200, 18000, 13440, 2640}},
        {"xoxx", {7200, 18000, 13440, 2640}},
        {"oxxx", {7200, 14400, 8640, 1440}},
        {"xxxx", {14400, 28800, 17040, 2640}}}},
  };
  return families;
}

// Platonic and Archimedean solids.
const std::vector<Family>& families_3d() {
  static const std::vector<Family> families = {
      {"A3",
       "33",
       {{"xoo", {4, 6, 4}},
        {"oxo", {6, 12, 8}},
        {"oox", {4, 6, 4}},
        {"xxo", {12, 18, 8}},
        {"xox", {12, 24, 14}},
        {"oxx", {12, 18, 8}},
        {"xxx", {24, 36, 14}}}},
      {"B3",
       "43",
       {{"xoo", {8, 12, 6}},
        {"oxo", {12, 24, 14}},
        {"oox", {6, 12, 8}},
        {"xxo", {24, 36, 14}},
        {"xox", {24, 48, 26}},
        {"oxx", {24, 36, 14}},
        {"xxx", {48, 72, 26}}}},
      {"H3",
       "53",
       {{"xoo", {20, 30, 12}},
        {"oxo", {30, 60, 32}},
        {"oox", {12, 30, 20}},
        {"xxo", {60, 90, 32}},
        {"xox", {60, 120, 62}},
        {"oxx", {60, 90, 32}},
        {"xxx", {120, 180, 62}}}},
  };
  return families;
}

double circumradius(const Complex& c) {
  return c.position(0).norm();
}

// Every edge has length 2, every vertex lies on one sphere about the origin, the alternating
// sum of the f-vector is the Euler characteristic of a sphere, and validate() accepts it.
// Tolerances are relative to the circumradius.
void check_uniform(const Complex& c, double rel = 1e-9) {
  const int n = c.ambient_dim();
  const ValidationReport report = validate(c);
  INFO(report.summary());
  CHECK(report.ok());
  REQUIRE(c.count(0) > 0);
  const double r = circumradius(c);
  double worst_radius = 0.0, worst_edge = 0.0;
  for (std::uint32_t v = 0; v < c.count(0); ++v)
    worst_radius = std::max(worst_radius, std::abs(c.position(v).norm() - r));
  for (std::uint32_t e = 0; e < c.count(1); ++e) {
    const auto [a, b] = c.edge(e);
    worst_edge = std::max(worst_edge, std::abs((c.position(a) - c.position(b)).norm() - 2.0));
  }
  CHECK(worst_radius <= rel * r);
  CHECK(worst_edge <= rel * r);
  long long euler = 0;
  const FVector f = c.fvector();
  REQUIRE(f.size() == static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) euler += (k % 2 == 0 ? 1 : -1) * static_cast<long long>(f[k]);
  CHECK(euler == (n % 2 == 1 ? 2 : 0));
}

// The header counts (V, F, E, C in the file, returned as V, E, F, C) and the circumradius / edge
// ratio of a 4OFF file, read independently of cw4d's reader.
struct OffFacts {
  FVector f;
  double radius_over_edge = 0.0;
  double radius_spread = 0.0;  // (max - min) / max distance from the centroid
};

OffFacts read_off_facts(const std::filesystem::path& path) {
  std::ifstream in(path);
  REQUIRE(in);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find('#'));
    if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
  }
  REQUIRE(lines.size() >= 3);
  REQUIRE(lines[0].find("4OFF") != std::string::npos);
  std::istringstream counts(lines[1]);
  std::size_t nv = 0, nf = 0, ne = 0, nc = 0;
  counts >> nv >> nf >> ne >> nc;
  REQUIRE(lines.size() >= 3 + nv);
  Eigen::MatrixXd p(4, static_cast<Eigen::Index>(nv));
  for (std::size_t v = 0; v < nv; ++v) {
    std::istringstream row(lines[2 + v]);
    for (int i = 0; i < 4; ++i) row >> p(i, static_cast<Eigen::Index>(v));
  }
  std::istringstream face(lines[2 + nv]);
  std::size_t size = 0, a = 0, b = 0;
  face >> size >> a >> b;
  REQUIRE((size >= 3 && a < nv && b < nv));
  const Eigen::Vector4d centre = p.rowwise().mean();
  double lo = 1e300, hi = 0.0;
  for (Eigen::Index v = 0; v < p.cols(); ++v) {
    const double r = (p.col(v) - centre).norm();
    lo = std::min(lo, r);
    hi = std::max(hi, r);
  }
  const double edge =
      (p.col(static_cast<Eigen::Index>(a)) - p.col(static_cast<Eigen::Index>(b))).norm();
  return {{nv, ne, nf, nc}, hi / edge, (hi - lo) / hi};
}

}  // namespace

TEST_CASE("every ringing of A4, B4, F4, H4 has the published f-vector", "[wythoff]") {
  for (const auto& family : families_4d()) {
    REQUIRE(family.ringings.size() == 15);
    for (const auto& r : family.ringings) {
      const std::string d = diagram(r.rings, family.labels);
      INFO(family.name << " " << d);
      const Complex c = make_wythoff(d);
      CHECK(c.ambient_dim() == 4);
      CHECK(c.fvector() == r.f);
      check_uniform(c);
    }
  }
}

TEST_CASE("the Miratope convex uniform and regular files agree in counts and radius/edge",
          "[wythoff][data]") {
  const std::filesystem::path root = std::filesystem::path(CW4D_TEST_DATA_DIR) / "miratope";
  std::set<std::string> unmapped;
  int compared = 0;
  for (const char* folder : {"convex uniform", "regular"}) {
    REQUIRE(std::filesystem::is_directory(root / folder));
    for (const auto& entry : std::filesystem::directory_iterator(root / folder)) {
      if (entry.path().extension() != ".off") continue;
      const std::string name = entry.path().stem().string();
      const auto d = uniform_polychoron_diagram(name);
      if (!d) {
        if (std::string(folder) == "convex uniform") unmapped.insert(name);
        continue;
      }
      INFO(name << " = " << *d);
      const OffFacts file = read_off_facts(entry.path());
      REQUIRE(file.radius_spread < 1e-9);
      const Complex c = make_wythoff(*d);
      CHECK(c.fvector() == file.f);
      CHECK(circumradius(c) / 2.0 == Approx(file.radius_over_edge).epsilon(1e-9));
      ++compared;
    }
  }
  // Everything but the two non-Wythoffian ones (and the six convex regular polychora).
  CHECK(unmapped == std::set<std::string>{"Grand antiprism", "Semisnub icositetrachoron"});
  CHECK(compared == 39 + 6);
}

TEST_CASE("every ringing of A3, B3, H3 is the right Platonic or Archimedean solid", "[wythoff]") {
  for (const auto& family : families_3d()) {
    REQUIRE(family.ringings.size() == 7);
    for (const auto& r : family.ringings) {
      const std::string d = diagram(r.rings, family.labels);
      INFO(family.name << " " << d);
      const Complex c = make_wythoff(d);
      CHECK(c.ambient_dim() == 3);
      CHECK(c.fvector() == r.f);
      check_uniform(c);
    }
  }
}

TEST_CASE("I2(p) gives a p-gon, x p x a 2p-gon", "[wythoff]") {
  // Rounding of -cos(pi/p) makes large polygons drift by ~p^2 * 1e-16 of their radius.
  for (int p : {3, 4, 5, 6, 7, 8, 12, 17, 1000, 10000}) {
    INFO("p = " << p);
    const auto n = static_cast<std::size_t>(p);
    for (const char* pattern : {"x%o", "o%x", "x%x"}) {
      std::string d = pattern;
      d.replace(1, 1, std::to_string(p));
      INFO(d);
      const Complex c = make_wythoff(d);
      const std::size_t sides = d.front() == d.back() ? 2 * n : n;
      CHECK(c.ambient_dim() == 2);
      CHECK(c.fvector() == FVector{sides, sides});
      check_uniform(c, p > 1000 ? 1e-8 : 1e-9);
    }
  }
  CHECK_THROWS_AS(make_wythoff("x10001o"), InputError);
  const Complex square = make_wythoff("x2x");
  CHECK(square.fvector() == FVector{4, 4});
  check_uniform(square);
}

TEST_CASE("disconnected diagrams and higher ranks fall out of the same construction", "[wythoff]") {
  struct Case {
    const char* d;
    FVector f;
  };
  const Case cases[] = {
      {"x5o2x", {10, 15, 7}},               // pentagonal prism
      {"x2x2x", {8, 12, 6}},                // cube as a product of segments
      {"x3o2x3o", {9, 18, 15, 6}},          // 3,3-duoprism
      {"x5x2x8o", {80, 160, 98, 18}},       // 10,8-duoprism
      {"x3o3o2x", {8, 16, 14, 6}},          // tetrahedral prism
      {"x3o3o3o3o", {6, 15, 20, 15, 6}},    // 5-simplex
      {"x4o3o3o3o", {32, 80, 80, 40, 10}},  // 5-cube
      {"x3o3o3o4o", {10, 40, 80, 80, 32}},  // 5-orthoplex
  };
  for (const auto& k : cases) {
    INFO(k.d);
    const Complex c = make_wythoff(k.d);
    CHECK(c.fvector() == k.f);
    check_uniform(c);
  }
}

TEST_CASE("bad Coxeter diagrams throw InputError", "[wythoff][errors]") {
  const char* bad[] = {
      "",
      "x",
      "o",
      "xo",
      "x3",
      "3x",
      "x3o3",
      "x1o",
      "x0o",
      "x 3o",
      "x3y",
      "x-3o",
      "x5/2x",  // a doubly covered pentagon
      "x6/4o",
      "x5/0o",
      "x5/5o",
      "x5/o",
      "x7/2o3o",  // infinite
      "x3o3o3o3o3o3o3o3o3o3o",
      "x99999999999o",
      "x3.5o",
      "o3o",
      "o3o3o3o",
      "x3o2o",
      "o2x",
      "x3o2o3o",  // no ring somewhere
      "x6o3o",
      "x4o4o",
      "x3o6o",
      "x3o3o4o3o",
      "x4o3o4o",  // affine
      "x5o3o3o3o",
      "x3o5o3o",
      "x7o3o",
      "x5o3o5o",  // hyperbolic
  };
  for (const char* d : bad) {
    INFO("'" << d << "'");
    CHECK_THROWS_AS(make_wythoff(d), InputError);
    CHECK_THROWS_AS(load_model(std::string("wythoff:") + d), InputError);
  }
  CoxeterDiagram mismatched{{true, false, false}, {3}};
  CHECK_THROWS_AS(make_wythoff(mismatched), InputError);
  CHECK_THROWS_WITH(make_wythoff("x6o3o"), Catch::Contains("infinite"));
  CHECK_THROWS_WITH(make_wythoff("o3o3o"), Catch::Contains("no ringed node"));
  CHECK_THROWS_WITH(make_wythoff("x3o2o"), Catch::Contains("component"));
}

TEST_CASE("the parser reads the linear notation", "[wythoff]") {
  const CoxeterDiagram d = parse_coxeter_diagram("X5o3o10x");
  CHECK(d.ringed == std::vector<bool>{true, false, false, true});
  CHECK(d.labels == std::vector<int>{5, 3, 10});
  CHECK(make_wythoff("X4O3O3O").fvector() == FVector{16, 32, 24, 8});
}

TEST_CASE("named uniform polychora map to their diagrams", "[wythoff][builtins]") {
  CHECK(load_model("24-cell").fvector() == FVector{24, 96, 96, 24});
  CHECK(load_model("icositetrachoron").fvector() == FVector{24, 96, 96, 24});
  CHECK(load_model("120-cell").fvector() == FVector{600, 1200, 720, 120});
  CHECK(load_model("Hecatonicosachoron").fvector() == FVector{600, 1200, 720, 120});
  CHECK(load_model("600-cell").fvector() == FVector{120, 720, 1200, 600});
  CHECK(load_model("hexacosichoron").fvector() == FVector{120, 720, 1200, 600});
  CHECK(load_model("rectified 5-cell").fvector() == FVector{10, 30, 30, 10});
  CHECK(load_model("Rectified pentachoron").fvector() == FVector{10, 30, 30, 10});
  CHECK(load_model("truncated-tesseract").fvector() == FVector{64, 128, 88, 24});
  CHECK(load_model("Truncated 8-cell").fvector() == FVector{64, 128, 88, 24});
  CHECK(load_model("truncated_16-cell").fvector() == FVector{48, 120, 96, 24});
  CHECK(load_model("cantellated 24-cell").fvector() == FVector{288, 864, 720, 144});
  CHECK(load_model("wythoff:x3o4o3o").fvector() == FVector{24, 96, 96, 24});

  struct Name {
    const char* name;
    const char* diagram;
  };
  const Name names[] = {
      {"24-cell", "x3o4o3o"},
      {"120-cell", "x5o3o3o"},
      {"600-cell", "x3o3o5o"},
      {"rectified 16-cell", "o3x3o4o"},
      {"truncated hexadecachoron", "x3x3o4o"},
      {"runcitruncated hexadecachoron", "x3x3o4x"},
      {"bitruncated tesseract", "o4x3x3o"},
      {"runcinated 5-cell", "x3o3o3x"},
      {"cantitruncated hexacosichoron", "x3x3x5o"},
      {"omnitruncated 120-cell", "x5x3x3x"},
      {"runcicantitruncated 120-cell", "x5x3x3x"},
      {"Omnitruncated   Icositetrachoron", "x3x4x3x"},
  };
  for (const auto& [name, d] : names) {
    INFO(name);
    CHECK(uniform_polychoron_diagram(name) == std::optional<std::string>(d));
    CHECK(is_builtin_spec(name));
  }
  for (const char* name :
       {"grand antiprism", "snub 24-cell", "truncated", "tesseracts", "truncated cube", ""}) {
    INFO(name);
    CHECK_FALSE(uniform_polychoron_diagram(name).has_value());
  }
  CHECK(is_builtin_spec("wythoff:x4o3o3o"));
  CHECK(is_builtin_spec("wythoff:garbage"));  // a built-in spec, rejected when loaded
  CHECK_THROWS_AS(load_model("wythoff:garbage"), InputError);
}

TEST_CASE("the regular built-ins keep their own coordinates", "[wythoff][builtins]") {
  const Complex tesseract = load_model("tesseract");
  CHECK(tesseract.positions().cwiseAbs().isApproxToConstant(1.0));
  const Complex simplex = load_model("5-cell");
  CHECK(simplex.position(0).norm() == Approx(1.0));
  const Complex orthoplex = load_model("16-cell");
  CHECK(orthoplex.positions().cwiseAbs().colwise().sum().isApproxToConstant(1.0));
  // The Wythoff tesseract is congruent: edge 2, circumradius 2.
  CHECK(circumradius(make_wythoff("x4o3o3o")) == Approx(2.0));
}
