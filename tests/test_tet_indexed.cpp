// The indexed tetrahedral slice (TetSliceMesh) against an oracle written here from the mesh's
// tetrahedra alone (per tetrahedron: the crossings of its sign-changing edges, the convex polygon
// they span, oriented along the cell's projected outward normal), its welding (one vertex per
// crossing edge), its closed oriented surface, the soup API (a separate per-tetrahedron cut with
// a geometric orientation test: the same triangles in the same order), transforms that reflect,
// and the mesh's edge index.
#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"
#include "support/temp_dir.hpp"

using namespace cw4d;

namespace {

// An L-shaped prism with two non-convex faces (meshed by TetGen).
const char* kLPrismObj =
    "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
    "v 0 0 1\nv 2 0 1\nv 2 1 1\nv 1 1 1\nv 1 2 1\nv 0 2 1\n"
    "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n"
    "f 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\n";

struct Model {
  std::string name;
  Complex complex;
  TetMesh mesh;
};

const std::vector<Model>& models() {
  static const std::vector<Model> all = [] {
    std::vector<Model> m;
    for (const char* spec :
         {"5-cell", "tesseract", "24-cell", "120-cell", "600-cell", "duoprism:5,7", "snub 24-cell",
          "grand antiprism", "cone:sphere:1,6", "glome:1,3", "duocylinder:1,9"}) {
      Complex c = load_model(spec, default_catalogue());
      TetMesh mesh = tetrahedralize(c);
      m.push_back({spec, std::move(c), std::move(mesh)});
    }
    static const test::TempDir dir("tet_indexed");
    dir.write("l.obj", kLPrismObj);
    Complex l = load_model("extrude:" + (dir / "l.obj").string(), default_catalogue());
    TetMesh mesh = tetrahedralize(l);
    m.push_back({"extrude:L", std::move(l), std::move(mesh)});
    return m;
  }();
  return all;
}

Eigen::Vector4d random_unit(std::mt19937& rng) {
  std::normal_distribution<double> g;
  Eigen::Vector4d v;
  for (int i = 0; i < 4; ++i) v(i) = g(rng);
  return v.normalized();
}

// A plane cutting the placed model somewhere strictly inside its height range.
Hyperplane random_plane(const TetMesh& mesh, const AffineTransform& xf, std::mt19937& rng) {
  const Eigen::Vector4d u = random_unit(rng);
  double lo = 1e300, hi = -1e300;
  for (Eigen::Index v = 0; v < mesh.positions.cols(); ++v) {
    const double h = u.dot(Eigen::Vector4d(xf.apply(mesh.positions.col(v))));
    lo = std::min(lo, h), hi = std::max(hi, h);
  }
  const double d =
      std::uniform_real_distribution<double>(lo + 0.02 * (hi - lo), hi - 0.02 * (hi - lo))(rng);
  return Hyperplane::from(u, d);
}

double mesh_scale(const TetMesh& mesh, const AffineTransform& xf) {
  double r = 0.0;
  for (Eigen::Index v = 0; v < mesh.positions.cols(); ++v)
    r = std::max(r, Eigen::Vector4d(xf.apply(mesh.positions.col(v))).norm());
  return std::max(r, 1.0);
}

Eigen::Vector3d pos(const TetSliceMesh& s, std::uint32_t v) {
  return s.position(v);
}

// What the oracle knows about one cut tetrahedron.
struct OracleCut {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;  // vertex pairs, a < b
  std::vector<Eigen::Vector3d> points;                         // their crossings, section coords
  std::vector<Eigen::Vector3d> uvw;                            // interpolated corner uvw
  Eigen::Vector3d normal;       // the cell's projected outward unit normal
  Eigen::Vector3d vector_area;  // of the polygon, along `normal`
};

// The cut of every tetrahedron by a plane none of whose vertices is near: the crossing of edge
// (a, b), a < b, at t = s_a / (s_a - s_b) (s the signed distance of the placed vertex), the
// polygon's area from its points ordered by angle around their centroid, its direction the cell
// normal transformed by A^-T and projected.
std::map<std::uint32_t, OracleCut> oracle(const TetMesh& mesh, const Hyperplane& plane,
                                          const AffineTransform& xf, bool& generic) {
  const HyperplaneFrame frame(plane);
  const Eigen::MatrixXd lin = xf.linear();
  const Eigen::Matrix4d normal_map = Eigen::Matrix4d(lin).inverse().transpose();
  const double scale = mesh_scale(mesh, xf);
  std::map<std::uint32_t, OracleCut> cuts;
  generic = true;
  for (std::uint32_t t = 0; t < mesh.size(); ++t) {
    Eigen::Vector4d x[4];
    double s[4];
    int positive = 0;
    for (int k = 0; k < 4; ++k) {
      x[k] = xf.apply(mesh.corner_position(t, k));
      s[k] = plane.signed_distance(x[k]);
      if (std::abs(s[k]) < 1e-9 * scale) generic = false;
      positive += s[k] > 0;
    }
    if (positive == 0 || positive == 4) continue;
    OracleCut c;
    for (int ka = 0; ka < 4; ++ka)
      for (int kb = ka + 1; kb < 4; ++kb) {
        if ((s[ka] > 0) == (s[kb] > 0)) continue;
        const std::uint32_t va = mesh.tets[t][static_cast<std::size_t>(ka)];
        const std::uint32_t vb = mesh.tets[t][static_cast<std::size_t>(kb)];
        const int i = va < vb ? ka : kb, j = va < vb ? kb : ka;
        const double u = s[i] / (s[i] - s[j]);
        const Eigen::Vector4d p = (1 - u) * x[i] + u * x[j];
        c.edges.emplace_back(std::min(va, vb), std::max(va, vb));
        c.points.push_back(frame.to_plane(p));
        c.uvw.push_back((1 - u) * mesh.corner_uvw_of(t, i) + u * mesh.corner_uvw_of(t, j));
      }
    const Eigen::Vector4d n4 = normal_map * mesh.tet_normal(t);
    c.normal = (frame.basis.transpose() * n4).normalized();
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& p : c.points) centre += p;
    centre /= static_cast<double>(c.points.size());
    const Eigen::Vector3d e1 = (c.points[0] - centre).normalized();
    const Eigen::Vector3d e2 = c.normal.cross(e1);
    std::vector<std::pair<double, Eigen::Vector3d>> ring;
    for (const auto& p : c.points)
      ring.emplace_back(std::atan2((p - centre).dot(e2), (p - centre).dot(e1)), p);
    std::sort(ring.begin(), ring.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    c.vector_area = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < ring.size(); ++k)
      c.vector_area +=
          0.5 * (ring[k].second - centre).cross(ring[(k + 1) % ring.size()].second - centre);
    if (c.vector_area.dot(c.normal) < 0) c.vector_area = -c.vector_area;
    cuts.emplace(t, std::move(c));
  }
  return cuts;
}

