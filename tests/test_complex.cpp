// Tests of the complex/ module: built-in polytopes against analytic f-vectors and volumes,
// validate() on deliberately broken complexes, build_complex errors, affine transforms and the
// model-spec parser.
#include <catch2/catch.hpp>

#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/complex/validate.hpp"

using namespace cw4d;

namespace {

double binomial(int n, int k) {
  if (k < 0 || k > n) return 0.0;
  double r = 1.0;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return std::round(r);
}

double factorial(int n) {
  double r = 1.0;
  for (int i = 2; i <= n; ++i) r *= i;
  return r;
}

std::vector<std::size_t> to_sizes(const std::vector<double>& v) {
  std::vector<std::size_t> out;
  for (double x : v) out.push_back(static_cast<std::size_t>(x));
  return out;
}

std::vector<std::size_t> simplex_fvector(int n) {
  std::vector<double> f;
  for (int k = 0; k < n; ++k) f.push_back(binomial(n + 1, k + 1));
  return to_sizes(f);
}

std::vector<std::size_t> cube_fvector(int n) {
  std::vector<double> f;
  for (int k = 0; k < n; ++k) f.push_back(binomial(n, k) * std::pow(2.0, n - k));
  return to_sizes(f);
}

std::vector<std::size_t> orthoplex_fvector(int n) {
  std::vector<double> f;
  for (int k = 0; k < n; ++k) f.push_back(std::pow(2.0, k + 1) * binomial(n, k + 1));
  return to_sizes(f);
}

// p,q-duoprism: pq vertices, 2pq edges, pq squares + p q-gons + q p-gons, p + q prisms.
std::vector<std::size_t> duoprism_fvector(std::size_t p, std::size_t q) {
  return {p * q, 2 * p * q, p * q + p + q, p + q};
}

double polygon_area(int p) {
  return 0.5 * p * std::sin(2.0 * std::numbers::pi / p);
}

// Volume of a regular n-simplex with edge a from the Cayley-Menger determinant:
// V^2 = (-1)^(n+1) / (2^n (n!)^2) * det(CM).
double cayley_menger_volume(int n, double a) {
  const int m = n + 2;
  Eigen::MatrixXd cm = Eigen::MatrixXd::Constant(m, m, a * a);
  for (int i = 0; i < m; ++i) {
    cm(i, i) = 0.0;
    cm(0, i) = 1.0;
    cm(i, 0) = 1.0;
  }
  cm(0, 0) = 0.0;
  const double sign = (n + 1) % 2 == 0 ? 1.0 : -1.0;
  const double v2 = sign * cm.determinant() / (std::pow(2.0, n) * factorial(n) * factorial(n));
  return std::sqrt(v2);
}

// Edge of the regular n-simplex of circumradius 1.
double unit_simplex_edge(int n) {
  return std::sqrt(2.0 * (n + 1) / n);
}

struct Named {
  std::string name;
  Complex complex;
  double volume;  // analytic n-volume
};

// Every built-in we test, with its analytic volume.
std::vector<Named> all_builtins() {
  std::vector<Named> out;
  for (int n = 2; n <= 6; ++n) {
    const double a = unit_simplex_edge(n);
    out.push_back({"simplex:" + std::to_string(n), make_simplex(n),
                   std::sqrt(n + 1.0) / factorial(n) * std::pow(a / std::sqrt(2.0), n)});
    out.push_back({"cube:" + std::to_string(n), make_cube(n), std::pow(2.0, n)});
    out.push_back(
        {"orthoplex:" + std::to_string(n), make_orthoplex(n), std::pow(2.0, n) / factorial(n)});
  }
  for (int p = 3; p <= 8; ++p)
    out.push_back({"polygon:" + std::to_string(p), make_polygon(p), polygon_area(p)});
  const int duo[][2] = {{3, 3}, {3, 4}, {4, 4}, {5, 7}, {6, 3}, {3, 12}, {8, 8}};
  for (auto [p, q] : duo)
    out.push_back({"duoprism:" + std::to_string(p) + "," + std::to_string(q), make_duoprism(p, q),
                   polygon_area(p) * polygon_area(q)});
  out.push_back({"5-cell", load_model("5-cell"), cayley_menger_volume(4, unit_simplex_edge(4))});
  out.push_back({"tesseract", load_model("tesseract"), 16.0});
  out.push_back({"16-cell", load_model("16-cell"), 16.0 / 24.0});
  out.push_back({"prism:cube:3", load_model("prism:cube:3"), 16.0});
  out.push_back({"prism:5-cell", load_model("prism:5-cell"),
                 2.0 * cayley_menger_volume(4, unit_simplex_edge(4))});
  out.push_back({"prism:polygon:5", load_model("prism:polygon:5"), 2.0 * polygon_area(5)});
  out.push_back({"prism:duoprism:3,4", load_model("prism:duoprism:3,4"),
                 2.0 * polygon_area(3) * polygon_area(4)});
  return out;
}

bool has_issue(const ValidationReport& r, int rank, std::uint32_t id) {
  return std::any_of(r.issues.begin(), r.issues.end(),
                     [&](const ValidationIssue& i) { return i.rank == rank && i.id == id; });
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Facet of rank n-1 whose stored outward normal is closest to `direction`.
std::uint32_t facet_towards(const Complex& c, const Eigen::VectorXd& direction) {
  std::uint32_t best = 0;
  double best_dot = -2.0;
  for (std::uint32_t f = 0; f < c.count(c.facet_rank()); ++f) {
    const double d = c.facet_normals().col(f).dot(direction);
    if (d > best_dot) {
      best_dot = d;
      best = f;
    }
  }
  return best;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// (a) f-vectors

TEST_CASE("an empty boundary table reads as one offset 0, and rows append to it", "[complex]") {
  Incidence t;
  CHECK(t.size() == 0);
  CHECK(t.empty());
  CHECK(t.entries() == 0);
  CHECK(t.offsets() == std::vector<std::uint32_t>{0});
  CHECK(t.well_formed(0));
  const std::uint32_t ids0[] = {3, 5}, ids1[] = {1, 2, 4};
  const std::int8_t signs0[] = {-1, 1}, signs1[] = {1, 1, -1};
  CHECK(t.add_row(ids0, signs0) == 0);
  CHECK(t.add_row(ids1, signs1) == 1);
  CHECK(t.offsets() == std::vector<std::uint32_t>{0, 2, 5});
  CHECK(t.row_size(1) == 3);
  CHECK(t.ids(1)[2] == 4);
  CHECK(t.signs(0)[0] == -1);
  CHECK(t.well_formed(6));
  CHECK_FALSE(t.well_formed(5));  // id 5 is not below 5
  const Incidence copy = t;
  CHECK(copy.offsets() == t.offsets());
  t.clear();
  CHECK(t.size() == 0);
  CHECK(t.offsets() == std::vector<std::uint32_t>{0});
  CHECK(t.well_formed(0));
  // An empty table with entries but no rows is not well formed.
  t.storage().ids.push_back(0);
  t.storage().signs.push_back(1);
  CHECK_FALSE(t.well_formed(1));
  // A writer that lays out the rows in place from an empty table.
  Incidence w;
  const Incidence::Storage st = w.storage();
  st.offsets.assign({0, 1});
  st.ids.assign({0});
  st.signs.assign({1});
  CHECK(w.size() == 1);
  CHECK(w.well_formed(1));
}

TEST_CASE("f-vectors of simplex, cube and orthoplex match the binomial formulas", "[builtins]") {
  for (int n = 2; n <= 6; ++n) {
    INFO("n = " << n);
    CHECK(make_simplex(n).fvector() == simplex_fvector(n));
    CHECK(make_cube(n).fvector() == cube_fvector(n));
    CHECK(make_orthoplex(n).fvector() == orthoplex_fvector(n));
    CHECK(load_model("simplex:" + std::to_string(n)).fvector() == simplex_fvector(n));
    CHECK(load_model("cube:" + std::to_string(n)).fvector() == cube_fvector(n));
    CHECK(load_model("orthoplex:" + std::to_string(n)).fvector() == orthoplex_fvector(n));
  }
}

TEST_CASE("published f-vectors for a few dimensions", "[builtins]") {
  // Spot values from the literature, independent of the formulas above.
  CHECK(make_simplex(3).fvector() == std::vector<std::size_t>{4, 6, 4});
  CHECK(make_cube(3).fvector() == std::vector<std::size_t>{8, 12, 6});
  CHECK(make_orthoplex(3).fvector() == std::vector<std::size_t>{6, 12, 8});
  CHECK(make_cube(5).fvector() == std::vector<std::size_t>{32, 80, 80, 40, 10});
  CHECK(make_orthoplex(5).fvector() == std::vector<std::size_t>{10, 40, 80, 80, 32});
  CHECK(make_simplex(6).fvector() == std::vector<std::size_t>{7, 21, 35, 35, 21, 7});
  CHECK(make_cube(6).fvector() == std::vector<std::size_t>{64, 192, 240, 160, 60, 12});
}

TEST_CASE("f-vectors of duoprisms", "[builtins]") {
  const int duo[][2] = {{3, 3}, {3, 4}, {4, 4}, {5, 7}, {6, 3}, {3, 12}, {10, 10}, {17, 5}};
  for (auto [p, q] : duo) {
    INFO("duoprism " << p << "," << q);
    CHECK(make_duoprism(p, q).fvector() == duoprism_fvector(p, q));
    CHECK(load_model("duoprism:" + std::to_string(p) + "," + std::to_string(q)).fvector() ==
          duoprism_fvector(p, q));
  }
  // The 4,4-duoprism is the tesseract.
  CHECK(make_duoprism(4, 4).fvector() == make_cube(4).fvector());
}

TEST_CASE("named 4D polytopes", "[builtins]") {
  CHECK(load_model("5-cell").fvector() == std::vector<std::size_t>{5, 10, 10, 5});
  CHECK(load_model("pentachoron").fvector() == std::vector<std::size_t>{5, 10, 10, 5});
  CHECK(load_model("tesseract").fvector() == std::vector<std::size_t>{16, 32, 24, 8});
  CHECK(load_model("8-cell").fvector() == std::vector<std::size_t>{16, 32, 24, 8});
  CHECK(load_model("16-cell").fvector() == std::vector<std::size_t>{8, 24, 32, 16});
  CHECK(load_model("Hexadecachoron").fvector() == std::vector<std::size_t>{8, 24, 32, 16});
  for (const char* name : {"5-cell", "tesseract", "16-cell"}) {
    INFO(name);
    const Complex c = load_model(name);
    CHECK(c.ambient_dim() == 4);
    CHECK(c.top_rank() == 3);
    CHECK(is_builtin_spec(name));
  }
}

TEST_CASE("simplex has circumradius 1 and equal edges", "[builtins]") {
  for (int n = 2; n <= 6; ++n) {
    INFO("n = " << n);
    const Complex c = make_simplex(n);
    const double a = unit_simplex_edge(n);
    for (std::uint32_t v = 0; v < c.count(0); ++v) CHECK(c.position(v).norm() == Approx(1.0));
    for (std::uint32_t e = 0; e < c.count(1); ++e) {
      auto ends = c.edge(e);
      CHECK((c.position(ends[0]) - c.position(ends[1])).norm() == Approx(a));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// (b) validity, volumes, normals

TEST_CASE("every built-in validates and encloses its analytic volume", "[builtins][volume]") {
  for (const auto& [name, c, volume] : all_builtins()) {
    INFO(name);
    const ValidationReport report = validate(c);
    INFO(report.summary());
    CHECK(report.ok());
    CHECK(signed_volume(c) == Approx(volume).epsilon(1e-9));
  }
}

TEST_CASE("the two formulas for the regular simplex volume agree", "[volume]") {
  // Guards the oracle itself: Cayley-Menger against sqrt(n+1)/n! (a/sqrt 2)^n.
  for (int n = 2; n <= 6; ++n) {
    const double a = unit_simplex_edge(n);
    CHECK(cayley_menger_volume(n, a) ==
          Approx(std::sqrt(n + 1.0) / factorial(n) * std::pow(a / std::sqrt(2.0), n)));
  }
  CHECK(cayley_menger_volume(2, 1.0) == Approx(std::sqrt(3.0) / 4.0));
  CHECK(cayley_menger_volume(3, 1.0) == Approx(1.0 / (6.0 * std::sqrt(2.0))));
}

TEST_CASE("facet normals of built-ins are unit and point away from the centroid",
          "[builtins][normals]") {
  for (const auto& [name, c, volume] : all_builtins()) {
    INFO(name);
    REQUIRE(c.has_facet_normals());
    const int fr = c.facet_rank();
    const Eigen::VectorXd centroid = c.positions().rowwise().mean();
    for (std::uint32_t f = 0; f < c.count(fr); ++f) {
      INFO("facet " << f);
      const Eigen::VectorXd n = c.facet_normals().col(f);
      CHECK(n.norm() == Approx(1.0).epsilon(1e-12));
      for (auto v : c.vertices_of(fr, f)) CHECK(n.dot(c.position(v) - centroid) > 1e-9);
      // The oriented area vector agrees with the stored normal.
      if (fr >= 2) {
        const Eigen::VectorXd a = facet_area_vector(c, f);
        CHECK(a.normalized().dot(n) == Approx(1.0).epsilon(1e-12));
        CHECK(a.norm() == Approx(element_volume(c, fr, f)).epsilon(1e-9));
      }
    }
  }
}

TEST_CASE("cube:4 equals the prism over cube:3", "[builtins]") {
  const Complex cube4 = make_cube(4);
  const Complex prism = make_product(make_cube(3), make_segment());
  CHECK(prism.fvector() == cube4.fvector());
  CHECK(signed_volume(prism) == Approx(signed_volume(cube4)));
  CHECK(validate(prism).ok());
  CHECK(load_model("prism:cube:3").fvector() == load_model("tesseract").fvector());
  // Products of polygons with polygons, segments with segments: more cubes.
  CHECK(make_product(make_polygon(4), make_polygon(4)).fvector() == cube4.fvector());
  const Complex square = make_product(make_segment(), make_segment());
  CHECK(square.fvector() == make_cube(2).fvector());
  CHECK(signed_volume(square) == Approx(4.0));
}

// ---------------------------------------------------------------------------------------------
// (c) validate() names what is broken

TEST_CASE("validate: a face whose edges are not a cycle in order", "[validate]") {
  Complex c = make_cube(3);
  auto ids = c.boundary_mut(2).ids_mut(3);
  auto signs = c.boundary_mut(2).signs_mut(3);
  std::swap(ids[0], ids[1]);
  std::swap(signs[0], signs[1]);
  const ValidationReport r = validate(c);
  REQUIRE_FALSE(r.ok());
  REQUIRE(r.issues.size() == 1);
  REQUIRE(r.issues[0].rank == 2);
  REQUIRE(r.issues[0].id == 3);
  CHECK(contains(r.issues[0].what, "face 3"));
  CHECK(contains(r.issues[0].what, "cycle"));
}

TEST_CASE("validate: a face edge traversed the wrong way", "[validate]") {
  Complex c = make_cube(4);
  c.boundary_mut(2).signs_mut(7)[2] *= -1;
  const ValidationReport r = validate(c);
  REQUIRE_FALSE(r.ok());
  REQUIRE(has_issue(r, 2, 7));
}

TEST_CASE("validate: a cell that is not closed (tesseract cell missing a face)", "[validate]") {
  ComplexSoup soup = to_soup(make_cube(4));
  REQUIRE(soup.higher.size() == 1);
  auto& cell = soup.higher[0][2];
  REQUIRE(cell.size() == 6);
  cell.erase(cell.begin() + 4);
  const Complex c = build_complex(soup);
  const ValidationReport r = validate(c);
  REQUIRE_FALSE(r.ok());
  REQUIRE(r.issues[0].rank == 3);
  REQUIRE(r.issues[0].id == 2);
  CHECK(contains(r.issues[0].what, "not closed"));
  for (const auto& issue : r.issues) {
    CHECK(issue.rank == 3);
    CHECK(issue.id == 2);
  }
}

TEST_CASE("validate: a 3D surface with a hole names the open edges", "[validate]") {
  const Complex cube = make_cube(3);
  ComplexSoup soup = to_soup(cube);
  const std::uint32_t removed = 4;
  std::vector<std::uint32_t> hole_edges(cube.boundary(2).ids(removed).begin(),
                                        cube.boundary(2).ids(removed).end());
  soup.faces.erase(soup.faces.begin() + removed);
  const Complex c = build_complex(soup);
  REQUIRE(c.count(1) == 12);  // explicit edges keep their ids
  const ValidationReport r = validate(c);
  REQUIRE(r.issues.size() == 4);
  for (auto e : hole_edges) REQUIRE(has_issue(r, 1, e));
  for (const auto& issue : r.issues) CHECK(contains(issue.what, "not closed"));
}

TEST_CASE("validate: a ridge shared by three facets", "[validate]") {
  // Three triangles hinged on the edge (0,1): not a closed surface.
  ComplexSoup soup;
  soup.ambient_dim = 3;
  soup.positions.resize(3, 5);
  soup.positions << 0, 1, 0, 0, 0,  //
      0, 0, 1, -1, 0,               //
      0, 0, 0, 0, 1;
  soup.faces = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};
  const Complex c = build_complex(soup);
  const ValidationReport r = validate(c);
  REQUIRE_FALSE(r.ok());
  REQUIRE(has_issue(r, 1, 0));  // edge (0,1) is the first edge built
  CHECK(contains(r.summary(), "3 facets"));
}

TEST_CASE("validate: one flipped facet of a tesseract", "[validate]") {
  Complex c = make_cube(4);
  const std::uint32_t last = static_cast<std::uint32_t>(c.count(3) - 1);
  c.flip(3, last);
  const ValidationReport r = validate(c);
  REQUIRE_FALSE(r.ok());
  // A cube cell has 6 faces, each shared with a neighbour oriented the other way.
  REQUIRE(r.issues.size() == 6);
  for (const auto& issue : r.issues) {
    REQUIRE(issue.rank == 3);
    REQUIRE(issue.id == last);
    CHECK(contains(issue.what, "orientation"));
  }

  Complex d = make_cube(4);
  d.flip(3, 0);
  const ValidationReport r0 = validate(d);
  REQUIRE(r0.issues.size() == 6);
  for (const auto& issue : r0.issues) {
    REQUIRE(issue.rank == 3);
    CHECK((issue.id == 0 || contains(issue.what, "with cell 0 ")));
  }
}

TEST_CASE("validate: one flipped face of a 3-cube", "[validate]") {
  Complex c = make_cube(3);
  c.flip(2, 5);
  const ValidationReport r = validate(c);
  REQUIRE(r.issues.size() == 4);
  for (const auto& issue : r.issues) {
    REQUIRE(issue.rank == 2);
    CHECK((issue.id == 5 || contains(issue.what, "with face 5 ")));
  }
}

TEST_CASE("validate: non-finite coordinates", "[validate]") {
  Complex c = make_cube(4);
  c.positions_mut()(2, 3) = std::numeric_limits<double>::quiet_NaN();
  ValidationReport r = validate(c);
  REQUIRE(r.issues.size() == 1);
  REQUIRE(r.issues[0].rank == 0);
  REQUIRE(r.issues[0].id == 3);
  CHECK(contains(r.issues[0].what, "vertex 3"));

  Complex d = make_simplex(4);
  d.positions_mut()(0, 4) = std::numeric_limits<double>::infinity();
  d.positions_mut()(3, 1) = -std::numeric_limits<double>::infinity();
  r = validate(d);
  REQUIRE(r.issues.size() == 2);
  REQUIRE(has_issue(r, 0, 1));
  REQUIRE(has_issue(r, 0, 4));
}

TEST_CASE("validate: ids out of range", "[validate]") {
  SECTION("a face lists an edge that does not exist") {
    Complex c = make_cube(4);
    c.boundary_mut(2).ids_mut(4)[0] = 9999;
    const ValidationReport r = validate(c);
    REQUIRE(r.issues.size() == 1);
    REQUIRE(r.issues[0].rank == 2);
    REQUIRE(r.issues[0].id == 4);
    CHECK(contains(r.issues[0].what, "9999"));
    CHECK(contains(r.issues[0].what, "out of range"));
  }
  SECTION("an edge lists a vertex that does not exist") {
    Complex c = make_cube(3);
    c.boundary_mut(1).ids_mut(3)[1] = 100;
    const ValidationReport r = validate(c);
    REQUIRE(r.issues.size() == 1);
    REQUIRE(r.issues[0].rank == 1);
    REQUIRE(r.issues[0].id == 3);
  }
  SECTION("a cell lists a face that does not exist") {
    Complex c = make_orthoplex(4);
    c.boundary_mut(3).ids_mut(11)[2] = static_cast<std::uint32_t>(c.count(2));
    const ValidationReport r = validate(c);
    REQUIRE(r.issues.size() == 1);
    REQUIRE(r.issues[0].rank == 3);
    REQUIRE(r.issues[0].id == 11);
  }
}

TEST_CASE("validate: a table whose own arrays disagree is reported, its rows not read",
          "[validate]") {
  SECTION("offsets out of order") {
    Complex c = make_cube(4);
    std::vector<std::uint32_t>& off = c.boundary_mut(2).storage().offsets;
    std::swap(off[4], off[5]);  // row 4 would end before it starts
    const ValidationReport r = validate(c);
    REQUIRE_FALSE(r.issues.empty());
    CHECK(r.issues[0].rank == 2);
    CHECK(r.issues[0].id == 4);  // row 4 ends (offset 5) before it starts (offset 4)
    CHECK(contains(r.issues[0].what, "offsets out of order"));
  }
  SECTION("fewer signs than ids") {
    Complex c = make_cube(4);
    c.boundary_mut(3).storage().signs.pop_back();
    const ValidationReport r = validate(c);
    REQUIRE_FALSE(r.issues.empty());
    CHECK(r.issues[0].rank == 3);
    CHECK(contains(r.issues[0].what, "arrays disagree"));
  }
  SECTION("offsets ending past the ids") {
    Complex c = make_cube(3);
    c.boundary_mut(1).storage().offsets.back() += 5;
    const ValidationReport r = validate(c);
    REQUIRE_FALSE(r.issues.empty());
    CHECK(r.issues[0].rank == 1);
    CHECK(contains(r.issues[0].what, "arrays disagree"));
  }
}

TEST_CASE("validate: repeated boundary entries", "[validate]") {
  SECTION("a cell lists a face twice") {
    Complex c = make_cube(4);
    auto ids = c.boundary_mut(3).ids_mut(2);
    const std::uint32_t face = ids[0];
    ids[1] = face;
    const ValidationReport r = validate(c);
    REQUIRE(r.issues.size() == 1);
    REQUIRE(r.issues[0].rank == 3);
    REQUIRE(r.issues[0].id == 2);
    CHECK(contains(r.issues[0].what, "face " + std::to_string(face) + " twice"));
  }
  SECTION("a face lists an edge twice") {
    Complex c = make_cube(3);
    auto ids = c.boundary_mut(2).ids_mut(1);
    ids[2] = ids[0];
    const ValidationReport r = validate(c);
    REQUIRE(r.issues.size() == 1);
    REQUIRE(r.issues[0].rank == 2);
    REQUIRE(r.issues[0].id == 1);
  }
  SECTION("an edge joins a vertex to itself") {
    Complex c = make_cube(3);
    auto ids = c.boundary_mut(1).ids_mut(6);
    ids[1] = ids[0];
    const ValidationReport r = validate(c);
    REQUIRE(r.issues.size() == 1);
    REQUIRE(r.issues[0].rank == 1);
    REQUIRE(r.issues[0].id == 6);
  }
}

TEST_CASE("validate: a non-planar facet", "[validate]") {
  SECTION("tesseract: a vertex moved off one cell's hyperplane") {
    Complex c = make_cube(4);
    // Vertex at (-1,-1,-1,-1), moved along +x: only the cell x = -1 loses planarity.
    std::uint32_t v = 0;
    for (; v < c.count(0); ++v)
      if ((c.position(v).array() == -1.0).all()) break;
    REQUIRE(v < c.count(0));
    const std::uint32_t cell = facet_towards(c, Eigen::Vector4d(-1, 0, 0, 0));
    c.positions_mut()(0, v) += 0.1;
    const ValidationReport r = validate(c);
    REQUIRE(r.issues.size() == 1);
    REQUIRE(r.issues[0].rank == 3);
    REQUIRE(r.issues[0].id == cell);
    CHECK(contains(r.issues[0].what, "not planar"));
    // Relaxing the option accepts it.
    ValidateOptions loose;
    loose.require_planar_facets = false;
    CHECK(validate(c, loose).ok());
  }
  SECTION("3-cube: a vertex moved off one face's plane") {
    Complex c = make_cube(3);
    const std::uint32_t face = facet_towards(c, Eigen::Vector3d(0, 0, 1));
    const std::uint32_t v = c.vertices_of(2, face)[0];
    // Move within the planes x = const and y = const that also hold v: only z changes.
    c.positions_mut()(2, v) += 0.05;
    const ValidationReport r = validate(c);
    REQUIRE(r.issues.size() == 1);
    REQUIRE(r.issues[0].rank == 2);
    REQUIRE(r.issues[0].id == face);
  }
}

TEST_CASE("validate: facets oriented inward", "[validate]") {
  for (const char* name : {"tesseract", "5-cell", "16-cell", "cube:3", "duoprism:3,5"}) {
    INFO(name);
    Complex c = load_model(name);
    const int fr = c.facet_rank();
    for (std::uint32_t f = 0; f < c.count(fr); ++f) c.flip(fr, f);
    const ValidationReport r = validate(c);
    REQUIRE(r.issues.size() == 1);
    REQUIRE(r.issues[0].rank == fr);
    REQUIRE(r.issues[0].id == 0);
    CHECK(contains(r.issues[0].what, "outward"));
    CHECK(signed_volume(c) < 0.0);
    // Without the closedness requirement the local structure is still fine.
    ValidateOptions open;
    open.require_closed = false;
    CHECK(validate(c, open).ok());
  }
}

TEST_CASE("validate: max_issues caps the report", "[validate]") {
  Complex c = make_cube(4);
  for (Eigen::Index v = 0; v < c.positions().cols(); ++v)
    c.positions_mut()(0, v) = std::numeric_limits<double>::quiet_NaN();
  ValidateOptions opt;
  opt.max_issues = 3;
  const ValidationReport r = validate(c, opt);
  CHECK(r.issues.size() == 3);
  CHECK(validate(c).issues.size() == 16);
  CHECK(contains(validate(c).summary(2), "and 14 more"));
}

TEST_CASE("orient_complex repairs scrambled orientations", "[validate][builder]") {
  for (const char* name : {"tesseract", "16-cell", "duoprism:3,7", "cube:5", "simplex:5"}) {
    INFO(name);
    Complex c = load_model(name);
    const double volume = signed_volume(c);
    const int fr = c.facet_rank();
    std::mt19937 rng(1234);
    for (std::uint32_t f = 0; f < c.count(fr); ++f)
      if (rng() % 2) c.flip(fr, f);
    orient_complex(c);
    const ValidationReport r = validate(c);
    INFO(r.summary());
    CHECK(r.ok());
    CHECK(signed_volume(c) == Approx(volume));
  }
}

// ---------------------------------------------------------------------------------------------
// (d) build_complex errors

TEST_CASE("build_complex rejects broken soups with TopologyError", "[builder]") {
  ComplexSoup base;
  base.ambient_dim = 3;
  base.positions = make_simplex(3).positions();
  base.faces = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {0, 2, 3}};
  REQUIRE(validate(build_complex(base)).ok());

  SECTION("face vertex out of range") {
    ComplexSoup s = base;
    s.faces[2] = {1, 3, 4};
    REQUIRE_THROWS_AS(build_complex(s), TopologyError);
    try {
      build_complex(s);
    } catch (const TopologyError& e) {
      CHECK(e.rank() == 2);
      CHECK(e.ids() == std::vector<std::uint32_t>{2});
    }
  }
  SECTION("explicit edge out of range") {
    ComplexSoup s = base;
    s.edges = {{0, 1}, {2, 7}};
    REQUIRE_THROWS_AS(build_complex(s), TopologyError);
    try {
      build_complex(s);
    } catch (const TopologyError& e) {
      CHECK(e.rank() == 1);
      CHECK(e.ids() == std::vector<std::uint32_t>{1});
    }
  }
  SECTION("explicit edge joins a vertex to itself") {
    ComplexSoup s = base;
    s.edges = {{2, 2}};
    REQUIRE_THROWS_AS(build_complex(s), TopologyError);
  }
  SECTION("face with fewer than 3 vertices") {
    ComplexSoup s = base;
    s.faces[1] = {0, 3};
    REQUIRE_THROWS_AS(build_complex(s), TopologyError);
    try {
      build_complex(s);
    } catch (const TopologyError& e) {
      CHECK(e.rank() == 2);
      CHECK(e.ids() == std::vector<std::uint32_t>{1});
    }
    s.faces[1] = {};
    REQUIRE_THROWS_AS(build_complex(s), TopologyError);
  }
  SECTION("face repeating a vertex") {
    ComplexSoup s = base;
    s.faces[3] = {0, 2, 0};
    REQUIRE_THROWS_AS(build_complex(s), TopologyError);
    try {
      build_complex(s);
    } catch (const TopologyError& e) {
      CHECK(e.rank() == 2);
      CHECK(e.ids() == std::vector<std::uint32_t>{3});
    }
    s.faces[3] = {0, 2, 3, 2};
    REQUIRE_THROWS_AS(build_complex(s), TopologyError);
  }
  SECTION("higher ranks: out of range, repeated, empty") {
    ComplexSoup s = to_soup(make_simplex(4));
    REQUIRE(s.higher.size() == 1);
    ComplexSoup t = s;
    t.higher[0][3].push_back(static_cast<std::uint32_t>(t.faces.size()));
    REQUIRE_THROWS_AS(build_complex(t), TopologyError);
    try {
      build_complex(t);
    } catch (const TopologyError& e) {
      CHECK(e.rank() == 3);
      CHECK(e.ids() == std::vector<std::uint32_t>{3});
    }
    t = s;
    t.higher[0][1][2] = t.higher[0][1][0];
    REQUIRE_THROWS_AS(build_complex(t), TopologyError);
    t = s;
    t.higher[0][4].clear();
    REQUIRE_THROWS_AS(build_complex(t), TopologyError);
  }
  SECTION("wrong position rows is an input error") {
    ComplexSoup s = base;
    s.ambient_dim = 4;
    REQUIRE_THROWS_AS(build_complex(s), InputError);
  }
}

TEST_CASE("to_soup and build_complex round trip", "[builder]") {
  for (const char* name : {"tesseract", "16-cell", "5-cell", "duoprism:3,5", "cube:3", "cube:5"}) {
    INFO(name);
    const Complex c = load_model(name);
    const Complex d = build_complex(to_soup(c));
    CHECK(d.fvector() == c.fvector());
    CHECK(d.positions() == c.positions());
    CHECK(validate(d).ok());
    CHECK(signed_volume(d) == Approx(signed_volume(c)));
  }
}

// ---------------------------------------------------------------------------------------------
// (e) affine transforms

TEST_CASE("rotations in the six planes of R^4 are orthogonal with det 1", "[transform]") {
  const std::pair<int, int> planes[] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (auto [i, j] : planes) {
    for (double angle : {0.0, 0.3, -1.2, 2.5, std::numbers::pi}) {
      INFO("plane " << i << j << " angle " << angle);
      const AffineTransform r = AffineTransform::rotation(4, i, j, angle);
      const Eigen::MatrixXd m = r.linear();
      CHECK((m.transpose() * m - Eigen::MatrixXd::Identity(4, 4)).norm() < 1e-14);
      CHECK(m.determinant() == Approx(1.0).epsilon(1e-14));
      CHECK(r.translation().isZero(0.0));
      // Axes outside the plane are fixed.
      for (int k = 0; k < 4; ++k)
        if (k != i && k != j) CHECK((m.col(k) - Eigen::VectorXd::Unit(4, k)).norm() < 1e-15);
      // e_i turns towards e_j by the angle.
      CHECK(m(i, i) == Approx(std::cos(angle)).margin(1e-15));
      CHECK(m(j, i) == Approx(std::sin(angle)).margin(1e-15));
    }
  }
}

TEST_CASE("rotation by 90 degrees in xy maps e_x to e_y", "[transform]") {
  const auto [i, j] = parse_rotation_plane("xy");
  const AffineTransform r = AffineTransform::rotation(4, i, j, std::numbers::pi / 2);
  const Eigen::VectorXd ex = Eigen::VectorXd::Unit(4, 0), ey = Eigen::VectorXd::Unit(4, 1);
  CHECK((r.apply(ex) - ey).norm() < 1e-15);
  CHECK((r.apply(ey) + ex).norm() < 1e-15);
  const auto [zi, wi] = parse_rotation_plane("zw");
  const AffineTransform rz = AffineTransform::rotation(4, zi, wi, std::numbers::pi / 2);
  CHECK((rz.apply(Eigen::VectorXd::Unit(4, 2)) - Eigen::VectorXd::Unit(4, 3)).norm() < 1e-15);
  // "yx" turns the other way.
  const auto [yi, xi] = parse_rotation_plane("yx");
  const AffineTransform back = AffineTransform::rotation(4, yi, xi, std::numbers::pi / 2);
  CHECK((back.apply(ey) - ex).norm() < 1e-15);
}

TEST_CASE("composition order, inverse and identity", "[transform]") {
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  auto random_vec = [&] {
    Eigen::VectorXd v(4);
    for (int k = 0; k < 4; ++k) v(k) = u(rng);
    return v;
  };
  for (int trial = 0; trial < 200; ++trial) {
    const AffineTransform a = AffineTransform::rotation(4, trial % 4, (trial + 1) % 4, u(rng)) *
                              AffineTransform::translation(random_vec());
    Eigen::VectorXd s = random_vec();
    for (int k = 0; k < 4; ++k) s(k) = std::copysign(0.5 + std::abs(s(k)), s(k));
    const AffineTransform b = AffineTransform::translation(random_vec()) *
                              AffineTransform::scale(s) *
                              AffineTransform::rotation(4, 3, trial % 3, u(rng));
    const Eigen::VectorXd x = random_vec();
    CHECK(((a * b).apply(x) - a.apply(b.apply(x))).norm() < 1e-12);
    CHECK(((b * a).apply(x) - b.apply(a.apply(x))).norm() < 1e-12);
    CHECK((a.inverse().apply(a.apply(x)) - x).norm() < 1e-12);
    CHECK((b.inverse().apply(b.apply(x)) - x).norm() < 1e-12);
    CHECK(((a * b).inverse().apply(x) - b.inverse().apply(a.inverse().apply(x))).norm() < 1e-11);
  }
  // Composition is not commutative.
  const AffineTransform r = AffineTransform::rotation(4, 0, 1, 0.5);
  const AffineTransform t = AffineTransform::translation(Eigen::Vector4d(1, 0, 0, 0));
  const Eigen::VectorXd o = Eigen::VectorXd::Zero(4);
  CHECK(((r * t).apply(o) - r.apply(Eigen::Vector4d(1, 0, 0, 0))).norm() < 1e-15);
  CHECK(((t * r).apply(o) - Eigen::VectorXd(Eigen::Vector4d(1, 0, 0, 0))).norm() < 1e-15);
  CHECK(AffineTransform::identity(4).is_identity());
  CHECK_FALSE(r.is_identity());
  CHECK_THROWS_AS(AffineTransform::scale(4, 0.0).inverse(), InputError);
  CHECK_THROWS_AS(AffineTransform::rotation(4, 1, 1, 0.3), InputError);
  CHECK_THROWS_AS(AffineTransform::rotation(4, 0, 4, 0.3), InputError);
  CHECK_THROWS_AS(AffineTransform::identity(3) * AffineTransform::identity(4), InputError);
}

TEST_CASE("parse_rotation_plane", "[transform]") {
  CHECK(parse_rotation_plane("xy") == std::pair<int, int>{0, 1});
  CHECK(parse_rotation_plane("xz") == std::pair<int, int>{0, 2});
  CHECK(parse_rotation_plane("xw") == std::pair<int, int>{0, 3});
  CHECK(parse_rotation_plane("yz") == std::pair<int, int>{1, 2});
  CHECK(parse_rotation_plane("yw") == std::pair<int, int>{1, 3});
  CHECK(parse_rotation_plane("zw") == std::pair<int, int>{2, 3});
  CHECK(parse_rotation_plane("wz") == std::pair<int, int>{3, 2});
  CHECK(parse_rotation_plane("XY") == std::pair<int, int>{0, 1});
  for (const char* bad : {"", "x", "xx", "ww", "xyz", "ab", "xq", "x y", "uv", "x-", "1 2"}) {
    INFO("'" << bad << "'");
    CHECK_THROWS_AS(parse_rotation_plane(bad), InputError);
  }
}

TEST_CASE("transformed complexes stay valid and outward", "[transform]") {
  SECTION("reflection of a tesseract") {
    const Complex c = make_cube(4);
    const AffineTransform mirror = AffineTransform::scale(Eigen::Vector4d(-1, 1, 1, 1));
    const Complex m = transformed(c, mirror);
    const ValidationReport r = validate(m);
    INFO(r.summary());
    CHECK(r.ok());
    CHECK(signed_volume(m) == Approx(16.0));
    CHECK(m.fvector() == c.fvector());
  }
  for (const char* name :
       {"5-cell", "16-cell", "tesseract", "duoprism:3,5", "cube:3", "simplex:3", "cube:5"}) {
    INFO(name);
    const Complex c = load_model(name);
    const int n = c.ambient_dim();
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd s(n), t(n);
    for (int k = 0; k < n; ++k) {
      s(k) = 0.5 + std::abs(u(rng));
      t(k) = u(rng);
    }
    s(0) = -s(0);  // one reflection
    const AffineTransform xf =
        AffineTransform::translation(t) * AffineTransform::rotation(n, 0, n - 1, 0.7) *
        AffineTransform::scale(s) * AffineTransform::rotation(n, 1, 2 % n, -0.4);
    const double det = xf.linear().determinant();
    REQUIRE(det < 0.0);
    const Complex m = transformed(c, xf);
    const ValidationReport r = validate(m);
    INFO(r.summary());
    CHECK(r.ok());
    CHECK(signed_volume(m) == Approx(std::abs(det) * signed_volume(c)).epsilon(1e-9));
    // Stored normals are unit and still point away from the (transformed) centroid.
    REQUIRE(m.has_facet_normals());
    const Eigen::VectorXd centroid = m.positions().rowwise().mean();
    for (std::uint32_t f = 0; f < m.count(n - 1); ++f) {
      const Eigen::VectorXd nf = m.facet_normals().col(f);
      CHECK(nf.norm() == Approx(1.0));
      for (auto v : m.vertices_of(n - 1, f)) CHECK(nf.dot(m.position(v) - centroid) > 1e-9);
      if (n >= 3) CHECK(facet_area_vector(m, f).normalized().dot(nf) == Approx(1.0));
    }
    // Orientation-preserving transform: same check.
    const AffineTransform rot = AffineTransform::rotation(n, 0, 1, 1.1);
    CHECK(validate(transformed(c, rot)).ok());
    CHECK(signed_volume(transformed(c, rot)) == Approx(signed_volume(c)));
  }
  SECTION("bad transforms") {
    const Complex c = make_cube(4);
    CHECK_THROWS_AS(transformed(c, AffineTransform::identity(3)), InputError);
    CHECK_THROWS_AS(transformed(c, AffineTransform::scale(Eigen::Vector4d(1, 1, 0, 1))),
                    InputError);
  }
}

// ---------------------------------------------------------------------------------------------
// (f) model specs

TEST_CASE("load_model rejects unknown specs and bad parameters", "[builtins][spec]") {
  for (const char* bad :
       {"cube:1",       "cube:0",           "cube:-2",      "simplex:0",      "simplex:1",
        "orthoplex:1",  "orthoplex:11",     "cube:11",      "simplex:13",     "polygon:2",
        "duoprism:2,5", "duoprism:5,2",     "duoprism:5",   "duoprism:3,4,5", "duoprism:",
        "duoprism:a,b", "cube:x",           "cube:",        "cube:3.5",       "cube: 3",
        "simplex:4x",   "no-such-polytope", "prism:cube:1", "prism:nothing"}) {
    INFO("spec '" << bad << "'");
    CHECK_THROWS_AS(load_model(bad), InputError);
  }
}

TEST_CASE("load_model accepts every listed built-in family", "[builtins][spec]") {
  CHECK(load_model("CUBE:3").fvector() == cube_fvector(3));
  CHECK(load_model("polygon:7").fvector() == std::vector<std::size_t>{7, 7});
  CHECK(load_model("prism:prism:cube:2").fvector() == cube_fvector(4));
  CHECK(is_builtin_spec("duoprism:3,4"));
  CHECK(is_builtin_spec("Tesseract"));
  CHECK_FALSE(is_builtin_spec("models/thing.4off"));
  CHECK_FALSE(is_builtin_spec("cube"));
  CHECK_FALSE(builtin_list().empty());
}

TEST_CASE("every non-const call, copy and move gives a complex a revision never seen before",
          "[complex]") {
  Complex c = make_cube(3);
  std::vector<std::uint64_t> seen{c.revision()};
  const auto changed = [&](const Complex& x) {
    const bool fresh = std::find(seen.begin(), seen.end(), x.revision()) == seen.end();
    seen.push_back(x.revision());
    return fresh;
  };
  // Reads keep it.
  (void)c.positions();
  (void)c.boundary(2);
  (void)c.facet_normals();
  (void)c.face_cycle(0);
  CHECK(c.revision() == seen.back());
  c.positions_mut();
  CHECK(changed(c));
  c.set_positions(c.positions());
  CHECK(changed(c));
  c.boundary_mut(2);
  CHECK(changed(c));
  c.flip(2, 0);
  CHECK(changed(c));
  c.add_edge(0, 1);
  CHECK(changed(c));
  c.set_facet_normals(Eigen::MatrixXd(3, 0));
  CHECK(changed(c));
  c.colors_mut(0);
  CHECK(changed(c));
  c.truncate(2);
  CHECK(changed(c));
  c.touch();
  CHECK(changed(c));
  Complex copy = c;
  CHECK(changed(copy));
  CHECK(c.revision() == seen[seen.size() - 2]);  // the source of a copy is unchanged
  Complex moved = std::move(copy);
  CHECK(changed(moved));
  CHECK(changed(copy));  // NOLINT(bugprone-use-after-move): a moved-from complex has changed
  copy = c;
  CHECK(changed(copy));
  copy = std::move(moved);
  CHECK(changed(copy));
  CHECK(changed(moved));  // NOLINT(bugprone-use-after-move)
}

TEST_CASE("revisions taken on several threads at once are all distinct", "[complex]") {
  // Four threads each give 20 000 complexes new revisions (more than one thread's block of
  // stamps), while the main thread takes some too: no value may appear twice.
  constexpr int kThreads = 4, kEach = 20000;
  std::vector<std::vector<std::uint64_t>> got(kThreads + 1);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&got, t] {
      Complex c(2);
      for (int i = 0; i < kEach; ++i) {
        c.touch();
        got[t].push_back(c.revision());
      }
    });
  Complex mine(3);
  for (int i = 0; i < kEach; ++i) {
    mine.touch();
    got[kThreads].push_back(mine.revision());
  }
  for (auto& th : threads) th.join();
  std::vector<std::uint64_t> all;
  for (const auto& g : got) all.insert(all.end(), g.begin(), g.end());
  REQUIRE(all.size() == std::size_t{kThreads + 1} * kEach);
  CHECK(std::find(all.begin(), all.end(), 0u) == all.end());
  std::sort(all.begin(), all.end());
  CHECK(std::adjacent_find(all.begin(), all.end()) == all.end());
}
