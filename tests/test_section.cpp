// Property tests of the layered hyperplane section over every built-in and the convex regular
// polychora of Miratope, with random and deliberately degenerate hyperplanes. Oracles: the
// B-spline cross-section formula (support/oracle.hpp), the closed form for cubes, brute force.
#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"
#include "cw4d/tetrahedralize/hull.hpp"
#include "support/oracle.hpp"
#include "support/planes.hpp"

using namespace cw4d;
using cw4d::test::random_orthogonal;
using cw4d::test::random_unit;
using cw4d::test::spanning;

namespace {

struct Shape {
  std::string name;
  Complex complex;
};

// Named groups of test shapes (geometry-central's fixture habit).
const std::vector<Shape>& shapes_4d() {
  static const std::vector<Shape> shapes = [] {
    std::vector<Shape> s;
    for (std::string spec :
         {"5-cell", "tesseract", "16-cell", "duoprism:3,4", "duoprism:5,7", "duoprism:12,9",
          "prism:simplex:3", "prism:orthoplex:3", "truncated tesseract", "snub 24-cell",
          "grand antiprism", "pyramid:cube:3", "dual:24-cell", "duocylinder:1,9",
          "prism:antiprism:5", "cone:sphere:1,6"})
      s.push_back({spec, load_model(spec, default_catalogue())});
    const std::string dir = std::string(CW4D_TEST_DATA_DIR) + "/miratope/regular/";
    for (std::string file : {"Icositetrachoron", "Hexacosichoron", "Hecatonicosachoron"})
      s.push_back({file, read_off_file(dir + file + ".off")});
    return s;
  }();
  return shapes;
}

const std::vector<Shape>& shapes_other_dims() {
  static const std::vector<Shape> shapes = [] {
    std::vector<Shape> s;
    for (std::string spec : {"cube:3", "simplex:3", "orthoplex:3", "prism:polygon:7", "cube:5",
                             "simplex:5", "orthoplex:5", "prism:tesseract"})
      s.push_back({spec, load_model(spec, default_catalogue())});
    return s;
  }();
  return shapes;
}

// Range of u . x over the model's vertices.
std::pair<double, double> extent(const Complex& c, const Eigen::VectorXd& u) {
  const Eigen::RowVectorXd h = u.transpose() * c.positions();
  return {h.minCoeff(), h.maxCoeff()};
}

double diameter(const Complex& c) {
  return 2.0 * max_radius(c) + 1e-300;
}

// Every property a section must have, checked against the model and the oracle.
void check_section(const Complex& model, const Hyperplane& plane, const Section& s,
                   double expected_volume, const std::string& what) {
  INFO(what);
  const int n = model.ambient_dim();
  const double scale = diameter(model);
  if (s.empty()) {
    CHECK(std::abs(expected_volume) <= 1e-9 * std::pow(scale, n - 1));
    return;
  }
  const Complex& c = s.complex;
  REQUIRE(c.ambient_dim() == n - 1);
  const ValidationReport report = validate(c);
  INFO(report.summary());
  REQUIRE(report.ok());  // closed, each ridge in two facets with opposite signs, outward, planar
  const double volume = signed_volume(c);
  CHECK(volume == Approx(expected_volume).epsilon(1e-9).margin(1e-12 * std::pow(scale, n - 1)));
  if (n == 4) {
    // A closed 2-manifold of genus 0: V - E + F = 2.
    CHECK(static_cast<long>(c.count(0)) - static_cast<long>(c.count(1)) +
              static_cast<long>(c.count(2)) ==
          2);
  }
  // Every vertex lies on the plane and on its source edge (or is its source vertex).
  const auto& mp = model.positions();
  for (std::uint32_t v = 0; v < c.count(0); ++v) {
    const Eigen::VectorXd x = s.world_position(v);
    REQUIRE(std::abs(plane.signed_distance(x)) <= 1e-9 * scale);
    const VertexSource& src = s.vertex_source[v];
    Eigen::VectorXd expect;
    if (src.rank == 0) {
      expect = mp.col(src.element);
    } else {
      const auto e = model.edge(src.element);
      REQUIRE(src.t > 0.0);
      REQUIRE(src.t < 1.0);
      expect = (1.0 - src.t) * mp.col(e[0]) + src.t * mp.col(e[1]);
    }
    REQUIRE((x - expect).norm() <= 1e-9 * scale);
  }
  // No duplicate vertices (crossings within 1e-9 of a model vertex are welded into one).
  for (std::uint32_t a = 0; a < c.count(0); ++a)
    for (std::uint32_t b = a + 1; b < c.count(0); ++b)
      REQUIRE((c.position(a) - c.position(b)).norm() > 1e-11 * scale);
  // Facets: no zero volume, convex solid, normal = geometric normal, lies in its source facet.
  const int fr = n - 2;
  REQUIRE(c.has_facet_normals());
  for (std::uint32_t f = 0; f < c.count(fr); ++f) {
    const Eigen::VectorXd area = facet_area_vector(c, f);
    // Not zero: the smallest legitimate facet comes from a plane one tolerance (1e-10 * scale)
    // away from a vertex.
    REQUIRE(area.norm() > 1e-20 * std::pow(scale, n - 2));
    const Eigen::VectorXd nrm = c.facet_normals().col(f);
    REQUIRE(nrm.dot(area.normalized()) == Approx(1.0).epsilon(1e-9));
    const std::uint32_t here = c.first_vertex(fr, f);
    for (std::uint32_t v = 0; v < c.count(0); ++v)
      REQUIRE(nrm.dot(c.position(v) - c.position(here)) <= 1e-9 * scale);
    const std::uint32_t cell = s.source[fr][f];
    const Eigen::VectorXd cn = model.facet_normals().col(cell);
    const double level = cn.dot(mp.col(model.first_vertex(n - 1, cell)));
    for (auto v : c.vertices_of(fr, f))
      REQUIRE(std::abs(cn.dot(s.world_position(v)) - level) <= 1e-9 * scale);
  }
}

void check_plane(const Shape& shape, const Hyperplane& plane, const std::string& what) {
  const Section s = section(shape.complex, plane);
  const double expected = test::bspline_section_volume(shape.complex, plane.normal, plane.offset);
  check_section(shape.complex, plane, s, expected, shape.name + ": " + what);
}

std::string describe(const Hyperplane& p) {
  std::ostringstream out;
  out.precision(17);
  out << "n = (" << p.normal.transpose() << "), d = " << p.offset;
  return out.str();
}

}  // namespace