// Every directed edge of the triangles appears once and its reverse once: a closed, consistently
// oriented surface of welded vertices.
void check_closed_oriented(const TetSliceMesh& s) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (std::size_t i = 0; i < s.triangle_count(); ++i)
    for (std::size_t k = 0; k < 3; ++k)
      ++directed[{s.triangles[3 * i + k], s.triangles[3 * i + (k + 1) % 3]}];
  for (const auto& [e, n] : directed) {
    REQUIRE(n == 1);
    const auto it = directed.find({e.second, e.first});
    REQUIRE(it != directed.end());
    REQUIRE(it->second == 1);
  }
}

void check_against_oracle(const Model& m, const Hyperplane& plane, const AffineTransform& xf) {
  INFO(m.name << ": n = (" << plane.normal.transpose() << "), d = " << plane.offset);
  bool generic = true;
  const auto cuts = oracle(m.mesh, plane, xf, generic);
  if (!generic) return;  // a vertex within 1e-9 of the plane: not the oracle's case
  const double scale = mesh_scale(m.mesh, xf);
  const double tol = 1e-10 * scale;
  TetSliceMesh s;
  slice_tets(m.mesh, plane, xf, s);
  REQUIRE(s.triangles.size() == 3 * s.triangle_count());
  REQUIRE(s.normals.size() == 3 * s.triangle_count());
  REQUIRE(s.uvw.size() == 9 * s.triangle_count());
  REQUIRE(s.cell.size() == s.triangle_count());
  REQUIRE(s.positions.size() == 3 * s.vertex_count());

  // Welding: exactly one vertex per crossing edge, at the edge's crossing.
  std::map<std::pair<std::uint32_t, std::uint32_t>, Eigen::Vector3d> crossing;
  for (const auto& [t, c] : cuts)
    for (std::size_t k = 0; k < c.edges.size(); ++k) crossing.emplace(c.edges[k], c.points[k]);
  REQUIRE(s.vertex_count() == crossing.size());
  std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
  for (std::uint32_t v = 0; v < s.vertex_count(); ++v) {
    const TetCutPoint& src = s.vertex_source[v];
    REQUIRE(src.a < src.b);
    REQUIRE(seen.insert({src.a, src.b}).second);
    const auto it = crossing.find({src.a, src.b});
    REQUIRE(it != crossing.end());
    REQUIRE((pos(s, v) - it->second).norm() < tol);
  }
  std::vector<char> used(s.vertex_count(), 0);
  for (auto v : s.triangles) {
    REQUIRE(v < s.vertex_count());
    used[v] = 1;
  }
  CHECK(std::count(used.begin(), used.end(), 0) == 0);

  // Per tetrahedron: its triangles come together, in tetrahedron order, and tile its polygon
  // with the polygon's orientation; corners are the polygon's points with their uvw.
  std::size_t i = 0;
  std::uint32_t last = 0;
  for (const auto& [t, c] : cuts) {
    REQUIRE(i < s.triangle_count());
    REQUIRE(s.tet[i] == t);
    REQUIRE((i == 0 || t > last));
    last = t;
    Eigen::Vector3d area = Eigen::Vector3d::Zero();
    for (; i < s.triangle_count() && s.tet[i] == t; ++i) {
      REQUIRE(s.cell[i] == m.mesh.tet_cell[t]);
      const Eigen::Vector3d n(s.normals[3 * i], s.normals[3 * i + 1], s.normals[3 * i + 2]);
      REQUIRE((n - c.normal).norm() < 1e-9);
      Eigen::Vector3d p[3];
      for (std::size_t k = 0; k < 3; ++k) {
        const std::uint32_t v = s.triangles[3 * i + k];
        p[k] = pos(s, v);
        const TetCutPoint& src = s.vertex_source[v];
        const auto e = std::find(c.edges.begin(), c.edges.end(), std::make_pair(src.a, src.b));
        REQUIRE(e != c.edges.end());  // a crossing of this tetrahedron's edges
        const auto j = static_cast<std::size_t>(e - c.edges.begin());
        const Eigen::Vector3d uvw(s.uvw[9 * i + 3 * k], s.uvw[9 * i + 3 * k + 1],
                                  s.uvw[9 * i + 3 * k + 2]);
        REQUIRE((uvw - c.uvw[j]).norm() < 1e-9);
      }
      const Eigen::Vector3d a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]);
      REQUIRE(a.dot(c.normal) > 0.0);  // outward
      area += a;
    }
    REQUIRE((area - c.vector_area).norm() < 1e-9 * scale * scale);
  }
  REQUIRE(i == s.triangle_count());
  check_closed_oriented(s);

  // The soup API (its own per-tetrahedron cut) gives the same triangles corner by corner, up to
  // rounding; to_soup is this slice corner by corner.
  const TetSection soup = slice_tets(m.mesh, plane, xf);
  TetSection expanded;
  to_soup(s, expanded);
  REQUIRE(soup.triangle_count() == s.triangle_count());
  REQUIRE(expanded.triangle_count() == s.triangle_count());
  REQUIRE(std::ranges::equal(soup.tet, s.tet));
  REQUIRE(std::ranges::equal(soup.cell, s.cell));
  REQUIRE(std::ranges::equal(expanded.tet, s.tet));
  REQUIRE(std::ranges::equal(expanded.cell, s.cell));
  for (std::size_t c = 0; c < 3 * s.triangle_count(); ++c) {
    const TetCutPoint& src = s.vertex_source[s.triangles[c]];
    const auto col = static_cast<Eigen::Index>(c);
    REQUIRE(soup.corners[c].a == src.a);
    REQUIRE(soup.corners[c].b == src.b);
    REQUIRE(std::abs(soup.corners[c].t - src.t) < 1e-12);
    REQUIRE((soup.positions.col(col) - pos(s, s.triangles[c])).norm() < tol);
    const Eigen::Vector3d n(s.normals[3 * (c / 3)], s.normals[3 * (c / 3) + 1],
                            s.normals[3 * (c / 3) + 2]);
    REQUIRE((soup.normals.col(col) - n).norm() < 1e-12);
    const Eigen::Vector3d uvw(s.uvw[3 * c], s.uvw[3 * c + 1], s.uvw[3 * c + 2]);
    REQUIRE((soup.uvw.col(col) - uvw).norm() < 1e-12);
    // to_soup: exact copies
    REQUIRE(expanded.corners[c].a == src.a);
    REQUIRE(expanded.corners[c].b == src.b);
    REQUIRE(expanded.corners[c].t == src.t);
    REQUIRE(expanded.positions.col(col) == pos(s, s.triangles[c]));
    REQUIRE(expanded.normals.col(col) == n);
    REQUIRE(expanded.uvw.col(col) == uvw);
  }
}

