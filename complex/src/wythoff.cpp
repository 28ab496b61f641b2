#include "cw4d/complex/wythoff.hpp"

#include "cw4d/complex/tolerances.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <numeric>
#include <optional>
#include <unordered_map>
#include <unordered_set>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/complex/validate.hpp"

namespace cw4d {

namespace {

constexpr int kMaxRank = 10;
constexpr int kMaxLabel = 10000;
constexpr std::size_t kMaxVertices = 2000000;
constexpr double kSameVertexRel = tol::wythoff_same_vertex_rel;
// Grid cell of the point hash; a point within kSameVertexRel of a cell border is also looked up
// in the neighbouring cell.
constexpr double kHashCellRel = 1e-5;
constexpr double kPositiveDefiniteMin = tol::wythoff_positive_definite_min;

using VertexList = std::vector<std::uint32_t>;

std::string quoted(std::string_view text) {
  return "Coxeter diagram " + quote_user_text(std::string(text));
}

std::string label_text(const CoxeterDiagram& d, std::size_t i) {
  std::string out = std::to_string(d.labels[i]);
  if (d.denominator(i) != 1) out += "/" + std::to_string(d.denominator(i));
  return out;
}

std::string to_text(const CoxeterDiagram& d) {
  std::string out;
  for (int i = 0; i < d.rank(); ++i) {
    if (i > 0) out += i - 1 < static_cast<int>(d.labels.size()) ? label_text(d, i - 1) : "?";
    out += d.ringed[i] ? 'x' : 'o';
  }
  return out;
}

bool is_star(const CoxeterDiagram& d) {
  for (std::size_t i = 0; i < d.labels.size(); ++i)
    if (d.denominator(i) != 1) return true;
  return false;
}

void check_shape(const CoxeterDiagram& d) {
  const std::string name = quoted(to_text(d));
  if (d.rank() < 2 || d.rank() > kMaxRank)
    throw InputError(name + " has " + std::to_string(d.rank()) + " nodes; 2 to " +
                     std::to_string(kMaxRank) + " are supported");
  if (d.labels.size() + 1 != d.ringed.size())
    throw InputError(name + ": expected " + std::to_string(d.ringed.size() - 1) +
                     " branch labels, got " + std::to_string(d.labels.size()));
  for (int label : d.labels)
    if (label < 2 || label > kMaxLabel)
      throw InputError(name + ": branch label " + std::to_string(label) + " is outside 2.." +
                       std::to_string(kMaxLabel));
  if (!d.denominators.empty() && d.denominators.size() != d.labels.size())
    throw InputError(name + ": expected " + std::to_string(d.labels.size()) +
                     " denominators, got " + std::to_string(d.denominators.size()));
  for (std::size_t i = 0; i < d.denominators.size(); ++i) {
    const int p = d.labels[i], q = d.denominators[i];
    if (q == 1) continue;
    if (q < 1 || q >= p || std::gcd(p, q) != 1)
      throw InputError(name + ": branch mark " + std::to_string(p) + "/" + std::to_string(q) +
                       " must be a fraction p/q in lowest terms with 1 <= q < p");
  }
}

// m(i, j): order of s_i s_j (1 on the diagonal, 2 for nodes that are not joined).
Eigen::MatrixXi coxeter_matrix(const CoxeterDiagram& d) {
  const int n = d.rank();
  Eigen::MatrixXi m = Eigen::MatrixXi::Constant(n, n, 2);
  for (int i = 0; i < n; ++i) m(i, i) = 1;
  for (int i = 0; i + 1 < n; ++i) m(i, i + 1) = m(i + 1, i) = d.labels[i];
  return m;
}

// True when every connected component of the diagram restricted to the nodes in `mask` holds a
// ringed node, i.e. the orbit of the base point under those generators is full-dimensional.
bool every_component_ringed(const Eigen::MatrixXi& m, const std::vector<bool>& ringed,
                            unsigned mask) {
  const int n = static_cast<int>(ringed.size());
  unsigned unseen = mask;
  while (unseen != 0) {
    const int start = std::countr_zero(unseen);
    unsigned component = 1u << start, frontier = component;
    while (frontier != 0) {
      const int i = std::countr_zero(frontier);
      frontier &= frontier - 1;
      for (int j = 0; j < n; ++j) {
        const unsigned bit = 1u << j;
        if ((mask & bit) && !(component & bit) && m(i, j) > 2) {
          component |= bit;
          frontier |= bit;
        }
      }
    }
    bool has_ring = false;
    for (int i = 0; i < n; ++i) has_ring = has_ring || ((component >> i & 1u) && ringed[i]);
    if (!has_ring) return false;
    unseen &= ~component;
  }
  return true;
}

// Unit simple roots as the rows of the Cholesky factor L of the Gram matrix (a_i . a_j = G_ij);
// the mirrors of the nodes joined by the mark p/q meet at the angle pi q / p.
Eigen::MatrixXd simple_roots(const CoxeterDiagram& d, const std::string& name) {
  const Eigen::Index n = d.rank();
  Eigen::MatrixXd gram = Eigen::MatrixXd::Identity(n, n);
  for (Eigen::Index i = 0; i + 1 < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (d.labels[k] == 2) continue;
    gram(i, i + 1) = gram(i + 1, i) =
        -std::cos(std::numbers::pi * d.denominator(k) / static_cast<double>(d.labels[k]));
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram, Eigen::EigenvaluesOnly);
  Eigen::LLT<Eigen::MatrixXd> llt(gram);
  if (eigen.eigenvalues().minCoeff() <= kPositiveDefiniteMin || llt.info() != Eigen::Success)
    throw InputError(name + (is_star(d) ? " is not a spherical Schwarz triangle or Goursat "
                                          "simplex (the Gram matrix of its mirrors is not "
                                          "positive definite)"
                                        : " generates an infinite Coxeter group (the Gram "
                                          "matrix of its simple roots is not positive "
                                          "definite); only finite groups give polytopes"));
  return llt.matrixL();
}

// Point p with p . a_i = 1 on ringed nodes and 0 on the others: reflecting it in a ringed
// mirror moves it by 2 a_i, so every edge has length 2.
Eigen::VectorXd base_point(const Eigen::MatrixXd& roots, const std::vector<bool>& ringed) {
  Eigen::VectorXd rhs(roots.rows());
  for (Eigen::Index i = 0; i < rhs.size(); ++i) rhs(i) = ringed[i] ? 1.0 : 0.0;
  return roots.triangularView<Eigen::Lower>().solve(rhs);
}

// Hash of points on a grid; a lookup also visits the neighbouring cell of every coordinate that
// lies near a cell border, so equal points (up to rounding) are always found.
class PointIndex {
 public:
  PointIndex(int dim, double scale)
      : dim_(dim), cell_(kHashCellRel * scale), same_(kSameVertexRel * scale) {}

