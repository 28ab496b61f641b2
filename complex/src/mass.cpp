#include "cw4d/complex/mass.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/validate.hpp"

namespace cw4d {

namespace {

double factorial(int k) {
  double r = 1;
  for (int i = 2; i <= k; ++i) r *= i;
  return r;
}

// A fixed direction in no coordinate plane and on no symmetry axis of the built-in models, for
// the rays of the winding numbers (a ray along an axis would graze the facets of a cube).
Eigen::VectorXd ray_direction(int n) {
  static constexpr double kDirection[] = {0.5377,  1.8339, -2.2588, 0.8622, 0.3188,  -1.3077,
                                          -0.4336, 0.3426, 3.5784,  2.7694, -1.3499, 3.0349};
  Eigen::VectorXd r(n);
  for (int i = 0; i < n; ++i) r(i) = kDirection[i % 12] + 0.1 * (i / 12);
  return r.normalized();
}

// Solves the n x n system a x = b (column-major a, overwritten) by elimination with partial
// pivoting and returns det(a); 0 (x unset) when a is singular.
double solve_in_place(double* a, double* b, double* x, int n) {
  double det = 1.0;
  for (int j = 0; j < n; ++j) {
    int p = j;
    double best = std::abs(a[j + n * j]);
    for (int i = j + 1; i < n; ++i)
      if (std::abs(a[i + n * j]) > best) best = std::abs(a[i + n * j]), p = i;
    if (best == 0.0) return 0.0;
    if (p != j) {
      for (int c = 0; c < n; ++c) std::swap(a[p + n * c], a[j + n * c]);
      std::swap(b[p], b[j]);
      det = -det;
    }
    const double pivot = a[j + n * j];
    det *= pivot;
    for (int i = j + 1; i < n; ++i) {
      const double l = a[i + n * j] / pivot;
      if (l == 0.0) continue;
      for (int c = j + 1; c < n; ++c) a[i + n * c] -= l * a[j + n * c];
      b[i] -= l * b[j];
    }
  }
  for (int i = n - 1; i >= 0; --i) {
    double s = b[i];
    for (int c = i + 1; c < n; ++c) s -= a[i + n * c] * x[c];
    x[i] = s / a[i + n * i];
  }
  return det;
}

// Winding numbers of the oriented boundary around a set of probe points, accumulated one
// oriented boundary simplex at a time (vertices q_0..q_{n-1}, scaled coordinates).
class WindingCounter {
 public:
  WindingCounter(int n, std::vector<Eigen::VectorXd> probes)
      : n_(n),
        probes_(std::move(probes)),
        counts_(probes_.size(), 0),
        r_(ray_direction(n)),
        a_(static_cast<std::size_t>(n) * n),
        b_(n),
        x_(n) {}

  void add(const std::vector<const double*>& q, int sign) {
    const int n = n_;
    // The simplex's box, to skip the probes whose ray cannot reach it.
    std::array<double, 16> lo_small{}, hi_small{};
    std::vector<double> lo_big, hi_big;
    double* lo = lo_small.data();
    double* hi = hi_small.data();
    if (n > 16) {
      lo_big.resize(n), hi_big.resize(n);
      lo = lo_big.data(), hi = hi_big.data();
    }
    for (int i = 0; i < n; ++i) {
      lo[i] = hi[i] = q[0][i];
      for (int j = 1; j < n; ++j)
        lo[i] = std::min(lo[i], q[j][i]), hi[i] = std::max(hi[i], q[j][i]);
    }
    // parity (-1)^(n-1): the outward normal is parity * X with X . y = det(e_1..e_{n-1}, y).
    const int parity = ((n - 1) % 2 == 0) ? 1 : -1;
    for (std::size_t k = 0; k < probes_.size(); ++k) {
      const double* p = probes_[k].data();
      // Slab test of the ray p + t r, t >= 0, against the box.
      double t0 = 0.0, t1 = INFINITY;
      bool miss = false;
      for (int i = 0; i < n && !miss; ++i) {
        const double ri = r_(i);
        const double u = (lo[i] - p[i]) / ri, v = (hi[i] - p[i]) / ri;
        t0 = std::max(t0, std::min(u, v));
        t1 = std::min(t1, std::max(u, v));
        miss = t0 > t1;
      }
      if (miss) continue;
      // q_0 + sum_i lambda_i (q_i - q_0) = p + t r:  [e_1 .. e_{n-1}, -r] (lambda, t) = p - q_0.
      for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i < n; ++i) a_[i + n * j] = q[j + 1][i] - q[0][i];
      for (int i = 0; i < n; ++i) a_[i + n * (n - 1)] = -r_(i), b_[i] = p[i] - q[0][i];
      const double det = solve_in_place(a_.data(), b_.data(), x_.data(), n);
      if (det == 0.0) continue;
      double sum = 0.0;
      bool inside = x_[n - 1] > 0.0;
      for (int i = 0; i + 1 < n && inside; ++i) {
        inside = x_[i] >= 0.0;
        sum += x_[i];
      }
      if (!inside || sum > 1.0) continue;
      // det(e, r) = -det: the ray leaves through the simplex when parity * det(e, r) > 0.
      counts_[k] += sign * (parity * -det > 0 ? 1 : -1);
    }
  }