bool same(const TetSliceMesh& a, const TetSliceMesh& b) {
  if (a.vertex_count() != b.vertex_count()) return false;
  for (std::size_t v = 0; v < a.vertex_count(); ++v)
    if (a.vertex_source[v].a != b.vertex_source[v].a ||
        a.vertex_source[v].b != b.vertex_source[v].b ||
        a.vertex_source[v].t != b.vertex_source[v].t)
      return false;
  return a.positions == b.positions && a.triangles == b.triangles && a.normals == b.normals &&
         a.uvw == b.uvw && a.tet == b.tet && a.cell == b.cell;
}

}  // namespace

TEST_CASE("tet mesh: the edge index lists every tetrahedron edge once", "[tet][indexed]") {
  for (const Model& m : models()) {
    INFO(m.name);
    const TetMesh& mesh = m.mesh;
    std::set<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (const auto& tv : mesh.tets)
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j)
          pairs.insert(
              {std::min(tv[static_cast<std::size_t>(i)], tv[static_cast<std::size_t>(j)]),
               std::max(tv[static_cast<std::size_t>(i)], tv[static_cast<std::size_t>(j)])});
    REQUIRE(mesh.edges.size() == pairs.size());
    std::set<std::pair<std::uint32_t, std::uint32_t>> listed;
    for (const auto& e : mesh.edges) {
      REQUIRE(e[0] < e[1]);
      listed.insert({e[0], e[1]});
    }
    REQUIRE(listed == pairs);
    REQUIRE(mesh.tet_edges.size() == mesh.size());
    for (std::size_t t = 0; t < mesh.size(); ++t)
      for (std::size_t k = 0; k < 6; ++k) {
        const auto& e = mesh.edges[mesh.tet_edges[t][k]];
        const std::uint32_t a =
            mesh.tets[t][static_cast<std::size_t>(TetMesh::kTetEdgeCorners[k][0])];
        const std::uint32_t b =
            mesh.tets[t][static_cast<std::size_t>(TetMesh::kTetEdgeCorners[k][1])];
        REQUIRE(e[0] == std::min(a, b));
        REQUIRE(e[1] == std::max(a, b));
      }
    // Blocks: consecutive runs of one cell's tetrahedra covering the mesh, with their vertices.
    REQUIRE(mesh.block_first.size() >= 2);
    REQUIRE(mesh.block_first.front() == 0);
    REQUIRE(mesh.block_first.back() == mesh.size());
    REQUIRE(mesh.block_vertex_first.size() == mesh.block_first.size());
    for (std::size_t b = 0; b + 1 < mesh.block_first.size(); ++b) {
      REQUIRE(mesh.block_first[b] < mesh.block_first[b + 1]);
      std::set<std::uint32_t> want;
      for (std::uint32_t t = mesh.block_first[b]; t < mesh.block_first[b + 1]; ++t) {
        REQUIRE(mesh.tet_cell[t] == mesh.tet_cell[mesh.block_first[b]]);
        want.insert(mesh.tets[t].begin(), mesh.tets[t].end());
      }
      if (b > 0)
        CHECK(mesh.tet_cell[mesh.block_first[b] - 1] != mesh.tet_cell[mesh.block_first[b]]);
      const std::vector<std::uint32_t> have(
          mesh.block_vertices.begin() + mesh.block_vertex_first[b],
          mesh.block_vertices.begin() + mesh.block_vertex_first[b + 1]);
      REQUIRE(have.size() == want.size());
      REQUIRE(std::set<std::uint32_t>(have.begin(), have.end()) == want);
    }
    CHECK(mesh.has_edge_index());
    // A closed 3-manifold: V - E + F - T = 0 with F = 2T (every triangle in two tetrahedra).
    const auto V = static_cast<long>(mesh.positions.cols());
    const auto T = static_cast<long>(mesh.size());
    CHECK(V - static_cast<long>(mesh.edges.size()) + 2 * T - T == 0);
    TetMesh changed = mesh;
    std::swap(changed.tets[0][0], changed.tets[0][1]);
    CHECK_FALSE(changed.has_edge_index());
  }
}

