// self_intersects against an independent oracle: every pair of triangles of the fan-triangulated
// section faces, decided with CGAL's exact predicates (Exact_predicates_inexact_constructions
// kernel, do_intersect of triangles and segments).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/wythoff.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"

using namespace cw4d;

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_3;
using Tri = K::Triangle_3;
using Seg = K::Segment_3;

struct OracleTri {
  std::array<std::uint32_t, 3> v;
  std::uint32_t face;
  Tri t;
  CGAL::Bbox_3 box;
};

// Whether the surface's faces (each a convex polygon, fan-triangulated) meet anywhere but where
// genuinely neighbouring faces do: along a common edge or at a common vertex. Triangles of one
// face are not compared. Triangles of two faces sharing two vertices u, w contain the segment uw:
// the faces meet there beyond their common boundary unless uw is an edge of both (then two
// non-coplanar triangles meet only in it). Triangles sharing one vertex v meet beyond v exactly
// when the edge opposite v of one meets the other (their intersection is convex, contains v and
// leaves through the edge opposite v of the triangle it ends in). Triangles sharing no vertex
// are tested whole. Closed triangles, exact predicates: touching counts.
bool oracle_self_intersects(const Complex& s) {
  std::vector<OracleTri> tris;
  std::set<std::pair<std::uint32_t, std::uint64_t>> edges;  // (face, min id * n + max id)
  auto pt = [&](std::uint32_t v) {
    const Eigen::VectorXd p = s.position(v);
    return Point(p(0), p(1), p(2));
  };
  for (std::uint32_t f = 0; f < s.count(2); ++f) {
    const auto c = s.face_cycle(f);
    REQUIRE(c.size() >= 3);
    for (std::size_t i = 0; i < c.size(); ++i) {
      const std::uint32_t u = c[i], w = c[(i + 1) % c.size()];
      edges.insert({f, std::uint64_t{std::min(u, w)} * s.count(0) + std::max(u, w)});
    }
    // (convex: every corner turns the same way about the face's area vector)
    Eigen::Vector3d area = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < c.size(); ++i)
      area += s.position(c[i]).head<3>().cross(s.position(c[(i + 1) % c.size()]).head<3>());
    for (std::size_t i = 0; i < c.size(); ++i) {
      const Eigen::Vector3d a = s.position(c[i]).head<3>(),
                            b = s.position(c[(i + 1) % c.size()]).head<3>(),
                            d = s.position(c[(i + 2) % c.size()]).head<3>();
      REQUIRE((b - a).cross(d - b).dot(area) > 0.0);
    }
    for (std::size_t i = 1; i + 1 < c.size(); ++i) {
      OracleTri t{{c[0], c[i], c[i + 1]}, f, Tri(pt(c[0]), pt(c[i]), pt(c[i + 1])), {}};
      t.box = t.t.bbox();
      tris.push_back(t);
    }
  }
  for (std::size_t i = 0; i < tris.size(); ++i)
    for (std::size_t j = i + 1; j < tris.size(); ++j) {
      const OracleTri &a = tris[i], &b = tris[j];
      if (a.face == b.face || !CGAL::do_overlap(a.box, b.box)) continue;
      int shared = 0, ia = -1, ib = -1;
      for (int x = 0; x < 3; ++x)
        for (int y = 0; y < 3; ++y)
          if (a.v[x] == b.v[y]) ++shared, ia = x, ib = y;
      if (shared >= 2) {
        std::uint32_t u = 0, w = 0;
        int k = 0;
        for (int x = 0; x < 3; ++x)
          for (int y = 0; y < 3; ++y)
            if (a.v[x] == b.v[y]) (k++ == 0 ? u : w) = a.v[x];
        const std::uint64_t key = std::uint64_t{std::min(u, w)} * s.count(0) + std::max(u, w);
        if (!edges.count({a.face, key}) || !edges.count({b.face, key})) return true;
        continue;
      }
      if (shared == 0) {
        if (CGAL::do_intersect(a.t, b.t)) return true;
        continue;
      }
      const Seg ea(a.t[(ia + 1) % 3], a.t[(ia + 2) % 3]), eb(b.t[(ib + 1) % 3], b.t[(ib + 2) % 3]);
      if (CGAL::do_intersect(ea, b.t) || CGAL::do_intersect(eb, a.t)) return true;
    }
  return false;
}

