// The caller-owned TetSlicer: no allocation once its buffers have grown (counted through this
// binary's replacement of the global operator new), the edge-shared crossings of the indexed
// slice bit for bit the per-tetrahedron crossings of the soup, the returning and free forms
// equal to a slicer's, and the licence fence's two entry points: tetrahedralize_cells (Eigen
// only, no mesher for non-convex cells) against tetrahedralize (TetGen for those cells).
#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <map>
#include <new>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"
#include "support/counting_new.hpp"
#include "support/temp_dir.hpp"

using namespace cw4d;

namespace {

// Generic planes through the model (seeded): a random unit normal, the offset strictly inside
// the model's height range along it.
std::vector<Hyperplane> generic_planes(const TetMesh& mesh, std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0.05, 0.95);
  std::vector<Hyperplane> planes;
  while (planes.size() < count) {
    Eigen::Vector4d n;
    for (int i = 0; i < 4; ++i) n(i) = g(rng);
    n.normalize();
    const Eigen::VectorXd h = n.transpose() * mesh.positions;
    const double lo = h.minCoeff(), hi = h.maxCoeff();
    planes.push_back(Hyperplane::from(Eigen::VectorXd(n), lo + u(rng) * (hi - lo)));
  }
  return planes;
}

bool same_bits(const double* a, const double* b, std::size_t n) {
  return std::memcmp(a, b, n * sizeof(double)) == 0;
}

}  // namespace

TEST_CASE("tet slicer: no allocation once the buffers have grown", "[tet][slicer]") {
  for (const char* spec : {"tesseract", "120-cell", "600-cell", "duoprism:32,32"}) {
    INFO(spec);
    const TetMesh mesh = tetrahedralize(load_model(spec));
    const auto planes = generic_planes(mesh, 64, 20240401u);
    const AffineTransform xf = AffineTransform::rotation(4, 0, 3, 0.3);
    TetSlicer slicer;
    TetSliceMesh out;
    TetSection soup;
    // First round: every buffer grows to its largest size over these planes (which the
    // counter sees: it counts this program's allocations).
    const std::size_t at_start = test::allocation_count();
    std::size_t triangles = 0;
    for (const auto& p : planes) {
      slicer.slice(mesh, p, out);
      triangles += out.triangle_count();
      slicer.slice(mesh, p, xf, out);
      slicer.slice(mesh, p, soup);
    }
    REQUIRE(triangles > 0);
    CHECK(test::allocation_count() > at_start);
    const void* data[] = {out.positions.data(),    out.triangles.data(), out.normals.data(),
                          out.uvw.data(),          out.tet.data(),       out.cell.data(),
                          out.vertex_source.data()};
    // Second round: nothing allocated through operator new, no array moved.
    const std::size_t before = test::allocation_count();
    std::size_t again = 0;
    for (const auto& p : planes) {
      slicer.slice(mesh, p, out);
      again += out.triangle_count();
      slicer.slice(mesh, p, xf, out);
    }
    const std::size_t allocated = test::allocation_count() - before;
    CHECK(allocated == 0);
    CHECK(again == triangles);
    const void* after[] = {out.positions.data(),    out.triangles.data(), out.normals.data(),
                           out.uvw.data(),          out.tet.data(),       out.cell.data(),
                           out.vertex_source.data()};
    for (std::size_t i = 0; i < 7; ++i) CHECK(after[i] == data[i]);
    // The soup: its vectors keep their storage too (its matrices are sized to each slice).
    const std::size_t before_soup = test::allocation_count();
    for (const auto& p : planes) slicer.slice(mesh, p, soup);
    CHECK(test::allocation_count() - before_soup == 0);
  }
}

