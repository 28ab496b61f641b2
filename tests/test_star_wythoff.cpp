// Star polytopes from Coxeter diagrams with fractional branch marks, checked against Miratope's
// 4OFF files (independent data: the regular and non-convex uniform polychora of its library),
// against published f-vectors of the Kepler-Poinsot and non-convex uniform polyhedra, and
// against the section volume oracle.
#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/operators.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/complex/wythoff.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"
#include "support/oracle.hpp"
#include "support/stride.hpp"

using namespace cw4d;

namespace {

using FVector = std::vector<std::size_t>;

// Shape invariants that do not depend on the frame, the vertex numbering or the scale: taken
// with the edge length as unit and the vertex centroid as centre.
struct Shape {
  FVector f;
  double radius = 0.0;                                // circumradius / edge
  std::vector<double> distances;                      // from one vertex to all others, sorted
  std::multiset<std::pair<std::size_t, long>> faces;  // (sides, distance of vertices i, i + 2)
  std::multiset<std::pair<std::size_t, std::size_t>> cells;  // (vertices, faces)
  double volume = 0.0;                                       // signed volume / edge^n
};

long rounded(double x) {
  return std::lround(x * 1e6);
}

std::vector<double> distances_from(const Complex& c, std::uint32_t v, double edge) {
  std::vector<double> out;
  for (std::uint32_t w = 0; w < c.count(0); ++w)
    if (w != v) out.push_back((c.position(w) - c.position(v)).norm() / edge);
  std::sort(out.begin(), out.end());
  return out;
}

Shape shape_of(const Complex& c) {
  Shape s;
  s.f = c.fvector();
  const std::vector<std::uint32_t> first = c.face_cycle(0);
  const double edge = (c.position(first[1]) - c.position(first[0])).norm();
  Eigen::VectorXd centre = Eigen::VectorXd::Zero(c.ambient_dim());
  for (std::uint32_t v = 0; v < c.count(0); ++v) centre += c.position(v);
  centre /= static_cast<double>(c.count(0));
  for (std::uint32_t v = 0; v < c.count(0); ++v)
    s.radius = std::max(s.radius, (c.position(v) - centre).norm() / edge);
  s.distances = distances_from(c, 0, edge);
  for (std::uint32_t f = 0; f < c.count(2); ++f) {
    const auto cycle = c.face_cycle(f);
    s.faces.insert(
        {cycle.size(), rounded((c.position(cycle[2]) - c.position(cycle[0])).norm() / edge)});
  }
  if (c.top_rank() >= 4)
    for (std::uint32_t k = 0; k < c.count(3); ++k) {
      std::set<std::uint32_t> verts;
      const auto faces = c.boundary(3).ids(k);
      for (auto f : faces)
        for (auto v : c.face_cycle(f)) verts.insert(v);
      s.cells.insert({verts.size(), faces.size()});
    }
  s.volume = signed_volume(c) / std::pow(edge, c.ambient_dim());
  return s;
}

// Every vertex sees the same distances (the construction is vertex-transitive): a few seeded
// vertices against vertex 0.
void check_vertex_transitive(const Complex& c, const Shape& s) {
  std::mt19937 rng(7);
  const auto first = c.face_cycle(0);
  const double edge = (c.position(first[1]) - c.position(first[0])).norm();
  for (int t = 0; t < 3; ++t) {
    const auto v = std::uniform_int_distribution<std::uint32_t>(0, c.count(0) - 1)(rng);
    const auto d = distances_from(c, v, edge);
    REQUIRE(d.size() == s.distances.size());
    for (std::size_t i = 0; i < d.size(); ++i) REQUIRE(d[i] == Approx(s.distances[i]).margin(1e-7));
  }
}

void check_same_shape(const Shape& built, const Shape& file) {
  CHECK(built.f == file.f);
  CHECK(built.radius == Approx(file.radius).epsilon(1e-9));
  REQUIRE(built.distances.size() == file.distances.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < built.distances.size(); ++i)
    worst = std::max(worst, std::abs(built.distances[i] - file.distances[i]));
  CHECK(worst < 1e-6);
  CHECK(built.faces == file.faces);
  CHECK(built.cells == file.cells);
  CHECK(built.volume == Approx(file.volume).epsilon(1e-6));
}

Eigen::VectorXd random_unit(std::mt19937& rng, int n) {
  std::normal_distribution<double> g;
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v(i) = g(rng);
  return v.normalized();
}

// Seeded sections: closed chains whose volume is the oracle's; true when one is flagged as
// self-intersecting.
bool check_sections(const Complex& c, std::mt19937& rng, int planes) {
  double r = 0.0;
  for (std::uint32_t v = 0; v < c.count(0); ++v) r = std::max(r, c.position(v).norm());
  bool flagged = false;
  for (int t = 0; t < planes; ++t) {
    const Eigen::VectorXd n = random_unit(rng, 4);
    const double d = std::uniform_real_distribution<double>(-0.6, 0.6)(rng) * r;
    INFO("n = " << n.transpose() << ", d = " << d);
    Section s;
    REQUIRE_NOTHROW(s = section(c, Hyperplane{n, d}));
    const double oracle = test::bspline_section_volume(c, n, d);
    CHECK(signed_volume(s.complex) == Approx(oracle).epsilon(1e-7).margin(1e-9 * r * r * r));
    flagged = flagged || s.self_intersecting;
  }
  return flagged;
}

std::vector<std::filesystem::path> off_files(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".off") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

const std::filesystem::path kMiratope = std::filesystem::path(CW4D_TEST_DATA_DIR) / "miratope";

}  // namespace