TEST_CASE("oracle: the B-spline section volume matches the closed form for cubes") {
  std::mt19937 rng(7);
  for (int n = 3; n <= 5; ++n) {
    const Complex cube = make_cube(n);
    for (int trial = 0; trial < 50; ++trial) {
      const Eigen::VectorXd u = random_unit(rng, n);
      const auto [lo, hi] = extent(cube, u);
      const double t = lo + (hi - lo) * std::uniform_real_distribution<double>(0.02, 0.98)(rng);
      CHECK(test::bspline_section_volume(cube, u, t) ==
            Approx(test::cube_section_volume(u, t)).epsilon(1e-9));
    }
  }
}

TEST_CASE("section: a table naming elements that do not exist is refused, not read") {
  // Each defect of one boundary table, and the rank the message must name.
  struct Defect {
    const char* what;
    int rank;
    std::function<void(Complex&)> apply;
  };
  const std::vector<Defect> defects = {
      {"an edge end beyond the vertices", 1,
       [](Complex& c) { c.boundary_mut(1).ids_mut(3)[1] = 1000000u; }},
      {"a face edge beyond the edges", 2,
       [](Complex& c) {
         c.boundary_mut(2).ids_mut(5)[0] = static_cast<std::uint32_t>(c.count(1));
       }},
      {"a cell face beyond the faces", 3,
       [](Complex& c) { c.boundary_mut(3).ids_mut(7)[2] = 4000000000u; }},
      {"face offsets out of order", 2,
       [](Complex& c) {
         std::vector<std::uint32_t>& off = c.boundary_mut(2).storage().offsets;
         std::swap(off[4], off[5]);
       }},
      {"a sign of 2", 3, [](Complex& c) { c.boundary_mut(3).signs_mut(0)[0] = 2; }},
      {"an edge with one end", 1,
       [](Complex& c) {
         const Incidence::Storage t = c.boundary_mut(1).storage();
         t.ids.pop_back();
         t.signs.pop_back();
         --t.offsets.back();
       }},
      {"a cell with an empty boundary", 3, [](Complex& c) { c.boundary_mut(3).add_row({}, {}); }},
  };
  const Hyperplane plane = Hyperplane::from(Eigen::Vector4d(0.3, 0.5, -0.7, 0.2), 0.05);
  for (const Defect& d : defects) {
    INFO(d.what);
    Complex c = load_model("tesseract");
    d.apply(c);
    REQUIRE_FALSE(validate(c).ok());
    const std::string rank = "rank-" + std::to_string(d.rank) + " boundary table";
    CHECK_THROWS_WITH(section(c, plane), Catch::Contains(rank));
    CHECK_THROWS_AS(section(c, plane), InputError);
    CHECK_THROWS_WITH(section_general(c, plane, AffineTransform::identity(4)),
                      Catch::Contains(rank));
    CHECK_THROWS_WITH(SliceModel(c), Catch::Contains(rank));
  }
  // The same model unharmed: still cut.
  const Complex c = load_model("tesseract");
  CHECK(section(c, plane).complex.count(2) > 0);
}

TEST_CASE("section: the tesseract cut by (1,1,1,1), 0 is a regular octahedron") {
  const Complex t = load_model("tesseract", default_catalogue());
  const Section s = section(t, Hyperplane::from(Eigen::Vector4d(1, 1, 1, 1), 0.0));
  REQUIRE(s.complex.fvector() == std::vector<std::size_t>{6, 12, 8});
  CHECK(signed_volume(s.complex) == Approx(32.0 / 3.0).epsilon(1e-12));
  CHECK(validate(s.complex).ok());
  double edge = -1;
  for (std::uint32_t e = 0; e < 12; ++e) {
    const auto [a, b] = s.complex.edge(e);
    const double len = (s.complex.position(a) - s.complex.position(b)).norm();
    if (edge < 0) edge = len;
    CHECK(len == Approx(edge).epsilon(1e-12));
  }
  for (std::uint32_t v = 0; v < 6; ++v) {
    CHECK(s.complex.position(v).norm() == Approx(2.0).epsilon(1e-12));  // e.g. (1,1,-1,-1)
    CHECK(s.vertex_source[v].rank == 0);  // it passes through vertices only
  }
  for (std::uint32_t f = 0; f < 8; ++f) CHECK(s.complex.boundary(2).row_size(f) == 3);
}

TEST_CASE("section: random hyperplanes over every 4D shape") {
  std::mt19937 rng(20261122);
  for (const Shape& shape : shapes_4d()) {
    const int trials = shape.complex.count(0) > 200 ? 40 : 200;
    for (int trial = 0; trial < trials; ++trial) {
      const Eigen::VectorXd u = random_unit(rng, 4);
      const auto [lo, hi] = extent(shape.complex, u);
      const double d =
          std::uniform_real_distribution<double>(lo - 0.1 * (hi - lo), hi + 0.1 * (hi - lo))(rng);
      const Hyperplane plane = Hyperplane::from(u, d);
      check_plane(shape, plane, describe(plane));
    }
  }
}

