#include "cw4d/complex/geometry.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <unordered_map>
#include <vector>

#include "cone_determinants.hpp"

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
// (outermost first), `cycle` is reused for face cycles; nothing is allocated per simplex.
struct SimplexWalker {
  const Complex& c;
  const std::function<void(std::span<const std::uint32_t>, int)>& f;
  int top;  // the rank of the element decomposed
  std::vector<std::uint32_t> prefix;
  std::vector<std::uint32_t> cycle;
  std::unordered_map<std::uint64_t, std::size_t> kept;  // (rank, element) -> offset in flags
  std::vector<std::uint8_t> flags;                      // 1: cone over this boundary entry

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
    // A cone from the apex over a boundary element that contains the apex is flat: skip it
    // whole (checking only the sub-simplices would keep flat slivers of rounding noise). The
    // apex is a function of the element, so which ones are skipped is too: below the top,
    // where one element is reached along many cones (an n-cube's ridges along (n-1)! of
    // them), the decisions are made once per element.
    // (flags grows in the walks below: indexed, not pointed into)
    std::size_t keep = flags.size();
    const bool memo = rank < top;
    if (memo) {
      const std::uint64_t key = (std::uint64_t{static_cast<std::uint32_t>(rank)} << 32) | i;
      const auto [it, fresh] = kept.try_emplace(key, flags.size());
      if (fresh)
        for (auto id : ids) flags.push_back(contains_vertex(c, rank - 1, id, apex) ? 0 : 1);
      keep = it->second;
    }
    prefix.push_back(apex);
    for (std::size_t j = 0; j < ids.size(); ++j) {
      if (memo ? !flags[keep + j] : contains_vertex(c, rank - 1, ids[j], apex)) continue;
      walk(rank - 1, ids[j], sign * signs[j]);
    }
    prefix.pop_back();
  }
};

// Dense kernels on column-major arrays (entry (i, j) of an n-row matrix at a[i + n * j]):
// simplices of a triangulation are measured by the ten thousand (the facets of an 8-cube have
// 80640), so each measure is one factorisation with no Eigen temporary, no allocation and no
// per-entry check.

// Storage for one n x n matrix, a permutation and two vectors: on the stack up to 8 x 8.
class Workspace {
  static constexpr int small = 8;
  double small_a_[small * small];
  double small_z_[small];
  double small_x_[small];
  int small_perm_[small];
  std::vector<double> big_a_, big_z_, big_x_;
  std::vector<int> big_perm_;

 public:
  double* a = small_a_;
  double* z = small_z_;
  double* x = small_x_;
  int* perm = small_perm_;

  explicit Workspace(int n) {
    if (n > small) {
      const auto size = static_cast<std::size_t>(n);
      big_a_.resize(size * size);
      big_z_.resize(size);
      big_x_.resize(size);
      big_perm_.resize(size);
      a = big_a_.data();
      z = big_z_.data();
      x = big_x_.data();
      perm = big_perm_.data();
    }
  }
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;
};

// Eliminates columns 0..cols-1 of the n-row matrix a in place with partial (row) pivoting,
// P a = L U: U on and above the diagonal, L's multipliers below it, perm[i] the original row
// now at row i. Returns sign(P) times the product of U's diagonal, or 0 (and stops) at a column
// with no non-zero pivot left: a is then of rank below cols.
double eliminate(double* a, int n, int cols, int* perm) {
  double d = 1.0;
  for (int i = 0; i < n; ++i) perm[i] = i;
  for (int j = 0; j < cols; ++j) {
    double* cj = a + n * j;
    int p = j;
    double best = std::abs(cj[j]);
    for (int i = j + 1; i < n; ++i) {
      if (std::abs(cj[i]) > best) {
        best = std::abs(cj[i]);
        p = i;
      }
    }
    if (best == 0.0) return 0.0;
    if (p != j) {
      for (int c = 0; c < cols; ++c) std::swap(a[p + n * c], a[j + n * c]);
      std::swap(perm[p], perm[j]);
      d = -d;
    }
    const double pivot = cj[j];
    d *= pivot;
    for (int i = j + 1; i < n; ++i) {
      const double l = cj[i] / pivot;
      cj[i] = l;
      for (int c = j + 1; c < cols; ++c) a[i + n * c] -= l * a[j + n * c];
    }
  }
  return d;
}

// Eigen's closed form of an N x N determinant (N <= 4).
template <int N>
double det_closed(const double* a) {
  return Eigen::Map<const Eigen::Matrix<double, N, N>>(a).determinant();
}

// det of the n x n matrix in w.a (overwritten): Eigen's closed forms up to 4 x 4, one
// elimination above.
double det_in_place(Workspace& w, int n) {
  switch (n) {
    case 1:
      return w.a[0];
    case 2:
      return det_closed<2>(w.a);
    case 3:
      return det_closed<3>(w.a);
    case 4:
      return det_closed<4>(w.a);
    default:
      return eliminate(w.a, n, n, w.perm);
  }
}