  // Id of the stored point within the tolerance of x, or no_index.
  std::uint32_t find(const double* x, const std::vector<double>& coords) const {
    std::vector<std::int64_t> cell(dim_), other(dim_);
    unsigned border = 0;
    for (int i = 0; i < dim_; ++i) {
      const double q = x[i] / cell_;
      cell[i] = std::llround(q);
      const double frac = q - static_cast<double>(cell[i]);
      other[i] = cell[i] + (frac < 0 ? -1 : 1);
      if (std::abs(frac) > 0.5 - 2.0 * kSameVertexRel / kHashCellRel) border |= 1u << i;
    }
    // Visit every combination of (own cell, neighbour) over the border coordinates.
    for (unsigned sub = border;; sub = (sub - 1) & border) {
      std::vector<std::int64_t> key = cell;
      for (int i = 0; i < dim_; ++i)
        if (sub >> i & 1u) key[i] = other[i];
      auto [lo, hi] = map_.equal_range(hash(key));
      for (auto it = lo; it != hi; ++it) {
        const double* y = coords.data() + static_cast<std::size_t>(it->second) * dim_;
        double dist = 0.0;
        for (int i = 0; i < dim_; ++i) dist = std::max(dist, std::abs(x[i] - y[i]));
        if (dist <= same_) return it->second;
      }
      if (sub == 0) break;
    }
    return no_index;
  }

  void insert(const double* x, std::uint32_t id) {
    std::vector<std::int64_t> key(dim_);
    for (int i = 0; i < dim_; ++i) key[i] = std::llround(x[i] / cell_);
    map_.emplace(hash(key), id);
  }

 private:
  static std::uint64_t hash(const std::vector<std::int64_t>& key) {
    std::uint64_t h = 0x9E3779B97F4A7C15ull;
    for (auto k : key) {
      h ^= static_cast<std::uint64_t>(k) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
      h *= 0xBF58476D1CE4E5B9ull;
    }
    return h ^ (h >> 31);
  }

