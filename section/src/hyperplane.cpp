#include "cw4d/section/hyperplane.hpp"

#include <Eigen/LU>

#include <cmath>

#include "cw4d/complex/error.hpp"

namespace cw4d {

double plane_value(const Eigen::VectorXd& n, double d, const double* x) {
  // Dot2 (Ogita, Rump, Oishi 2005): p + c is the sum of the exact products and -d, c collecting
  // the rounding errors of every product (fma) and every addition (TwoSum).
  double p = -d, c = 0.0;
  for (Eigen::Index i = 0; i < n.size(); ++i) {
    const double h = n[i] * x[i];
    const double r = std::fma(n[i], x[i], -h);  // exact: n_i x_i = h + r
    const double sum = p + h;
    const double z = sum - p;
    const double e = (p - (sum - z)) + (h - z);  // exact: p + h = sum + e
    p = sum;
    c += e + r;
  }
  return p + c;
}

Hyperplane Hyperplane::from(const Eigen::VectorXd& n, double d) {
  if (n.size() < 1 || !n.allFinite()) throw InputError("hyperplane normal is not finite");
  const double len = n.norm();
  if (!(len > 0.0)) throw InputError("hyperplane normal is zero");
  if (!std::isfinite(d)) throw InputError("hyperplane offset is not finite");
  return Hyperplane{n / len, d};
}

Eigen::MatrixXd hyperplane_basis(const Eigen::VectorXd& nrm) {
  const Eigen::Index n = nrm.size();
  Eigen::Index j = 0;
  for (Eigen::Index i = 1; i < n; ++i)
    if (std::abs(nrm(i)) >= std::abs(nrm(j))) j = i;
  const double sgn = nrm(j) >= 0.0 ? 1.0 : -1.0;
  // Householder reflection H = I - 2 u u^T / (u^T u) with u = sgn e_j + nrm maps e_j to -sgn nrm;
  // |u|^2 = 2 + 2 |nrm_j| >= 2, so this is stable.
  Eigen::VectorXd u = nrm;
  u(j) += sgn;
  const double uu = u.squaredNorm();
  Eigen::MatrixXd basis(n, n - 1);
  Eigen::Index col = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (i == j) continue;
    Eigen::VectorXd e = Eigen::VectorXd::Unit(n, i);
    basis.col(col++) = e - (2.0 * u(i) / uu) * u;
  }
  if (n >= 2) {
    Eigen::MatrixXd frame(n, n);
    frame.leftCols(n - 1) = basis;
    frame.col(n - 1) = nrm;
    if (frame.determinant() < 0.0) basis.col(0) = -basis.col(0);
  }
  return basis;
}

HyperplaneFrame::HyperplaneFrame(const Hyperplane& p) : plane(p), basis(hyperplane_basis(p.normal)) {}

}  // namespace cw4d