TEST_CASE("the sixteen regular polychora from their diagrams match Miratope's files",
          "[wythoff][star][data]") {
  const std::map<std::string, std::string> convex = {
      {"Pentachoron", "x3o3o3o"},        {"Tesseract", "x4o3o3o"},
      {"Hexadecachoron", "x3o3o4o"},     {"Icositetrachoron", "x3o4o3o"},
      {"Hecatonicosachoron", "x5o3o3o"}, {"Hexacosichoron", "x3o3o5o"}};
  const auto files = off_files(kMiratope / "regular");
  REQUIRE(files.size() == 16);
  std::mt19937 rng(1818);
  int stars = 0, flagged = 0;
  for (const auto& path : files) {
    const std::string name = path.stem().string();
    const auto it = convex.find(name);
    const auto star = star_polychoron_diagram(name);
    REQUIRE((it != convex.end() || star.has_value()));
    const std::string diagram = it != convex.end() ? it->second : *star;
    INFO(name << " = " << diagram);
    const Complex built = make_wythoff(diagram);
    const Complex file = read_off_file(path.string());
    const ValidationReport report = validate(built);
    INFO(report.summary());
    CHECK(report.ok());
    const Shape b = shape_of(built);
    check_same_shape(b, shape_of(file));
    check_vertex_transitive(built, b);
    CHECK(is_convex(built) == (it != convex.end()));
    const bool self_intersecting = check_sections(built, rng, 6);
    if (star) {
      ++stars;
      flagged += self_intersecting ? 1 : 0;
      // The names load as models too, in their short and dashed forms.
      CHECK(load_model(name).fvector() == b.f);
    }
  }
  CHECK(stars == 10);
  // Six seeded planes find a self-intersection in every star one (test_self_intersection checks
  // the flag against exact triangle tests, the icosahedral 120-cell among them).
  CHECK(flagged == 10);
}

TEST_CASE("the regular star polychora have their Schlaefli-Hess names", "[wythoff][star]") {
  struct Case {
    const char* name;
    const char* diagram;
    FVector f;
  };
  // Schlaefli symbols and counts from H. S. M. Coxeter, "Regular Polytopes" (1973), table IV.
  const Case cases[] = {
      {"icosahedral 120-cell", "x3o5o5/2o", {120, 720, 1200, 120}},
      {"small stellated 120-cell", "x5/2o5o3o", {120, 1200, 720, 120}},
      {"great 120-cell", "x5o5/2o5o", {120, 720, 720, 120}},
      {"grand 120-cell", "x5o3o5/2o", {120, 720, 720, 120}},
      {"great stellated 120-cell", "x5/2o3o5o", {120, 720, 720, 120}},
      {"grand stellated 120-cell", "x5/2o5o5/2o", {120, 720, 720, 120}},
      {"great grand 120-cell", "x5o5/2o3o", {120, 1200, 720, 120}},
      {"great icosahedral 120-cell", "x3o5/2o5o", {120, 720, 1200, 120}},
      {"grand 600-cell", "x3o3o5/2o", {120, 720, 1200, 600}},
      {"great grand stellated 120-cell", "x5/2o3o3o", {600, 1200, 720, 120}},
  };
  for (const Case& k : cases) {
    INFO(k.name);
    CHECK(star_polychoron_diagram(k.name) == std::optional<std::string>(k.diagram));
    std::string dashed = k.name;
    std::replace(dashed.begin(), dashed.end(), ' ', '-');
    CHECK(star_polychoron_diagram(dashed) == std::optional<std::string>(k.diagram));
    // Coxeter lists (N0, N1, N2, N3) = vertices, edges, faces, cells.
    CHECK(make_wythoff(k.diagram).fvector() == k.f);
    CHECK(load_model(dashed).fvector() == k.f);
  }
  CHECK(star_polychoron_diagram("Great-Grand_Stellated 120-CELL") ==
        std::optional<std::string>("x5/2o3o3o"));
  CHECK(star_polychoron_diagram("stellated 120-cell") == std::optional<std::string>("x5/2o5o3o"));
  CHECK_FALSE(star_polychoron_diagram("great grand great 120-cell").has_value());
  CHECK_FALSE(star_polychoron_diagram("120-cell").has_value());
  // A misspelt name is suggested.
  CHECK_THROWS_WITH(load_model("great grand stelated 120-cell"),
                    Catch::Contains("did you mean 'great grand stellated 120-cell'"));
}