  int dim_;
  double cell_, same_;
  std::unordered_multimap<std::uint64_t, std::uint32_t> map_;
};

// The vertices (orbit of the base point) and the permutation each generator induces on them.
struct Orbit {
  Eigen::MatrixXd positions;                     // n x V, vertex 0 = base point
  std::vector<std::vector<std::uint32_t>> perm;  // perm[g][v]: image of vertex v under s_g
  std::size_t size() const { return static_cast<std::size_t>(positions.cols()); }
};

Orbit vertex_orbit(const Eigen::MatrixXd& roots, const Eigen::VectorXd& base,
                   const std::string& name) {
  const int n = static_cast<int>(roots.rows());
  PointIndex index(n, base.norm());
  std::vector<double> coords(base.data(), base.data() + n);
  index.insert(coords.data(), 0);
  Orbit orbit;
  orbit.perm.resize(n);
  std::vector<double> image(n);
  for (std::uint32_t v = 0; v < coords.size() / n; ++v) {
    for (int g = 0; g < n; ++g) {
      const double* x = coords.data() + static_cast<std::size_t>(v) * n;
      double dot = 0.0;
      for (int i = 0; i < n; ++i) dot += x[i] * roots(g, i);
      for (int i = 0; i < n; ++i) image[i] = x[i] - 2.0 * dot * roots(g, i);
      std::uint32_t id = index.find(image.data(), coords);
      if (id == no_index) {
        id = static_cast<std::uint32_t>(coords.size() / n);
        if (id >= kMaxVertices)
          throw InputError(name + " has more than " + std::to_string(kMaxVertices) + " vertices");
        coords.insert(coords.end(), image.begin(), image.end());
        index.insert(image.data(), id);
      }
      orbit.perm[g].push_back(id);
    }
  }
  orbit.positions = Eigen::Map<const Eigen::MatrixXd>(coords.data(), n,
                                                      static_cast<Eigen::Index>(coords.size() / n));
  return orbit;
}

std::vector<int> nodes_of(unsigned mask) {
  std::vector<int> out;
  for (; mask != 0; mask &= mask - 1) out.push_back(std::countr_zero(mask));
  return out;
}

// Vertices of the polygon of generators s, t through the base point, in cycle order: the points
// w p for the chambers w = 1, s, st, sts, ... around the common wall (m = order of st), with
// repeats dropped where the newly appended generator fixes p.
VertexList base_polygon(const Orbit& orbit, int s, int t, int m) {
  VertexList cycle;
  for (int k = 0; k < 2 * m; ++k) {
    std::uint32_t v = 0;
    for (int i = k; i >= 1; --i) v = orbit.perm[i % 2 == 1 ? s : t][v];
    if (cycle.empty() || cycle.back() != v) cycle.push_back(v);
  }
  if (cycle.size() > 1 && cycle.back() == cycle.front()) cycle.pop_back();
  return cycle;
}

// Sorted vertices of the orbit of the base point under the given generators.
VertexList base_face(const Orbit& orbit, const std::vector<int>& gens) {
  VertexList out{0};
  std::unordered_set<std::uint32_t> seen{0};
  for (std::size_t i = 0; i < out.size(); ++i)
    for (int g : gens) {
      const std::uint32_t w = orbit.perm[g][out[i]];
      if (seen.insert(w).second) out.push_back(w);
    }
  std::sort(out.begin(), out.end());
  return out;
}

struct VertexListHash {
  std::size_t operator()(const VertexList& v) const {
    std::uint64_t h = 0xcbf29ce484222325ull;
    for (auto x : v) h = (h ^ x) * 0x100000001b3ull;
    return static_cast<std::size_t>(h ^ (h >> 29));
  }
};
using FaceIndex = std::unordered_map<VertexList, std::uint32_t, VertexListHash>;

// Unit normals of the mirrors of the group generated by the reflections `gens` (one per mirror,
// the sign fixed by a generic direction): the orbit of the simple roots. nullopt when there are
// more than `cap`, i.e. the group is infinite.
std::optional<std::vector<Eigen::VectorXd>> mirror_normals(const Eigen::MatrixXd& roots,
                                                           const std::vector<int>& gens,
                                                           std::size_t cap) {
  const int n = static_cast<int>(roots.rows());
  Eigen::VectorXd generic(n);
  for (int i = 0; i < n; ++i) generic(i) = 1.0 / std::sqrt(2.0 + 1.618033988749895 * i);
  PointIndex index(n, 1.0);
  std::vector<double> coords;
  std::vector<Eigen::VectorXd> out;
  auto add = [&](Eigen::VectorXd r) {
    if (r.dot(generic) < 0) r = -r;
    if (index.find(r.data(), coords) != no_index) return;
    index.insert(r.data(), static_cast<std::uint32_t>(out.size()));
    coords.insert(coords.end(), r.data(), r.data() + n);
    out.push_back(std::move(r));
  };
  for (int g : gens) add(roots.row(g).transpose());
  for (std::size_t i = 0; i < out.size() && out.size() <= cap; ++i)
    for (int g : gens) {
      const Eigen::VectorXd a = roots.row(g).transpose();
      add(out[i] - 2.0 * out[i].dot(a) * a);
    }
  if (out.size() > cap) return std::nullopt;
  return out;
}

// Order of an irreducible finite reflection group of rank r with `mirrors` reflections (the
// classification, e.g. J. E. Humphreys, "Reflection Groups and Coxeter Groups" (1990), 2.11 and
// 3.18: A_r, B_r, D_r, E_6..8, F_4, H_3, H_4, I_2(p)). Only B_6 and E_6 share (r, mirrors); E_6
// is simply laced. nullopt for a pair no finite group has.
std::optional<double> irreducible_order(int r, std::size_t mirrors, bool simply_laced) {
  double factorial = 1.0;  // r!
  for (int i = 2; i <= r; ++i) factorial *= i;
  const auto N = static_cast<double>(mirrors);
  if (r == 1) return mirrors == 1 ? std::optional<double>(2.0) : std::nullopt;
  if (r == 2) return 2.0 * N;
  if (r == 6 && mirrors == 36) return simply_laced ? 51840.0 : 46080.0;
  if (N == r * (r + 1) / 2.0) return factorial * (r + 1);             // A_r
  if (N == r * r) return factorial * std::ldexp(1.0, r);              // B_r
  if (N == r * (r - 1.0)) return factorial * std::ldexp(1.0, r - 1);  // D_r (r >= 4)
  if (r == 3 && mirrors == 15) return 120.0;                          // H_3
  if (r == 4 && mirrors == 24) return 1152.0;                         // F_4
  if (r == 4 && mirrors == 60) return 14400.0;                        // H_4
  if (r == 7 && mirrors == 63) return 2903040.0;                      // E_7
  if (r == 8 && mirrors == 120) return 696729600.0;                   // E_8
  return std::nullopt;
}

// Order of the group generated by the reflections in `gens`: its mirrors fall into mutually
// orthogonal irreducible systems, each known by its rank and number of mirrors. nullopt when
// the group is infinite (more than `cap` mirrors) or unknown.
std::optional<double> group_order(const Eigen::MatrixXd& roots, const std::vector<int>& gens,
                                  std::size_t cap) {
  if (gens.empty()) return 1.0;
  if (gens.size() == 1) return 2.0;
  const auto mirrors = mirror_normals(roots, gens, cap);
  if (!mirrors) return std::nullopt;
  const std::size_t count = mirrors->size();
  const double orthogonal = 1e-9;
  std::vector<int> component(count, -1);
  double order = 1.0;
  for (std::size_t s = 0; s < count; ++s) {
    if (component[s] >= 0) continue;
    component[s] = static_cast<int>(s);
    std::vector<std::size_t> members{s};
    bool simply_laced = true;
    for (std::size_t i = 0; i < members.size(); ++i)
      for (std::size_t j = 0; j < count; ++j) {
        const double c = std::abs((*mirrors)[members[i]].dot((*mirrors)[j]));
        if (j == members[i] || c <= orthogonal) continue;
        if (std::abs(c - 0.5) > orthogonal) simply_laced = false;
        if (component[j] < 0) {
          component[j] = static_cast<int>(s);
          members.push_back(j);
        }
      }
    Eigen::MatrixXd span(roots.cols(), static_cast<Eigen::Index>(members.size()));
    for (std::size_t i = 0; i < members.size(); ++i)
      span.col(static_cast<Eigen::Index>(i)) = (*mirrors)[members[i]];
    Eigen::FullPivLU<Eigen::MatrixXd> lu(span);
    lu.setThreshold(1e-9);
    const auto part = irreducible_order(static_cast<int>(lu.rank()), members.size(), simply_laced);
    if (!part) return std::nullopt;
    order *= *part;
  }
  return order;
}

// The f-vector and orientation work of the polytope, from group orders alone (no element is
// built). The k-faces of a Wythoffian polytope are the cosets w W_{J+K} for the k-sets J of
// nodes whose every component holds a ring, K the unringed nodes outside J joined to none of
// J (W_{J+K} fixes the face of J through the base point); M. Champagne, M. Kjiri, J. Patera,
// R. T. Sharp, "Description of reflection-generated polytopes using decorated Coxeter
// diagrams" (1995). Each face is itself the uniform polytope of its sub-diagram, transitive on
// its vertices, so the simplices orientation_work counts for it (a fan from any vertex over the
// facets that miss it) depend on its type only: w(J) = sum over the facet types J' of J of
// (their number) * (the share missing a vertex, 1 - V(J')/V(J)) * w(J').
std::optional<WythoffSize> estimate(const CoxeterDiagram& d, const Eigen::MatrixXi& m,
                                    const Eigen::MatrixXd& roots) {
  const int n = d.rank();
  std::size_t cap = 120 + static_cast<std::size_t>(n * n);
  for (int label : d.labels) cap += static_cast<std::size_t>(label);
  // |W_J| is the product over J's runs of joined nodes (generators of different runs commute).
  std::unordered_map<unsigned, double> run_order;
  auto order = [&](unsigned mask) -> std::optional<double> {
    double out = 1.0;
    for (int i = 0; i < n;) {
      if (!(mask >> i & 1u)) {
        ++i;
        continue;
      }
      int j = i;
      while (j + 1 < n && (mask >> (j + 1) & 1u) && m(j, j + 1) > 2) ++j;
      const unsigned run = ((2u << j) - 1) & ~((1u << i) - 1);
      auto it = run_order.find(run);
      if (j == i + 1) {
        out *= 2.0 * m(i, j);  // I_2(p), also for a mark p/q (the same mirrors)
        i = j + 1;
        continue;
      }
      if (it == run_order.end()) {
        const auto o = group_order(roots, nodes_of(run), cap);
        if (!o) return std::nullopt;
        it = run_order.emplace(run, *o).first;
      }
      out *= it->second;
      i = j + 1;
    }
    return out;
  };
  unsigned unringed = 0;
  for (int i = 0; i < n; ++i)
    if (!d.ringed[i]) unringed |= 1u << i;
  // Number of faces of type J in the element of type T (J within T).
  bool known = true;
  auto faces = [&](unsigned J, unsigned T) {
    unsigned K = 0;
    for (int i = 0; i < n; ++i) {
      if (!(T >> i & 1u) || (J >> i & 1u) || !(unringed >> i & 1u)) continue;
      bool joined = false;
      for (int j = 0; j < n; ++j) joined = joined || ((J >> j & 1u) && m(i, j) > 2);
      if (!joined) K |= 1u << i;
    }
    const auto whole = order(T), stab = order(J | K);
    if (!whole || !stab) {
      known = false;
      return 0.0;
    }
    return *whole / *stab;
  };
  const unsigned all = (1u << n) - 1;
  WythoffSize e;
  e.f.assign(static_cast<std::size_t>(n), 0.0);
  std::vector<double> w(std::size_t{1} << n, 0.0);
  // The containment tests of the walk (for_each_simplex skips the cone over a boundary element
  // that holds the apex, found by a search down to the faces): B[T], what the search reads at
  // one element of type T (its boundary ids, and at a cell the edges of each face); D[T], at
  // most what one search below a T-element reads (its whole closure of ranks >= 3: the search
  // visits each element once and stops early only when it finds the apex); C[T], what the walk
  // of a T-element reads in its tests, recursing into the facets that miss its apex (the same
  // share as in w).
  std::vector<double> B(w.size(), 0.0), D(w.size(), 0.0), C(w.size(), 0.0);
  for (unsigned T = 1; T <= all; ++T) {
    const int k = std::popcount(T);
    if (k == n || !every_component_ringed(m, d.ringed, T)) continue;
    e.f[static_cast<std::size_t>(k)] += faces(T, all);
    if (k == 2) {
      const std::vector<int> g = nodes_of(T);
      const double sides = m(g[0], g[1]) * (d.ringed[g[0]] && d.ringed[g[1]] ? 2.0 : 1.0);
      w[T] = sides - 2.0;
    } else if (k >= 3) {
      const double vertices = faces(0, T);
      double facets = 0.0, edges = 0.0;
      for (int i = 0; i < n; ++i) {
        const unsigned J = T & ~(1u << i);
        if (J == T || !every_component_ringed(m, d.ringed, J)) continue;
        const double count = faces(J, T), miss = 1.0 - faces(0, J) / vertices;
        w[T] += count * miss * w[J];
        facets += count;
        C[T] += count * ((k == 3 ? w[J] + 2.0 : D[J]) + miss * C[J]);
        if (k == 3 && every_component_ringed(m, d.ringed, 1u << i)) edges += faces(1u << i, T);
      }
      B[T] = facets + (k == 3 ? 2.0 * edges : 0.0);
      D[T] = B[T];
      for (unsigned Y = (T - 1) & T; Y != 0; Y = (Y - 1) & T)
        if (std::popcount(Y) >= 3 && every_component_ringed(m, d.ringed, Y))
          D[T] += faces(Y, T) * B[Y];
    }
  }
  e.f[0] = faces(0, all);
  if (!known) return std::nullopt;
  if (n == 2) {
    e.orientation_work = e.f[1];
  } else {
    for (unsigned T = 1; T < all; ++T)
      if (std::popcount(T) == n - 1 && every_component_ringed(m, d.ringed, T)) {
        e.orientation_work += faces(T, all) * w[T];
        e.containment_reads += faces(T, all) * C[T];
      }
    e.orientation_work *= static_cast<double>(n) * n * n / 64.0;
  }
  return e;
}

// The elements of one rank: their vertices, the seed (base element) of each sub-diagram, the
// permutation every generator induces on them, and (rank >= 3) their boundaries.
struct Elements {
  std::vector<VertexList> verts;           // a cycle for rank 2, sorted otherwise
  std::vector<std::uint32_t> type;         // index into masks
  std::vector<unsigned> masks;             // sub-diagram of each type
  std::vector<std::uint32_t> seeds;        // id of the base element of each type
  std::vector<std::uint32_t> parent, via;  // discovered as act[via][parent]
  std::vector<std::vector<std::uint32_t>> act;
  std::vector<VertexList> bound;
};

std::string mask_text(const CoxeterDiagram& d, unsigned mask) {
  std::string out;
  for (int i = 0; i < d.rank(); ++i) out += (mask >> i & 1u) ? (d.ringed[i] ? 'x' : 'o') : '.';
  return out;
}

const char* rank_word(int k) {
  return k == 1 ? "edges" : k == 2 ? "faces" : k == 3 ? "cells" : "elements";
}

// Adds the orbit of `base` (of type t) under the whole group; faces are identified by their
// sorted vertex sets and keep the order of `base` (a cycle stays a cycle, since the generators
// are isometries). An image equal to an element of another sub-diagram is a degeneracy.
void add_orbit(VertexList base, std::uint32_t t, const Orbit& orbit, FaceIndex& seen, Elements& e,
               const std::string& name, const CoxeterDiagram& d, int k, bool fold) {
  const int n = static_cast<int>(orbit.perm.size());
  auto coincide = [&](std::uint32_t other) {
    throw InputError(name + " is degenerate: its " + rank_word(k) + " of the sub-diagrams " +
                     mask_text(d, e.masks[t]) + " and " + mask_text(d, e.masks[e.type[other]]) +
                     " coincide");
  };
  VertexList key = base;
  std::sort(key.begin(), key.end());
  const auto [it, fresh] =
      seen.try_emplace(std::move(key), static_cast<std::uint32_t>(e.verts.size()));
  // Folded vertices make edges of different sub-diagrams coincide: they are one edge.
  const bool merge = fold && k == 1;
  if (!fresh && merge) {
    e.seeds.push_back(it->second);
    return;
  }
  if (!fresh) coincide(it->second);
  std::size_t next = e.verts.size();
  e.seeds.push_back(static_cast<std::uint32_t>(next));
  e.verts.push_back(std::move(base));
  e.type.push_back(t);
  e.parent.push_back(0);
  e.via.push_back(0);
  e.act.resize(n);
  VertexList image;
  for (; next < e.verts.size(); ++next) {
    for (int g = 0; g < n; ++g) {
      image.clear();
      for (auto v : e.verts[next]) image.push_back(orbit.perm[g][v]);
      key = image;
      std::sort(key.begin(), key.end());
      const auto id = static_cast<std::uint32_t>(e.verts.size());
      const auto [at, added] = seen.try_emplace(std::move(key), id);
      if (added) {
        e.verts.push_back(image);
        e.type.push_back(t);
        e.parent.push_back(static_cast<std::uint32_t>(next));
        e.via.push_back(static_cast<std::uint32_t>(g));
      } else if (e.type[at->second] != t && !merge) {
        coincide(at->second);
      }
      e.act[g].push_back(at->second);
    }
  }
}

// All elements of rank k (1 <= k < n): one orbit per admissible set K of k generators, seeded
// with the face of the base point spanned by K. For k >= 3 the boundary of that seed is the
// orbit under K of the seeds of the admissible (k-1)-subsets of K (the faces of a Wythoffian
// polytope are the cosets of its parabolic subgroups, incident when they meet), carried to the
// rest of the orbit by the generators.
Elements elements_of_rank(int k, const Eigen::MatrixXi& m, const CoxeterDiagram& d,
                          const Orbit& orbit, const Elements* lower, const std::string& name,
                          bool fold) {
  const int n = d.rank();
  FaceIndex seen;
  Elements e;
  for (unsigned mask = 1; mask < (1u << n); ++mask) {
    if (std::popcount(mask) != k || !every_component_ringed(m, d.ringed, mask)) continue;
    const std::vector<int> gens = nodes_of(mask);
    VertexList base = k == 2 ? base_polygon(orbit, gens[0], gens[1], m(gens[0], gens[1]))
                             : base_face(orbit, gens);
    if (k == 2) {
      VertexList sorted = base;
      std::sort(sorted.begin(), sorted.end());
      const auto m2 = static_cast<std::size_t>(m(gens[0], gens[1]));
      const std::size_t sides = d.ringed[gens[0]] && d.ringed[gens[1]] ? 2 * m2 : m2;
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end() || base.size() != sides)
        throw InputError(name + " is degenerate: the face of the sub-diagram " +
                         mask_text(d, mask) + " runs through coinciding vertices");
    }
    if (k >= 2) {
      Eigen::VectorXd centre = Eigen::VectorXd::Zero(n);
      for (auto v : base) centre += orbit.positions.col(v);
      if (centre.norm() / static_cast<double>(base.size()) <=
          kSameVertexRel * orbit.positions.col(0).norm())
        throw InputError(name + " is degenerate: the " + std::string(rank_word(k)) +
                         " of the sub-diagram " + mask_text(d, mask) +
                         " pass through the centre (hemi-" + (k == 2 ? "faces" : "cells") +
                         " are not supported)");
    }
    const auto t = static_cast<std::uint32_t>(e.masks.size());
    e.masks.push_back(mask);
    const std::size_t first = e.verts.size();
    add_orbit(std::move(base), t, orbit, seen, e, name, d, k, fold);
    if (k < 3) continue;
    // Boundary of the seed.
    VertexList bound;
    std::unordered_set<std::uint32_t> in;
    for (std::size_t j = 0; j < lower->masks.size(); ++j) {
      if ((lower->masks[j] & ~mask) != 0) continue;
      const std::uint32_t s = lower->seeds[j];
      if (!in.insert(s).second) continue;
      bound.push_back(s);
      for (std::size_t i = bound.size() - 1; i < bound.size(); ++i)
        for (int g : gens) {
          const std::uint32_t w = lower->act[g][bound[i]];
          if (in.insert(w).second) bound.push_back(w);
        }
    }
    e.bound.resize(e.verts.size());
    std::sort(bound.begin(), bound.end());
    e.bound[first] = std::move(bound);
    for (std::size_t f = first + 1; f < e.verts.size(); ++f) {
      VertexList& b = e.bound[f];
      for (auto x : e.bound[e.parent[f]]) b.push_back(lower->act[e.via[f]][x]);
      std::sort(b.begin(), b.end());
    }
  }
  return e;
}

}  // namespace