TEST_CASE("tet slicer: edge-shared crossings are the per-tetrahedron crossings, bit for bit",
          "[tet][slicer]") {
  for (const char* spec :
       {"5-cell", "tesseract", "24-cell", "120-cell", "600-cell", "duoprism:5,7", "glome:1,3"}) {
    INFO(spec);
    const Complex model = load_model(spec, default_catalogue());
    const TetMesh mesh = tetrahedralize(model);
    // A reflection (det < 0: the indexed cut turns every polygon), rotations and a shift.
    const AffineTransform xf =
        AffineTransform::translation(Eigen::Vector4d(0.01, -0.02, 0.03, 0.0)) *
        AffineTransform::rotation(4, 1, 2, 0.7) * AffineTransform::rotation(4, 0, 3, -0.4) *
        AffineTransform::scale(Eigen::Vector4d(1.0, -1.0, 1.0, 1.0));
    TetSlicer slicer;
    TetSliceMesh indexed;
    TetSection soup;
    std::size_t checked = 0;
    for (const auto& p : generic_planes(mesh, 24, 7u)) {
      slicer.slice(mesh, p, xf, indexed);
      slicer.slice(mesh, p, xf, soup);
      REQUIRE(soup.triangle_count() == indexed.triangle_count());
      // Each crossing edge gives one vertex: no two vertices share an edge.
      std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> seen;
      for (std::uint32_t v = 0; v < indexed.vertex_count(); ++v)
        CHECK(
            seen.emplace(std::make_pair(indexed.vertex_source[v].a, indexed.vertex_source[v].b), v)
                .second);
      for (std::size_t i = 0; i < soup.triangle_count(); ++i) {
        REQUIRE(soup.tet[i] == indexed.tet[i]);
        REQUIRE(soup.cell[i] == indexed.cell[i]);
        CHECK(same_bits(&soup.normals(0, static_cast<Eigen::Index>(3 * i)), &indexed.normals[3 * i],
                        3));
        // The soup's corner cycle is the indexed one's, starting anywhere.
        std::uint32_t v[3];
        for (std::size_t k = 0; k < 3; ++k) v[k] = indexed.triangles[3 * i + k];
        for (std::size_t k = 0; k < 3; ++k) {
          const std::size_t c = 3 * i + k;
          const TetCutPoint& cp = soup.corners[c];
          const auto it = seen.find({cp.a, cp.b});
          REQUIRE(it != seen.end());
          const std::uint32_t vid = it->second;
          CHECK((vid == v[0] || vid == v[1] || vid == v[2]));
          const double* sp = &soup.positions(0, static_cast<Eigen::Index>(c));
          CHECK(same_bits(sp, &indexed.positions[3 * std::size_t{vid}], 3));
          CHECK(same_bits(&cp.t, &indexed.vertex_source[vid].t, 1));
          // uvw of the corner (per tetrahedron, along its own edge): the indexed corner of the
          // same vertex in this triangle.
          for (std::size_t j = 0; j < 3; ++j)
            if (v[j] == vid)
              CHECK(same_bits(&soup.uvw(0, static_cast<Eigen::Index>(c)),
                              &indexed.uvw[9 * i + 3 * j], 3));
          ++checked;
        }
      }
    }
    CHECK(checked > 0);
  }
}

TEST_CASE("tet slicer: the returning and free forms are a slicer's slice", "[tet][slicer]") {
  const TetMesh mesh = tetrahedralize(load_model("24-cell"));
  TetSlicer slicer;
  TetSection into;
  TetSliceMesh indexed, free_indexed;
  for (const auto& p : generic_planes(mesh, 16, 3u)) {
    const TetSection a = slicer.slice(mesh, p);
    const TetSection b = slice_tets(mesh, p);
    slicer.slice(mesh, p, into);
    REQUIRE(a.triangle_count() > 0);
    CHECK(a.positions == into.positions);
    CHECK(b.positions == into.positions);
    CHECK(a.uvw == into.uvw);
    CHECK(a.tet == into.tet);
    slicer.slice(mesh, p, indexed);
    slice_tets(mesh, p, free_indexed);
    CHECK(indexed.positions == free_indexed.positions);
    CHECK(indexed.triangles == free_indexed.triangles);
  }
  // A moved-from slicer still slices.
  TetSlicer moved = std::move(slicer);
  TetSlicer& reused = slicer;
  const auto p = generic_planes(mesh, 1, 5u).front();
  CHECK(reused.slice(mesh, p).positions == moved.slice(mesh, p).positions);
}