TEST_CASE("every non-convex uniform Miratope file is built from its diagram",
          "[wythoff][star][data]") {
  const auto files = off_files(kMiratope / "nonconvex uniform");
  REQUIRE(files.size() == 31);
  std::set<std::string> unmapped;
  std::mt19937 rng(2718);
  int built_count = 0, flagged = 0, folded = 0;
  // (every fourth under the sanitizers: test::loop_stride)
  const std::size_t stride = test::loop_stride();
  for (std::size_t i = 0; i < files.size(); i += stride) {
    const auto& path = files[i];
    const std::string name = path.stem().string();
    const auto named = star_polychoron(name);
    if (!named) {
      unmapped.insert(name);
      continue;
    }
    INFO(name << " = " << named->diagram << (named->folded ? " (folded)" : ""));
    const Complex built = make_star_polychoron(name);
    const ValidationReport report = validate(built);
    INFO(report.summary());
    CHECK(report.ok());
    const Shape b = shape_of(built);
    check_same_shape(b, shape_of(read_off_file(path.string())));
    check_vertex_transitive(built, b);
    CHECK_FALSE(is_convex(built));
    CHECK(load_model(name).fvector() == b.f);
    flagged += check_sections(built, rng, 2) ? 1 : 0;
    ++built_count;
    folded += named->folded ? 1 : 0;
  }
  CHECK(unmapped.empty());
  // x5/2o3o3x puts four of its Wythoff vertices on each point (and its edges in pairs):
  // Miratope's file is that folded figure, built only on request, never from the bare diagram.
  // (the 28th file: not among every fourth)
  CHECK(folded == (stride == 1 ? 1 : 0));
  CHECK(star_polychoron("Runcinated great grand stellated hecatonicosachoron")->folded);
  CHECK_THROWS_WITH(make_wythoff("x5/2o3o3x"), Catch::Contains("vertices coincide"));
  CHECK_THROWS_WITH(load_model("wythoff:x5/2o3o3x"), Catch::Contains("vertices coincide"));
  CHECK(make_wythoff("x5/2o3o3x", WythoffOptions{true}).fvector() ==
        FVector{600, 3600, 7440, 2640});
  // Folding identifies vertices and edges only: coinciding faces are still refused.
  CHECK_THROWS_WITH(make_wythoff("x5/2x", WythoffOptions{true}), Catch::Contains("degenerate"));
  CHECK(built_count == static_cast<int>(test::strided_count(31, stride)));
  CHECK(flagged == built_count);  // every one self-intersects in one of its two seeded sections
}