CoxeterDiagram parse_coxeter_diagram(std::string_view text) {
  const std::string name = quoted(text);
  CoxeterDiagram d;
  std::size_t i = 0;
  while (true) {
    if (i >= text.size())
      throw InputError(name + (text.empty() ? " is empty" : " ends with a branch label"));
    const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(text[i])));
    if (c != 'x' && c != 'o')
      throw InputError(name + ": expected a node 'x' or 'o' at position " + std::to_string(i) +
                       ", found '" + text[i] + "'");
    d.ringed.push_back(c == 'x');
    if (++i == text.size()) break;
    std::size_t j = i;
    while (j < text.size() && text[j] >= '0' && text[j] <= '9') ++j;
    if (j == i)
      throw InputError(name + ": expected an integer branch label at position " +
                       std::to_string(i) + ", found '" + text[i] + "' (write 3 explicitly)");
    int label = 0;
    const auto [ptr, ec] = std::from_chars(text.data() + i, text.data() + j, label);
    if (ec != std::errc() || ptr != text.data() + j || label < 2 || label > kMaxLabel)
      throw InputError(name + ": branch label '" + std::string(text.substr(i, j - i)) +
                       "' is outside 2.." + std::to_string(kMaxLabel));
    int denominator = 1;
    if (j < text.size() && text[j] == '/') {
      std::size_t k = j + 1;
      while (k < text.size() && text[k] >= '0' && text[k] <= '9') ++k;
      const auto [qp, qec] = std::from_chars(text.data() + j + 1, text.data() + k, denominator);
      if (k == j + 1 || qec != std::errc() || qp != text.data() + k)
        throw InputError(name + ": expected an integer denominator after '/' at position " +
                         std::to_string(j));
      j = k;
    }
    d.labels.push_back(label);
    d.denominators.push_back(denominator);
    i = j;
  }
  check_shape(d);
  return d;
}

