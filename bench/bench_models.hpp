#pragma once
// Big inputs for the slicer benchmarks (bench_slicer, bench_slicer_cgal, bench_memory), all
// deterministic: a disjoint union of translated tesseracts in one Complex, a triangulated torus
// as a closed Complex in R^3, a scene of randomly placed small polytopes, and the byte counts
// of a Complex and of SliceBuffers.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/slicer.hpp"

namespace cw4d::bench {

/// Bytes of a complex's arrays: positions, every boundary table, facet normals.
inline std::size_t complex_bytes(const Complex& c) {
  std::size_t b = static_cast<std::size_t>(c.positions().size()) * sizeof(double) +
                  static_cast<std::size_t>(c.facet_normals().size()) * sizeof(double);
  for (int k = 1; k <= c.top_rank(); ++k) {
    const Incidence& t = c.boundary(k);
    b += t.offsets().size() * 4 + t.all_ids().size() * 4 + t.all_signs().size();
  }
  return b;
}

/// Bytes of the section in the buffers (sizes, not capacities).
inline std::size_t buffers_bytes(const SliceBuffers& s) {
  std::size_t b = s.coords.size() * sizeof(double) + s.vertex_source.size() * sizeof(VertexSource) +
                  s.facet_normals.size() * sizeof(double);
  for (const Incidence& t : s.boundary)
    b += t.offsets().size() * 4 + t.all_ids().size() * 4 + t.all_signs().size();
  for (const auto& v : s.source) b += v.size() * 4;
  return b;
}

/// One Complex holding grid[0] x grid[1] x grid[2] x grid[3] disjoint copies of the tesseract
/// ([-1, 1]^4) at spacing 3: every rank copied with shifted ids, facet normals tiled. With
/// `solids` each copy also gets its rank-4 solid (its 8 outward cells, sign +1; the built-in
/// tesseract stores none), else the top rank is 3.
inline Complex tesseract_union(std::array<int, 4> grid, bool solids) {
  Complex t = load_model("tesseract");
  if (solids && t.top_rank() == 3) {
    std::vector<std::uint32_t> cells(t.count(3));
    for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = static_cast<std::uint32_t>(i);
    const std::vector<std::int8_t> plus(cells.size(), 1);
    t.boundary_mut(4).add_row(cells, plus);
  }
  const std::size_t copies = static_cast<std::size_t>(grid[0]) * grid[1] * grid[2] * grid[3];
  const int top = solids ? 4 : 3;
  Complex u(4);
  const Eigen::Index nv = static_cast<Eigen::Index>(t.count(0));
  Eigen::MatrixXd p(4, nv * static_cast<Eigen::Index>(copies));
  Eigen::MatrixXd normals(4, t.facet_normals().cols() * static_cast<Eigen::Index>(copies));
  for (int k = 1; k <= top; ++k)
    u.boundary_mut(k).reserve(t.count(k) * copies, t.boundary(k).entries() * copies);
  std::vector<std::uint32_t> ids;
  std::size_t copy = 0;
  for (int a = 0; a < grid[0]; ++a)
    for (int b = 0; b < grid[1]; ++b)
      for (int c = 0; c < grid[2]; ++c)
        for (int d = 0; d < grid[3]; ++d, ++copy) {
          const Eigen::Vector4d shift(3.0 * a, 3.0 * b, 3.0 * c, 3.0 * d);
          const Eigen::Index v0 = static_cast<Eigen::Index>(copy) * nv;
          p.middleCols(v0, nv) = t.positions().colwise() + shift;
          normals.middleCols(static_cast<Eigen::Index>(copy) * t.facet_normals().cols(),
                             t.facet_normals().cols()) = t.facet_normals();
          for (int k = 1; k <= top; ++k) {
            const Incidence& src = t.boundary(k);
            const auto base = static_cast<std::uint32_t>(copy * t.count(k - 1));
            for (std::size_t r = 0; r < src.size(); ++r) {
              ids.assign(src.ids(r).begin(), src.ids(r).end());
              for (auto& id : ids) id += base;
              u.boundary_mut(k).add_row(ids, src.signs(r));
            }
          }
        }
  u.set_positions(std::move(p));
  u.set_facet_normals(std::move(normals));
  return u;
}

/// The torus ((R + r cos v) cos u, (R + r cos v) sin u, r sin v), R = 1, r = 0.4, on an
/// nu x nv grid, each quad split into two triangles; a closed Complex in R^3 (vertices, 3 edges
/// per vertex, 2 triangles per vertex, outward facet normals) with one rank-3 solid when
/// `solid`. tris(i) lists triangle i's corners (counter-clockwise seen from outside), the same
/// order as its face in the Complex, for building other meshes.
struct Torus {
  int nu = 0, nv = 0;
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<std::uint32_t, 3>> tris;
  Complex complex{3};
};

inline Torus make_torus(int nu, int nv, bool solid) {
  constexpr double R = 1.0, r = 0.4;
  Torus t;
  t.nu = nu;
  t.nv = nv;
  const auto vid = [&](int i, int j) {
    return static_cast<std::uint32_t>((i % nu) * nv + (j % nv));
  };
  const std::size_t n = static_cast<std::size_t>(nu) * nv;
  Eigen::MatrixXd p(3, static_cast<Eigen::Index>(n));
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double u = 2.0 * std::numbers::pi * i / nu, v = 2.0 * std::numbers::pi * j / nv;
      const Eigen::Vector3d x((R + r * std::cos(v)) * std::cos(u),
                              (R + r * std::cos(v)) * std::sin(u), r * std::sin(v));
      p.col(vid(i, j)) = x;
      t.points.push_back(x);
    }
  Complex& c = t.complex;
  c.set_positions(std::move(p));
  // Edges 3 v + {0: v -> v+u, 1: v -> v+v, 2: v -> v+u+v}.
  Incidence& edges = c.boundary_mut(1);
  edges.reserve(3 * n, 6 * n);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      c.add_edge(vid(i, j), vid(i + 1, j));
      c.add_edge(vid(i, j), vid(i, j + 1));
      c.add_edge(vid(i, j), vid(i + 1, j + 1));
    }
  Incidence& faces = c.boundary_mut(2);
  faces.reserve(2 * n, 6 * n);
  Eigen::MatrixXd normals(3, static_cast<Eigen::Index>(2 * n));
  Eigen::Index f = 0;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const std::uint32_t a = vid(i, j), b = vid(i + 1, j), cc = vid(i + 1, j + 1),
                          d = vid(i, j + 1);
      // a -> b -> c: e_u(a) +, e_v(b) +, e_d(a) -;  a -> c -> d: e_d(a) +, e_u(d) -, e_v(a) -.
      const std::uint32_t t1[3] = {3 * a, 3 * b + 1, 3 * a + 2},
                          t2[3] = {3 * a + 2, 3 * d, 3 * a + 1};
      const std::int8_t s1[3] = {1, 1, -1}, s2[3] = {1, -1, -1};
      faces.add_row(t1, s1);
      faces.add_row(t2, s2);
      t.tris.push_back({a, b, cc});
      t.tris.push_back({a, cc, d});
      const auto& P = t.points;
      normals.col(f++) = (P[b] - P[a]).cross(P[cc] - P[a]).normalized();
      normals.col(f++) = (P[cc] - P[a]).cross(P[d] - P[a]).normalized();
    }
  c.set_facet_normals(std::move(normals));
  if (solid) {
    std::vector<std::uint32_t> all(2 * n);
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<std::uint32_t>(i);
    std::vector<std::int8_t> plus(2 * n, 1);
    c.boundary_mut(3).add_row(all, plus);
  }
  return t;
}

/// `count` objects, a tesseract or (every third) a 24-cell, each turned by six random
/// rotations and moved to a uniform random point of [0, box[0]] x ... x [0, box[3]].
inline Scene scattered_scene(std::size_t count, const Eigen::Vector4d& box, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto tesseract = std::make_shared<const Complex>(load_model("tesseract"));
  auto cell24 = std::make_shared<const Complex>(load_model("24-cell"));
  Scene scene;
  scene.objects.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    SceneObject obj;
    obj.model = i % 3 == 2 ? "24-cell" : "tesseract";
    obj.complex = i % 3 == 2 ? cell24 : tesseract;
    AffineTransform xf = AffineTransform::identity(4);
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        xf = AffineTransform::rotation(4, a, b, 2.0 * std::numbers::pi * unit(rng)) * xf;
    Eigen::VectorXd t(4);
    for (int a = 0; a < 4; ++a) t[a] = box[a] * unit(rng);
    obj.transform = AffineTransform::translation(t) * xf;
    scene.objects.push_back(std::move(obj));
  }
  return scene;
}

/// A generic unit normal in R^n from a seed.
inline Eigen::VectorXd seeded_normal(int n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = gauss(rng);
  return v.normalized();
}

}  // namespace cw4d::bench