TEST_CASE("section: random hyperplanes in dimensions 3 and 5") {
  std::mt19937 rng(35);
  for (const Shape& shape : shapes_other_dims()) {
    const int n = shape.complex.ambient_dim();
    for (int trial = 0; trial < 100; ++trial) {
      const Eigen::VectorXd u = random_unit(rng, n);
      const auto [lo, hi] = extent(shape.complex, u);
      const double d = std::uniform_real_distribution<double>(lo, hi)(rng);
      const Hyperplane plane = Hyperplane::from(u, d);
      check_plane(shape, plane, describe(plane));
    }
  }
}

TEST_CASE("section: cubes of dimension 3 to 6 against the closed form") {
  std::mt19937 rng(3);
  for (int n = 3; n <= 6; ++n) {
    const Complex cube = make_cube(n);
    for (int trial = 0; trial < 40; ++trial) {
      const Eigen::VectorXd u = random_unit(rng, n);
      const double d = std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
      const Section s = section(cube, Hyperplane::from(u, d));
      INFO("n = " << n << ", u = " << u.transpose() << ", d = " << d);
      CHECK(signed_volume(s.complex) == Approx(test::cube_section_volume(u, d)).epsilon(1e-9));
      CHECK(validate(s.complex).ok());
    }
  }
}

// --- degenerate families: each pins planes that pass through lower-dimensional elements ----

namespace {

void degenerate_family(int rank, int trials_per_shape, std::uint32_t seed) {
  std::mt19937 rng(seed);
  for (const Shape& shape : shapes_4d()) {
    const Complex& c = shape.complex;
    const int trials = c.count(0) > 200 ? trials_per_shape / 4 : trials_per_shape;
    for (int trial = 0; trial < trials; ++trial) {
      const auto id = std::uniform_int_distribution<std::uint32_t>(
          0, static_cast<std::uint32_t>(c.count(rank) - 1))(rng);
      const Eigen::MatrixXd dirs = rank == 0 ? Eigen::MatrixXd(4, 0) : spanning(c, rank, id);
      const Eigen::VectorXd u = random_orthogonal(rng, dirs);
      const double d = u.dot(c.position(c.first_vertex(rank, id)));
      const Hyperplane plane = Hyperplane::from(u, d);
      check_plane(shape, plane,
                  "plane containing rank-" + std::to_string(rank) + " element " +
                      std::to_string(id) + ", " + describe(plane));
    }
  }
}

}  // namespace

TEST_CASE("degenerate: planes through a vertex") {
  degenerate_family(0, 150, 101);
}
TEST_CASE("degenerate: planes containing an edge") {
  degenerate_family(1, 150, 102);
}
TEST_CASE("degenerate: planes containing a face") {
  degenerate_family(2, 150, 103);
}

TEST_CASE("degenerate: planes containing a cell give that cell as a solid") {
  for (const Shape& shape : shapes_4d()) {
    const Complex& c = shape.complex;
    const std::uint32_t step = c.count(3) > 50 ? 17 : 1;
    for (std::uint32_t cell = 0; cell < c.count(3); cell += step) {
      for (double flip : {1.0, -1.0}) {
        // The facet's own hyperplane, approached from either side (normal +N or -N).
        const Eigen::VectorXd u = flip * c.facet_normals().col(cell);
        const double d = u.dot(c.position(c.first_vertex(3, cell)));
        const Hyperplane plane = Hyperplane::from(u, d);
        const Section s = section(c, plane);
        INFO(shape.name << " cell " << cell << (flip > 0 ? " (+N)" : " (-N)"));
        const auto verts = c.vertices_of(3, cell);
        REQUIRE(s.complex.count(0) == verts.size());
        REQUIRE(s.complex.count(2) == c.boundary(3).row_size(cell));
        check_section(c, plane, s, element_volume(c, 3, cell), shape.name + " cell");
      }
    }
  }
}

TEST_CASE("degenerate: grid-snapped planes on the tesseract, 16-cell and 24-cell") {
  // Small integer normals and offsets on a coarse grid hit vertices, edges and faces at once.
  for (const Shape& shape : shapes_4d()) {
    if (shape.name != "tesseract" && shape.name != "16-cell" && shape.name != "Icositetrachoron")
      continue;
    int planes = 0;
    for (int a = -1; a <= 2; ++a)
      for (int b = -1; b <= 1; ++b)
        for (int cc = 0; cc <= 1; ++cc)
          for (int w = 0; w <= 2; ++w) {
            Eigen::Vector4d nrm(a, b, cc, w);
            if (nrm.isZero()) continue;
            const double len = nrm.norm();
            for (int k = -4; k <= 4; ++k) {
              // offsets chosen so that n.x = k/2 exactly for integer n (before normalizing)
              const Hyperplane plane{nrm / len, 0.5 * k / len};
              const auto [lo, hi] = extent(shape.complex, plane.normal);
              const double mid = 0.5 * (lo + hi);
              double expected =
                  test::bspline_section_volume(shape.complex, plane.normal, plane.offset);
              // A plane holding a whole facet sits on a jump of the oracle: take the inner limit.
              const double h = 1e-9 * (hi - lo);
              if (std::abs(plane.offset - hi) < h || std::abs(plane.offset - lo) < h) {
                const double inward = plane.offset > mid ? -1e-7 : 1e-7;
                expected = test::bspline_section_volume(shape.complex, plane.normal,
                                                        plane.offset + inward);
                const Section s = section(shape.complex, plane);
                if (!s.empty()) {
                  check_section(shape.complex, plane, s, signed_volume(s.complex),
                                shape.name + " supporting " + describe(plane));
                  CHECK(signed_volume(s.complex) == Approx(expected).epsilon(1e-5));
                }
                continue;
              }
              check_plane(shape, plane, "grid " + describe(plane));
              ++planes;
            }
          }
    CHECK(planes > 400);
  }
}