Complex make_wythoff(const CoxeterDiagram& d, const WythoffOptions& options) {
  check_shape(d);
  const std::string name = quoted(to_text(d));
  const int n = d.rank();
  const Eigen::MatrixXi m = coxeter_matrix(d);
  if (!every_component_ringed(m, d.ringed, (1u << n) - 1))
    throw InputError(name + (std::find(d.ringed.begin(), d.ringed.end(), true) == d.ringed.end()
                                 ? " has no ringed node"
                                 : " has a connected component without a ringed node (the "
                                   "result would not be full-dimensional)"));
  const Eigen::MatrixXd roots = simple_roots(d, name);
  const Eigen::VectorXd base = base_point(roots, d.ringed);
  const bool star = is_star(d);
  if (star) {
    // Finite group: finitely many mirrors. Non-degenerate vertices: the base point lies on the
    // mirrors of the unringed nodes' subgroup only (else its orbit folds onto itself).
    std::size_t cap = 120 + static_cast<std::size_t>(n * n);
    for (int label : d.labels) cap += static_cast<std::size_t>(label);
    std::vector<int> all(n), unringed;
    for (int i = 0; i < n; ++i) {
      all[i] = i;
      if (!d.ringed[i]) unringed.push_back(i);
    }
    const auto mirrors = mirror_normals(roots, all, cap);
    if (!mirrors)
      throw InputError(name +
                       " generates an infinite group (its mirrors at the angles pi q/p "
                       "of the marks do not close up)");
    std::size_t through = 0;
    for (const auto& r : *mirrors)
      if (std::abs(r.dot(base)) <= kSameVertexRel * base.norm()) ++through;
    const std::size_t own = unringed.empty() ? 0 : mirror_normals(roots, unringed, cap)->size();
    // A polygon has nothing to fold onto: its edges would double.
    if (through != own && !(options.fold_coincident_vertices && n >= 3))
      throw InputError(name +
                       " is degenerate: its vertices coincide (the base point lies on a mirror "
                       "of the group outside the unringed nodes' subgroup)");
  }
  // Refuse before building what build_complex would refuse after it, what would take longer
  // than that budget to build (counting the walk's containment reads), or what has more
  // vertices than the orbit may hold.
  if (const auto size = estimate(d, m, roots)) {
    if (size->f[0] > static_cast<double>(kMaxVertices))
      throw InputError(name + " has more than " + std::to_string(kMaxVertices) + " vertices (" +
                       std::to_string(static_cast<long long>(std::min(size->f[0], 9e18))) + ")");
    // Beyond R^7 the walk's containment tests cost more than its simplices: one read of
    // theirs takes about 1/50 of a 4D simplex's orientation (measured: 11 ns against 0.55 us).
    const double work = size->orientation_work + size->containment_reads / 50.0;
    if (work > max_orientation_work)
      throw InputError(name + " is too large: its facets cut into the equivalent of " +
                       std::to_string(static_cast<long long>(std::min(work, 9e18))) +
                       " 4D simplices, cw4d handles at most " +
                       std::to_string(static_cast<long long>(max_orientation_work)));
  }
  const Orbit orbit = vertex_orbit(roots, base, name);

  std::vector<Elements> elems(n);  // elems[k]: rank k, 1 <= k < n
  for (int k = 1; k < n; ++k)
    elems[k] = elements_of_rank(k, m, d, orbit, k > 1 ? &elems[k - 1] : nullptr, name,
                                options.fold_coincident_vertices);

  ComplexSoup soup;
  soup.ambient_dim = n;
  soup.positions = orbit.positions;
  for (int k = 3; k < n; ++k) soup.higher.push_back(std::move(elems[k].bound));
  if (n == 2) {
    for (const auto& e : elems[1].verts) soup.edges.push_back({e[0], e[1]});
  } else {
    soup.faces = std::move(elems[2].verts);
  }
  Complex c = build_complex(soup);
  if (star) {
    const ValidationReport report = validate(c);
    if (!report.ok())
      throw InputError(name + " is degenerate: its elements do not close up into a polytope (" +
                       report.summary(1) + ")");
  }
  return c;
}

