// Tests of the section atlas (atlas.hpp) against independent counts: the critical offsets are
// the vertex heights computed here, and the f-vector of a convex polytope's section by a plane
// through no vertex is read off the heights alone (a section vertex per edge, an edge per
// 2-face and a polygon per 3-cell that has vertices on both sides), at seeded random offsets
// inside each interval.
#include <catch2/catch.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <bit>
#include <random>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/atlas.hpp"
#include "cw4d/section/section.hpp"

using namespace cw4d;
using F = std::vector<std::size_t>;

namespace {

// The f-vector of the section of a convex 4-polytope by n.x = d through no vertex, from the
// vertex heights only.
F counted_fvector(const Complex& c, const Eigen::VectorXd& unit, double d) {
  F f(3, 0);
  for (int rank = 1; rank <= 3; ++rank)
    for (std::uint32_t i = 0; i < c.count(rank); ++i) {
      bool below = false, above = false;
      for (auto v : c.vertices_of(rank, i)) {
        const double h = unit.dot(c.position(v)) - d;
        below |= h<0, above |= h> 0;
      }
      if (below && above) ++f[static_cast<std::size_t>(rank - 1)];
    }
  return f;
}

F section_fvector(const Complex& c, const Eigen::VectorXd& unit, double d) {
  const Section s = section(c, Hyperplane::from(unit, d));
  return {s.complex.count(0), s.complex.count(1), s.complex.count(2)};
}

Eigen::VectorXd vec(std::initializer_list<double> x) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(x.size()));
  std::copy(x.begin(), x.end(), v.data());
  return v;
}

}  // namespace

TEST_CASE("atlas: the tesseract along an axis", "[atlas]") {
  const Atlas a = section_atlas(make_cube(4), vec({3, 0, 0, 0}));
  CHECK(a.critical_offsets == std::vector<double>{-1, 1});
  REQUIRE(a.intervals.size() == 1);
  CHECK(a.intervals[0].from == -1);
  CHECK(a.intervals[0].to == 1);
  CHECK(a.intervals[0].section.offset == 0);
  CHECK(a.intervals[0].section.fvector == F{8, 12, 6});  // a cube
  // The planes x = +-1 hold a whole cell: the cube itself.
  REQUIRE(a.critical.size() == 2);
  CHECK(a.critical[0].fvector == F{8, 12, 6});
  CHECK(a.critical[1].fvector == F{8, 12, 6});
}

TEST_CASE("atlas: the tesseract along its long diagonal", "[atlas]") {
  // Heights (+-1 +-1 +-1 +-1)/2: -2, -1, 0, 1, 2 (1, 4, 6, 4, 1 vertices). Between the levels
  // with m and m+1 coordinates +1 lie C(4,m)(4-m) edges (4, 12, 12, 4), the 2-faces whose
  // heights span the level (6, 18, 18, 6) and the cubes (4, 8, 8, 4): tetrahedron, truncated
  // tetrahedron, truncated tetrahedron, tetrahedron.
  const Complex t = make_cube(4);
  const Atlas a = section_atlas(t, vec({1, 1, 1, 1}));
  CHECK(a.critical_offsets == std::vector<double>{-2, -1, 0, 1, 2});
  REQUIRE(a.intervals.size() == 4);
  CHECK(a.intervals[0].section.fvector == F{4, 6, 4});
  CHECK(a.intervals[1].section.fvector == F{12, 18, 8});
  CHECK(a.intervals[2].section.fvector == F{12, 18, 8});
  CHECK(a.intervals[3].section.fvector == F{4, 6, 4});
  // Through the middle six vertices: the octahedron; through four: their tetrahedron.
  REQUIRE(a.critical.size() == 5);
  CHECK(a.critical[1].fvector == F{4, 6, 4});
  CHECK(a.critical[2].fvector == F{6, 12, 8});
  CHECK(a.critical[3].fvector == F{4, 6, 4});
}

TEST_CASE("atlas: the 4-simplex along a generic normal", "[atlas]") {
  // A plane with k vertices below crosses k(5-k) edges, 10 - C(k,3) - C(5-k,3) triangles and
  // 5 - C(k,4) - C(5-k,4) tetrahedra: (4,6,4), (6,9,5), (6,9,5), (4,6,4).
  const Atlas a = section_atlas(make_simplex(4), vec({0.3, -1.1, 0.7, 2.9}));
  REQUIRE(a.critical_offsets.size() == 5);
  REQUIRE(a.intervals.size() == 4);
  CHECK(a.intervals[0].section.fvector == F{4, 6, 4});
  CHECK(a.intervals[1].section.fvector == F{6, 9, 5});
  CHECK(a.intervals[2].section.fvector == F{6, 9, 5});
  CHECK(a.intervals[3].section.fvector == F{4, 6, 4});
}

