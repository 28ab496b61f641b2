#include "cw4d/complex/builder.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <deque>
#include <string>
#include <unordered_map>

#include "cone_determinants.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/tolerances.hpp"

namespace cw4d {

namespace {

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

// For each (k-2)-element: the (position in row, coefficient) pairs of the rank-(k-1) boundary
// elements that contain it. Used for both the internal sign solve of one element and the global
// facet coherence solve.
struct Incident {
  std::uint32_t ridge;
  std::uint32_t owner;  // index of the (k-1)-element (position in a row, or a facet id)
  std::int8_t coef;
};

// Solves multipliers sigma[owner] in {+1,-1} such that every ridge shared by exactly two owners
// gets cancelling coefficients. Unconstrained components start at +1. Returns the component
// number of every owner.
std::vector<std::uint32_t> solve_signs(std::vector<Incident>& inc, std::size_t owners,
                                       std::vector<std::int8_t>& sigma) {
  std::sort(inc.begin(), inc.end(), [](const Incident& a, const Incident& b) {
    return a.ridge != b.ridge ? a.ridge < b.ridge : a.owner < b.owner;
  });
  // adjacency: owner -> (other owner, relation r) meaning sigma[other] = r * sigma[owner]
  std::vector<std::vector<std::pair<std::uint32_t, std::int8_t>>> adj(owners);
  for (std::size_t i = 0; i < inc.size();) {
    std::size_t j = i;
    while (j < inc.size() && inc[j].ridge == inc[i].ridge) ++j;
    if (j - i == 2 && inc[i].owner != inc[i + 1].owner) {
      const auto r = static_cast<std::int8_t>(-inc[i].coef * inc[i + 1].coef);
      adj[inc[i].owner].push_back({inc[i + 1].owner, r});
      adj[inc[i + 1].owner].push_back({inc[i].owner, r});
    }
    i = j;
  }
  sigma.assign(owners, 0);
  std::vector<std::uint32_t> component(owners, 0);
  std::uint32_t comp = 0;
  std::deque<std::uint32_t> queue;
  for (std::uint32_t start = 0; start < owners; ++start) {
    if (sigma[start] != 0) continue;
    sigma[start] = 1;
    component[start] = comp;
    queue.push_back(start);
    while (!queue.empty()) {
      const std::uint32_t o = queue.front();
      queue.pop_front();
      for (auto [other, r] : adj[o]) {
        if (sigma[other] != 0) continue;
        sigma[other] = static_cast<std::int8_t>(r * sigma[o]);
        component[other] = comp;
        queue.push_back(other);
      }
    }
    ++comp;
  }
  return component;
}

void orient_internal(Complex& c, int rank) {
  Incidence& table = c.boundary_mut(rank);
  const Incidence& below = c.boundary(rank - 1);
  std::vector<Incident> inc;
  std::vector<std::int8_t> sigma;
  for (std::uint32_t x = 0; x < table.size(); ++x) {
    auto ids = table.ids(x);
    inc.clear();
    for (std::uint32_t j = 0; j < ids.size(); ++j) {
      auto gids = below.ids(ids[j]);
      auto gsigns = below.signs(ids[j]);
      for (std::size_t t = 0; t < gids.size(); ++t) inc.push_back({gids[t], j, gsigns[t]});
    }
    solve_signs(inc, ids.size(), sigma);
    auto signs = table.signs_mut(x);
    for (std::size_t j = 0; j < signs.size(); ++j) signs[j] = sigma[j];
  }
}

double component_volume(const Complex& c, const std::vector<std::uint32_t>& facets, double scale) {
  const int n = c.ambient_dim();
  const auto& p = c.positions();
  std::vector<std::uint32_t> verts;
  for (auto f : facets) {
    auto v = c.vertices_of(n - 1, f);
    verts.insert(verts.end(), v.begin(), v.end());
  }
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  Eigen::VectorXd centre = Eigen::VectorXd::Zero(n);
  for (auto v : verts) centre += scale * p.col(v);
  if (!verts.empty()) centre /= static_cast<double>(verts.size());
  return facet_cone_determinants(c, facets, centre, scale);
}

}  // namespace

double orientation_work(const Complex& c) {
  const int n = c.ambient_dim();
  const int fr = std::min(c.top_rank(), n - 1);
  if (fr < 2) return static_cast<double>(c.count(std::max(fr, 0)));
  // w[k][i]: the simplices for_each_simplex cuts element i of rank k into (a fan of each face
  // from its first vertex; a cone from the first vertex over the boundary elements that miss
  // it), by dynamic programming over the ranks instead of walking the flags.
  std::vector<double> below(c.count(2));
  for (std::uint32_t f = 0; f < c.count(2); ++f)
    below[f] = static_cast<double>(c.boundary(2).ids(f).size()) - 2.0;
  // Sorted vertex sets of the rank-(k-1) elements, kept from rank 3 up (faces are checked on
  // their edges, so a 4D model needs none).
  std::vector<std::vector<std::uint32_t>> verts;
  const auto face_has = [&](std::uint32_t f, std::uint32_t v) {
    for (auto e : c.boundary(2).ids(f)) {
      const auto ends = c.edge(e);
      if (ends[0] == v || ends[1] == v) return true;
    }
    return false;
  };
  for (int k = 3; k <= fr; ++k) {
    const Incidence& table = c.boundary(k);
    std::vector<double> w(table.size(), 0.0);
    std::vector<std::vector<std::uint32_t>> next(k < fr ? table.size() : 0);
    for (std::uint32_t i = 0; i < table.size(); ++i) {
      const std::uint32_t apex = c.first_vertex(k, i);
      for (auto j : table.ids(i)) {
        const bool has =
            k == 3 ? face_has(j, apex) : std::binary_search(verts[j].begin(), verts[j].end(), apex);
        if (!has) w[i] += below[j];
        if (k < fr) {
          if (k == 3) {
            for (auto e : c.boundary(2).ids(j)) {
              const auto ends = c.edge(e);
              next[i].push_back(ends[0]);
              next[i].push_back(ends[1]);
            }
          } else {
            next[i].insert(next[i].end(), verts[j].begin(), verts[j].end());
          }
        }
      }
      if (k < fr) {
        std::sort(next[i].begin(), next[i].end());
        next[i].erase(std::unique(next[i].begin(), next[i].end()), next[i].end());
      }
    }
    below = std::move(w);
    verts = std::move(next);
  }
  double total = 0.0;
  for (double x : below) total += x;
  // Each simplex costs an n x n determinant (and n of them for a facet normal).
  return total * n * n * n / 64.0;
}

void orient_complex(Complex& c) {
  const int n = c.ambient_dim();
  const int facet_rank = n - 1;
  for (int k = 3; k <= std::min(c.top_rank(), facet_rank); ++k) orient_internal(c, k);
  if (facet_rank >= 1 && c.count(facet_rank) > 0) {
    const std::size_t nf = c.count(facet_rank);
    std::vector<Incident> inc;
    const Incidence& facets = c.boundary(facet_rank);
    for (std::uint32_t f = 0; f < nf; ++f) {
      auto ids = facets.ids(f);
      auto signs = facets.signs(f);
      for (std::size_t t = 0; t < ids.size(); ++t) inc.push_back({ids[t], f, signs[t]});
    }
    std::vector<std::int8_t> sigma;
    auto component = solve_signs(inc, nf, sigma);
    for (std::uint32_t f = 0; f < nf; ++f)
      if (sigma[f] < 0) c.flip(facet_rank, f);
    const std::uint32_t ncomp =
        nf == 0 ? 0 : *std::max_element(component.begin(), component.end()) + 1;
    std::vector<std::vector<std::uint32_t>> members(ncomp);
    for (std::uint32_t f = 0; f < nf; ++f) members[component[f]].push_back(f);
    // Signs and directions only: decided on exactly rescaled positions (position_scale), so
    // that models in huge or tiny units orient like the same model near unit size.
    const double scale = position_scale(c);
    for (const auto& group : members) {
      if (component_volume(c, group, scale) < 0.0)
        for (auto f : group) c.flip(facet_rank, f);
    }
    Eigen::MatrixXd normals(n, nf);
    for (std::uint32_t f = 0; f < nf; ++f) {
      Eigen::VectorXd a = facet_area_vector(c, f, scale);
      const double len = a.norm();
      normals.col(f) = len > 0.0 ? Eigen::VectorXd(a / len) : Eigen::VectorXd::Zero(n);
    }
    c.set_facet_normals(std::move(normals));
  }
  if (c.top_rank() >= n && n >= 2) {
    Incidence& solids = c.boundary_mut(n);
    for (std::uint32_t s = 0; s < solids.size(); ++s)
      for (auto& sign : solids.signs_mut(s)) sign = 1;
  }
}

Complex build_complex(const ComplexSoup& soup, const BuildOptions& options) {
  const int n = soup.ambient_dim;
  if (n < 1) throw InputError("build_complex: ambient dimension must be >= 1");
  if (soup.positions.rows() != n && soup.positions.cols() > 0)
    throw InputError("build_complex: positions have " + std::to_string(soup.positions.rows()) +
                     " rows, expected " + std::to_string(n));
  Complex c(n);
  c.set_positions(soup.positions.cols() > 0 ? soup.positions : Eigen::MatrixXd(n, 0));
  const auto nv = static_cast<std::uint32_t>(c.count(0));

  std::unordered_map<std::uint64_t, std::uint32_t> edge_ids;
  auto edge_of = [&](std::uint32_t a, std::uint32_t b) {
    auto [it, fresh] = edge_ids.try_emplace(edge_key(a, b), 0);
    if (fresh) it->second = c.add_edge(std::min(a, b), std::max(a, b));
    return it->second;
  };
  if (!soup.edges.empty() || !soup.faces.empty()) c.boundary_mut(1);
  for (std::uint32_t e = 0; e < soup.edges.size(); ++e) {
    auto [a, b] = soup.edges[e];
    if (a >= nv || b >= nv)
      throw TopologyError(1, {e}, "edge " + std::to_string(e) + " refers to a vertex out of range");
    if (a == b)
      throw TopologyError(
          1, {e},
          "edge " + std::to_string(e) + " joins vertex " + std::to_string(a) + " to itself");
    edge_of(a, b);
  }
  if (!soup.faces.empty()) {
    Incidence& faces = c.boundary_mut(2);
    std::vector<std::uint32_t> ids;
    std::vector<std::int8_t> signs;
    std::vector<std::uint32_t> sorted;
    for (std::uint32_t f = 0; f < soup.faces.size(); ++f) {
      const auto& cyc = soup.faces[f];
      const std::string name = "face " + std::to_string(f);
      if (cyc.size() < 3) throw TopologyError(2, {f}, name + " has fewer than 3 vertices");
      sorted = cyc;
      std::sort(sorted.begin(), sorted.end());
      if (sorted.back() >= nv)
        throw TopologyError(2, {f},
                            name + " refers to vertex " + std::to_string(sorted.back()) +
                                " but there are " + std::to_string(nv) + " vertices");
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
        throw TopologyError(2, {f}, name + " repeats a vertex");
      ids.clear();
      signs.clear();
      for (std::size_t i = 0; i < cyc.size(); ++i) {
        const std::uint32_t a = cyc[i], b = cyc[(i + 1) % cyc.size()];
        ids.push_back(edge_of(a, b));
        signs.push_back(a < b ? 1 : -1);
      }
      faces.add_row(ids, signs);
    }
  }
  for (std::size_t j = 0; j < soup.higher.size(); ++j) {
    const int rank = static_cast<int>(j) + 3;
    Incidence& table = c.boundary_mut(rank);
    const std::size_t below = c.count(rank - 1);
    std::vector<std::uint32_t> sorted;
    std::vector<std::int8_t> signs;
    for (std::uint32_t x = 0; x < soup.higher[j].size(); ++x) {
      const auto& list = soup.higher[j][x];
      const std::string name = "rank-" + std::to_string(rank) + " element " + std::to_string(x);
      if (list.empty()) throw TopologyError(rank, {x}, name + " has an empty boundary");
      sorted = list;
      std::sort(sorted.begin(), sorted.end());
      if (sorted.back() >= below)
        throw TopologyError(rank, {x},
                            name + " refers to element " + std::to_string(sorted.back()) +
                                " of rank " + std::to_string(rank - 1) + " but there are " +
                                std::to_string(below));
      if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
        throw TopologyError(rank, {x}, name + " lists a boundary element twice");
      signs.assign(list.size(), 1);
      table.add_row(list, signs);
    }
  }
  if (!soup.face_colors.empty()) c.colors_mut(2) = soup.face_colors;
  for (std::size_t j = 0; j < soup.higher_colors.size(); ++j)
    if (!soup.higher_colors[j].empty())
      c.colors_mut(static_cast<int>(j) + 3) = soup.higher_colors[j];
  if (options.orient) {
    // One estimate for every model, however it was made (a family, an operator, a product, a
    // file): the work of orienting it, and of every later volume and normal, before doing it.
    const double work = orientation_work(c);
    if (work > max_orientation_work)
      throw InputError("the model is too large: its facets cut into the equivalent of " +
                       std::to_string(static_cast<long long>(std::min(work, 9e18))) +
                       " 4D simplices, cw4d handles at most " +
                       std::to_string(static_cast<long long>(max_orientation_work)));
    orient_complex(c);
  }
  assert(c.well_formed());
  return c;
}

ComplexSoup to_soup(const Complex& c) {
  ComplexSoup soup;
  soup.ambient_dim = c.ambient_dim();
  soup.positions = c.positions();
  for (std::uint32_t e = 0; e < c.count(1); ++e) {
    auto ed = c.edge(e);
    soup.edges.push_back({ed[0], ed[1]});
  }
  for (std::uint32_t f = 0; f < c.count(2); ++f) soup.faces.push_back(c.face_cycle(f));
  for (int k = 3; k <= c.top_rank(); ++k) {
    auto& level = soup.higher.emplace_back();
    const Incidence& table = c.boundary(k);
    for (std::uint32_t x = 0; x < table.size(); ++x) {
      auto ids = table.ids(x);
      level.emplace_back(ids.begin(), ids.end());
    }
  }
  soup.face_colors = c.colors(2);
  for (int k = 3; k <= c.top_rank(); ++k) soup.higher_colors.push_back(c.colors(k));
  return soup;
}

}  // namespace cw4d
