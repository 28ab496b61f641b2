#include "cw4d/complex/geometry.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <vector>

namespace cw4d {

namespace {

void simplices_rec(const Complex& c, int rank, std::uint32_t i, std::vector<std::uint32_t>& buf,
                   const std::function<void(std::span<const std::uint32_t>, int)>& f) {
  if (rank == 1) {
    auto e = c.edge(i);
    std::uint32_t v[2] = {e[0], e[1]};
    f(v, 1);
    return;
  }
  if (rank == 2) {
    std::vector<std::uint32_t> cycle = c.face_cycle(i);
    for (std::size_t k = 1; k + 1 < cycle.size(); ++k) {
      std::uint32_t v[3] = {cycle[0], cycle[k], cycle[k + 1]};
      f(v, 1);
    }
    return;
  }
  const std::uint32_t apex = c.first_vertex(rank, i);
  const Incidence& table = c.boundary(rank);
  auto ids = table.ids(i);
  auto signs = table.signs(i);
  for (std::size_t j = 0; j < ids.size(); ++j) {
    const int sigma = signs[j];
    // A cone from the apex over a boundary element that contains the apex is flat: skip it
    // whole (checking only the sub-simplices would keep flat slivers of rounding noise).
    const auto verts = c.vertices_of(rank - 1, ids[j]);
    if (std::binary_search(verts.begin(), verts.end(), apex)) continue;
    simplices_rec(c, rank - 1, ids[j], buf, [&](std::span<const std::uint32_t> sub, int s) {
      std::vector<std::uint32_t> cone;
      cone.reserve(sub.size() + 1);
      cone.push_back(apex);
      cone.insert(cone.end(), sub.begin(), sub.end());
      f(cone, sigma * s);
    });
  }
}

double factorial(int k) {
  double r = 1;
  for (int i = 2; i <= k; ++i) r *= i;
  return r;
}

}  // namespace

void for_each_simplex(const Complex& complex, int rank, std::uint32_t i,
                      const std::function<void(std::span<const std::uint32_t>, int)>& f) {
  std::vector<std::uint32_t> buf;
  simplices_rec(complex, rank, i, buf, f);
}

Eigen::VectorXd generalized_cross(const Eigen::MatrixXd& u) {
  const Eigen::Index n = u.rows();
  Eigen::VectorXd x(n);
  Eigen::MatrixXd m(n, n);
  m.leftCols(n - 1) = u;
  for (Eigen::Index j = 0; j < n; ++j) {
    m.col(n - 1).setZero();
    m(j, n - 1) = 1.0;
    x(j) = m.determinant();
  }
  return x;
}

Eigen::VectorXd facet_area_vector(const Complex& complex, std::uint32_t facet) {
  const int n = complex.ambient_dim();
  const int k = n - 1;
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd u(n, k);
  const auto& p = complex.positions();
  for_each_simplex(complex, k, facet, [&](std::span<const std::uint32_t> v, int sign) {
    for (int j = 0; j < k; ++j) u.col(j) = p.col(v[j + 1]) - p.col(v[0]);
    sum += static_cast<double>(sign) * generalized_cross(u);
  });
  const double parity = (k % 2 == 0) ? 1.0 : -1.0;
  return parity * sum / factorial(k);
}

double signed_volume(const Complex& complex) {
  const int n = complex.ambient_dim();
  const int k = n - 1;
  if (complex.count(k) == 0 || k < 1) return 0.0;
  const auto& p = complex.positions();
  const Eigen::VectorXd c = p.rowwise().mean();
  Eigen::MatrixXd m(n, n);
  double total = 0.0;
  for (std::uint32_t f = 0; f < complex.count(k); ++f) {
    for_each_simplex(complex, k, f, [&](std::span<const std::uint32_t> v, int sign) {
      for (int j = 0; j < n; ++j) m.col(j) = p.col(v[j]) - c;
      total += sign * m.determinant();
    });
  }
  return total / factorial(n);
}

double element_volume(const Complex& complex, int rank, std::uint32_t i) {
  const auto& p = complex.positions();
  const int n = complex.ambient_dim();
  Eigen::MatrixXd u(n, rank);
  double total = 0.0;
  for_each_simplex(complex, rank, i, [&](std::span<const std::uint32_t> v, int) {
    for (int j = 0; j < rank; ++j) u.col(j) = p.col(v[j + 1]) - p.col(v[0]);
    const double g = (u.transpose() * u).determinant();
    total += std::sqrt(std::max(0.0, g));
  });
  return total / factorial(rank);
}

Bounds bounds(const Complex& complex) {
  const auto& p = complex.positions();
  if (p.cols() == 0) {
    return {Eigen::VectorXd::Zero(complex.ambient_dim()),
            Eigen::VectorXd::Zero(complex.ambient_dim())};
  }
  return {p.rowwise().minCoeff(), p.rowwise().maxCoeff()};
}

double max_radius(const Complex& complex) {
  const auto& p = complex.positions();
  if (p.cols() == 0) return 0.0;
  return p.colwise().norm().maxCoeff();
}

}  // namespace cw4d