Eigen::VectorXd random_unit(std::mt19937& rng, int n) {
  std::normal_distribution<double> g;
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v(i) = g(rng);
  return v.normalized();
}

// Seeded planes through a model (offsets within 0.6 of its circumradius): for each non-empty
// section, whether self_intersects (through Section::self_intersecting) and the oracle agree.
struct Tally {
  int sections = 0, oracle = 0, flagged = 0, agree = 0;
};

Tally compare(const Complex& c, unsigned seed, int planes) {
  double r = 0.0;
  for (std::uint32_t v = 0; v < c.count(0); ++v) r = std::max(r, c.position(v).norm());
  std::mt19937 rng(seed);
  Tally t;
  for (int i = 0; i < planes; ++i) {
    const Eigen::VectorXd n = random_unit(rng, 4);
    const double d = std::uniform_real_distribution<double>(-0.6, 0.6)(rng) * r;
    const Section s = section(c, Hyperplane{n, d});
    if (s.empty()) continue;
    INFO("n = " << n.transpose() << ", d = " << d);
    const bool oracle = oracle_self_intersects(s.complex);
    CHECK(s.self_intersecting == oracle);
    CHECK(self_intersects(s.complex) == oracle);
    ++t.sections;
    t.oracle += oracle ? 1 : 0;
    t.flagged += s.self_intersecting ? 1 : 0;
    t.agree += s.self_intersecting == oracle ? 1 : 0;
  }
  return t;
}

}  // namespace

// The regular star polychora whose cells are convex (icosahedra, dodecahedra, tetrahedra), so
// that every section face is a convex polygon the oracle can fan-triangulate.
TEST_CASE("self_intersects agrees with exact triangle tests on star polychoron sections",
          "[self_intersection][star]") {
  for (const char* name : {"icosahedral 120-cell", "grand 120-cell", "grand 600-cell"}) {
    INFO(name);
    const Tally t = compare(make_star_polychoron(name), 2718, 30);
    CHECK(t.sections >= 25);
    CHECK(t.agree == t.sections);
  }
}

TEST_CASE("self_intersects agrees with exact triangle tests on Miratope's icosahedral 120-cell",
          "[self_intersection][star][data]") {
  const auto path = std::filesystem::path(CW4D_TEST_DATA_DIR) / "miratope" / "regular" /
                    "Icosahedral hecatonicosachoron.off";
  const Tally t = compare(read_off_file(path.string()), 1618, 30);
  CHECK(t.sections >= 25);
  CHECK(t.agree == t.sections);
}

TEST_CASE("self_intersects flags no section of a convex polychoron, as the oracle finds",
          "[self_intersection][convex]") {
  for (const char* name : {"tesseract", "24-cell", "120-cell", "600-cell"}) {
    INFO(name);
    const Tally t = compare(load_model(name), 3141, 30);
    CHECK(t.sections >= 25);
    CHECK(t.oracle == 0);
    CHECK(t.flagged == 0);
  }
}

// Non-convex but embedded boundaries (round built-ins with convex cells): sections the oracle
// finds embedded, and self_intersects must not flag them, though neighbouring faces of their
// sections fold both ways.
TEST_CASE("self_intersects agrees with exact triangle tests on non-convex embedded models",
          "[self_intersection][nonconvex]") {
  for (const char* spec : {"tiger:2,2,0.6,12", "spheritorus:2,0.7,12", "ditorus:3,1.5,0.5,10"}) {
    INFO(spec);
    const Tally t = compare(load_model(spec), 1414, 30);
    CHECK(t.sections >= 20);
    CHECK(t.oracle == 0);
    CHECK(t.agree == t.sections);
  }
}

