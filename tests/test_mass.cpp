// Tests of the mass properties (mass.hpp) against analytic values that share none of its code:
// boxes and products from one-dimensional integrals, regular polygons from the textbook
// second moment A (6 R^2 - s^2) / 24, the regular simplices' volume from their edge length
// and the tetrahedron's moment of inertia m a^2 / 20, the 120-cell's closed-form volume, the
// 3-sphere's pi^2 r^4 / 2 approached by its hulls, the parallel axis theorem under rotations
// and translations, a non-convex picture frame, and the published densities of the regular
// star polychora as winding numbers.
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/mass.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/operators.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"

using namespace cw4d;
using Catch::Matchers::WithinAbs;
using Catch::Matchers::WithinRel;

namespace {

constexpr double pi = std::numbers::pi;

void require_matrix(const Eigen::MatrixXd& got, const Eigen::MatrixXd& want, double tol) {
  REQUIRE(got.rows() == want.rows());
  REQUIRE(got.cols() == want.cols());
  INFO("got\n" << got << "\nwant\n" << want);
  REQUIRE((got - want).cwiseAbs().maxCoeff() <= tol * std::max(1.0, want.cwiseAbs().maxCoeff()));
}

double edge_length(const Complex& c) {
  const auto e = c.edge(0);
  return (c.position(e[1]) - c.position(e[0])).norm();
}

// A regular p-gon of circumradius r: area, perimeter and int x^2 dA (= int y^2 dA) about its
// centre.
struct Polygon {
  double area, perimeter, moment;
};
Polygon regular_polygon(int p, double r) {
  const double s = 2 * r * std::sin(pi / p);
  const double area = 0.5 * p * r * r * std::sin(2 * pi / p);
  return {area, p * s, area * (6 * r * r - s * s) / 24};
}

}  // namespace

TEST_CASE("mass: the tesseract [-1,1]^4 and the cube [-1,1]^3", "[mass]") {
  const MassProperties m = mass_properties(make_cube(4));
  CHECK(m.dim == 4);
  CHECK_THAT(m.hypervolume, WithinRel(16.0, 1e-14));
  CHECK_THAT(m.boundary_volume, WithinRel(64.0, 1e-14));  // 8 cubes of volume 8
  CHECK(m.centroid.cwiseAbs().maxCoeff() < 1e-14);
  require_matrix(m.second_moment, Eigen::MatrixXd::Identity(4, 4) * 16.0 / 3.0, 1e-14);
  CHECK_FALSE(m.winding_weighted);

  const MassProperties c = mass_properties(make_cube(3));
  CHECK_THAT(c.hypervolume, WithinRel(8.0, 1e-14));
  CHECK_THAT(c.boundary_volume, WithinRel(24.0, 1e-14));
  require_matrix(c.second_moment, Eigen::MatrixXd::Identity(3, 3) * 8.0 / 3.0, 1e-14);
  CHECK_FALSE(c.winding_weighted);
}

TEST_CASE("mass: regular polygons in R^2", "[mass]") {
  for (int p : {3, 6, 17}) {
    const Polygon want = regular_polygon(p, 1.0);
    const MassProperties m = mass_properties(make_polygon(p));
    CHECK(m.dim == 2);
    CHECK_THAT(m.hypervolume, WithinRel(want.area, 1e-13));
    CHECK_THAT(m.boundary_volume, WithinRel(want.perimeter, 1e-13));
    require_matrix(m.second_moment, Eigen::MatrixXd::Identity(2, 2) * want.moment, 1e-13);
  }
}

