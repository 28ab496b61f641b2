// Tests of the measures in geometry.hpp against oracles that share none of their code: the
// generalized cross product against explicit cofactor determinants (Eigen's full-pivoting LU)
// and against its defining properties (orthogonal to every u_i, as long as the parallelotope's
// volume sqrt(det(U^T U)), det(U, x) > 0); area vectors and volumes of polytopes in R^2..R^8
// against analytic values and against the affine map's cofactor matrix.
#include <catch2/catch.hpp>

#include <Eigen/Core>
#include <Eigen/LU>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/complex/validate.hpp"

using namespace cw4d;

namespace {

double full_det(const Eigen::MatrixXd& m) {
  if (m.rows() == 0) return 1.0;
  return Eigen::FullPivLU<Eigen::MatrixXd>(m).determinant();
}

// x_j = det(u_1, ..., u_{n-1}, e_j), one determinant per component.
Eigen::VectorXd cofactor_cross(const Eigen::MatrixXd& u) {
  const Eigen::Index n = u.rows();
  Eigen::MatrixXd m(n, n);
  m.leftCols(n - 1) = u;
  Eigen::VectorXd x(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    m.col(n - 1).setZero();
    m(j, n - 1) = 1.0;
    x(j) = full_det(m);
  }
  return x;
}

// Product of the column norms: bounds |det| of any n x n matrix of u's columns and a unit
// vector (Hadamard), so the scale of every cofactor.
double hadamard(const Eigen::MatrixXd& u) {
  double h = 1.0;
  for (Eigen::Index j = 0; j < u.cols(); ++j) h *= u.col(j).norm();
  return h;
}

double factorial(int n) {
  double r = 1.0;
  for (int i = 2; i <= n; ++i) r *= i;
  return r;
}

}  // namespace

TEST_CASE("generalized_cross equals the cofactor determinants on random matrices", "[geometry]") {
  std::mt19937 rng(20261203);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (int n = 1; n <= 10; ++n) {  // 9 and 10 take the path for more than 8 rows
    for (int trial = 0; trial < 40; ++trial) {
      INFO("n = " << n << ", trial " << trial);
      Eigen::MatrixXd u(n, n - 1);
      for (Eigen::Index i = 0; i < u.size(); ++i) u.data()[i] = entry(rng);
      if (trial % 4 == 1 && n > 1) u *= 1e-3;  // scale does not matter: every term is degree n-1
      if (trial % 4 == 2 && n > 2) u.col(0) *= 1e6;
      const Eigen::VectorXd x = generalized_cross(u);
      const Eigen::VectorXd oracle = cofactor_cross(u);
      const double h = hadamard(u);
      REQUIRE(x.size() == n);
      CHECK((x - oracle).lpNorm<Eigen::Infinity>() <= 1e-12 * h);
      // x . u_i = det(u, u_i) = 0, |x| = the (n-1)-volume of the parallelotope of the u_i, and
      // (u, x) is positively oriented.
      for (Eigen::Index i = 0; i < u.cols(); ++i)
        CHECK(std::abs(x.dot(u.col(i))) <= 1e-12 * h * u.col(i).norm());
      const double volume = std::sqrt(full_det(u.transpose() * u));
      CHECK(x.norm() == Approx(volume).epsilon(1e-10));
      Eigen::MatrixXd ux(n, n);
      ux << u, x;
      CHECK(full_det(ux) == Approx(x.squaredNorm()).epsilon(1e-10));
      // The defining identity on an arbitrary y.
      Eigen::VectorXd y(n);
      for (Eigen::Index i = 0; i < n; ++i) y(i) = entry(rng);
      Eigen::MatrixXd uy(n, n);
      uy << u, y;
      CHECK(std::abs(x.dot(y) - full_det(uy)) <= 1e-12 * h * y.norm());
    }
  }
}

TEST_CASE("generalized_cross of integer matrices is the integer cofactor vector", "[geometry]") {
  std::mt19937 rng(8);
  std::uniform_int_distribution<int> entry(-3, 3);
  for (int n = 2; n <= 9; ++n) {
    for (int trial = 0; trial < 30; ++trial) {
      INFO("n = " << n << ", trial " << trial);
      Eigen::MatrixXd u(n, n - 1);
      for (Eigen::Index i = 0; i < u.size(); ++i) u.data()[i] = entry(rng);
      const Eigen::VectorXd x = generalized_cross(u);
      const Eigen::VectorXd oracle = cofactor_cross(u);
      for (Eigen::Index j = 0; j < n; ++j) {
        CHECK(std::abs(oracle(j) - std::round(oracle(j))) <= 1e-9);
        CHECK(std::abs(x(j) - std::round(oracle(j))) <= 1e-9);
      }
    }
  }
}