// Hand-made pairs of faces (3D OFF, not closed): crossings the old neighbour rule (faces sharing
// a vertex are not compared) missed, and neighbours that do not cross.
TEST_CASE("self_intersects finds faces crossing beyond the vertices they share",
          "[self_intersection][hand]") {
  auto off = [](const std::string& text) {
    std::istringstream in(text);
    return read_off(in, "hand");
  };
  // Two squares in the planes y = 0 and x = 0 sharing their diagonal from (0,0,-1) to (0,0,1).
  const Complex chord =
      off("OFF\n6 2 0\n0 0 -1\n1 0 0\n0 0 1\n-1 0 0\n0 1 0\n0 -1 0\n4 0 1 2 3\n4 0 4 2 5\n");
  // Two triangles sharing the vertex 0, in the planes z = 0 and y = 0, crossing along the x axis.
  const Complex fan = off("OFF\n5 2 0\n0 0 0\n2 -1 0\n2 1 0\n3 0 -1\n3 0 1\n3 0 1 2\n3 0 3 4\n");
  // The same triangles with the second turned to z < 0 only: they meet in the vertex alone.
  const Complex touch = off("OFF\n5 2 0\n0 0 0\n2 -1 0\n2 1 0\n3 0 -1\n3 0 -2\n3 0 1 2\n3 0 3 4\n");
  // Two squares folded along a common edge (a book): neighbours that do not cross.
  const Complex book =
      off("OFF\n6 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n1 0 1\n0 0 1\n4 0 1 2 3\n4 1 0 5 4\n");
  CHECK(oracle_self_intersects(chord));
  CHECK(self_intersects(chord));
  CHECK(oracle_self_intersects(fan));
  CHECK(self_intersects(fan));
  CHECK_FALSE(oracle_self_intersects(touch));
  CHECK_FALSE(self_intersects(touch));
  CHECK_FALSE(oracle_self_intersects(book));
  CHECK_FALSE(self_intersects(book));
}

// Two non-convex faces in the planes z = 0 and y = 0 sharing a run of collinear vertices along
// the x axis, x = 3, ..., 2 + n (ids 0 .. n-1), and the ends of the chord from x = 0 to x = 2
// (ids n, n + 1: beyond the 8 smallest shared ids once n >= 8). With `cross`, each face is a
// strip on the negative side of the axis plus a triangle over the chord on the positive side,
// so the chord's midpoint lies inside both and they pass through each other (like two slotted
// cards); without, each face is a rectangle on the positive side with that triangle cut away,
// and they meet only in their common boundary.
Complex collinear_pair(int n, bool cross) {
  std::ostringstream text;
  const int x_end = 2 + n, far = cross ? -1 : 2;
  const int count = n + 2 + 6;
  text << "OFF\n" << count << " 2 0\n";
  for (int i = 1; i <= n; ++i) text << 2 + i << " 0 0\n";  // ids 0 .. n-1: the run
  const int u = n, w = n + 1;                              // x = 0 and x = 2
  text << "0 0 0\n2 0 0\n";
  const int fa = n + 2, ga = n + 5;  // apex, far corner at x_end, far corner at x = 0
  text << "1 1 0\n" << x_end << ' ' << far << " 0\n0 " << far << " 0\n";
  text << "1 0 1\n" << x_end << " 0 " << far << "\n0 0 " << far << '\n';
  auto face = [&](int apex, int corner_end, int corner_start) {
    text << 5 + n << ' ' << u << ' ' << apex << ' ' << w;
    for (int i = 0; i < n; ++i) text << ' ' << i;
    text << ' ' << corner_end << ' ' << corner_start << '\n';
  };
  face(fa, fa + 1, fa + 2);
  face(ga, ga + 1, ga + 2);
  std::istringstream in(text.str());
  return read_off(in, "collinear");
}

TEST_CASE("self_intersects sees every vertex two faces share, however many",
          "[self_intersection][hand]") {
  for (int n = 0; n <= 12; ++n) {
    INFO(n + 2 << " shared vertices");
    CHECK(self_intersects(collinear_pair(n, true)));
    CHECK_FALSE(self_intersects(collinear_pair(n, false)));
  }
}