Complex make_wythoff(const CoxeterDiagram& d) {
  return make_wythoff(d, WythoffOptions{});
}

std::optional<WythoffSize> wythoff_size(const CoxeterDiagram& d) {
  check_shape(d);
  const Eigen::MatrixXi m = coxeter_matrix(d);
  if (!every_component_ringed(m, d.ringed, (1u << d.rank()) - 1)) return std::nullopt;
  return estimate(d, m, simple_roots(d, quoted(to_text(d))));
}

Complex make_wythoff(std::string_view diagram, const WythoffOptions& options) {
  return make_wythoff(parse_coxeter_diagram(diagram), options);
}

Complex make_wythoff(std::string_view diagram) {
  return make_wythoff(parse_coxeter_diagram(diagram));
}

std::optional<std::string> uniform_polychoron_diagram(std::string_view name) {
  std::string s;
  for (char ch : name) {
    ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    if (ch == ' ' || ch == '_') ch = '-';
    if (ch != '-' || (!s.empty() && s.back() != '-')) s += ch;
  }
  struct Base {
    const char* names[2];
    const char* labels;
  };
  // The 16-cell is the B4 diagram read from the 3 end, the 600-cell the H4 one.
  static const Base bases[] = {
      {{"pentachoron", "5-cell"}, "333"},          {{"tesseract", "8-cell"}, "433"},
      {{"hexadecachoron", "16-cell"}, "334"},      {{"icositetrachoron", "24-cell"}, "343"},
      {{"hecatonicosachoron", "120-cell"}, "533"}, {{"hexacosichoron", "600-cell"}, "335"}};
  struct Operation {
    const char* prefix;
    const char* rings;
  };
  static const Operation operations[] = {
      {"", "xooo"},
      {"truncated-", "xxoo"},
      {"rectified-", "oxoo"},
      {"bitruncated-", "oxxo"},
      {"cantellated-", "xoxo"},
      {"runcinated-", "xoox"},
      {"cantitruncated-", "xxxo"},
      {"runcitruncated-", "xxox"},
      {"omnitruncated-", "xxxx"},
      {"runcicantitruncated-", "xxxx"},
  };
  for (const auto& op : operations)
    for (const auto& base : bases)
      for (const char* base_name : base.names) {
        if (s != std::string(op.prefix) + base_name) continue;
        std::string diagram;
        for (int i = 0; i < 4; ++i) {
          if (i > 0) diagram += base.labels[i - 1];
          diagram += op.rings[i];
        }
        return diagram;
      }
  return std::nullopt;
}

}  // namespace cw4d