TEST_CASE("tet slicer, indexed: the oracle's polygons, welded and outward", "[tet][indexed]") {
  std::mt19937 rng(8812);
  for (const Model& m : models()) {
    const int trials = m.mesh.size() > 2000 ? 12 : 40;
    for (int trial = 0; trial < trials; ++trial) {
      const AffineTransform id = AffineTransform::identity(4);
      check_against_oracle(m, random_plane(m.mesh, id, rng), id);
    }
  }
}

TEST_CASE("tet slicer, indexed: placements, including reflections", "[tet][indexed]") {
  std::mt19937 rng(4242);
  const AffineTransform turn = AffineTransform::translation(Eigen::Vector4d(0.5, -0.2, 0, 0.25)) *
                               AffineTransform::rotation(4, 0, 3, 0.3) *
                               AffineTransform::rotation(4, 1, 2, -1.1);
  const AffineTransform mirror =
      turn * AffineTransform::scale(Eigen::Vector4d(-1.0, 1.0, 1.0, 1.0));
  const AffineTransform squash = AffineTransform::scale(Eigen::Vector4d(1.5, 0.5, 1.0, -2.0));
  for (const Model& m : models()) {
    if (m.mesh.size() > 2000) continue;
    for (const AffineTransform* xf : {&turn, &mirror, &squash})
      for (int trial = 0; trial < 8; ++trial) {
        const Hyperplane plane = random_plane(m.mesh, *xf, rng);
        check_against_oracle(m, plane, *xf);
        // The same volume as the CW path's section of the placed model.
        TetSliceMesh s;
        slice_tets(m.mesh, plane, *xf, s);
        double v = 0.0;
        for (std::size_t i = 0; i < s.triangle_count(); ++i)
          v += pos(s, s.triangles[3 * i])
                   .dot(pos(s, s.triangles[3 * i + 1]).cross(pos(s, s.triangles[3 * i + 2])));
        const Section cw = section(m.complex, plane, *xf);
        INFO(m.name << " trial " << trial);
        CHECK(v / 6.0 == Approx(cw.empty() ? 0.0 : signed_volume(cw.complex)).epsilon(1e-9));
      }
  }
}