TEST_CASE("section: planes that miss or only touch the model give an empty section") {
  const Complex t = load_model("tesseract", default_catalogue());
  CHECK(section(t, Hyperplane::from(Eigen::Vector4d(0, 0, 0, 1), 1.5)).empty());
  CHECK(section(t, Hyperplane::from(Eigen::Vector4d(1, 1, 1, 1), 2.0)).empty());  // a vertex
  CHECK(section(t, Hyperplane::from(Eigen::Vector4d(1, 1, 1, 0), std::sqrt(3.0)))
            .empty());  // an edge
  CHECK(
      section(t, Hyperplane::from(Eigen::Vector4d(1, 1, 0, 0), std::sqrt(2.0))).empty());  // a face
  const Complex c16 = load_model("16-cell", default_catalogue());
  CHECK(section(c16, Hyperplane::from(Eigen::Vector4d(0, 0, 0, 1), 1.0)).empty());  // a vertex
}

TEST_CASE("section: the faces are exactly the cuts of the cells that straddle the plane") {
  std::mt19937 rng(11);
  for (const Shape& shape : shapes_4d()) {
    const Complex& c = shape.complex;
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::VectorXd u = random_unit(rng, 4);
      const auto [lo, hi] = extent(c, u);
      const double d = std::uniform_real_distribution<double>(lo, hi)(rng);
      const Section s = section(c, Hyperplane::from(u, d));
      std::vector<std::uint32_t> straddling;  // brute force over the cells' vertices
      for (std::uint32_t cell = 0; cell < c.count(3); ++cell) {
        bool below = false, above = false;
        for (auto v : c.vertices_of(3, cell)) {
          below |= u.dot(c.position(v)) < d;
          above |= u.dot(c.position(v)) > d;
        }
        if (below && above) straddling.push_back(cell);
      }
      std::vector<std::uint32_t> sources = s.source[2];
      std::sort(sources.begin(), sources.end());
      CHECK(sources == straddling);
    }
  }
}

TEST_CASE("section: cutting a transformed model equals cutting with the transformed plane") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-3.14159, 3.14159), shift(-0.5, 0.5);
  const char* planes[] = {"xy", "xz", "xw", "yz", "yw", "zw"};
  for (const Shape& shape : shapes_4d()) {
    for (int trial = 0; trial < 10; ++trial) {
      AffineTransform xf(4);
      for (const char* p : planes) {
        const auto [i, j] = parse_rotation_plane(p);
        xf = AffineTransform::rotation(4, i, j, angle(rng)) * xf;
      }
      if (trial % 3 == 1) xf = AffineTransform::scale(Eigen::Vector4d(1.5, 0.7, 1.0, 1.2)) * xf;
      if (trial % 3 == 2) xf = AffineTransform::scale(Eigen::Vector4d(-1, 1, 1, 1)) * xf;  // mirror
      xf = AffineTransform::translation(
               Eigen::Vector4d(shift(rng), shift(rng), shift(rng), shift(rng))) *
           xf;
      const Complex moved = transformed(shape.complex, xf);
      const Eigen::VectorXd u = random_unit(rng, 4);
      const auto [lo, hi] = extent(moved, u);
      const Hyperplane plane =
          Hyperplane::from(u, std::uniform_real_distribution<double>(lo, hi)(rng));
      const Section a = section(shape.complex, plane, xf);
      const Section b = section(moved, plane);
      INFO(shape.name << " trial " << trial);
      check_section(moved, plane, b,
                    test::bspline_section_volume(moved, plane.normal, plane.offset), "moved model");
      REQUIRE(a.complex.fvector() == b.complex.fvector());
      REQUIRE(validate(a.complex).ok());
      CHECK(signed_volume(a.complex) == Approx(signed_volume(b.complex)).epsilon(1e-9));
      for (std::uint32_t v = 0; v < a.complex.count(0); ++v)
        CHECK((a.complex.position(v) - b.complex.position(v)).norm() < 1e-9 * diameter(moved));
      for (std::uint32_t f = 0; f < a.complex.count(2); ++f)
        CHECK(a.complex.facet_normals().col(f).dot(b.complex.facet_normals().col(f)) ==
              Approx(1.0).epsilon(1e-9));
    }
  }
}

TEST_CASE("section: a section of a section is a closed polygon with the oracle's area") {
  std::mt19937 rng(9);
  for (const Shape& shape : shapes_4d()) {
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::VectorXd u = random_unit(rng, 4);
      const auto [lo, hi] = extent(shape.complex, u);
      const Section s3 = section(shape.complex, Hyperplane::from(u, 0.5 * (lo + hi)));
      REQUIRE(!s3.empty());
      const Eigen::VectorXd u3 = random_unit(rng, 3);
      const auto [lo3, hi3] = extent(s3.complex, u3);
      const Hyperplane p3 =
          Hyperplane::from(u3, std::uniform_real_distribution<double>(lo3, hi3)(rng));
      const Section s2 = section(s3.complex, p3);
      INFO(shape.name << " trial " << trial);
      REQUIRE(validate(s2.complex).ok());
      CHECK(s2.complex.count(0) == s2.complex.count(1));  // one closed polygon
      CHECK(signed_volume(s2.complex) ==
            Approx(test::bspline_section_volume(s3.complex, p3.normal, p3.offset)).epsilon(1e-9));
    }
  }
}