TEST_CASE("mass: regular simplices", "[mass]") {
  // The regular tetrahedron of edge a: volume a^3 / (6 sqrt 2), moment of inertia about any
  // axis through its centroid m a^2 / 20, so int x^2 dV = V a^2 / 40 (isotropic).
  {
    const Complex t = make_simplex(3);
    const double a = edge_length(t);
    const MassProperties m = mass_properties(t);
    const double v = a * a * a / (6 * std::sqrt(2.0));
    CHECK_THAT(m.hypervolume, WithinRel(v, 1e-13));
    CHECK_THAT(m.boundary_volume, WithinRel(std::sqrt(3.0) * a * a, 1e-13));
    require_matrix(m.second_moment, Eigen::MatrixXd::Identity(3, 3) * v * a * a / 40, 1e-13);
  }
  // The regular n-simplex of edge a: volume a^n sqrt(n+1) / (n! 2^(n/2)), its facets n+1
  // regular (n-1)-simplices; about its centroid (the mean of its vertices) the second moment
  // is V R^2 / (n (n + 2)) I with R^2 = n a^2 / (2 (n + 1)) its circumradius squared.
  for (int n : {4, 5}) {
    const Complex s = make_simplex(n);
    const double a = edge_length(s);
    const auto vol = [](int k, double e) {
      double f = 1;
      for (int i = 2; i <= k; ++i) f *= i;
      return std::pow(e, k) * std::sqrt(k + 1.0) / (f * std::pow(2.0, k / 2.0));
    };
    const MassProperties m = mass_properties(s);
    const Eigen::VectorXd mean = s.positions().rowwise().mean();
    CHECK_THAT(m.hypervolume, WithinRel(vol(n, a), 1e-13));
    CHECK_THAT(m.boundary_volume, WithinRel((n + 1) * vol(n - 1, a), 1e-13));
    CHECK((m.centroid - mean).norm() < 1e-14);
    const double r2 = n * a * a / (2.0 * (n + 1));
    const Eigen::MatrixXd central =
        m.second_moment - m.hypervolume * m.centroid * m.centroid.transpose();
    require_matrix(central, Eigen::MatrixXd::Identity(n, n) * m.hypervolume * r2 / (n * (n + 2)),
                   1e-13);
  }
}

TEST_CASE("mass: duoprisms from their polygons", "[mass]") {
  // P x Q in R^4: volume A_P A_Q, boundary (perimeter_P A_Q + A_P perimeter_Q), second moment
  // diag(I_P A_Q, I_P A_Q, A_P I_Q, A_P I_Q), centroid 0.
  for (auto [p, q] : {std::pair{3, 4}, {5, 7}, {6, 6}, {12, 3}}) {
    const Complex d = make_duoprism(p, q);
    // The circumradii as built (the polygons of the x,y and z,w planes).
    const double rp = d.positions().topRows(2).col(0).norm();
    const double rq = d.positions().bottomRows(2).col(0).norm();
    const Polygon a = regular_polygon(p, rp), b = regular_polygon(q, rq);
    const MassProperties m = mass_properties(d);
    INFO(p << "," << q);
    CHECK_THAT(m.hypervolume, WithinRel(a.area * b.area, 1e-13));
    CHECK_THAT(m.boundary_volume, WithinRel(a.perimeter * b.area + a.area * b.perimeter, 1e-13));
    CHECK(m.centroid.cwiseAbs().maxCoeff() < 1e-14);
    Eigen::VectorXd diag(4);
    diag << a.moment * b.area, a.moment * b.area, a.area * b.moment, a.area * b.moment;
    require_matrix(m.second_moment, diag.asDiagonal().toDenseMatrix(), 1e-13);
    CHECK_FALSE(m.winding_weighted);
  }
}