TEST_CASE("tet slicer: UVW left out changes nothing else, bit for bit", "[tet][slicer]") {
  for (const char* spec : {"tesseract", "24-cell", "120-cell", "600-cell", "duoprism:5,7"}) {
    INFO(spec);
    const TetMesh mesh = tetrahedralize(load_model(spec, default_catalogue()));
    const AffineTransform xf = AffineTransform::rotation(4, 1, 3, 0.45) *
                               AffineTransform::scale(Eigen::Vector4d(1.0, 1.0, -1.0, 1.0));
    TetSlicer with, without(TetSliceOptions{false});
    CHECK(with.options().uvw);
    CHECK_FALSE(without.options().uvw);
    TetSliceMesh a, b;
    TetSection sa, sb;
    auto planes = generic_planes(mesh, 24, 11u);
    // Planes through mesh vertices too (the general loop, welded), and one that misses.
    for (Eigen::Index v : {Eigen::Index{0}, mesh.positions.cols() / 2}) {
      const Eigen::Vector4d n = Eigen::Vector4d(1.0, 0.5, -0.25, 0.75).normalized();
      const Eigen::VectorXd x = xf.apply(Eigen::VectorXd(mesh.positions.col(v)));
      planes.push_back(Hyperplane::from(Eigen::VectorXd(n), n.dot(Eigen::Vector4d(x))));
    }
    planes.push_back(Hyperplane::from(Eigen::VectorXd(Eigen::Vector4d::UnitW()), 1e6));
    std::size_t triangles = 0;
    for (const auto& p : planes) {
      with.slice(mesh, p, xf, a);
      without.slice(mesh, p, xf, b);
      triangles += a.triangle_count();
      CHECK(a.uvw.size() == 9 * a.triangle_count());
      CHECK(b.uvw.empty());
      REQUIRE(a.triangles == b.triangles);
      CHECK(a.tet == b.tet);
      CHECK(a.cell == b.cell);
      REQUIRE(a.positions.size() == b.positions.size());
      CHECK(same_bits(a.positions.data(), b.positions.data(), a.positions.size()));
      REQUIRE(a.normals.size() == b.normals.size());
      CHECK(same_bits(a.normals.data(), b.normals.data(), a.normals.size()));
      REQUIRE(a.vertex_source.size() == b.vertex_source.size());
      for (std::size_t v = 0; v < a.vertex_source.size(); ++v) {
        CHECK(a.vertex_source[v] == b.vertex_source[v]);
        CHECK(same_bits(&a.vertex_source[v].t, &b.vertex_source[v].t, 1));
      }
      with.slice(mesh, p, xf, sa);
      without.slice(mesh, p, xf, sb);
      CHECK(sb.uvw.cols() == 0);
      CHECK(sa.uvw.cols() == sa.positions.cols());
      CHECK(sa.positions == sb.positions);
      CHECK(sa.normals == sb.normals);
      CHECK(sa.corners == sb.corners);
      CHECK(sa.tet == sb.tet);
      // to_soup of a mesh without UVW is the soup without UVW.
      TetSection from_mesh;
      to_soup(b, from_mesh);
      CHECK(from_mesh.uvw.cols() == 0);
      CHECK(from_mesh.positions.cols() == 3 * static_cast<Eigen::Index>(b.triangle_count()));
    }
    CHECK(triangles > 0);
    // Turned on again, the same slicer gives UVW again, equal to the other's.
    without.set_options(TetSliceOptions{});
    without.slice(mesh, planes.front(), xf, b);
    with.slice(mesh, planes.front(), xf, a);
    CHECK(a.uvw == b.uvw);
  }
  // Without UVW, the section's corner UVW cannot be given: said, not guessed.
  const Complex model = load_model("tesseract");
  const TetMesh mesh = tetrahedralize(model);
  TetSlicer without(TetSliceOptions{false});
  const TetSection cut = without.slice(
      mesh, Hyperplane::from(Eigen::VectorXd(Eigen::Vector4d(1, 1, 1, 1).normalized()), 0.1));
  REQUIRE(cut.triangle_count() > 0);
  CHECK_THROWS_AS(tet_section_uvw(cut, to_section(cut, model)), InputError);
}