TEST_CASE("hyperplane basis: orthonormal, right-handed, deterministic, natural for +w") {
  std::mt19937 rng(1);
  for (int n = 2; n <= 6; ++n) {
    for (int trial = 0; trial < 50; ++trial) {
      Eigen::VectorXd u = random_unit(rng, n);
      if (trial == 0) u = Eigen::VectorXd::Unit(n, n - 1);
      if (trial == 1) u = -Eigen::VectorXd::Unit(n, n - 1);
      if (trial == 2) u = Eigen::VectorXd::Unit(n, 0);
      const Eigen::MatrixXd b = hyperplane_basis(u);
      REQUIRE((b.transpose() * b - Eigen::MatrixXd::Identity(n - 1, n - 1)).norm() < 1e-12);
      REQUIRE((b.transpose() * u).norm() < 1e-12);
      Eigen::MatrixXd frame(n, n);
      frame << b, u;
      REQUIRE(frame.determinant() == Approx(1.0));
      REQUIRE(hyperplane_basis(u) == b);
    }
  }
  const Eigen::MatrixXd b = hyperplane_basis(Eigen::Vector4d(0, 0, 0, 1));
  CHECK(b == Eigen::MatrixXd::Identity(4, 3));
}

TEST_CASE("hyperplane basis: right-handed for every largest coordinate, sign, tie and scale") {
  // The orientation is decided without elimination; Eigen's LU determinant of the frame is the
  // independent check, over normals whose largest coordinate (by magnitude) sits in every place
  // with either sign, exact ties (which pick the last of the largest), normals that are not unit
  // (the raw-pointer form does not normalise), and dimensions past the old stack bound of 8.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-1.0, 1.0);
  for (int n = 2; n <= 10; ++n) {
    std::vector<Eigen::VectorXd> normals;
    for (int j = 0; j < n; ++j)
      for (double s : {1.0, -1.0}) {
        Eigen::VectorXd u = Eigen::VectorXd::Zero(n);
        u[j] = s;
        normals.push_back(u);
        for (int trial = 0; trial < 6; ++trial) {
          Eigen::VectorXd v(n);
          for (int i = 0; i < n; ++i) v[i] = 0.9 * coord(rng);
          v[j] = s;
          normals.push_back(v.normalized());
          normals.push_back(v * (trial % 2 ? 3.5 : 0.25));  // not unit
        }
      }
    for (int trial = 0; trial < 8; ++trial) {  // ties of the largest magnitude
      Eigen::VectorXd v(n);
      for (int i = 0; i < n; ++i) v[i] = (rng() & 1u) ? 1.0 : -1.0;
      normals.push_back(v / std::sqrt(static_cast<double>(n)));
    }
    for (const Eigen::VectorXd& u : normals) {
      Eigen::MatrixXd b(n, n - 1);
      hyperplane_basis(u.data(), n, b.data());
      CHECK(b == hyperplane_basis(u));
      Eigen::MatrixXd frame(n, n);
      frame << b, u;
      INFO("n = " << n << ", normal " << u.transpose());
      CHECK(frame.determinant() > 0.0);
    }
  }
}

TEST_CASE("hyperplane: a zero or non-finite normal is rejected") {
  CHECK_THROWS_AS(Hyperplane::from(Eigen::Vector4d::Zero(), 0.0), InputError);
  CHECK_THROWS_AS(Hyperplane::from(Eigen::Vector4d(1, NAN, 0, 0), 0.0), InputError);
  CHECK_THROWS_AS(Hyperplane::from(Eigen::Vector4d(1, 0, 0, 0), INFINITY), InputError);
  const Complex t = load_model("tesseract", default_catalogue());
  CHECK_THROWS_AS(section(t, Hyperplane::from(Eigen::Vector3d(1, 0, 0), 0.0)), InputError);
}

// --- regressions, named after the bugs they pin -----------------------------------------------

TEST_CASE("regression: cutting a 2D complex (a section of a section of a section)") {
  const Section points = section(make_polygon(4), Hyperplane::from(Eigen::Vector2d(1, 0), 0.1));
  REQUIRE(points.complex.count(0) == 2);
  CHECK(points.complex.ambient_dim() == 1);
  // 4D -> 3D -> 2D -> 1D: the last cut of a closed polygon is two points.
  const Section s3 = section(load_model("tesseract", default_catalogue()),
                             Hyperplane::from(Eigen::Vector4d(0.1, 0.2, 0.3, 1), 0.1));
  const Section s2 = section(s3.complex, Hyperplane::from(Eigen::Vector3d(0.2, 0.1, 1), 0.05));
  const Section s1 = section(s2.complex, Hyperplane::from(Eigen::Vector2d(0.3, 1), 0.02));
  REQUIRE(validate(s2.complex).ok());
  CHECK(s1.complex.count(0) == 2);
}

namespace {

// Volume of {x in [-1,1]^3 : a.x >= t} for a > 0 componentwise (inclusion-exclusion).
double cube_cap_volume(const Eigen::Vector3d& a, double t) {
  const double tau = (t + a.sum()) / 2.0;  // x = 2u - 1
  double below = 0.0;
  for (int mask = 0; mask < 8; ++mask) {
    double shift = 0.0;
    int bits = 0;
    for (int i = 0; i < 3; ++i)
      if (mask >> i & 1) shift += a(i), ++bits;
    if (tau - shift > 0) below += (bits % 2 ? -1.0 : 1.0) * std::pow(tau - shift, 3);
  }
  below /= 6.0 * a.prod();
  return 8.0 * (1.0 - below);
}

}  // namespace

