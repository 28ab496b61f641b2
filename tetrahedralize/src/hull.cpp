// Convex hull -> face lattice. CGAL's dD triangulation gives the hull as simplices (exact
// predicates, so the simplicial hull is right even for rounded golden-ratio coordinates); the
// rest is ours: simplices on one hyperplane become one facet, lower faces are the intersections
// of pairs of higher faces that span a flat of the right dimension, and a point is a vertex
// only when the facets through it meet in that point alone.
//
// This is the only translation unit that includes CGAL (compile time, and the GPL fence).
#include <CGAL/Epick_d.h>
#include <CGAL/Spatial_sort_traits_adapter_d.h>
#include <CGAL/Triangulation.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/tetrahedralize/hull.hpp"

namespace cw4d {

namespace {

// Fixed-dimension kernels: about 5x faster than Dynamic_dimension_tag on the 14400 points of the
// omnitruncated 120-cell (fewer allocations, static filters); one instantiation per dimension.
template <int D>
using Kernel = CGAL::Epick_d<CGAL::Dimension_tag<D>>;
template <int D>
using Triangulation = CGAL::Triangulation<
    Kernel<D>, CGAL::Triangulation_data_structure<
                   CGAL::Dimension_tag<D>, CGAL::Triangulation_vertex<Kernel<D>, std::uint32_t>,
                   CGAL::Triangulation_full_cell<Kernel<D>, std::uint32_t>>>;

using Ids = std::vector<std::uint32_t>;  // sorted point ids

struct Plane {
  Eigen::VectorXd normal;  // unit, outward
  double offset = 0.0;     // normal . x = offset on the plane
  double distance(Eigen::Ref<const Eigen::VectorXd> x) const { return normal.dot(x) - offset; }
};

// Hull simplex: dim point ids; neighbours[i] is the hull simplex across the ridge without
// points[i].
struct HullSimplex {
  Ids points;
  Ids neighbours;
  double quality = 0.0;  // parallelepiped volume / R^(dim-1)
  Plane plane;
};

Ids sorted_intersection(const Ids& a, const Ids& b) {
  Ids out;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

// Greedy affine basis of the points ids (Gram-Schmidt on the farthest point each step): the
// affine rank counts the steps that reach beyond tol. basis gets the orthonormal directions.
int affine_rank(const Eigen::MatrixXd& p, const Ids& ids, double tol, Eigen::MatrixXd* basis) {
  const Eigen::Index dim = p.rows();
  Eigen::MatrixXd dirs(dim, dim);
  int rank = 0;
  if (ids.empty()) return -1;
  const Eigen::VectorXd origin = p.col(ids[0]);
  while (rank < dim) {
    double best = tol;
    Eigen::VectorXd best_r;
    for (std::uint32_t id : ids) {
      Eigen::VectorXd r = p.col(id) - origin;
      for (int j = 0; j < rank; ++j) r -= dirs.col(j).dot(r) * dirs.col(j);
      const double len = r.norm();
      if (len > best) {
        best = len;
        best_r = r / len;
      }
    }
    if (best_r.size() == 0) break;
    dirs.col(rank++) = best_r;
  }
  if (basis) *basis = dirs.leftCols(rank);
  return rank;
}

// Least-squares hyperplane of the points ids, oriented like `like`.
Plane fit_plane(const Eigen::MatrixXd& p, const Ids& ids, const Eigen::VectorXd& like) {
  const Eigen::Index dim = p.rows();
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(dim);
  for (std::uint32_t id : ids) mean += p.col(id);
  mean /= static_cast<double>(ids.size());
  Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(dim, dim);
  for (std::uint32_t id : ids) {
    const Eigen::VectorXd r = p.col(id) - mean;
    cov.noalias() += r * r.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
  Plane plane{eig.eigenvectors().col(0), 0.0};  // eigenvalues ascending
  if (plane.normal.dot(like) < 0) plane.normal = -plane.normal;
  plane.offset = plane.normal.dot(mean);
  return plane;
}

// Near-duplicate removal: the first of points within tol of each other stays (input order).
Ids unique_points(const Eigen::MatrixXd& p, double tol) {
  std::multimap<double, std::uint32_t> by_x;  // kept points by first coordinate
  Ids kept;
  for (std::uint32_t id = 0; id < static_cast<std::uint32_t>(p.cols()); ++id) {
    const double x = p(0, id);
    bool duplicate = false;
    for (auto it = by_x.lower_bound(x - tol); it != by_x.end() && it->first <= x + tol; ++it)
      if ((p.col(id) - p.col(it->second)).norm() <= tol) {
        duplicate = true;
        break;
      }
    if (duplicate) continue;
    by_x.emplace(x, id);
    kept.push_back(id);
  }
  return kept;
}

// The simplices of the hull: the infinite full cells of a triangulation of the points ids, as
// point ids plus the hull neighbours (cell ids); planes are filled in by the caller.
template <int D>
std::vector<HullSimplex> cgal_hull_simplices(const Eigen::MatrixXd& p, const Ids& ids) {
  using K = Kernel<D>;
  using T = Triangulation<D>;
  std::vector<typename K::Point_d> pts;
  pts.reserve(ids.size());
  for (std::uint32_t id : ids) pts.emplace_back(p.col(id).data(), p.col(id).data() + D);
  // Insert in spatial order, as CGAL's range insert does, but keep each vertex's point id.
  std::vector<std::size_t> order(pts.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  using Map = typename CGAL::Pointer_property_map<typename K::Point_d>::const_type;
  CGAL::spatial_sort(
      order.begin(), order.end(),
      CGAL::Spatial_sort_traits_adapter_d<K, Map>(CGAL::make_property_map(std::as_const(pts))));
  T t(D);
  typename T::Full_cell_handle hint;
  for (std::size_t i : order) {
    auto v = t.insert(pts[i], hint);
    v->data() = ids[i];  // near duplicates were removed before, so this is v's only point
    hint = v->full_cell();
  }
  if (t.current_dimension() < D)
    throw InputError("convex_hull: the points lie in a lower-dimensional flat");

  std::vector<typename T::Full_cell_handle> cells;
  for (auto c = t.full_cells_begin(); c != t.full_cells_end(); ++c)
    if (t.is_infinite(c)) {
      c->data() = static_cast<std::uint32_t>(cells.size());
      cells.push_back(c);
    }
  std::vector<HullSimplex> out(cells.size());
  for (std::size_t s = 0; s < cells.size(); ++s) {
    const auto c = cells[s];
    const int inf = c->index(t.infinite_vertex());
    for (int i = 0; i <= D; ++i) {
      if (i == inf) continue;
      out[s].points.push_back(c->vertex(i)->data());
      out[s].neighbours.push_back(c->neighbor(i)->data());  // infinite too: shares that vertex
    }
  }
  return out;
}

// Hull simplices with their outward planes and shape quality.
std::vector<HullSimplex> hull_simplices(const Eigen::MatrixXd& p, const Ids& ids,
                                        const Eigen::VectorXd& centre, double radius) {
  const int dim = static_cast<int>(p.rows());
  std::vector<HullSimplex> out =
      dim == 3 ? cgal_hull_simplices<3>(p, ids) : cgal_hull_simplices<4>(p, ids);
  Eigen::MatrixXd u(dim, dim - 1);
  for (HullSimplex& h : out) {
    const Eigen::VectorXd q0 = p.col(h.points[0]);
    for (int j = 1; j < dim; ++j) u.col(j - 1) = p.col(h.points[j]) - q0;
    // The normal is the kernel of u^T; its length from the Gram determinant is the volume.
    Eigen::FullPivLU<Eigen::MatrixXd> lu(u.transpose());
    const Eigen::MatrixXd ker = lu.kernel();
    const double volume = std::sqrt(std::max(0.0, (u.transpose() * u).determinant()));
    h.quality = volume / std::pow(radius, dim - 1);
    if (ker.cols() == 1 && ker.col(0).norm() > 0) {
      h.plane.normal = ker.col(0).normalized();
      if (h.plane.normal.dot(q0 - centre) < 0) h.plane.normal = -h.plane.normal;
      h.plane.offset = h.plane.normal.dot(q0);
    } else {
      h.quality = 0.0;
    }
  }
  return out;
}

struct UnionFind {
  Ids parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void unite(std::uint32_t a, std::uint32_t b) { parent[find(a)] = find(b); }
};

// point -> the facets through it.
std::vector<Ids> incidence(std::size_t n_points, const std::vector<Ids>& sets) {
  std::vector<Ids> out(n_points);
  for (std::uint32_t f = 0; f < sets.size(); ++f)
    for (std::uint32_t id : sets[f]) out[id].push_back(f);
  return out;
}

// Facets of the hull as sorted point sets: coplanar hull simplices grouped by flooding from the
// best-shaped unassigned simplex, groups on one plane merged, and each facet completed with
// every nearby point on its plane.
std::vector<Ids> hull_facets(const Eigen::MatrixXd& p, std::vector<HullSimplex>& simplices,
                             double tol) {
  const int dim = static_cast<int>(p.rows());
  Ids order(simplices.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return simplices[a].quality > simplices[b].quality;
  });
  Ids group(simplices.size(), no_index);
  std::vector<Plane> planes;
  std::vector<Ids> sets;
  for (std::uint32_t seed : order) {
    if (group[seed] != no_index || simplices[seed].quality <= 0.0) continue;
    const auto g = static_cast<std::uint32_t>(planes.size());
    const Plane plane = simplices[seed].plane;
    planes.push_back(plane);
    Ids members{seed}, stack{seed};
    group[seed] = g;
    while (!stack.empty()) {
      const std::uint32_t s = stack.back();
      stack.pop_back();
      for (std::uint32_t nb : simplices[s].neighbours) {
        if (group[nb] != no_index) continue;
        const bool on = std::all_of(
            simplices[nb].points.begin(), simplices[nb].points.end(),
            [&](std::uint32_t id) { return std::abs(plane.distance(p.col(id))) <= tol; });
        if (!on) continue;
        group[nb] = g;
        members.push_back(nb);
        stack.push_back(nb);
      }
    }
    Ids set;
    for (std::uint32_t s : members)
      set.insert(set.end(), simplices[s].points.begin(), simplices[s].points.end());
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    sets.push_back(std::move(set));
  }
  for (std::size_t g = 0; g < sets.size(); ++g) planes[g] = fit_plane(p, sets[g], planes[g].normal);

  // Groups that are one facet split by a sliver: same plane, sharing a point.
  const auto on_plane = [&](const Plane& plane, const Ids& set) {
    return std::all_of(set.begin(), set.end(), [&](std::uint32_t id) {
      return std::abs(plane.distance(p.col(id))) <= tol;
    });
  };
  UnionFind uf(sets.size());
  {
    const std::vector<Ids> through = incidence(static_cast<std::size_t>(p.cols()), sets);
    for (std::uint32_t f = 0; f < sets.size(); ++f)
      for (std::uint32_t id : sets[f])
        for (std::uint32_t g : through[id])
          if (g > f && uf.find(f) != uf.find(g) && planes[f].normal.dot(planes[g].normal) > 0 &&
              on_plane(planes[f], sets[g]))
            uf.unite(f, g);
  }
  std::map<std::uint32_t, Ids> merged;
  for (std::uint32_t f = 0; f < sets.size(); ++f) {
    Ids& m = merged[uf.find(f)];
    m.insert(m.end(), sets[f].begin(), sets[f].end());
  }
  std::vector<Ids> facets;
  std::vector<Plane> facet_planes;
  for (auto& [root, set] : merged) {
    std::sort(set.begin(), set.end());
    set.erase(std::unique(set.begin(), set.end()), set.end());
    // Groups seeded by slivers on a lower face span no hyperplane: not facets.
    if (static_cast<int>(set.size()) < dim || affine_rank(p, set, tol, nullptr) < dim - 1) continue;
    facet_planes.push_back(
        set.size() == sets[root].size() ? planes[root] : fit_plane(p, set, planes[root].normal));
    facets.push_back(std::move(set));
  }

  // Points on a facet's plane that only neighbouring facets' simplices reached.
  const std::vector<Ids> through = incidence(static_cast<std::size_t>(p.cols()), facets);
  std::vector<Ids> completed = facets;
  for (std::uint32_t f = 0; f < facets.size(); ++f) {
    for (std::uint32_t id : facets[f])
      for (std::uint32_t g : through[id])
        if (g != f)
          for (std::uint32_t other : facets[g])
            if (std::abs(facet_planes[f].distance(p.col(other))) <= tol)
              completed[f].push_back(other);
    std::sort(completed[f].begin(), completed[f].end());
    completed[f].erase(std::unique(completed[f].begin(), completed[f].end()), completed[f].end());
  }
  return completed;
}

// A point is a vertex when the facets through it have only it in common.
std::vector<bool> hull_vertices(std::size_t n_points, const std::vector<Ids>& facets) {
  const std::vector<Ids> through = incidence(n_points, facets);
  std::vector<bool> vertex(n_points, false);
  for (std::uint32_t id = 0; id < n_points; ++id) {
    if (through[id].empty()) continue;
    Ids common = facets[through[id][0]];
    for (std::size_t k = 1; k < through[id].size() && common.size() > 1; ++k)
      common = sorted_intersection(common, facets[through[id][k]]);
    vertex[id] = common.size() == 1;
  }
  return vertex;
}

// Vertices of a polygon in cyclic order around its centroid, in its own plane.
Ids polygon_cycle(const Eigen::MatrixXd& p, const Ids& ids, double tol) {
  Eigen::MatrixXd basis;
  affine_rank(p, ids, tol, &basis);
  Eigen::VectorXd centroid = Eigen::VectorXd::Zero(p.rows());
  for (std::uint32_t id : ids) centroid += p.col(id);
  centroid /= static_cast<double>(ids.size());
  std::vector<std::pair<double, std::uint32_t>> by_angle;
  for (std::uint32_t id : ids) {
    const Eigen::VectorXd r = p.col(id) - centroid;
    by_angle.emplace_back(std::atan2(basis.col(1).dot(r), basis.col(0).dot(r)), id);
  }
  std::sort(by_angle.begin(), by_angle.end());
  Ids cycle;
  for (const auto& [angle, id] : by_angle) cycle.push_back(id);
  return cycle;
}

}  // namespace

Complex convex_hull(const Eigen::MatrixXd& input) {
  const int dim = static_cast<int>(input.rows());
  if (dim < 3 || dim > 4)
    throw InputError("convex_hull: points must have 3 or 4 coordinates, got " +
                     std::to_string(dim));
  if (input.cols() < dim + 1)
    throw InputError("convex_hull: " + std::to_string(dim) + "D hull needs at least " +
                     std::to_string(dim + 1) + " points, got " + std::to_string(input.cols()));
  if (input.cols() > std::numeric_limits<std::int32_t>::max())
    throw InputError("convex_hull: too many points");
  if (!input.allFinite()) throw InputError("convex_hull: a coordinate is not finite");
  // Every decision below is made on the points times a power of two that brings them near unit
  // size (exact), so the hull of points in units of 1e200 or 1e-200 is that of the same points
  // near 1 (squares of 1e200 would overflow, of 1e-200 underflow to 0).
  const double big = input.cwiseAbs().maxCoeff();
  if (big == 0.0) throw InputError("convex_hull: all points coincide (at the origin)");
  const Eigen::MatrixXd points = input * std::ldexp(1.0, std::min(-std::ilogb(big), 1000));

  const Eigen::VectorXd centre = points.rowwise().mean();
  const double radius = (points.colwise() - centre).colwise().norm().maxCoeff();
  const double tol = tol::hull_coplanar_rel * radius;
  const Ids ids = unique_points(points, tol);
  // Flat input: the width along the direction of least spread (CGAL checks exact flatness).
  {
    Eigen::MatrixXd cov = Eigen::MatrixXd::Zero(dim, dim);
    for (std::uint32_t id : ids) {
      const Eigen::VectorXd r = points.col(id) - centre;
      cov.noalias() += r * r.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(cov);
    double width = 0.0;
    for (std::uint32_t id : ids)
      width = std::max(width, std::abs(eig.eigenvectors().col(0).dot(points.col(id) - centre)));
    if (radius == 0.0 || ids.size() == 1) throw InputError("convex_hull: all points coincide");
    if (static_cast<int>(ids.size()) < dim + 1 || width <= tol)
      throw InputError("convex_hull: the points lie in a lower-dimensional flat");
  }

  std::vector<HullSimplex> simplices = hull_simplices(points, ids, centre, radius);
  const std::vector<Ids> facet_points = hull_facets(points, simplices, tol);
  const std::vector<bool> is_vertex =
      hull_vertices(static_cast<std::size_t>(points.cols()), facet_points);

  // level[k]: vertex sets of the rank-k faces; below[k]: their rank-(k-1) faces (k >= 3).
  std::vector<std::vector<Ids>> level(dim), below(dim);
  for (const Ids& set : facet_points) {
    Ids verts;
    for (std::uint32_t id : set)
      if (is_vertex[id]) verts.push_back(id);
    if (static_cast<int>(verts.size()) < dim)
      throw InputError("convex_hull: the points are too close to degenerate for a hull");
    level[dim - 1].push_back(std::move(verts));
  }
  // Every (k-1)-face is where two k-faces meet in a (k-1)-flat, and each k-face containing it
  // meets another one there, so pairs of k-faces sharing a vertex find them all.
  for (int k = dim - 1; k >= 3; --k) {
    const std::vector<Ids>& faces = level[k];
    const std::vector<Ids> through = incidence(static_cast<std::size_t>(points.cols()), faces);
    std::map<Ids, std::uint32_t> index;
    below[k].resize(faces.size());
    Ids stamp(faces.size(), no_index);
    for (std::uint32_t f = 0; f < faces.size(); ++f)
      for (std::uint32_t v : faces[f])
        for (std::uint32_t g : through[v]) {
          if (g <= f || stamp[g] == f) continue;
          stamp[g] = f;
          Ids common = sorted_intersection(faces[f], faces[g]);
          if (static_cast<int>(common.size()) < k ||
              affine_rank(points, common, tol, nullptr) != k - 1)
            continue;
          const auto [it, fresh] =
              index.emplace(common, static_cast<std::uint32_t>(level[k - 1].size()));
          if (fresh) level[k - 1].push_back(std::move(common));
          below[k][f].push_back(it->second);
          below[k][g].push_back(it->second);
        }
    for (Ids& row : below[k]) {
      std::sort(row.begin(), row.end());
      row.erase(std::unique(row.begin(), row.end()), row.end());
    }
  }

  // Renumber the vertices in input order.
  Ids new_id(static_cast<std::size_t>(points.cols()), no_index);
  std::uint32_t n_vertices = 0;
  for (std::uint32_t id = 0; id < new_id.size(); ++id)
    if (is_vertex[id]) new_id[id] = n_vertices++;
  ComplexSoup soup;
  soup.ambient_dim = dim;
  soup.positions.resize(dim, n_vertices);
  for (std::uint32_t id = 0; id < new_id.size(); ++id)
    if (new_id[id] != no_index) soup.positions.col(new_id[id]) = input.col(id);
  for (const Ids& face : level[2]) {
    Ids cycle = polygon_cycle(points, face, tol);
    for (auto& v : cycle) v = new_id[v];
    soup.faces.push_back(std::move(cycle));
  }
  for (int k = 3; k < dim; ++k) soup.higher.push_back(std::move(below[k]));
  return build_complex(soup);
}

}  // namespace cw4d