TEST_CASE("mass: a rotated and translated copy obeys the parallel axis theorem", "[mass]") {
  // x' = L x + t: V' = V |det L|, c' = L c + t, M' = L M L^T + L m t^T + t m^T L^T + V t t^T
  // with m = V c (about the origin).
  std::mt19937 rng(20261206);
  std::uniform_real_distribution<double> angle(-pi, pi), shift(-3.0, 3.0);
  for (const char* spec : {"duoprism:5,7", "24-cell", "wythoff:x4x3o3o"}) {
    const Complex model = load_model(spec);
    const MassProperties m = mass_properties(model);
    AffineTransform place = AffineTransform::identity(4);
    for (auto [i, j] : {std::pair{0, 3}, {1, 2}, {0, 1}, {2, 3}})
      place = AffineTransform::rotation(4, i, j, angle(rng)) * place;
    Eigen::VectorXd t(4);
    t << shift(rng), shift(rng), shift(rng), shift(rng);
    place = AffineTransform::translation(t) * place;
    const MassProperties moved = mass_properties(transformed(model, place));
    const Eigen::MatrixXd& l = place.linear();
    const Eigen::VectorXd first = m.hypervolume * m.centroid;
    INFO(spec);
    CHECK_THAT(moved.hypervolume, WithinRel(m.hypervolume, 1e-12));
    CHECK_THAT(moved.boundary_volume, WithinRel(m.boundary_volume, 1e-12));
    CHECK((moved.centroid - (l * m.centroid + t)).norm() < 1e-12 * (1 + t.norm()));
    const Eigen::MatrixXd want = l * m.second_moment * l.transpose() + l * first * t.transpose() +
                                 t * first.transpose() * l.transpose() +
                                 m.hypervolume * t * t.transpose();
    require_matrix(moved.second_moment, want, 1e-12);
  }
  // A uniform scale s multiplies V by s^4, the boundary by s^3, M by s^6; a reflection keeps
  // them (the transform re-orients the facets).
  const Complex cube = make_cube(4);
  const MassProperties big = mass_properties(transformed(cube, AffineTransform::scale(4, 1e30)));
  CHECK_THAT(big.hypervolume, WithinRel(16e120, 1e-13));
  CHECK_THAT(big.boundary_volume, WithinRel(64e90, 1e-13));
  CHECK_THAT(big.second_moment(2, 2), WithinRel(16.0 / 3.0 * 1e180, 1e-13));
  Eigen::VectorXd flip = Eigen::VectorXd::Ones(4);
  flip(1) = -1;
  const MassProperties mirrored =
      mass_properties(transformed(load_model("duoprism:3,5"), AffineTransform::scale(flip)));
  CHECK(mirrored.hypervolume > 0);
}

TEST_CASE("mass: a non-convex picture frame and its prism", "[mass]") {
  // frame.off: [-2,2]^2 minus (-1,1)^2, times [-1,1] in z. Area 12, height 2: V = 24;
  // int x^2 = 2 (int over [-2,2]^2 - int over [-1,1]^2) = 2 (64/3 - 4/3) = 40; int z^2 =
  // 12 * 2/3 = 8; boundary: outer sides 32, inner sides 16, top and bottom 24.
  const Complex frame = read_off_file(std::string(CW4D_TEST_DATA_DIR) + "/frame.off");
  const MassProperties m = mass_properties(frame);
  CHECK_THAT(m.hypervolume, WithinRel(24.0, 1e-14));
  CHECK_THAT(m.boundary_volume, WithinRel(72.0, 1e-14));
  CHECK(m.centroid.cwiseAbs().maxCoeff() < 1e-14);
  Eigen::VectorXd diag(3);
  diag << 40, 40, 8;
  require_matrix(m.second_moment, diag.asDiagonal().toDenseMatrix(), 1e-14);
  CHECK_FALSE(m.winding_weighted);
  // Its prism, times [-1,1] in w: V = 48, boundary 72 * 2 + 2 * 24, int w^2 = 24 * 2/3.
  const MassProperties p = mass_properties(make_prism(frame, 2.0));
  CHECK_THAT(p.hypervolume, WithinRel(48.0, 1e-14));
  CHECK_THAT(p.boundary_volume, WithinRel(192.0, 1e-14));
  Eigen::VectorXd diag4(4);
  diag4 << 80, 80, 16, 16;
  require_matrix(p.second_moment, diag4.asDiagonal().toDenseMatrix(), 1e-14);
  CHECK_FALSE(p.winding_weighted);
}