TEST_CASE("regression: planes nearly parallel to a facet keep planar faces and the true volume") {
  // n = (1e-9, 2e-9, 4e-9, 1): the plane is tilted by ~5e-9 rad from the cell w = 1. A wide ON
  // band used to snap a vertex 2e-10 away from the plane and bend its polygons by 2%.
  const Complex t = load_model("tesseract", default_catalogue());
  const Eigen::Vector4d n(1e-9, 2e-9, 4e-9, 1.0);
  for (double delta : {-8e-10, -3e-10, -1e-10, 1e-10, 3e-10, 8e-10, 2e-9, 5e-9}) {
    const double d = 1.0 + delta;  // the distance along n/|n| (|n| = 1 to 1e-17)
    const Hyperplane plane = Hyperplane::from(n, d);
    const Section s = section(t, plane);
    INFO("d = 1 + " << delta);
    // The section projects onto {x in [-1,1]^3 : x + 2y + 4z >= (1 + delta - d|n|...)/1e-9}.
    const double level = (1.0 - plane.offset * n.norm()) / -1e-9;  // x + 2y + 4z >= level
    const double expected = cube_cap_volume(Eigen::Vector3d(1, 2, 4), level);
    if (expected <= 0.0) {
      CHECK(s.empty());
      continue;
    }
    REQUIRE(!s.empty());
    INFO(validate(s.complex).summary());
    REQUIRE(validate(s.complex).ok());
    CHECK(signed_volume(s.complex) == Approx(expected).epsilon(1e-6));
  }
}

TEST_CASE("regression: the ON band follows rounding error, not the distance from the origin") {
  // A 5-cell moved 1e8 away: vertices 0.01 from the plane are not on it, whether the move is
  // baked into the coordinates or passed as the model-to-world transform.
  const Complex cell = make_simplex(4);
  for (double far : {1e4, 1e6, 1e8}) {
    const AffineTransform move = AffineTransform::translation(Eigen::Vector4d(far, -far, far, far));
    const Complex baked = transformed(cell, move);
    const double wmax = baked.positions().row(3).maxCoeff();
    const Hyperplane plane = Hyperplane::from(Eigen::Vector4d(0, 0, 0, 1), wmax - 0.01);
    const Section a = section(baked, plane);
    const Section b = section(cell, plane, move);
    INFO("offset " << far);
    REQUIRE(!a.empty());
    REQUIRE(a.complex.fvector() == b.complex.fvector());
    CHECK(signed_volume(a.complex) == Approx(signed_volume(b.complex)).epsilon(1e-4));
  }
}

namespace {

// The oracle for a plane u.x = d nearly parallel to cell k (level l: the mean of N.x over its
// vertices, N its outward normal): near the cell the section is the part of the cell on the inner
// side of the plane's trace in the cell's hyperplane, up to slivers of relative size O(tilt). The
// trace {y : m.y = e} (y coordinates in the cell's hyperplane about l N, m = B^T u, e = d - u.lN)
// and the clip of the cell's vertices by it are computed in 113-bit arithmetic (__float128), so a
// trace tilted 1e-15 rad is still where its equation puts it; the volume is the hull (CGAL's
// convex_hull) of the cell's vertices inside and the crossings of its edges. Shares nothing with
// the layered cut but the model.
using Quad = __float128;

double cell_cut_volume(const Complex& c, std::uint32_t k, const Eigen::Vector4d& u, double d,
                       double level) {
  const Eigen::Vector4d nrm = c.facet_normals().col(k);
  const Eigen::MatrixXd basis = hyperplane_basis(Eigen::VectorXd(nrm));
  Quad m[3] = {0, 0, 0}, e = d;
  for (int i = 0; i < 4; ++i) e -= Quad(u[i]) * Quad(level) * Quad(nrm[i]);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) m[j] += Quad(basis(i, j)) * Quad(u[i]);
  const double inward = u.dot(nrm) > 0.0 ? 1.0 : -1.0;
  const auto verts = c.vertices_of(3, k);
  std::map<std::uint32_t, std::array<Quad, 3>> y;
  std::map<std::uint32_t, Quad> f;  // > 0: inside
  for (auto v : verts) {
    std::array<Quad, 3> yv{0, 0, 0};
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i)
        yv[j] += Quad(basis(i, j)) * (Quad(c.position(v)[i]) - Quad(level) * Quad(nrm[i]));
    y[v] = yv;
    f[v] = Quad(inward) * (m[0] * yv[0] + m[1] * yv[1] + m[2] * yv[2] - e);
  }
  std::vector<Eigen::Vector3d> points;
  for (auto v : verts)
    if (f[v] >= 0) points.push_back({double(y[v][0]), double(y[v][1]), double(y[v][2])});
  std::vector<std::uint32_t> edges;
  for (auto face : c.boundary(3).ids(k))
    for (auto edge : c.boundary(2).ids(face)) edges.push_back(edge);
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (auto edge : edges) {
    const auto [a, b] = c.edge(edge);
    if ((f[a] >= 0) == (f[b] >= 0)) continue;
    const Quad t = f[a] / (f[a] - f[b]);
    Eigen::Vector3d x;
    for (int j = 0; j < 3; ++j) x[j] = double(y[a][j] + t * (y[b][j] - y[a][j]));
    points.push_back(x);
  }
  if (points.size() < 4) return 0.0;
  Eigen::MatrixXd pts(3, static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) pts.col(static_cast<Eigen::Index>(i)) = points[i];
  try {
    return signed_volume(convex_hull(pts));
  } catch (const InputError&) {
    return 0.0;  // a sliver the hull cannot tell from flat
  }
}

// The volume of cell k of a 4D complex, as the hull of its vertices in its hyperplane.
double cell_volume(const Complex& c, std::uint32_t k) {
  const Eigen::Vector4d nrm = c.facet_normals().col(k);
  const Eigen::MatrixXd basis = hyperplane_basis(Eigen::VectorXd(nrm));
  const auto verts = c.vertices_of(3, k);
  Eigen::MatrixXd pts(3, static_cast<Eigen::Index>(verts.size()));
  for (std::size_t i = 0; i < verts.size(); ++i)
    pts.col(static_cast<Eigen::Index>(i)) = basis.transpose() * c.position(verts[i]);
  return signed_volume(convex_hull(pts));
}

