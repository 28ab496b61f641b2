#include "support/oracle.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>

#include "cw4d/complex/geometry.hpp"

namespace cw4d::test {

double bspline(std::vector<double> x, double t) {
  std::sort(x.begin(), x.end());
  const int k_max = static_cast<int>(x.size()) - 1;  // order of the spline
  if (t < x.front() || t >= x.back()) return 0.0;
  std::vector<double> m(x.size() - 1);
  for (std::size_t i = 0; i + 1 < x.size(); ++i)
    m[i] = (x[i] <= t && t < x[i + 1] && x[i + 1] > x[i]) ? 1.0 / (x[i + 1] - x[i]) : 0.0;
  for (int k = 2; k <= k_max; ++k) {
    for (std::size_t i = 0; i + k < x.size(); ++i) {
      const double span = x[i + k] - x[i];
      m[i] =
          span > 0.0 ? k * ((t - x[i]) * m[i] + (x[i + k] - t) * m[i + 1]) / ((k - 1) * span) : 0.0;
    }
  }
  return m[0];
}

double bspline_section_volume(const Complex& c, const Eigen::VectorXd& u, double t) {
  const int n = c.ambient_dim();
  const auto& p = c.positions();
  const Eigen::VectorXd centre = p.rowwise().mean();
  Eigen::MatrixXd m(n, n);
  double nfact = 1.0;
  for (int i = 2; i <= n; ++i) nfact *= i;
  double total = 0.0;
  std::vector<double> knots(n + 1);
  for (std::uint32_t f = 0; f < c.count(n - 1); ++f) {
    for_each_simplex(c, n - 1, f, [&](std::span<const std::uint32_t> v, int sign) {
      for (int j = 0; j < n; ++j) m.col(j) = p.col(v[j]) - centre;
      const double vol = sign * m.determinant() / nfact;
      if (std::abs(vol) < 1e-300) return;
      knots[0] = u.dot(centre);
      for (int j = 0; j < n; ++j) knots[j + 1] = u.dot(p.col(v[j]));
      total += vol * bspline(knots, t);
    });
  }
  return total;
}

double cube_section_volume(const Eigen::VectorXd& u, double t) {
  const int n = static_cast<int>(u.size());
  // x = 2y - 1 maps [0,1]^n onto [-1,1]^n; reflect axes with u_i < 0 so all weights are > 0.
  Eigen::VectorXd a = u.cwiseAbs();
  double tau = (t + u.sum()) / 2.0;
  for (int i = 0; i < n; ++i)
    if (u(i) < 0) tau -= u(i);
  double prod = 1.0, fact = 1.0;
  for (int i = 0; i < n; ++i) prod *= a(i);
  for (int i = 2; i <= n - 1; ++i) fact *= i;
  double sum = 0.0;
  for (std::uint32_t mask = 0; mask < (1u << n); ++mask) {
    double shift = 0.0;
    int bits = 0;
    for (int i = 0; i < n; ++i)
      if (mask >> i & 1u) shift += a(i), ++bits;
    const double r = tau - shift;
    if (r > 0) sum += (bits % 2 ? -1.0 : 1.0) * std::pow(r, n - 1);
  }
  const double unit = a.norm() * sum / (fact * prod);  // section of [0,1]^n
  return std::pow(2.0, n - 1) * unit;
}

}  // namespace cw4d::test