TEST_CASE("mass: the 120-cell against its closed form", "[mass]") {
  // Edge a: hypervolume (15/4)(105 + 47 sqrt 5) a^4; 120 dodecahedra of (15 + 7 sqrt 5)/4 a^3.
  const Complex c = load_model("120-cell");
  const double a = edge_length(c);
  const MassProperties m = mass_properties(c);
  const double s5 = std::sqrt(5.0);
  CHECK_THAT(m.hypervolume, WithinRel(3.75 * (105 + 47 * s5) * std::pow(a, 4), 1e-13));
  CHECK_THAT(m.boundary_volume, WithinRel(120 * (15 + 7 * s5) / 4 * std::pow(a, 3), 1e-13));
  CHECK(m.centroid.cwiseAbs().maxCoeff() < 1e-12);
  // Symmetric enough to be isotropic: M = (trace / 4) I.
  require_matrix(m.second_moment, Eigen::MatrixXd::Identity(4, 4) * m.second_moment.trace() / 4,
                 1e-13);
  CHECK_FALSE(m.winding_weighted);
}

TEST_CASE("mass: the glome's hulls approach the 3-sphere", "[mass]") {
  // The ball of radius r in R^4: volume pi^2 r^4 / 2, boundary 2 pi^2 r^3, int x^2 = V r^2 / 6.
  const double r = 1.5;
  const double v = pi * pi * std::pow(r, 4) / 2;
  double last = INFINITY;
  for (int n : {4, 6, 8}) {
    const Complex g = load_model("glome:1.5," + std::to_string(n), default_catalogue());
    const MassProperties m = mass_properties(g);
    const double error = (v - m.hypervolume) / v;  // inscribed: below the ball's volume
    INFO("N = " << n << ": relative error " << error);
    CHECK(error > 0);
    CHECK(error < last);
    last = error;
    CHECK(m.boundary_volume < 2 * pi * pi * r * r * r);
    // (the hull's vertices are not centrally symmetric: the centroid is near 0, not at it)
    CHECK(m.centroid.norm() < 0.01 * r);
    for (int i = 0; i < 4; ++i)
      CHECK_THAT(m.second_moment(i, i) / m.hypervolume, WithinRel(r * r / 6, 4 * error + 0.02));
  }
  CHECK(last < 0.05);
}

TEST_CASE("mass: star polychora are winding-weighted, with their densities", "[mass]") {
  // The densities of the regular star polychora (Coxeter, Regular Polytopes, table VI).
  for (auto [name, density] : {std::pair{"icosahedral 120-cell", 4},
                               {"great 120-cell", 6},
                               {"grand 120-cell", 20},
                               {"great grand stellated 120-cell", 191}}) {
    const Complex star = load_model(name);
    INFO(name);
    CHECK(winding_number(star, Eigen::VectorXd::Zero(4)) == density);
    const MassProperties m = mass_properties(star);
    CHECK(m.winding_weighted);
    CHECK(m.hypervolume > 0);
  }
  CHECK(winding_number(make_cube(4), Eigen::VectorXd::Zero(4)) == 1);
  CHECK(winding_number(make_cube(4), Eigen::VectorXd::Constant(4, 1.5)) == 0);
}

TEST_CASE("mass: open models and bad input are refused", "[mass]") {
  ComplexSoup soup = to_soup(make_cube(4));
  soup.higher.resize(1);      // no solid
  soup.higher[0].pop_back();  // drop a cube: the boundary has a hole
  const Complex open = build_complex(soup);
  CHECK_THROWS_AS(mass_properties(open), TopologyError);
  CHECK_THROWS_WITH(mass_properties(open), Catch::Contains("not closed"));
  CHECK_THROWS_AS(mass_properties(Complex(4)), InputError);
  Complex nan = make_cube(3);
  nan.positions_mut()(0, 0) = NAN;
  CHECK_THROWS_AS(mass_properties(nan), InputError);
  CHECK_THROWS_AS(winding_number(make_cube(4), Eigen::VectorXd::Zero(3)), InputError);
}