// Planar to 1e-8 of the model's size (a few weld distances: welding moves a vertex by up to
// twice 1e-9 of the diagonal) and convex: every vertex behind every face's plane, to 1e-7.
void check_planar_convex(const Section& s, double scale) {
  const Complex& c = s.complex;
  for (std::uint32_t f = 0; f < c.count(2); ++f) {
    const auto verts = c.vertices_of(2, f);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (auto v : verts) centre += c.position(v);
    centre /= static_cast<double>(verts.size());
    double size = 0.0;
    for (auto v : verts) size = std::max(size, (c.position(v) - centre).norm());
    // The geometric normal of a face 1e-8 across is noise: take the source cell's projected
    // normal there (the section's facet normal), the area vector elsewhere.
    const Eigen::Vector3d nrm = size > 1e-3 * scale
                                    ? Eigen::Vector3d(facet_area_vector(c, f).normalized())
                                    : Eigen::Vector3d(c.facet_normals().col(f));
    for (auto v : verts) REQUIRE(std::abs(nrm.dot(c.position(v) - centre)) <= 1e-8 * scale);
    for (std::uint32_t v = 0; v < c.count(0); ++v)
      REQUIRE(nrm.dot(c.position(v) - centre) <= 1e-7 * scale);
  }
}

}  // namespace

TEST_CASE("regression: planes tilted 1e-6 to 1e-16 rad from cells and vertex layers",
          "[degenerate][tilt]") {
  // Where a plane is nearly parallel to a cell, rounding of the cell's vertices moves the
  // crossings on its edges by (rounding / tilt): a plane tilted 1e-12 rad from a cell of the
  // 120-cell used to give a non-convex section 0.07% short of the oracle.
  std::mt19937 rng(1412);
  // At 1e-13 a cell of the 120-cell has vertices within (rounding / tilt) of the plane's trace:
  // their sides are decided in the facet hyperplanes, as the crossings are placed, not by their
  // rounded positions (which gave 3 of these planes a polygon off its plane).
  const double tilts[] = {1e-6, 1e-8, 1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15, 1e-16};
  int planes = 0, snapped = 0;
  for (const std::string spec : {"tesseract", "24-cell", "600-cell", "120-cell"}) {
    const Complex c = load_model(spec);
    const double r = max_radius(c), scale = 2.0 * r;
    // (base normal, offset, cell whose hyperplane it is or -1)
    struct Base {
      Eigen::Vector4d u;
      double d;
      int cell;
      double level;  // of the cell along its outward normal
    };
    std::vector<Base> bases;
    const std::uint32_t step = static_cast<std::uint32_t>(std::max<std::size_t>(1, c.count(3) / 3));
    for (std::uint32_t k = 0; k < c.count(3); k += step) {
      double level = 0.0;
      const auto verts = c.vertices_of(3, k);
      for (auto v : verts) level += c.facet_normals().col(k).dot(c.position(v));
      level /= static_cast<double>(verts.size());
      for (double flip : {1.0, -1.0})
        bases.push_back(
            {flip * c.facet_normals().col(k), flip * level, static_cast<int>(k), level});
    }
    // Vertex layers: the levels of the vertices along the direction of vertex 0, inner ones.
    const Eigen::Vector4d axis = c.position(0).normalized();
    std::vector<double> levels;
    for (std::uint32_t v = 0; v < c.count(0); ++v) levels.push_back(axis.dot(c.position(v)));
    std::sort(levels.begin(), levels.end());
    std::vector<double> layers;
    for (double l : levels)
      if (layers.empty() || l - layers.back() > 1e-9 * r) layers.push_back(l);
    for (std::size_t i = 1; i + 1 < layers.size(); i += std::max<std::size_t>(1, layers.size() / 3))
      bases.push_back({axis, layers[i], -1, 0.0});
    for (const Base& base : bases)
      for (double tilt : tilts)
        for (int rep = 0; rep < 2; ++rep) {
          Eigen::Vector4d w = random_orthogonal(rng, Eigen::MatrixXd(base.u));
          const Eigen::Vector4d u = (base.u + tilt * w).normalized();
          const Hyperplane plane{u, base.d};
          INFO(spec << (base.cell >= 0 ? " cell " + std::to_string(base.cell) : " layer")
                    << " tilt " << tilt << " " << describe(plane));
          const Section s = section(c, plane);
          ++planes;
          // Slivers beside the cell, and the tilt of a layer plane, change the volume by O(tilt).
          const double eps = 1e-7 + 10.0 * tilt;
          const double oracle =
              base.cell >= 0
                  ? cell_cut_volume(c, static_cast<std::uint32_t>(base.cell), u, base.d, base.level)
                  : test::bspline_section_volume(c, base.u, base.d);
          INFO("oracle " << oracle);
          if (s.empty()) {
            CHECK(oracle <= 1e-9 * std::pow(scale, 3));
            continue;
          }
          INFO(validate(s.complex).summary());
          REQUIRE(validate(s.complex).ok());
          check_planar_convex(s, scale);
          const double volume = signed_volume(s.complex);
          if (base.cell < 0) {
            CHECK(volume == Approx(oracle).epsilon(eps).margin(1e-9 * std::pow(scale, 3)));
            continue;
          }
          // A plane within the ON band (on_plane_tolerance) of every vertex of the cell
          // contains the cell; one whose values on the cell leave the band by 2x cuts it.
          const double band = on_plane_tolerance(1.0, r, base.d);
          double spread = 0.0;
          for (auto v : c.vertices_of(3, static_cast<std::uint32_t>(base.cell)))
            spread = std::max(spread, std::abs(u.dot(c.position(v)) - base.d));
          const double cell = cell_volume(c, static_cast<std::uint32_t>(base.cell));
          // Where the plane meets the cell's hyperplane is known only to (the rounding of the
          // cell's offset) / tilt: 16 ulps of r moved by that across the cell's cut.
          const double conditioning =
              std::pow(cell, 2.0 / 3.0) * 16.0 * std::numeric_limits<double>::epsilon() * r / tilt;
          auto near = [&](double want) {
            return std::abs(volume - want) <=
                   eps * std::abs(want) + conditioning + 1e-9 * std::pow(scale, 3);
          };
          if (spread <= 0.5 * band) {
            ++snapped;
            CHECK(near(cell));
          } else if (spread >= 2.0 * band) {
            CHECK(near(oracle));
          } else {
            CHECK((near(cell) || near(oracle)));
          }
        }
  }
  CHECK(planes > 450);
  CHECK(snapped > 0);
}