TEST_CASE("Kepler-Poinsot and non-convex uniform polyhedra from fractional marks",
          "[wythoff][star]") {
  struct Case {
    const char* diagram;
    FVector f;
    int sides_max;  // largest face, counted as vertices of the cycle
  };
  // Counts from H. S. M. Coxeter, M. S. Longuet-Higgins, J. C. P. Miller, "Uniform polyhedra"
  // (1954).
  const Case cases[] = {
      {"x5/2o5o", {12, 30, 12}, 5},     // small stellated dodecahedron {5/2,5}
      {"o5/2o5x", {12, 30, 12}, 5},     // great dodecahedron {5,5/2}
      {"x5o5/2o", {12, 30, 12}, 5},     // great dodecahedron {5,5/2}
      {"x5/2o3o", {20, 30, 12}, 5},     // great stellated dodecahedron {5/2,3}
      {"x3o5/2o", {12, 30, 20}, 3},     // great icosahedron {3,5/2}
      {"o5/2x5o", {30, 60, 24}, 5},     // dodecadodecahedron
      {"o3x5/2o", {30, 60, 32}, 5},     // great icosidodecahedron
      {"x3x5/2o", {60, 90, 32}, 6},     // truncated great icosahedron
      {"x5/3x3o", {60, 90, 32}, 10},    // great stellated truncated dodecahedron {10/3}
      {"x4/3x3o", {24, 36, 14}, 8},     // stellated truncated hexahedron {8/3}
      {"x4/3o3x", {24, 48, 26}, 4},     // non-convex great rhombicuboctahedron
      {"x4/3x3x", {48, 72, 26}, 8},     // great truncated cuboctahedron
      {"x5/2o5x", {60, 120, 54}, 5},    // rhombidodecadodecahedron
      {"x5/3o3x", {60, 120, 62}, 5},    // non-convex great rhombicosidodecahedron
      {"x5/3x3x", {120, 180, 62}, 10},  // great truncated icosidodecahedron
      {"x2x5/2o", {10, 15, 7}, 5},      // pentagrammic prism
  };
  for (const Case& k : cases) {
    INFO(k.diagram);
    const Complex c = make_wythoff(k.diagram);
    CHECK(c.ambient_dim() == 3);
    CHECK(c.fvector() == k.f);
    const ValidationReport report = validate(c);
    INFO(report.summary());
    CHECK(report.ok());
    CHECK_FALSE(is_convex(c));
    CHECK(signed_volume(c) > 0.0);
    std::size_t sides = 0;
    for (std::uint32_t f = 0; f < c.count(2); ++f) sides = std::max(sides, c.face_cycle(f).size());
    CHECK(sides == static_cast<std::size_t>(k.sides_max));
    // Every edge has length 2 and every vertex the same radius.
    for (std::uint32_t e = 0; e < c.count(1); ++e) {
      const auto ends = c.boundary(1).ids(e);
      CHECK((c.position(ends[0]) - c.position(ends[1])).norm() == Approx(2.0).epsilon(1e-12));
    }
  }
}

TEST_CASE("star polygons: {p/q} from x p/q o, {2p/q} from x p/q x, in rotation order",
          "[wythoff][star]") {
  struct Case {
    const char* diagram;
    std::size_t n;
    int p, q;  // the cycle turns by 2 pi q / p per edge
  };
  const Case cases[] = {{"x5/2o", 5, 5, 2},  {"x5/3o", 5, 5, 3},   {"x7/3o", 7, 7, 3},
                        {"x8/3o", 8, 8, 3},  {"x5/3x", 10, 10, 3}, {"x8/3x", 16, 16, 3},
                        {"x7/3x", 14, 14, 3}};
  for (const Case& k : cases) {
    INFO(k.diagram);
    const Complex c = make_wythoff(k.diagram);
    CHECK(c.fvector() == FVector{k.n, k.n});
    CHECK(validate(c).ok());
    // Walk the edges: consecutive vertices subtend the angle 2 pi q / p at the centre.
    const double angle = 2.0 * std::acos(-1.0) * std::min(k.q, k.p - k.q) / k.p;
    for (std::uint32_t e = 0; e < c.count(1); ++e) {
      const auto ends = c.boundary(1).ids(e);
      const Eigen::VectorXd a = c.position(ends[0]), b = c.position(ends[1]);
      CHECK(std::acos(std::clamp(a.dot(b) / (a.norm() * b.norm()), -1.0, 1.0)) ==
            Approx(angle).epsilon(1e-9));
      CHECK((a - b).norm() == Approx(2.0).epsilon(1e-12));
    }
  }
}