TEST_CASE("tet slicer: no allocation without UVW either", "[tet][slicer]") {
  const TetMesh mesh = tetrahedralize(load_model("120-cell"));
  const auto planes = generic_planes(mesh, 64, 20240401u);
  TetSlicer slicer(TetSliceOptions{false});
  TetSliceMesh out;
  for (const auto& p : planes) slicer.slice(mesh, p, out);
  const std::size_t before = test::allocation_count();
  std::size_t triangles = 0;
  for (const auto& p : planes) {
    slicer.slice(mesh, p, out);
    triangles += out.triangle_count();
  }
  CHECK(test::allocation_count() - before == 0);
  CHECK(triangles > 0);
}

TEST_CASE("tetrahedralize_cells: convex cells as tetrahedralize, non-convex ones left out",
          "[tet][fence]") {
  for (const char* spec : {"tesseract", "120-cell", "duoprism:5,7", "glome:1,3"}) {
    INFO(spec);
    const Complex c = load_model(spec, default_catalogue());
    TetStats with, without;
    const TetMesh a = tetrahedralize(c, {}, &with);
    const TetMesh b = tetrahedralize_cells(c, {}, {}, &without);
    CHECK(with.tetgen_cells == 0);
    CHECK(without.skipped_cells == 0);
    CHECK(a.tets == b.tets);
    CHECK(a.tet_cell == b.tet_cell);
    CHECK(a.positions == b.positions);
    CHECK(a.corner_uvw == b.corner_uvw);
    CHECK(a.tet_edges == b.tet_edges);
  }
  // An L-shaped prism extruded: two non-convex cells, meshed by TetGen in tetrahedralize, left
  // out by tetrahedralize_cells without a mesher; every other cell's tetrahedra are the same.
  const test::TempDir dir("tet_slicer");
  dir.write("l.obj",
            "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\n"
            "v 0 0 1\nv 2 0 1\nv 2 1 1\nv 1 1 1\nv 1 2 1\nv 0 2 1\n"
            "f 6 5 4 3 2 1\nf 7 8 9 10 11 12\n"
            "f 1 2 8 7\nf 2 3 9 8\nf 3 4 10 9\nf 4 5 11 10\nf 5 6 12 11\nf 6 1 7 12\n");
  const Complex l = load_model("extrude:" + (dir / "l.obj").string(), default_catalogue());
  TetStats with, without;
  const TetMesh a = tetrahedralize(l, {}, &with);
  const TetMesh b = tetrahedralize_cells(l, {}, {}, &without);
  CHECK(with.tetgen_cells > 0);
  CHECK(without.skipped_cells == with.tetgen_cells);
  std::vector<std::array<std::uint32_t, 4>> kept;
  std::vector<char> convex(l.count(3), 0);
  for (const std::uint32_t cell : b.tet_cell) convex[cell] = 1;
  for (std::size_t t = 0; t < a.size(); ++t)
    if (convex[a.tet_cell[t]]) kept.push_back(a.tets[t]);
  CHECK(kept == b.tets);
  CHECK(b.cell_count() == l.count(3));
  // A mesher given by the caller is used for exactly those cells.
  std::size_t calls = 0;
  const NonConvexCellMesher refuse =
      [&](const Complex&, std::uint32_t cell, const std::vector<std::uint32_t>&,
          const std::vector<std::array<std::uint32_t, 3>>&, const Eigen::Vector4d&) -> CellTets {
    ++calls;
    throw MeshingError(cell, 0, "refused");
  };
  CHECK_THROWS_AS(tetrahedralize_cells(l, {}, refuse), MeshingError);
  CHECK(calls == 1);
}

namespace {

// Whether two arrays hold the same elements, byte for byte (sizes too).
template <class A, class B>
bool same_bytes(const A& a, const B& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(a[0])) == 0);
}

bool same_bytes(const TetSliceMesh& a, const TetSliceMesh& b) {
  return same_bytes(a.positions, b.positions) && same_bytes(a.vertex_source, b.vertex_source) &&
         same_bytes(a.triangles, b.triangles) && same_bytes(a.normals, b.normals) &&
         same_bytes(a.uvw, b.uvw) && same_bytes(a.tet, b.tet) && same_bytes(a.cell, b.cell);
}

