#include "cw4d/section/hyperplane.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <vector>

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
  const double big = n.cwiseAbs().maxCoeff();
  if (!(big > 0.0)) throw InputError("hyperplane normal is zero");
  if (!std::isfinite(d)) throw InputError("hyperplane offset is not finite");
  // Scaled by a power of two first (exact), so that the length of normals such as
  // (1e308, 1e308, 0, 0) or (0, 0, 0, 1e-320) neither overflows nor underflows.
  const int e = std::ilogb(big);
  const Eigen::VectorXd m = n.unaryExpr([e](double x) { return std::scalbn(x, -e); });
  return Hyperplane{m / m.norm(), d};
}

namespace {

// D > 0: the dimension fixed at compile time (the loops unroll; the same operations in the same
// order as for D = 0, so the same bits).
template <int D>
void basis_of(const double* nrm, int dim, double* basis) {
  const int n = D > 0 ? D : dim;
  int j = 0;
  for (int i = 1; i < n; ++i)
    if (std::abs(nrm[i]) >= std::abs(nrm[j])) j = i;
  const double sgn = nrm[j] >= 0.0 ? 1.0 : -1.0;
  // Householder reflection H = I - 2 u u^T / (u^T u) with u = sgn e_j + nrm maps e_j to -sgn nrm;
  // |u|^2 = 2 + 2 |nrm_j| >= 2, so this is stable.
  double uu = 0.0;
  for (int i = 0; i < n; ++i) {
    const double ui = nrm[i] + (i == j ? sgn : 0.0);
    uu += ui * ui;
  }
  int col = 0;
  for (int i = 0; i < n; ++i) {
    if (i == j) continue;
    const double f = 2.0 * nrm[i] / uu;  // (u_i = nrm_i for i != j)
    for (int r = 0; r < n; ++r) {
      const double ur = nrm[r] + (r == j ? sgn : 0.0);
      basis[col * n + r] = (r == i ? 1.0 : 0.0) - f * ur;
    }
    ++col;
  }
  // (b_1, ..., b_{n-1}, nrm) must be right-handed. H is a reflection (determinant -1) and
  // the frame is H's columns without the j-th, then nrm, whose j-th coordinate in H's columns,
  // (H nrm)_j = -sgn (|nrm_j| |nrm|^2 + |nrm_j| + 2 |nrm|^2) / |u|^2, has the sign -sgn for
  // every nonzero normal; moving that column from place j to the end takes n - 1 - j swaps. So
  // the frame's determinant has the sign sgn (-1)^(n-1-j), exactly: no elimination needed.
  const bool odd = (n - 1 - j) % 2 == 1;
  if (n >= 2 && (sgn < 0.0) != odd)
    for (int r = 0; r < n; ++r) basis[r] = -basis[r];
}

}  // namespace

void hyperplane_basis(const double* nrm, int n, double* basis) {
  if (n == 4)
    basis_of<4>(nrm, n, basis);
  else if (n == 3)
    basis_of<3>(nrm, n, basis);
  else
    basis_of<0>(nrm, n, basis);
}

Eigen::MatrixXd hyperplane_basis(const Eigen::VectorXd& nrm) {
  const Eigen::Index n = nrm.size();
  Eigen::MatrixXd basis(n, n - 1);
  hyperplane_basis(nrm.data(), static_cast<int>(n), basis.data());
  return basis;
}

HyperplaneFrame::HyperplaneFrame(const Hyperplane& p)
    : plane(p), basis(hyperplane_basis(p.normal)) {}

}  // namespace cw4d
