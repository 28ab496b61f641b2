#include "cw4d/complex/wythoff.hpp"

#include "cw4d/complex/tolerances.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>
#include <unordered_set>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/error.hpp"

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
  return "Coxeter diagram '" + std::string(text) + "'";
}

std::string to_text(const CoxeterDiagram& d) {
  std::string out;
  for (int i = 0; i < d.rank(); ++i) {
    if (i > 0)
      out += i - 1 < static_cast<int>(d.labels.size()) ? std::to_string(d.labels[i - 1]) : "?";
    out += d.ringed[i] ? 'x' : 'o';
  }
  return out;
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

// Unit simple roots as the rows of the Cholesky factor L of the Gram matrix (a_i . a_j = G_ij).
Eigen::MatrixXd simple_roots(const Eigen::MatrixXi& m, const std::string& name) {
  const auto n = m.rows();
  Eigen::MatrixXd gram(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      gram(i, j) = i == j ? 1.0 : m(i, j) == 2 ? 0.0 : -std::cos(std::numbers::pi / m(i, j));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram, Eigen::EigenvaluesOnly);
  Eigen::LLT<Eigen::MatrixXd> llt(gram);
  if (eigen.eigenvalues().minCoeff() <= kPositiveDefiniteMin || llt.info() != Eigen::Success)
    throw InputError(name +
                     " generates an infinite Coxeter group (the Gram matrix of its "
                     "simple roots is not positive definite); only finite groups give "
                     "polytopes");
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

  // Id of the stored point within the tolerance of x, or kNone.
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
    return kNone;
  }

  void insert(const double* x, std::uint32_t id) {
    std::vector<std::int64_t> key(dim_);
    for (int i = 0; i < dim_; ++i) key[i] = std::llround(x[i] / cell_);
    map_.emplace(hash(key), id);
  }

  static constexpr std::uint32_t kNone = 0xffffffffu;

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
      if (id == PointIndex::kNone) {
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

// Appends the images of `base` under the whole group that `seen` does not hold yet. Faces are
// identified by their sorted vertex sets; the stored lists keep the order of `base` (a cycle
// stays a cycle, since the generators are isometries).
void add_face_orbit(VertexList base, const Orbit& orbit, FaceIndex& seen,
                    std::vector<VertexList>& out) {
  VertexList key = base;
  std::sort(key.begin(), key.end());
  if (!seen.try_emplace(std::move(key), static_cast<std::uint32_t>(out.size())).second) return;
  std::size_t next = out.size();
  out.push_back(std::move(base));
  VertexList image;
  for (; next < out.size(); ++next) {
    for (const auto& perm : orbit.perm) {
      image.clear();
      for (auto v : out[next]) image.push_back(perm[v]);
      key = image;
      std::sort(key.begin(), key.end());
      if (seen.try_emplace(std::move(key), static_cast<std::uint32_t>(out.size())).second)
        out.push_back(image);
    }
  }
}

// All elements of rank k (1 <= k < n): one orbit per admissible set J of k generators, seeded
// with the face of the base point spanned by J.
std::vector<VertexList> elements_of_rank(int k, const Eigen::MatrixXi& m,
                                         const std::vector<bool>& ringed, const Orbit& orbit) {
  const int n = static_cast<int>(ringed.size());
  FaceIndex seen;
  std::vector<VertexList> out;
  for (unsigned mask = 1; mask < (1u << n); ++mask) {
    if (std::popcount(mask) != k || !every_component_ringed(m, ringed, mask)) continue;
    const std::vector<int> gens = nodes_of(mask);
    add_face_orbit(k == 2 ? base_polygon(orbit, gens[0], gens[1], m(gens[0], gens[1]))
                          : base_face(orbit, gens),
                   orbit, seen, out);
  }
  return out;
}

// For each upper element, the ids of the lower elements whose vertices all belong to it (faces of
// a convex polytope are determined by their vertex sets).
std::vector<VertexList> boundaries(const std::vector<VertexList>& upper,
                                   const std::vector<VertexList>& lower, std::size_t vertices) {
  std::vector<std::uint32_t> start(vertices + 1, 0);  // inverted index vertex -> lower elements
  for (const auto& f : lower)
    for (auto v : f) ++start[v + 1];
  for (std::size_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1), owners(start.back());
  for (std::uint32_t f = 0; f < lower.size(); ++f)
    for (auto v : lower[f]) owners[fill[v]++] = f;

  std::vector<std::uint32_t> hits(lower.size(), 0);
  std::vector<std::uint32_t> touched;
  std::vector<VertexList> out(upper.size());
  for (std::size_t e = 0; e < upper.size(); ++e) {
    touched.clear();
    for (auto v : upper[e])
      for (auto i = start[v]; i < start[v + 1]; ++i)
        if (hits[owners[i]]++ == 0) touched.push_back(owners[i]);
    for (auto f : touched) {
      if (hits[f] == lower[f].size()) out[e].push_back(f);
      hits[f] = 0;
    }
    std::sort(out[e].begin(), out[e].end());
  }
  return out;
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
                       ", found '" + text[i] + "'" +
                       (text[i] == '/' ? " (fractional labels are not supported)" : ""));
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
    d.labels.push_back(label);
    i = j;
  }
  check_shape(d);
  return d;
}

Complex make_wythoff(const CoxeterDiagram& d) {
  check_shape(d);
  const std::string name = quoted(to_text(d));
  const int n = d.rank();
  const Eigen::MatrixXi m = coxeter_matrix(d);
  if (!every_component_ringed(m, d.ringed, (1u << n) - 1))
    throw InputError(name + (std::find(d.ringed.begin(), d.ringed.end(), true) == d.ringed.end()
                                 ? " has no ringed node"
                                 : " has a connected component without a ringed node (the "
                                   "result would not be full-dimensional)"));
  const Eigen::MatrixXd roots = simple_roots(m, name);
  const Orbit orbit = vertex_orbit(roots, base_point(roots, d.ringed), name);

  std::vector<std::vector<VertexList>> elems(n);  // elems[k]: rank k, 1 <= k < n
  for (int k = 1; k < n; ++k) elems[k] = elements_of_rank(k, m, d.ringed, orbit);

  ComplexSoup soup;
  soup.ambient_dim = n;
  soup.positions = orbit.positions;
  for (int k = 3; k < n; ++k)
    soup.higher.push_back(boundaries(elems[k], elems[k - 1], orbit.size()));
  if (n == 2) {
    for (const auto& e : elems[1]) soup.edges.push_back({e[0], e[1]});
  } else {
    soup.faces = std::move(elems[2]);
  }
  return build_complex(soup);
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