namespace cw4d {

namespace {

// Word-level canonical form of a polychoron's name: lower case, words joined by '-', the Greek
// base words and Miratope's spellings put in English, so that "Quasicantitruncated
// icosatetrachoron", "quasicantitruncated icositetrachoron" and "quasicantitruncated 24-cell"
// compare equal.
std::string canonical_name(std::string_view text) {
  std::vector<std::string> words(1);
  for (char ch : text) {
    if (ch == ' ' || ch == '_' || ch == '-' || ch == '\t') {
      if (!words.back().empty()) words.emplace_back();
    } else {
      words.back() += static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    }
  }
  if (words.back().empty()) words.pop_back();
  static const std::pair<const char*, const char*> english[] = {
      {"pentachoron", "5-cell"},
      {"tesseract", "8-cell"},
      {"hexadecachoron", "16-cell"},
      {"icositetrachoron", "24-cell"},
      {"icosatetrachoron", "24-cell"},
      {"hecatonicosachoron", "120-cell"},
      {"hexacosichoron", "600-cell"},
      {"runcicantitruncated", "omnitruncated"},
      {"semisnub", "snub"}};
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i) {
    std::string w = words[i];
    // "small stellated 120-cell" is the stellated 120-cell (Miratope, Coxeter's tables).
    if (w == "small" && i + 1 < words.size() && words[i + 1] == "stellated") continue;
    for (const auto& [greek, plain] : english)
      if (w == greek) w = plain;
    if (!out.empty()) out += '-';
    out += w;
  }
  return out;
}

// cw4d's English name: the table's, or Miratope's with the Greek base word in English (the
// tesseract keeps its name).
std::string english_of(const UniformPolychoron& p) {
  if (p.english) return p.english;
  std::string s = p.name;
  static const std::pair<const char*, const char*> english[] = {
      {"pentachoron", "5-cell"},          {"hexadecachoron", "16-cell"},
      {"icositetrachoron", "24-cell"},    {"icosatetrachoron", "24-cell"},
      {"hecatonicosachoron", "120-cell"}, {"hexacosichoron", "600-cell"}};
  for (const auto& [greek, plain] : english) {
    const auto at = s.find(greek);
    if (at != std::string::npos) s.replace(at, std::string_view(greek).size(), plain);
  }
  return s;
}

}  // namespace

const std::vector<UniformPolychoron>& uniform_polychora() {
  // Miratope's library (the Miratope authors: lib/4D of miratope-rs) names its uniform
  // polychora after the Polytope Wiki (J. Bowers' names); each file is checked against the
  // diagram here by tests/test_catalogue_names.cpp.
  static const std::vector<UniformPolychoron> table = {
      // The six convex regular polychora: the built-ins of the same English names.
      {"pentachoron", "5-cell", "x3o3o3o", true, false, "5-cell"},
      {"tesseract", nullptr, "x4o3o3o", true, false, "tesseract"},
      {"hexadecachoron", "16-cell", "x3o3o4o", true, false, "16-cell"},
      {"icositetrachoron", "24-cell", "x3o4o3o", true, false, "24-cell"},
      {"hecatonicosachoron", "120-cell", "x5o3o3o", true, false, "120-cell"},
      {"hexacosichoron", "600-cell", "x3o3o5o", true, false, "600-cell"},
      // The convex uniform polychora of the linear diagrams A4, B4, F4, H4.
      {"truncated pentachoron", nullptr, "x3x3o3o", true},
      {"rectified pentachoron", nullptr, "o3x3o3o", true},
      {"bitruncated pentachoron", nullptr, "o3x3x3o", true},
      {"cantellated pentachoron", nullptr, "x3o3x3o", true},
      {"runcinated pentachoron", nullptr, "x3o3o3x", true},
      {"cantitruncated pentachoron", nullptr, "x3x3x3o", true},
      {"runcitruncated pentachoron", nullptr, "x3x3o3x", true},
      {"omnitruncated pentachoron", nullptr, "x3x3x3x", true},
      {"truncated tesseract", nullptr, "x4x3o3o", true},
      {"rectified tesseract", nullptr, "o4x3o3o", true},
      {"bitruncated tesseract", nullptr, "o4x3x3o", true},
      {"cantellated tesseract", nullptr, "x4o3x3o", true},
      {"runcinated tesseract", nullptr, "x4o3o3x", true},
      {"cantitruncated tesseract", nullptr, "x4x3x3o", true},
      {"runcitruncated tesseract", nullptr, "x4x3o3x", true},
      {"omnitruncated tesseract", nullptr, "x4x3x3x", true},
      {"truncated hexadecachoron", nullptr, "x3x3o4o", true},
      {"runcitruncated hexadecachoron", nullptr, "x3x3o4x", true},
      {"truncated icositetrachoron", nullptr, "x3x4o3o", true},
      {"rectified icositetrachoron", nullptr, "o3x4o3o", true},
      {"bitruncated icositetrachoron", nullptr, "o3x4x3o", true},
      {"cantellated icositetrachoron", nullptr, "x3o4x3o", true},
      {"runcinated icositetrachoron", nullptr, "x3o4o3x", true},
      {"cantitruncated icositetrachoron", nullptr, "x3x4x3o", true},
      {"runcitruncated icositetrachoron", nullptr, "x3x4o3x", true},
      {"omnitruncated icositetrachoron", nullptr, "x3x4x3x", true},
      {"truncated hecatonicosachoron", nullptr, "x5x3o3o", true},
      {"rectified hecatonicosachoron", nullptr, "o5x3o3o", true},
      {"bitruncated hecatonicosachoron", nullptr, "o5x3x3o", true},
      {"cantellated hecatonicosachoron", nullptr, "x5o3x3o", true},
      {"runcinated hecatonicosachoron", nullptr, "x5o3o3x", true},
      {"cantitruncated hecatonicosachoron", nullptr, "x5x3x3o", true},
      {"runcitruncated hecatonicosachoron", nullptr, "x5x3o3x", true},
      {"omnitruncated hecatonicosachoron", nullptr, "x5x3x3x", true},
      {"truncated hexacosichoron", nullptr, "x3x3o5o", true},
      {"rectified hexacosichoron", nullptr, "o3x3o5o", true},
      {"cantellated hexacosichoron", nullptr, "x3o3x5o", true},
      {"cantitruncated hexacosichoron", nullptr, "x3x3x5o", true},
      {"runcitruncated hexacosichoron", nullptr, "x3x3o5x", true},
      // The two convex uniform polychora that are no plain ringing of a linear diagram: the
      // snub 24-cell s3s4o3o is the alternation of x3x4o3o (half its vertices); the grand
      // antiprism has no Wythoff construction from a linear diagram (J. H. Conway,
      // M. J. T. Guy, "Four-dimensional Archimedean polytopes", 1965). Both are built as
      // convex hulls by default_catalogue().
      {"semisnub icositetrachoron", "snub 24-cell", "s3s4o3o", true, false, "snub 24-cell"},
      {"grand antiprism", nullptr, "", true, false, "grand antiprism"},
      // The ten regular star polychora (Schlaefli-Hess), by their Schlaefli symbols as in
      // H. S. M. Coxeter, "Regular Polytopes" (1973), table IV.
      {"icosahedral hecatonicosachoron", "icosahedral 120-cell", "x3o5o5/2o", false},
      {"stellated hecatonicosachoron", "small stellated 120-cell", "x5/2o5o3o", false},
      {"great hecatonicosachoron", "great 120-cell", "x5o5/2o5o", false},
      {"grand hecatonicosachoron", "grand 120-cell", "x5o3o5/2o", false},
      {"great stellated hecatonicosachoron", "great stellated 120-cell", "x5/2o3o5o", false},
      {"grand stellated hecatonicosachoron", "grand stellated 120-cell", "x5/2o5o5/2o", false},
      {"great grand hecatonicosachoron", "great grand 120-cell", "x5o5/2o3o", false},
      {"great icosahedral hecatonicosachoron", "great icosahedral 120-cell", "x3o5/2o5o", false},
      {"grand hexacosichoron", "grand 600-cell", "x3o3o5/2o", false},
      {"great grand stellated hecatonicosachoron", "great grand stellated 120-cell", "x5/2o3o3o",
       false},
      // Non-convex uniform polychora. Four Wythoff vertices of x5/2o3o3x coincide at each
      // point (and its edges in pairs): Miratope's file is the folded figure.
      {"biquasitruncated icositetrachoron", nullptr, "o3x4/3x3o", false},
      {"bitruncated great grand stellated hecatonicosachoron", nullptr, "o5/2x3x3o", false},
      {"bitruncated icosahedral hecatonicosachoron", nullptr, "o3x5x5/2o", false},
      {"cantellated grand hexacosichoron", nullptr, "x3o3x5/2o", false},
      {"cantellated icosahedral hecatonicosachoron", nullptr, "x3o5x5/2o", false},
      {"cantellated stellated hecatonicosachoron", nullptr, "x5/2o5x3o", false},
      {"cantitruncated grand hexacosichoron", nullptr, "x3x3x5/2o", false},
      {"quasicantellated icositetrachoron", nullptr, "x3o4/3x3o", false},
      {"quasicantellated tesseract", nullptr, "x4/3o3x3o", false},
      {"quasicantitruncated icosatetrachoron", nullptr, "x3x4/3x3o", false},
      {"quasicantitruncated tesseract", nullptr, "x4/3x3x3o", false},
      {"quasiomnitruncated icositetrachoron", nullptr, "x3x4/3x3x", false},
      {"quasiomnitruncated tesseract", nullptr, "x4/3x3x3x", false},
      {"quasiruncicantellated tesseract", nullptr, "x4/3o3x3x", false},
      {"quasiruncinated icositetrachoron", nullptr, "x3o4/3o3x", false},
      {"quasiruncinated tesseract", nullptr, "x4/3o3o3x", false},
      {"quasiruncitruncated icositetrachoron", nullptr, "x3x4/3o3x", false},
      {"quasiruncitruncated tesseract", nullptr, "x4/3x3o3x", false},
      {"quasitruncated tesseract", nullptr, "x4/3x3o3o", false},
      {"rectified grand hecatonicosachoron", nullptr, "o5x3o5/2o", false},
      {"rectified grand stellated hecatonicosachoron", nullptr, "o5/2x5o5/2o", false},
      {"rectified great grand hecatonicosachoron", nullptr, "o5x5/2o3o", false},
      {"rectified great hecatonicosachoron", nullptr, "o5x5/2o5o", false},
      {"rectified great icosahedral hecatonicosachoron", nullptr, "o3x5/2o5o", false},
      {"rectified great stellated hecatonicosachoron", nullptr, "o5/2x3o5o", false},
      {"rectified icosahedral hecatonicosachoron", nullptr, "o3x5o5/2o", false},
      {"rectified stellated hecatonicosachoron", nullptr, "o5/2x5o3o", false},
      {"runcinated icosahedral hecatonicosachoron", nullptr, "x3o5o5/2x", false},
      {"runcinated great grand stellated hecatonicosachoron", nullptr, "x5/2o3o3x", false, true},
      {"truncated grand hexacosichoron", nullptr, "x3x3o5/2o", false},
      {"truncated icosahedral hecatonicosachoron", nullptr, "x3x5o5/2o", false},
  };
  return table;
}