TEST_CASE("tet slicer, indexed: planes through vertices weld the soup", "[tet][indexed]") {
  std::mt19937 rng(977);
  for (const Model& m : models()) {
    if (m.mesh.size() > 2000) continue;
    INFO(m.name);
    for (int trial = 0; trial < 12; ++trial) {
      const auto v =
          std::uniform_int_distribution<Eigen::Index>(0, m.mesh.positions.cols() - 1)(rng);
      const Eigen::Vector4d x = m.mesh.positions.col(v);
      Eigen::Vector4d u = random_unit(rng);
      if (trial % 3 == 1) u = Eigen::Vector4d::Unit(trial % 4);  // axis planes: whole facets
      const Hyperplane plane = Hyperplane::from(u, u.dot(x));
      const TetSection soup = slice_tets(m.mesh, plane);
      TetSliceMesh s;
      slice_tets(m.mesh, plane, s);
      // One vertex per distinct corner source, and the soup corner by corner.
      std::set<std::pair<std::uint32_t, std::uint32_t>> sources;
      for (const auto& c : soup.corners) sources.insert({c.a, c.b});
      REQUIRE(s.vertex_count() == sources.size());
      std::set<std::pair<std::uint32_t, std::uint32_t>> seen;
      for (const auto& c : s.vertex_source) REQUIRE(seen.insert({c.a, c.b}).second);
      TetSection expanded;
      to_soup(s, expanded);
      REQUIRE(expanded.positions == soup.positions);
      REQUIRE(expanded.normals == soup.normals);
      REQUIRE(expanded.uvw == soup.uvw);
      REQUIRE(expanded.corners == soup.corners);
      REQUIRE(expanded.tet == soup.tet);
      REQUIRE(expanded.cell == soup.cell);
    }
  }
}