TEST_CASE("regression: 120-cell sections by planes tilted 1e-12 rad off a cell through its vertex",
          "[degenerate][tilt]") {
  // A plane through a vertex of a cell, tilted 1e-12 rad from it, meets that cell's other
  // vertices at plane values of ~1e-12 x their distance from the trace: an error of 1e-16 in
  // such a value (a solve in doubles) moves the vertex across the trace by 1e-4. Vertices that
  // near the trace then took one side by their values and the other where the facets' planes
  // put the crossings, a crossing stayed at its rounded t off the cut polygon's plane, and the
  // section was not convex (its vertices' hull 4.6e-4 larger than its volume). The section of
  // a convex polytope is convex: the hull of its vertices (CGAL) encloses its volume exactly.
  const Complex c = load_model("120-cell");
  std::mt19937 rng(2026);
  std::normal_distribution<double> gauss;
  const double tilt = 1e-12;
  double worst = 0.0;
  int planes = 0;
  for (std::uint32_t k = 0; k < c.count(3); ++k) {
    const Eigen::Vector4d n0 = c.facet_normals().col(k);
    const auto verts = c.vertices_of(3, k);
    for (int trial = 0; trial < 3; ++trial) {
      Eigen::Vector4d t;
      for (int i = 0; i < 4; ++i) t[i] = gauss(rng);
      t -= t.dot(n0) * n0;
      t.normalize();
      const Eigen::Vector4d u = std::cos(tilt) * n0 + std::sin(tilt) * t;
      const auto v = verts[std::uniform_int_distribution<std::size_t>(0, verts.size() - 1)(rng)];
      const Section s = section(c, Hyperplane{u, u.dot(c.position(v))});
      if (s.empty()) continue;
      ++planes;
      const double volume = signed_volume(s.complex);
      const double hull = signed_volume(convex_hull(s.complex.positions()));
      INFO("cell " << k << " trial " << trial << " volume " << volume << " hull " << hull);
      CHECK(volume > 0.0);
      CHECK(std::abs(hull - volume) <= 1e-9 * hull);
      worst = std::max(worst, std::abs(hull - volume) / hull);
    }
  }
  INFO("worst relative hull excess " << worst);
  CHECK(planes >= 300);
}

// section() keeps compiled models per thread, keyed on the complex's address and revision():
// every change between two calls must show in the second (oracle: the volumes of the cube's
// and the 16-cell's sections in closed form).
TEST_CASE("section() sees every change made to a complex between calls", "[section][cache]") {
  const Hyperplane plane = Hyperplane::from(Eigen::Vector4d(0, 0, 0, 1), 0.25);
  const auto volume = [&](const Complex& c) {
    const Section s = section(c, plane);
    return s.empty() ? 0.0 : signed_volume(s.complex);
  };
  // [-s, s]^4 cut at w = 0.25 (|0.25| < s) is [-s, s]^3; the 16-cell |x|_1 <= 1 cut there is
  // the octahedron of radius 0.75, of volume 4/3 0.75^3.
  const double octahedron = 4.0 / 3.0 * 0.75 * 0.75 * 0.75;

  Complex c = make_cube(4);
  CHECK(volume(c) == Approx(8.0));
  c.positions_mut() *= 2.0;
  CHECK(volume(c) == Approx(64.0));
  {
    Eigen::MatrixXd& kept = c.positions_mut();
    CHECK(volume(c) == Approx(64.0));
    kept *= 0.5;  // written after the call: seen once touched
    c.touch();
    CHECK(volume(c) == Approx(8.0));
  }
  Eigen::MatrixXd shifted = c.positions();
  shifted.row(3).array() += 1.5;  // the plane now misses [-1, 1]^3 x [0.5, 2.5]
  c.set_positions(shifted);
  CHECK(volume(c) == 0.0);
  shifted.row(3).array() -= 1.5;
  c.set_positions(shifted);  // the same arrays as a state seen before
  CHECK(volume(c) == Approx(8.0));

  // A cell flipped and flipped back (two new revisions, the first state's arrays).
  c.flip(3, 0);
  c.flip(3, 0);
  CHECK(volume(c) == Approx(8.0));

  // Assignment, and another complex built at the same address.
  c = make_orthoplex(4);
  CHECK(volume(c) == Approx(octahedron));
  c = make_cube(4);
  CHECK(volume(c) == Approx(8.0));
  std::optional<Complex> slot;
  slot.emplace(make_orthoplex(4));
  const Complex* address = &*slot;
  CHECK(volume(*slot) == Approx(octahedron));
  slot.reset();
  slot.emplace(make_cube(4));
  REQUIRE(&*slot == address);
  CHECK(volume(*slot) == Approx(8.0));
}