std::string english_name(const UniformPolychoron& polychoron) {
  return english_of(polychoron);
}

std::optional<UniformPolychoron> find_uniform_polychoron(std::string_view name) {
  if (name.size() > 200) return std::nullopt;
  // Other names of the same polychora: Miratope's folder index calls x4/3o3x3x (its file
  // "Quasiruncicantellated tesseract") the quasiruncitruncated hexadecachoron, as x4o3x3x is
  // both the runcicantellated tesseract and the runcitruncated 16-cell; "sadi" is Bowers'.
  static const std::pair<const char*, const char*> aliases[] = {
      {"quasiruncitruncated hexadecachoron", "quasiruncicantellated tesseract"},
      {"runcicantellated tesseract", "runcitruncated hexadecachoron"},
      {"sadi", "semisnub icositetrachoron"},
      {"gap", "grand antiprism"}};
  std::string s = canonical_name(name);
  if (s.empty()) return std::nullopt;
  for (const auto& [alias, target] : aliases)
    if (s == canonical_name(alias)) s = canonical_name(target);
  for (const UniformPolychoron& p : uniform_polychora())
    if (s == canonical_name(p.name) || s == canonical_name(english_of(p))) return p;
  return std::nullopt;
}

const std::vector<NamedDiagram>& star_polychoron_names() {
  // The non-convex entries of uniform_polychora(): the ten regular star polychora by their
  // English (Schlaefli-Hess) names first, then the others by Miratope's names.
  static const std::vector<NamedDiagram> names = [] {
    std::vector<NamedDiagram> out;
    for (const UniformPolychoron& p : uniform_polychora())
      if (!p.convex) out.push_back({p.english ? p.english : p.name, p.diagram, p.folded});
    return out;
  }();
  return names;
}

std::optional<NamedDiagram> star_polychoron(std::string_view name) {
  const auto p = find_uniform_polychoron(name);
  if (!p || p->convex) return std::nullopt;
  return NamedDiagram{p->english ? p->english : p->name, p->diagram, p->folded};
}

std::optional<std::string> star_polychoron_diagram(std::string_view name) {
  const auto e = star_polychoron(name);
  if (!e) return std::nullopt;
  return std::string(e->diagram);
}

Complex make_star_polychoron(std::string_view name) {
  const auto e = star_polychoron(name);
  if (!e) throw InputError(quote_user_text(std::string(name)) + " names no star polychoron");
  return make_wythoff(e->diagram, WythoffOptions{e->folded});
}

}  // namespace cw4d