TEST_CASE("degenerate and impossible fractional diagrams are refused with the reason",
          "[wythoff][star][errors]") {
  // The base point on a mirror outside the unringed nodes' subgroup: x5/2x is a doubly covered
  // pentagon, x3/2o3x folds the cuboctahedron's construction onto the octahedron's vertices.
  for (const char* d : {"x5/2x", "x3/2o3x", "x5/2o3o3x", "x2x5/2x", "x5/4o3x"}) {
    INFO(d);
    CHECK_THROWS_WITH(make_wythoff(d), Catch::Contains("is degenerate: its vertices coincide"));
    CHECK_THROWS_AS(load_model(std::string("wythoff:") + d), InputError);
  }
  // Folding the vertices (on request only) still refuses every other degeneracy, by name.
  const WythoffOptions fold{true};
  CHECK_THROWS_WITH(make_wythoff("x2x5/2x", fold),
                    Catch::Contains("faces of the sub-diagrams x.x and xx. coincide"));
  CHECK_THROWS_WITH(make_wythoff("x3/2o3x", fold),
                    Catch::Contains("faces of the sub-diagram x.x pass through the centre"));
  CHECK_THROWS_WITH(make_wythoff("x3o5/2x", fold), Catch::Contains("do not close up"));
  CHECK_THROWS_WITH(make_wythoff("x5/2x", fold), Catch::Contains("vertices coincide"));
  CHECK_THROWS_WITH(make_wythoff("x7/2o3o"), Catch::Contains("infinite group"));
  CHECK_THROWS_WITH(make_wythoff("x5/4o5/4o"), Catch::Contains("not a spherical"));
  CHECK_THROWS_WITH(make_wythoff("x6/4o"), Catch::Contains("lowest terms"));
  CHECK_THROWS_WITH(make_wythoff("x5/7o"), Catch::Contains("1 <= q < p"));
  CHECK_THROWS_WITH(make_wythoff("x5/o"), Catch::Contains("denominator"));
  const CoxeterDiagram d = parse_coxeter_diagram("x5/2o3o4/3x");
  CHECK(d.labels == std::vector<int>{5, 3, 4});
  CHECK(d.denominators == std::vector<int>{2, 1, 3});
}

TEST_CASE("every fractional 3-node diagram and every B4/F4-type 4-node one builds or is refused",
          "[wythoff][star][errors]") {
  // A sweep over the marks of the finite groups: each diagram either gives a valid, outward
  // oriented complex with every edge of length 2 and one circumradius, or an InputError that
  // names one of the documented reasons, never another exception.
  const std::vector<std::string> reasons = {
      "infinite",           "not a spherical", "vertices coincide",   "coincide",
      "through the centre", "do not close up", "coinciding vertices", "component without"};
  auto sweep = [&](const std::vector<std::string>& marks, int nodes, int& built, int& refused) {
    std::vector<std::size_t> pick(static_cast<std::size_t>(nodes - 1), 0);
    while (true) {
      for (unsigned rings = 1; rings < (1u << nodes); ++rings) {
        std::string d;
        for (int i = 0; i < nodes; ++i) {
          if (i > 0) d += marks[pick[static_cast<std::size_t>(i - 1)]];
          d += (rings >> i & 1u) ? 'x' : 'o';
        }
        INFO(d);
        try {
          const Complex c = make_wythoff(d);
          ++built;
          REQUIRE(validate(c).ok());
          REQUIRE(signed_volume(c) > 0.0);
          const double r = c.position(0).norm();
          for (std::uint32_t v = 0; v < c.count(0); ++v)
            REQUIRE(c.position(v).norm() == Approx(r).epsilon(1e-9));
          for (std::uint32_t e = 0; e < c.count(1); ++e) {
            const auto ends = c.boundary(1).ids(e);
            REQUIRE((c.position(ends[0]) - c.position(ends[1])).norm() ==
                    Approx(2.0).epsilon(1e-9));
          }
        } catch (const InputError& e) {
          ++refused;
          const std::string what = e.what();
          INFO(what);
          CHECK(std::any_of(reasons.begin(), reasons.end(), [&](const std::string& r) {
            return what.find(r) != std::string::npos;
          }));
        }
      }
      std::size_t i = 0;
      while (i < pick.size() && ++pick[i] == marks.size()) pick[i++] = 0;
      if (i == pick.size()) break;
    }
  };
  int built = 0, refused = 0;
  sweep({"2", "3", "3/2", "4", "4/3", "5", "5/2", "5/3", "5/4", "7/2", "8/3"}, 3, built, refused);
  CHECK(built > 200);
  CHECK(refused > 400);
  built = refused = 0;
  sweep({"3", "3/2", "4", "4/3"}, 4, built, refused);
  CHECK(built > 300);
  CHECK(refused > 300);
}