TEST_CASE("tet slicer, indexed: deterministic across threads and reused buffers",
          "[tet][indexed]") {
  const Model& m = models()[4];  // the 600-cell
  std::mt19937 rng(31337);
  std::vector<Hyperplane> planes;
  for (int i = 0; i < 24; ++i)
    planes.push_back(random_plane(m.mesh, AffineTransform::identity(4), rng));
  std::vector<TetSliceMesh> fresh(planes.size());
  for (std::size_t i = 0; i < planes.size(); ++i) slice_tets(m.mesh, planes[i], fresh[i]);
  // One buffer reused over all planes (in reverse order), in another thread.
  std::vector<char> equal(planes.size(), 0);
  std::thread worker([&] {
    TetSliceMesh reused;
    for (std::size_t i = planes.size(); i-- > 0;) {
      slice_tets(m.mesh, planes[i], reused);
      equal[i] = same(reused, fresh[i]);
    }
  });
  worker.join();
  for (std::size_t i = 0; i < planes.size(); ++i) CHECK(equal[i]);
  // A mesh whose edge index was dropped slices the same.
  TetMesh bare = m.mesh;
  bare.edges.clear();
  bare.tet_edges.clear();
  bare.block_first.clear();
  bare.block_vertex_first.clear();
  bare.block_vertices.clear();
  for (std::size_t i = 0; i < planes.size(); ++i) {
    TetSliceMesh s;
    slice_tets(bare, planes[i], s);
    CHECK(same(s, fresh[i]));
  }
}

TEST_CASE("tet slicer, indexed: an edge index out of range is noticed, not trusted",
          "[tet][indexed]") {
  std::mt19937 rng(4242);
  for (const std::size_t which : {std::size_t{3}, std::size_t{4}}) {  // 120-cell, 600-cell
    const Model& m = models()[which];
    // The edge list shrunk under tet_edges: ids beyond its end.
    Model shrunk{m.name + ", edge list shrunk", Complex(m.complex), m.mesh};
    shrunk.mesh.edges.resize(shrunk.mesh.edges.size() / 2);
    REQUIRE_FALSE(shrunk.mesh.has_edge_index());
    // Block vertices beyond the vertex count.
    Model blocks{m.name + ", block vertices out of range", Complex(m.complex), m.mesh};
    for (auto& v : blocks.mesh.block_vertices) v += static_cast<std::uint32_t>(1u << 30);
    REQUIRE_FALSE(blocks.mesh.has_edge_index());
    // Edge ends beyond the vertex count.
    Model ends{m.name + ", edge ends out of range", Complex(m.complex), m.mesh};
    for (auto& e : ends.mesh.edges) e[1] += static_cast<std::uint32_t>(1u << 30);
    REQUIRE_FALSE(ends.mesh.has_edge_index());
    // Blocks out of order, every other one all the tetrahedra again (overlapping: listed as they
    // stand, more tetrahedra than the mesh has).
    Model ranges{m.name + ", block ranges overlapping", Complex(m.complex), m.mesh};
    std::vector<std::uint32_t>& bf = ranges.mesh.block_first;
    const auto T = static_cast<std::uint32_t>(ranges.mesh.size());
    for (std::size_t b = 0; b < bf.size(); ++b) bf[b] = b % 2 ? T : 0;
    bf.back() = T;
    REQUIRE_FALSE(ranges.mesh.has_edge_index());
    for (int trial = 0; trial < 12; ++trial) {
      const AffineTransform id = AffineTransform::identity(4);
      const Hyperplane plane = random_plane(m.mesh, id, rng);
      check_against_oracle(shrunk, plane, id);
      check_against_oracle(blocks, plane, id);
      check_against_oracle(ends, plane, id);
      check_against_oracle(ranges, plane, id);
    }
  }
}