  const std::vector<int>& counts() const { return counts_; }

 private:
  int n_;
  std::vector<Eigen::VectorXd> probes_;
  std::vector<int> counts_;
  Eigen::VectorXd r_;
  std::vector<double> a_, b_, x_;
};

void check_input(const Complex& complex) {
  const int n = complex.ambient_dim();
  if (n < 2)
    throw InputError("mass properties need a solid in R^2 or above; this model lives in R^" +
                     std::to_string(n));
  check_tables(complex);
  const int k = n - 1;
  if (complex.top_rank() < k || complex.count(k) == 0)
    throw InputError("the model has no facets (elements of rank " + std::to_string(k) +
                     "): it bounds no solid");
  if (!complex.positions().allFinite())
    throw InputError("the model has a coordinate that is NaN or infinite");
  // Every ridge in exactly two facets with opposite signs: the facets close up.
  const Incidence& facets = complex.boundary(k);
  const std::size_t ridges = complex.count(k - 1);
  std::vector<std::uint8_t> uses(ridges, 0);
  std::vector<int> sums(ridges, 0);
  for (std::size_t f = 0; f < facets.size(); ++f) {
    auto ids = facets.ids(f);
    auto signs = facets.signs(f);
    for (std::size_t j = 0; j < ids.size(); ++j) {
      if (uses[ids[j]] < 255) ++uses[ids[j]];
      sums[ids[j]] += signs[j];
    }
  }
  for (std::size_t r = 0; r < ridges; ++r) {
    if (uses[r] == 0) continue;  // an element no facet uses (not part of the boundary)
    if (uses[r] != 2 || sums[r] != 0)
      throw TopologyError(
          k - 1, {static_cast<std::uint32_t>(r)},
          "the model is not closed: " + std::string(k - 1 == 0 ? "vertex " : "ridge ") +
              std::to_string(r) + " (rank " + std::to_string(k - 1) + ") lies in " +
              std::to_string(uses[r]) + (uses[r] == 1 ? " facet" : " facets") +
              (uses[r] == 2 ? " with the same sign" : "") +
              ", not in two with opposite signs: mass properties need a closed boundary");
  }
}

// The probe points of the winding check, in scaled coordinates: the vertex mean, and points a
// small odd fraction of the model's size inside up to 32 facets (from the facet's vertex mean
// against its outward area vector).
std::vector<Eigen::VectorXd> winding_probes(const Complex& complex, double scale,
                                            const Eigen::VectorXd& mean) {
  const int n = complex.ambient_dim();
  const auto& p = complex.positions();
  std::vector<Eigen::VectorXd> probes{mean};
  const double diameter = scale * (p.rowwise().maxCoeff() - p.rowwise().minCoeff()).norm();
  const double step = 0.0012345 * diameter;
  const std::size_t facets = complex.count(n - 1);
  const std::size_t count = std::min<std::size_t>(facets, 32);
  for (std::size_t j = 0; j < count; ++j) {
    const auto f = static_cast<std::uint32_t>(j * facets / count);
    const Eigen::VectorXd area = facet_area_vector(complex, f, scale);
    const double length = area.norm();
    if (!(length > 0.0) || !std::isfinite(length)) continue;
    Eigen::VectorXd centre = Eigen::VectorXd::Zero(n);
    const auto vertices = complex.vertices_of(n - 1, f);
    for (auto v : vertices) centre += scale * p.col(v);
    centre /= static_cast<double>(vertices.size());
    probes.push_back(centre - step / length * area);
  }
  return probes;
}

}  // namespace

int winding_number(const Complex& complex, const Eigen::VectorXd& point) {
  check_input(complex);
  const int n = complex.ambient_dim();
  if (point.size() != n)
    throw InputError("the point has " + std::to_string(point.size()) +
                     " coordinates; the model lives in R^" + std::to_string(n));
  const double scale = position_scale(complex);
  WindingCounter counter(n, {scale * point});
  std::vector<const double*> q(static_cast<std::size_t>(n));
  const Eigen::MatrixXd sp = scale * complex.positions();
  const double* base = sp.data();
  for (std::uint32_t f = 0; f < complex.count(n - 1); ++f)
    for_each_simplex(complex, n - 1, f, [&](std::span<const std::uint32_t> v, int sign) {
      for (int j = 0; j < n; ++j) q[j] = base + static_cast<std::size_t>(n) * v[j];
      counter.add(q, sign);
    });
  return counter.counts()[0];
}