// Fills every array's storage (up to its capacity) with bytes no slice writes, then empties it:
// a slice that grows the array again within its storage must write every element it keeps.
void poison(TetSliceMesh& m) {
  auto fill = [](auto& v) {
    v.resize(v.capacity());
    if (!v.empty()) std::memset(static_cast<void*>(v.data()), 0xA5, v.size() * sizeof(v[0]));
    v.clear();
  };
  fill(m.positions);
  fill(m.vertex_source);
  fill(m.triangles);
  fill(m.normals);
  fill(m.uvw);
  fill(m.tet);
  fill(m.cell);
}

}  // namespace

TEST_CASE("tet slicer: a larger slice into a reused mesh is a fresh mesh's, bit for bit",
          "[tet][slicer]") {
  // TetSliceMesh's arrays are not zero-filled when they grow: every element the slice keeps is
  // written by the slicer. Slices of alternating size into one mesh whose storage holds junk,
  // each against a fresh slicer's slice into a fresh mesh.
  for (const char* spec : {"tesseract", "120-cell", "600-cell", "duoprism:5,7"}) {
    INFO(spec);
    const TetMesh mesh = tetrahedralize(load_model(spec, default_catalogue()));
    const AffineTransform xf = AffineTransform::rotation(4, 0, 2, 0.7);
    auto planes = generic_planes(mesh, 24, 97u);
    // A plane through a mesh vertex (the general loop, welded) and one that misses.
    {
      const Eigen::Vector4d n = Eigen::Vector4d(0.5, -1.0, 0.25, 0.75).normalized();
      const Eigen::VectorXd x = xf.apply(Eigen::VectorXd(mesh.positions.col(3)));
      planes.push_back(Hyperplane::from(Eigen::VectorXd(n), n.dot(Eigen::Vector4d(x))));
      planes.push_back(Hyperplane::from(Eigen::VectorXd(Eigen::Vector4d::UnitX()), -1e6));
    }
    for (const bool uvw : {true, false}) {
      INFO("uvw " << uvw);
      const TetSliceOptions options{uvw};
      // The planes by triangle count, then taken smallest, largest, next smallest, ...: every
      // other slice is larger than the one before.
      std::vector<std::pair<std::size_t, std::size_t>> by_size;
      for (std::size_t i = 0; i < planes.size(); ++i) {
        TetSlicer fresh(options);
        TetSliceMesh m;
        fresh.slice(mesh, planes[i], xf, m);
        by_size.emplace_back(m.triangle_count(), i);
      }
      std::sort(by_size.begin(), by_size.end());
      std::vector<std::size_t> order;
      for (std::size_t lo = 0, hi = by_size.size(); lo < hi;) {
        order.push_back(by_size[lo++].second);
        if (lo < hi) order.push_back(by_size[--hi].second);
      }
      TetSlicer reused_slicer(options);
      TetSliceMesh reused;
      std::size_t larger = 0, checked = 0;
      for (int round = 0; round < 2; ++round) {
        for (const std::size_t i : order) {
          const std::size_t before = reused.triangle_count();
          poison(reused);
          reused_slicer.slice(mesh, planes[i], xf, reused);
          TetSlicer fresh(options);
          TetSliceMesh expected;
          fresh.slice(mesh, planes[i], xf, expected);
          CHECK(same_bytes(reused, expected));
          larger += reused.triangle_count() > before;
          ++checked;
        }
      }
      CHECK(checked == 2 * planes.size());
      CHECK(larger >= planes.size() / 2);
      // The other option on the same mesh: UVW appears or goes, the rest is the same.
      reused_slicer.set_options(TetSliceOptions{!uvw});
      poison(reused);
      reused_slicer.slice(mesh, planes[order.back()], xf, reused);
      TetSlicer fresh(TetSliceOptions{!uvw});
      TetSliceMesh expected;
      fresh.slice(mesh, planes[order.back()], xf, expected);
      CHECK(same_bytes(reused, expected));
    }
  }
}