// The generalized cross product x of the n x (n-1) matrix u in w.a (overwritten), with
// x . y = det(u, y) for every y, from one factorisation P u = L U instead of n cofactors:
// [P u | e_n] = [L | e_n] [U 0; 0 1], so det(u, y) = sign(P) prod(U) (z . P y) with z the
// solution of [L | e_n]^T z = e_n (one back substitution), and x = sign(P) prod(U) P^T z.
// A u of rank below n-1 gives x = 0, as every cofactor is then 0. Up to R^4 the n cofactors
// are Eigen's closed forms (as cheap, and the results of R^3 and R^4 stay as they were).
void cross_in_place(Workspace& w, int n, double* x) {
  const int k = n - 1;
  if (n <= 4) {
    double* last = w.a + n * k;
    for (int j = 0; j < n; ++j) {
      std::fill(last, last + n, 0.0);
      last[j] = 1.0;
      x[j] = det_in_place(w, n);
    }
    return;
  }
  const double d = eliminate(w.a, n, k, w.perm);
  if (d == 0.0) {
    std::fill(x, x + n, 0.0);
    return;
  }
  double* z = w.z;
  z[n - 1] = 1.0;
  for (int m = k - 1; m >= 0; --m) {
    const double* lm = w.a + n * m;
    double s = 0.0;
    for (int r = m + 1; r < n; ++r) s += lm[r] * z[r];
    z[m] = -s;
  }
  for (int i = 0; i < n; ++i) x[w.perm[i]] = d * z[i];
}

double factorial(int k) {
  double r = 1;
  for (int i = 2; i <= k; ++i) r *= i;
  return r;
}

}  // namespace

void for_each_simplex(const Complex& complex, int rank, std::uint32_t i,
                      const std::function<void(std::span<const std::uint32_t>, int)>& f) {
  SimplexWalker walker{complex, f, rank, {}, {}, {}, {}};
  walker.walk(rank, i, 1);
}

Eigen::VectorXd generalized_cross(const Eigen::MatrixXd& u) {
  const int n = static_cast<int>(u.rows());
  assert(u.cols() == n - 1);
  Workspace w(n);
  std::copy(u.data(), u.data() + u.size(), w.a);
  Eigen::VectorXd x(n);
  cross_in_place(w, n, x.data());
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
  double* s = sum.data();
  Workspace w(n);
  const double* p = complex.positions().data();
  for_each_simplex(complex, k, facet, [&](std::span<const std::uint32_t> v, int sign) {
    const double* p0 = p + static_cast<std::size_t>(n) * v[0];
    for (int j = 0; j < k; ++j) {
      const double* pj = p + static_cast<std::size_t>(n) * v[j + 1];
      for (int i = 0; i < n; ++i) w.a[i + n * j] = scale * pj[i] - scale * p0[i];
    }
    cross_in_place(w, n, w.x);
    for (int i = 0; i < n; ++i) s[i] += static_cast<double>(sign) * w.x[i];
  });
  const double parity = (k % 2 == 0) ? 1.0 : -1.0;
  return parity * sum / factorial(k);
}

namespace {

// Sum (and sum of magnitudes) of det(scale p_0 - centre, ..., scale p_{n-1} - centre) over the
// simplices of facet f.
void add_cone_determinants(const Complex& complex, std::uint32_t f, const double* centre,
                           double scale, Workspace& w, double& total, double& absolute) {
  const int n = complex.ambient_dim();
  const double* p = complex.positions().data();
  for_each_simplex(complex, n - 1, f, [&](std::span<const std::uint32_t> v, int sign) {
    for (int j = 0; j < n; ++j) {
      const double* pj = p + static_cast<std::size_t>(n) * v[j];
      for (int i = 0; i < n; ++i) w.a[i + n * j] = scale * pj[i] - centre[i];
    }
    const double d = det_in_place(w, n);
    total += sign * d;
    absolute += std::abs(d);
  });
}

}  // namespace

double signed_volume(const Complex& complex, double scale, double* magnitude) {
  const int n = complex.ambient_dim();
  const int k = n - 1;
  if (complex.count(k) == 0 || k < 1) return 0.0;
  const Eigen::VectorXd c = (scale * complex.positions()).rowwise().mean();
  Workspace w(n);
  double total = 0.0, absolute = 0.0;
  for (std::uint32_t f = 0; f < complex.count(k); ++f)
    add_cone_determinants(complex, f, c.data(), scale, w, total, absolute);
  if (magnitude) *magnitude = absolute / factorial(n);
  return total / factorial(n);
}

double facet_cone_determinants(const Complex& complex, std::span<const std::uint32_t> facets,
                               const Eigen::VectorXd& centre, double scale) {
  const int n = complex.ambient_dim();
  if (n < 2) return 0.0;
  Workspace w(n);
  double total = 0.0, absolute = 0.0;
  for (auto f : facets) add_cone_determinants(complex, f, centre.data(), scale, w, total, absolute);
  return total;
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