namespace {

struct Sums {
  double volume = 0.0, boundary = 0.0;
  Eigen::VectorXd first;
  Eigen::MatrixXd second;
};

// The signed cone integrals over every boundary simplex, in coordinates relative to `apex`.
// Mat is an n x n matrix type (fixed-capacity on the stack for small n: no allocation per
// simplex).
template <typename Mat>
Sums integrate(const Complex& complex, double scale, const Eigen::MatrixXd& sp,
               const Eigen::VectorXd& apex, WindingCounter& counter) {
  using Vec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, Mat::MaxRowsAtCompileTime, 1>;
  const int n = complex.ambient_dim();
  const int k = n - 1;
  const double* base = sp.data();
  Mat y(n, n), second = Mat::Zero(n, n);
  Vec s(n), first = Vec::Zero(n), a = apex;
  std::vector<const double*> q(static_cast<std::size_t>(n));
  // Summed as determinants (n! times the signed volumes) and divided once at the end, as
  // signed_volume does: a box's integer determinants then add up exactly.
  double total = 0.0;
  Sums sums;
  for (std::uint32_t f = 0; f < complex.count(k); ++f) {
    for_each_simplex(complex, k, f, [&](std::span<const std::uint32_t> v, int sign) {
      for (int j = 0; j < n; ++j) {
        q[j] = base + static_cast<std::size_t>(n) * v[j];
        for (int i = 0; i < n; ++i) y(i, j) = q[j][i] - a(i);
      }
      counter.add(q, sign);
      const double det = sign * y.determinant();
      if (det == 0.0) return;
      s = y.rowwise().sum();
      total += det;
      first += det * s;
      second.noalias() += det * y * y.transpose();
      second.noalias() += det * s * s.transpose();
    });
    sums.boundary += facet_area_vector(complex, f, scale).norm();
  }
  const double nf = factorial(n);
  sums.volume = total / nf;
  first /= nf * (n + 1);
  second /= nf * (n + 1) * (n + 2);
  sums.first = first;
  sums.second = second;
  return sums;
}

}  // namespace

MassProperties mass_properties(const Complex& complex) {
  check_input(complex);
  const int n = complex.ambient_dim();
  const int k = n - 1;
  const double scale = position_scale(complex);
  const int e = std::ilogb(scale);  // scale = 2^e exactly
  const Eigen::MatrixXd sp = scale * complex.positions();
  const Eigen::VectorXd apex = sp.rowwise().mean();

  WindingCounter counter(n, winding_probes(complex, scale, apex));
  // Fixed sizes up to R^4 take Eigen's closed-form determinants (exact for small integer
  // coordinates, as signed_volume); larger ones an LU on the stack up to R^8.
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 8, 8>;
  const Sums sums = n == 2   ? integrate<Eigen::Matrix2d>(complex, scale, sp, apex, counter)
                    : n == 3 ? integrate<Eigen::Matrix3d>(complex, scale, sp, apex, counter)
                    : n == 4 ? integrate<Eigen::Matrix4d>(complex, scale, sp, apex, counter)
                    : n <= 8 ? integrate<Small>(complex, scale, sp, apex, counter)
                             : integrate<Eigen::MatrixXd>(complex, scale, sp, apex, counter);
  const double volume = sums.volume, boundary = sums.boundary;
  const Eigen::VectorXd& first = sums.first;
  const Eigen::MatrixXd& second = sums.second;
  if (!std::isfinite(volume) || !first.allFinite() || !second.allFinite())
    throw InputError("the mass properties are beyond the range of a double");
  if (volume == 0.0) throw InputError("the model encloses no volume: it has no centroid");

  MassProperties m;
  m.dim = n;
  // Back from the scaled coordinates (x = x_scaled / 2^e): exact powers of two.
  const Eigen::VectorXd c = apex + first / volume;
  m.hypervolume = std::ldexp(volume, -n * e);
  m.boundary_volume = std::ldexp(boundary, -k * e);
  m.centroid = c.unaryExpr([e](double x) { return std::ldexp(x, -e); });
  const Eigen::MatrixXd about_origin = second + first * apex.transpose() +
                                       apex * first.transpose() + volume * apex * apex.transpose();
  m.second_moment =
      about_origin.unaryExpr([n, e](double x) { return std::ldexp(x, -(n + 2) * e); });
  m.second_moment = 0.5 * (m.second_moment + m.second_moment.transpose()).eval();
  if (!std::isfinite(m.hypervolume) || !std::isfinite(m.boundary_volume) ||
      !m.centroid.allFinite() || !m.second_moment.allFinite())
    throw InputError("the mass properties are beyond the range of a double");
  for (int w : counter.counts())
    if (w != 0 && w != 1) m.winding_weighted = true;
  return m;
}

}  // namespace cw4d