TEST_CASE("generalized_cross of a rank-deficient matrix is zero", "[geometry]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (int n = 3; n <= 10; ++n) {
    INFO("n = " << n);
    Eigen::MatrixXd u(n, n - 1);
    for (Eigen::Index i = 0; i < u.size(); ++i) u.data()[i] = entry(rng);
    Eigen::MatrixXd zero_column = u;
    zero_column.col(n / 2 - 1).setZero();
    CHECK(generalized_cross(zero_column) == Eigen::VectorXd::Zero(n));
    Eigen::MatrixXd dependent = u;  // the last column a combination of the first one or two
    dependent.col(n - 2) = 0.75 * u.col(0);
    if (n > 3) dependent.col(n - 2) -= 2.0 * u.col(1);
    CHECK(generalized_cross(dependent).norm() <= 1e-13 * hadamard(dependent));
    Eigen::MatrixXd zero_row = u;  // a valid u in a coordinate hyperplane: x is along e_r
    zero_row.row(1).setZero();
    const Eigen::VectorXd x = generalized_cross(zero_row);
    for (Eigen::Index j = 0; j < n; ++j)
      if (j != 1) CHECK(x(j) == 0.0);
    CHECK(x(1) != 0.0);
    CHECK(x(1) == Approx(cofactor_cross(zero_row)(1)).epsilon(1e-12));
  }
}

TEST_CASE("area vectors and volumes of cubes, simplices and orthoplexes up to R^8",
          "[geometry][builtins]") {
  for (int n = 2; n <= 8; ++n) {
    INFO("n = " << n);
    const Complex cube = make_cube(n);
    REQUIRE(validate(cube).ok());
    CHECK(signed_volume(cube) == Approx(std::pow(2.0, n)).epsilon(1e-12));
    // Each facet of the cube [-1, 1]^n: the outward axis times 2^(n-1), exactly.
    const int fr = n - 1;
    REQUIRE(cube.has_facet_normals());
    for (std::uint32_t f = 0; f < cube.count(fr); ++f) {
      const Eigen::VectorXd a = facet_area_vector(cube, f);
      const Eigen::VectorXd expected = std::pow(2.0, n - 1) * cube.facet_normals().col(f);
      CHECK((a - expected).lpNorm<Eigen::Infinity>() <= 1e-12 * expected.norm());
    }
    const Complex orthoplex = make_orthoplex(n);
    CHECK(signed_volume(orthoplex) == Approx(std::pow(2.0, n) / factorial(n)).epsilon(1e-12));
    const Complex simplex = make_simplex(n);  // circumradius 1
    const double edge = std::sqrt(2.0 * (n + 1) / n);
    CHECK(signed_volume(simplex) ==
          Approx(std::sqrt(n + 1.0) / factorial(n) * std::pow(edge / std::sqrt(2.0), n))
              .epsilon(1e-12));
    // Orthoplex and simplex facets: their own (n-1)-volume along the stored outward normal.
    for (const Complex* c : {&orthoplex, &simplex}) {
      REQUIRE(c->has_facet_normals());
      for (std::uint32_t f = 0; f < c->count(fr); ++f) {
        const Eigen::VectorXd a = facet_area_vector(*c, f);
        CHECK(a.norm() == Approx(element_volume(*c, fr, f)).epsilon(1e-12));
        CHECK(a.normalized().dot(c->facet_normals().col(f)) == Approx(1.0).epsilon(1e-12));
      }
    }
  }
}

TEST_CASE("area vectors and volumes follow a linear map's cofactor matrix in R^3..R^8",
          "[geometry]") {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (int n = 3; n <= 8; ++n) {
    for (const std::string& name : {std::string("simplex:"), std::string("orthoplex:")}) {
      const Complex c = load_model(name + std::to_string(n));
      INFO(name << n);
      Eigen::MatrixXd a = Eigen::MatrixXd::Identity(n, n);
      for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] += 0.5 * entry(rng);
      double det = full_det(a);
      if (det < 0.0) {  // keep the orientation: the facets' signs are then unchanged
        a.col(0) = -a.col(0);
        det = -det;
      }
      Eigen::VectorXd t(n);
      for (Eigen::Index i = 0; i < n; ++i) t(i) = entry(rng);
      const Complex m = transformed(c, AffineTransform(a, t));
      CHECK(signed_volume(m) == Approx(det * signed_volume(c)).epsilon(1e-11));
      // The area vector of an (n-1)-chain maps by det(A) A^-T.
      const Eigen::MatrixXd cof = det * a.inverse().transpose();
      for (std::uint32_t f = 0; f < c.count(n - 1); ++f) {
        const Eigen::VectorXd expected = cof * facet_area_vector(c, f);
        const Eigen::VectorXd got = facet_area_vector(m, f);
        CHECK((got - expected).norm() <= 1e-11 * expected.norm());
      }
    }
  }
}
