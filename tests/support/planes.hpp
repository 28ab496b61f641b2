#pragma once
// Seeded random directions for the section tests: unit vectors, vectors orthogonal to an
// element of a model (for planes through a vertex, containing an edge, a face or a cell).
#include <Eigen/Dense>

#include <cstdint>
#include <random>

#include "cw4d/complex/complex.hpp"

namespace cw4d::test {

/// A uniformly distributed unit vector in R^n.
inline Eigen::VectorXd random_unit(std::mt19937& rng, int n) {
  std::normal_distribution<double> g;
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v(i) = g(rng);
  return v.normalized();
}

/// A random unit vector orthogonal to the span of the columns of `dirs`, ignoring the rounding
/// noise of coordinates read from files (singular values below 1e-6 of the largest).
inline Eigen::VectorXd random_orthogonal(std::mt19937& rng, const Eigen::MatrixXd& dirs) {
  Eigen::VectorXd v = random_unit(rng, static_cast<int>(dirs.rows()));
  if (dirs.cols() > 0) {
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(dirs, Eigen::ComputeFullU);
    const auto& sv = svd.singularValues();
    Eigen::Index rank = 0;
    while (rank < sv.size() && sv(rank) > 1e-6 * sv(0)) ++rank;
    const Eigen::MatrixXd basis = svd.matrixU().leftCols(rank);
    v -= basis * (basis.transpose() * v);
  }
  return v.normalized();
}

/// Directions spanned by element i of a rank: differences of its vertices to the first one.
inline Eigen::MatrixXd spanning(const Complex& c, int rank, std::uint32_t i) {
  const auto verts = c.vertices_of(rank, i);
  Eigen::MatrixXd d(c.ambient_dim(), static_cast<Eigen::Index>(verts.size()) - 1);
  for (std::size_t k = 1; k < verts.size(); ++k)
    d.col(static_cast<Eigen::Index>(k - 1)) = c.position(verts[k]) - c.position(verts[0]);
  return d;
}

}  // namespace cw4d::test