TEST_CASE("atlas: the 24-cell along a seeded random normal", "[atlas]") {
  std::mt19937 rng(4242);
  std::normal_distribution<double> gauss;
  const Complex c = load_model("24-cell");
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd n = vec({gauss(rng), gauss(rng), gauss(rng), gauss(rng)});
    const Eigen::VectorXd unit = n.normalized();
    const Atlas a = section_atlas(c, n);
    // The critical offsets are the 24 distinct vertex heights.
    std::vector<double> h;
    for (std::uint32_t v = 0; v < c.count(0); ++v) h.push_back(unit.dot(c.position(v)));
    std::sort(h.begin(), h.end());
    REQUIRE(a.critical_offsets.size() == 24);
    for (std::size_t i = 0; i < h.size(); ++i)
      CHECK(std::abs(a.critical_offsets[i] - h[i]) < 1e-14);
    REQUIRE(a.intervals.size() == 23);
    for (const auto& iv : a.intervals) {
      INFO("interval (" << iv.from << ", " << iv.to << ")");
      CHECK(iv.section.fvector == counted_fvector(c, unit, iv.section.offset));
      std::uniform_real_distribution<double> inside(iv.from, iv.to);
      for (int k = 0; k < 4; ++k) {
        const double d = inside(rng);
        if (d <= iv.from || d >= iv.to) continue;
        CHECK(section_fvector(c, unit, d) == iv.section.fvector);
        CHECK(counted_fvector(c, unit, d) == iv.section.fvector);
      }
    }
  }
}

TEST_CASE("atlas: placement, merging and bad input", "[atlas]") {
  // A placed model: the heights of the moved vertices (the tesseract shifted by 0.5 along x).
  Eigen::VectorXd t = Eigen::VectorXd::Zero(4);
  t(0) = 0.5;
  const Atlas a = section_atlas(make_cube(4), vec({1, 0, 0, 0}), AffineTransform::translation(t));
  CHECK(a.critical_offsets == std::vector<double>{-0.5, 1.5});
  // Heights closer than the tolerance merge; farther ones do not.
  Complex c = make_cube(4);
  c.positions_mut()(0, 0) += 1e-12;
  CHECK(critical_offsets(c, vec({1, 0, 0, 0}), AffineTransform::identity(4)).size() == 2);
  c.positions_mut()(0, 0) += 1e-6;
  CHECK(critical_offsets(c, vec({1, 0, 0, 0}), AffineTransform::identity(4)).size() == 3);
  CHECK_THROWS_AS(section_atlas(make_cube(4), vec({0, 0, 0, 0})), InputError);
  CHECK_THROWS_AS(section_atlas(make_cube(4), vec({1, 0, 0})), InputError);
}

TEST_CASE("atlas: where the plane only touches the model, the contact's f-vector", "[atlas]") {
  // The face of the cube [-1, 1]^4 on which n.x is largest, for n with m nonzero components
  // (of either sign, permuted, placed by a rotation), is a (4 - m)-cube: 2^d vertices,
  // d 2^(d-1) edges and C(d, 2) 2^(d-2) squares for d = 4 - m. For m = 1 it is a whole cell,
  // which section() returns: no contact then; for m >= 2 the section is empty.
  const Complex t = make_cube(4);
  const F cube_face[5] = {{}, {8, 12, 6}, {4, 4, 1}, {2, 1, 0}, {1, 0, 0}};
  const AffineTransform turn = AffineTransform::rotation(4, 0, 3, 0.3);
  for (int mask = 1; mask < 16; ++mask) {
    const int m = std::popcount(static_cast<unsigned>(mask));
    Eigen::VectorXd n(4);
    for (int j = 0; j < 4; ++j) n[j] = (mask >> j & 1) ? (j % 2 ? -1.0 : 1.0) : 0.0;
    for (const bool placed : {false, true}) {
      INFO("mask " << mask << (placed ? " placed" : ""));
      const Atlas a = placed ? section_atlas(t, turn.linear() * n, turn) : section_atlas(t, n);
      REQUIRE(a.critical.size() == static_cast<std::size_t>(m + 1));
      for (const std::size_t end : {std::size_t{0}, a.critical.size() - 1}) {
        const AtlasSection& c = a.critical[end];
        if (m == 1) {
          CHECK(c.fvector == cube_face[1]);
          CHECK(c.contact.empty());
        } else {
          CHECK(c.fvector == F{0, 0, 0});
          CHECK(c.contact == cube_face[m]);
        }
      }
      // Between the ends every critical section is a solid's: no contact.
      for (std::size_t i = 1; i + 1 < a.critical.size(); ++i) {
        CHECK(a.critical[i].fvector != F{0, 0, 0});
        CHECK(a.critical[i].contact.empty());
      }
      for (const auto& i : a.intervals) CHECK(i.section.contact.empty());
    }
  }
  // In R^3: the cube along (1, 1, 0) touches in an edge, the octahedron along (1, 2, 3) in a
  // vertex (counts of ranks 0 and 1).
  const Atlas cube = section_atlas(make_cube(3), vec({1, 1, 0}));
  CHECK(cube.critical.front().contact == F{2, 1});
  CHECK(cube.critical.back().contact == F{2, 1});
  const Atlas octa = section_atlas(make_orthoplex(3), vec({1, 2, 3}));
  CHECK(octa.critical.front().contact == F{1, 0});
  CHECK(octa.critical.back().contact == F{1, 0});
}
