#include "cw4d/complex/geometry.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <vector>

namespace cw4d {

namespace {

bool contains_vertex(const Complex& c, int rank, std::uint32_t i, std::uint32_t v) {
  if (rank == 0) return i == v;
  if (rank == 1) {
    const auto e = c.edge(i);
    return e[0] == v || e[1] == v;
  }
  const auto face_has = [&](std::uint32_t f) {
    for (auto id : c.boundary(2).ids(f)) {
      const auto e = c.edge(id);
      if (e[0] == v || e[1] == v) return true;
    }
    return false;
  };
  if (rank == 2) return face_has(i);
  // Higher ranks: a search down to the faces that visits each element once. Recursing into
  // every boundary element instead would reach each face once per chain to it, exponentially
  // often in the rank (a 9-cube has 9! 2^9 flags but 512 vertices).
  thread_local std::vector<std::vector<std::uint32_t>> seen;  // generation stamps per rank
  thread_local std::uint32_t generation = 0;
  thread_local std::vector<std::pair<int, std::uint32_t>> stack;
  if (static_cast<int>(seen.size()) <= rank) seen.resize(static_cast<std::size_t>(rank) + 1);
  if (++generation == 0) {
    for (auto& s : seen) std::fill(s.begin(), s.end(), 0u);
    generation = 1;
  }
  stack.assign(1, {rank, i});
  while (!stack.empty()) {
    const auto [k, x] = stack.back();
    stack.pop_back();
    for (auto id : c.boundary(k).ids(x)) {
      if (k - 1 == 2) {
        if (face_has(id)) return true;
        continue;
      }
      auto& stamps = seen[static_cast<std::size_t>(k - 1)];
      if (stamps.size() < c.count(k - 1)) stamps.resize(c.count(k - 1), 0u);
      if (stamps[id] == generation) continue;
      stamps[id] = generation;
      stack.push_back({k - 1, id});
    }
  }
  return false;
}

// Emits prefix + the simplices of element i. `prefix` holds the apexes of the enclosing cones
// (outermost first), `scratch` is reused for face cycles; nothing is allocated per simplex.
struct SimplexWalker {
  const Complex& c;
  const std::function<void(std::span<const std::uint32_t>, int)>& f;
  std::vector<std::uint32_t> prefix;
  std::vector<std::uint32_t> cycle;

  void emit(std::initializer_list<std::uint32_t> tail, int sign) {
    const std::size_t base = prefix.size();
    prefix.insert(prefix.end(), tail);
    f(prefix, sign);
    prefix.resize(base);
  }

  void walk(int rank, std::uint32_t i, int sign) {
    if (rank == 1) {
      const auto e = c.edge(i);
      emit({e[0], e[1]}, sign);
      return;
    }
    if (rank == 2) {
      const Incidence& faces = c.boundary(2);
      auto ids = faces.ids(i);
      auto signs = faces.signs(i);
      cycle.clear();
      for (std::size_t k = 0; k < ids.size(); ++k) {
        const auto e = c.edge(ids[k]);
        cycle.push_back(signs[k] > 0 ? e[0] : e[1]);
      }
      for (std::size_t k = 1; k + 1 < cycle.size(); ++k)
        emit({cycle[0], cycle[k], cycle[k + 1]}, sign);
      return;
    }
    const std::uint32_t apex = c.first_vertex(rank, i);
    const Incidence& table = c.boundary(rank);
    auto ids = table.ids(i);
    auto signs = table.signs(i);
    prefix.push_back(apex);
    for (std::size_t j = 0; j < ids.size(); ++j) {
      // A cone from the apex over a boundary element that contains the apex is flat: skip it
      // whole (checking only the sub-simplices would keep flat slivers of rounding noise).
      if (contains_vertex(c, rank - 1, ids[j], apex)) continue;
      walk(rank - 1, ids[j], sign * signs[j]);
    }
    prefix.pop_back();
  }
};

// det of an n x n matrix: Eigen's closed forms for n <= 4 and its partial-pivoting LU at a
// fixed size up to 8, on the stack; only larger ones allocate.
template <int N>
double det_fixed(const Eigen::MatrixXd& m) {
  return Eigen::Matrix<double, N, N>(m).determinant();
}

double det(const Eigen::MatrixXd& m) {
  switch (m.rows()) {
    case 1:
      return m(0, 0);
    case 2:
      return det_fixed<2>(m);
    case 3:
      return det_fixed<3>(m);
    case 4:
      return det_fixed<4>(m);
    case 5:
      return det_fixed<5>(m);
    case 6:
      return det_fixed<6>(m);
    case 7:
      return det_fixed<7>(m);
    case 8:
      return det_fixed<8>(m);
    default:
      return m.determinant();
  }
}

// generalized_cross into x, with m an n x n work matrix (nothing allocated when both have
// their sizes already).
void generalized_cross_into(const Eigen::MatrixXd& u, Eigen::MatrixXd& m, Eigen::VectorXd& x) {
  const Eigen::Index n = u.rows();
  x.resize(n);
  m.resize(n, n);
  m.leftCols(n - 1) = u;
  for (Eigen::Index j = 0; j < n; ++j) {
    m.col(n - 1).setZero();
    m(j, n - 1) = 1.0;
    x(j) = det(m);
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
  SimplexWalker walker{complex, f, {}, {}};
  walker.walk(rank, i, 1);
}

Eigen::VectorXd generalized_cross(const Eigen::MatrixXd& u) {
  Eigen::MatrixXd m;
  Eigen::VectorXd x;
  generalized_cross_into(u, m, x);
  return x;
}

double position_scale(const Complex& complex) {
  const auto& p = complex.positions();
  double big = 0.0;
  for (Eigen::Index i = 0; i < p.size(); ++i)
    if (std::isfinite(p.data()[i])) big = std::max(big, std::abs(p.data()[i]));
  if (big == 0.0 || (big >= 0x1p-60 && big <= 0x1p60)) return 1.0;
  return std::ldexp(1.0, std::min(-std::ilogb(big), 1000));  // 2^1000: finite
}

Eigen::VectorXd facet_area_vector(const Complex& complex, std::uint32_t facet, double scale) {
  const int n = complex.ambient_dim();
  const int k = n - 1;
  Eigen::VectorXd sum = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd u(n, k), m(n, n);
  Eigen::VectorXd x(n);
  const auto& p = complex.positions();
  for_each_simplex(complex, k, facet, [&](std::span<const std::uint32_t> v, int sign) {
    for (int j = 0; j < k; ++j) u.col(j) = scale * p.col(v[j + 1]) - scale * p.col(v[0]);
    generalized_cross_into(u, m, x);
    sum += static_cast<double>(sign) * x;
  });
  const double parity = (k % 2 == 0) ? 1.0 : -1.0;
  return parity * sum / factorial(k);
}

double signed_volume(const Complex& complex, double scale, double* magnitude) {
  const int n = complex.ambient_dim();
  const int k = n - 1;
  if (complex.count(k) == 0 || k < 1) return 0.0;
  const auto& p = complex.positions();
  const Eigen::VectorXd c = (scale * p).rowwise().mean();
  Eigen::MatrixXd m(n, n);
  double total = 0.0, absolute = 0.0;
  for (std::uint32_t f = 0; f < complex.count(k); ++f) {
    for_each_simplex(complex, k, f, [&](std::span<const std::uint32_t> v, int sign) {
      for (int j = 0; j < n; ++j) m.col(j) = scale * p.col(v[j]) - c;
      const double d = det(m);
      total += sign * d;
      absolute += std::abs(d);
    });
  }
  if (magnitude) *magnitude = absolute / factorial(n);
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
