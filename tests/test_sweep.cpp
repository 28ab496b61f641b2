// Slicer::sweep against the plain call: every layer's buffers must be exactly (element for
// element, bit for bit) what Slicer::slice gives for that plane, including the fallback reason,
// for dense sweeps (many layers between two vertex heights, so most layers reuse the previous
// layer's connectivity), sparse and unsorted ones (many vertices passed between layers),
// normals with many equal vertex heights, layers through vertices, placed and mirrored models,
// clustered compilations, non-convex models whose cuts the kernel leaves to the generic
// gathering, and 1 and 2 threads.
#include <Eigen/Dense>
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/section/slicer.hpp"
#include "support/planes.hpp"

using namespace cw4d;

namespace {

// Everything a SliceBuffers exposes, compared exactly; the first difference, or empty.
std::string difference(const SliceBuffers& a, const SliceBuffers& b) {
  if (a.dim != b.dim) return "dim";
  if (a.general != b.general) return "general";
  if (a.fallback != b.fallback) return "fallback";
  if (a.reused_topology != b.reused_topology) return "reused_topology";
  if (a.plane.normal != b.plane.normal || a.plane.offset != b.plane.offset) return "plane";
  if (a.coords != b.coords) return "coords";
  if (a.vertex_source.size() != b.vertex_source.size()) return "vertex count";
  for (std::size_t i = 0; i < a.vertex_source.size(); ++i)
    if (a.vertex_source[i].element != b.vertex_source[i].element ||
        a.vertex_source[i].rank != b.vertex_source[i].rank ||
        a.vertex_source[i].t != b.vertex_source[i].t)
      return "vertex_source";
  if (a.boundary.size() != b.boundary.size()) return "ranks";
  for (std::size_t r = 0; r < a.boundary.size(); ++r)
    if (a.boundary[r].offsets() != b.boundary[r].offsets() ||
        a.boundary[r].all_ids() != b.boundary[r].all_ids() ||
        a.boundary[r].all_signs() != b.boundary[r].all_signs())
      return "boundary of rank " + std::to_string(r + 1);
  if (a.source != b.source) return "source";
  if (a.facet_normals != b.facet_normals) return "facet_normals";
  return {};
}

AffineTransform placement(std::mt19937& rng, bool mirror) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd m(4, 4);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m(i, j) = u(rng);
  m += 2.0 * Eigen::MatrixXd::Identity(4, 4);  // well conditioned
  if (mirror) m.row(0) = -m.row(0);
  if ((m.determinant() < 0) != mirror) m.row(1) = -m.row(1);
  Eigen::VectorXd t(4);
  for (int i = 0; i < 4; ++i) t(i) = u(rng);
  return AffineTransform(m, t);
}

// The world-space heights n.x of the model's vertices (placed by xf), sorted.
std::vector<double> heights(const Complex& c, const Eigen::VectorXd& unit,
                            const AffineTransform& xf) {
  std::vector<double> h;
  for (std::uint32_t v = 0; v < c.count(0); ++v) h.push_back(unit.dot(xf.apply(c.position(v))));
  std::sort(h.begin(), h.end());
  return h;
}

struct Counts {
  std::size_t layers = 0, general = 0, empty = 0;
};

// Sweeps with 1 and 2 threads and compares every layer with a fresh slice().
void check_sweep(const SliceModel& compiled, const Eigen::VectorXd& normal,
                 const std::vector<double>& offsets, const AffineTransform& xf, Counts& counts) {
  Slicer sweeper;
  std::vector<SliceBuffers> layers, threaded;
  sweeper.sweep(compiled, normal, offsets, xf, layers, 1);
  Slicer().sweep(compiled, normal, offsets, xf, threaded, 2);
  REQUIRE(layers.size() == offsets.size());
  REQUIRE(threaded.size() == offsets.size());
  Slicer single;
  SliceBuffers one;
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    single.slice(compiled, Hyperplane::from(normal, offsets[k]), xf, one);
    const std::string why = difference(layers[k], one);
    if (!why.empty()) FAIL("layer " << k << " (offset " << offsets[k] << "): " << why);
    const std::string why2 = difference(threaded[k], one);
    if (!why2.empty()) FAIL("2 threads, layer " << k << ": " << why2);
    ++counts.layers;
    counts.general += one.general;
    counts.empty += one.empty();
  }
}

// 512 layers evenly spaced across the model (and a little beyond), sorted: several between
// two vertex heights of every model tested.
std::vector<double> dense(const std::vector<double>& h) {
  const double lo = h.front(), hi = h.back(), pad = 0.02 * (hi - lo);
  std::vector<double> d(512);
  for (std::size_t i = 0; i < d.size(); ++i)
    d[i] = lo - pad + (hi - lo + 2 * pad) * (static_cast<double>(i) + 0.5) / 512.0;
  return d;
}

// 16 random layers inside the model, unsorted, one repeated.
std::vector<double> sparse(std::mt19937& rng, const std::vector<double>& h) {
  std::uniform_real_distribution<double> u(h.front(), h.back());
  std::vector<double> d(16);
  for (double& x : d) x = u(rng);
  d[7] = d[3];
  return d;
}

// Dense layers with some exactly at vertex heights (through vertices: the general path) and
// some one rounding step beside them.
std::vector<double> through_vertices(std::mt19937& rng, const std::vector<double>& h) {
  std::vector<double> d = dense(h);
  std::uniform_int_distribution<std::size_t> pick(0, h.size() - 1);
  for (int i = 0; i < 24; ++i) {
    const double x = h[pick(rng)];
    d.push_back(x);
    d.push_back(std::nextafter(x, 1e300));
    d.push_back(x + 1e-9 * (h.back() - h.front()));
  }
  std::sort(d.begin(), d.end());
  return d;
}

}  // namespace

TEST_CASE("sweep: every layer exactly as slice(), dense, sparse and through vertices",
          "[slicer][sweep]") {
  std::mt19937 rng(20261202);
  Counts counts;
  for (const std::string spec :
       {"tesseract", "24-cell", "120-cell", "600-cell", "duoprism:32,32", "5-cell", "16-cell"}) {
    INFO(spec);
    const Complex model = load_model(spec);
    const SliceModel compiled(model, SliceModelOptions::unclustered());
    REQUIRE(compiled.fast());
    for (int round = 0; round < 4; ++round) {
      INFO("round " << round);
      // Generic normals (not unit), then a coordinate axis (many equal vertex heights).
      Eigen::VectorXd normal = test::random_unit(rng, 4) * (0.5 + round);
      if (round == 3) normal = Eigen::Vector4d(0.0, 0.0, 0.0, 2.0);
      const AffineTransform xf = round == 1   ? placement(rng, false)
                                 : round == 2 ? placement(rng, true)
                                              : AffineTransform::identity(4);
      const std::vector<double> h = heights(model, normal.normalized(), xf);
      check_sweep(compiled, normal, dense(h), xf, counts);
      check_sweep(compiled, normal, sparse(rng, h), xf, counts);
      check_sweep(compiled, normal, through_vertices(rng, h), xf, counts);
    }
  }
  // The comparison covered fast, general (layers through vertices) and empty layers.
  CHECK(counts.general > 100);
  CHECK(counts.empty > 100);
  CHECK(counts.layers - counts.general - counts.empty > 25000);
}

TEST_CASE("sweep: the omnitruncated 120-cell and clustered compilations", "[slicer][sweep]") {
  std::mt19937 rng(20261203);
  Counts counts;
  {
    const Complex model = load_model("omnitruncated 120-cell");
    const SliceModel compiled(model, SliceModelOptions::unclustered());
    const Eigen::VectorXd normal = test::random_unit(rng, 4);
    const AffineTransform id = AffineTransform::identity(4);
    const std::vector<double> h = heights(model, normal, id);
    check_sweep(compiled, normal, dense(h), id, counts);
    check_sweep(compiled, normal, sparse(rng, h), id, counts);
  }
  // Clusters renumber the elements: the order of a slice is still increasing internal id.
  for (const std::string spec : {"120-cell", "600-cell"}) {
    INFO(spec);
    const Complex model = load_model(spec);
    const SliceModel clustered(model, {16, 8});
    REQUIRE(clustered.cluster_count() > 10);
    const Eigen::VectorXd normal = test::random_unit(rng, 4);
    const AffineTransform xf = placement(rng, true);
    const std::vector<double> h = heights(model, normal, xf);
    check_sweep(clustered, normal, dense(h), xf, counts);
    check_sweep(clustered, normal, through_vertices(rng, h), xf, counts);
  }
  CHECK(counts.layers - counts.general - counts.empty > 2000);
}

TEST_CASE("sweep: a non-convex model whose cuts the kernel leaves to the generic gathering",
          "[slicer][sweep]") {
  // The prism over a picture frame: its two frame cells are cut in two loops by many planes,
  // which the kernel passes to the generic gathering (and the sweep to slice()); the layers
  // after those must again be exactly slice()'s.
  std::mt19937 rng(20261204);
  Counts counts;
  const Complex model = load_model(std::string("prism:") + CW4D_TEST_DATA_DIR + "/frame.off");
  const SliceModel compiled(model, SliceModelOptions::unclustered());
  REQUIRE(compiled.fast());
  Slicer probe;
  SliceBuffers one;
  for (int round = 0; round < 6; ++round) {
    INFO("round " << round);
    const Eigen::VectorXd normal = test::random_unit(rng, 4);
    const AffineTransform xf = round % 2 == 0 ? AffineTransform::identity(4) : placement(rng, true);
    const std::vector<double> h = heights(model, normal, xf);
    const std::vector<double> d = dense(h);
    for (double x : d) probe.slice(compiled, Hyperplane::from(normal, x), xf, one);
    check_sweep(compiled, normal, d, xf, counts);
    check_sweep(compiled, normal, sparse(rng, h), xf, counts);
    check_sweep(compiled, normal, through_vertices(rng, h), xf, counts);
  }
  // Some of those layers did go through the generic gathering.
  CHECK(probe.generic_elements() > 0);
  CHECK(counts.layers - counts.general - counts.empty > 3000);
}

TEST_CASE("sweep: many vertices passed per layer, mirrored, and layers at vertex heights",
          "[slicer][sweep]") {
  // Models whose layers each pass tens to hundreds of vertices (every layer renews much of the
  // structure, below the quarter that rebuilds it): a large duoprism and the omnitruncated
  // 120-cell, 48 to 256 layers, identity and mirrored placements (the polygons reversed as
  // written), some layers exactly at vertex heights and one rounding step beside them.
  std::mt19937 rng(20261205);
  Counts counts;
  for (const std::string spec : {"duoprism:48,40", "omnitruncated 120-cell"}) {
    INFO(spec);
    const Complex model = load_model(spec);
    const SliceModel compiled(model, SliceModelOptions::unclustered());
    for (int round = 0; round < 2; ++round) {
      INFO("round " << round);
      const Eigen::VectorXd normal = test::random_unit(rng, 4);
      const AffineTransform xf = round == 0 ? AffineTransform::identity(4) : placement(rng, true);
      const std::vector<double> h = heights(model, normal, xf);
      for (std::size_t count : {256u, 48u}) {
        std::vector<double> d(count);
        for (std::size_t i = 0; i < count; ++i)
          d[i] = h.front() + (h.back() - h.front()) * (static_cast<double>(i) + 0.5) /
                                 static_cast<double>(count);
        std::uniform_int_distribution<std::size_t> pick(0, h.size() - 1);
        for (int i = 0; i < 4; ++i) {
          const double x = h[pick(rng)];
          d.push_back(x);
          d.push_back(std::nextafter(x, 1e300));
        }
        check_sweep(compiled, normal, d, xf, counts);
      }
    }
  }
  CHECK(counts.general > 0);
  CHECK(counts.layers - counts.general - counts.empty > 1000);
}

TEST_CASE("sweep: several solids (two tesseracts sharing a cube)", "[slicer][sweep]") {
  // A 2 x 1 x 1 x 1 box cut into two unit tesseracts: the cut of each solid is gathered above
  // the polygons (not the single solid's row).
  ComplexSoup soup;
  soup.ambient_dim = 4;
  auto vid = [](int x, int y, int z, int w) {
    return static_cast<std::uint32_t>(((x * 2 + y) * 2 + z) * 2 + w);
  };
  soup.positions.resize(4, 24);
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 2; ++y)
      for (int z = 0; z < 2; ++z)
        for (int w = 0; w < 2; ++w)
          soup.positions.col(vid(x, y, z, w)) = Eigen::Vector4d(x, y, z, w);
  const int size[4] = {3, 2, 2, 2};
  auto at = [&](const int* p) { return vid(p[0], p[1], p[2], p[3]); };
  std::map<std::vector<std::uint32_t>, std::uint32_t> square_id, cube_id;
  auto key = [](std::vector<std::uint32_t> v) {
    std::sort(v.begin(), v.end());
    return v;
  };
  // Unit squares (axes i < j from each base point) and unit cubes (axes i < j < k).
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      for (int b = 0; b < 24; ++b) {
        int p[4] = {b / 8, (b / 4) % 2, (b / 2) % 2, b % 2};
        if (p[i] + 1 >= size[i] || p[j] + 1 >= size[j]) continue;
        int q[4][4];
        for (int c = 0; c < 4; ++c) std::copy(p, p + 4, q[c]);
        ++q[1][i], ++q[2][i], ++q[2][j], ++q[3][j];
        const std::vector<std::uint32_t> cycle = {at(q[0]), at(q[1]), at(q[2]), at(q[3])};
        square_id[key(cycle)] = static_cast<std::uint32_t>(soup.faces.size());
        soup.faces.push_back(cycle);
      }
  soup.higher.resize(2);
  auto corners = [&](const int* p, std::initializer_list<int> axes) {
    std::vector<std::uint32_t> v;
    const std::vector<int> ax(axes);
    for (int mask = 0; mask < (1 << ax.size()); ++mask) {
      int q[4] = {p[0], p[1], p[2], p[3]};
      for (std::size_t a = 0; a < ax.size(); ++a) q[ax[a]] += (mask >> a) & 1;
      v.push_back(at(q));
    }
    return key(v);
  };
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      for (int k = j + 1; k < 4; ++k)
        for (int b = 0; b < 24; ++b) {
          int p[4] = {b / 8, (b / 4) % 2, (b / 2) % 2, b % 2};
          if (p[i] + 1 >= size[i] || p[j] + 1 >= size[j] || p[k] + 1 >= size[k]) continue;
          std::vector<std::uint32_t> faces;
          const int ax[3] = {i, j, k};
          for (int drop = 0; drop < 3; ++drop)
            for (int side = 0; side < 2; ++side) {
              int q[4] = {p[0], p[1], p[2], p[3]};
              q[ax[drop]] += side;
              faces.push_back(square_id.at(corners(q, {ax[(drop + 1) % 3], ax[(drop + 2) % 3]})));
            }
          cube_id[corners(p, {i, j, k})] = static_cast<std::uint32_t>(soup.higher[0].size());
          soup.higher[0].push_back(faces);
        }
  for (int x = 0; x < 2; ++x) {
    const int p[4] = {x, 0, 0, 0};
    std::vector<std::uint32_t> cubes;
    const int axes[4] = {0, 1, 2, 3};
    for (int drop = 0; drop < 4; ++drop)
      for (int side = 0; side < 2; ++side) {
        int q[4] = {p[0], p[1], p[2], p[3]};
        q[axes[drop]] += side;
        std::vector<int> rest;
        for (int a = 0; a < 4; ++a)
          if (a != drop) rest.push_back(a);
        cubes.push_back(cube_id.at(corners(q, {rest[0], rest[1], rest[2]})));
      }
    soup.higher[1].push_back(cubes);
  }
  const Complex model = build_complex(soup);
  REQUIRE(model.count(4) == 2);
  const SliceModel compiled(model, SliceModelOptions::unclustered());
  REQUIRE(compiled.fast());
  std::mt19937 rng(20261206);
  Counts counts;
  for (int round = 0; round < 4; ++round) {
    INFO("round " << round);
    const Eigen::VectorXd normal = test::random_unit(rng, 4);
    const AffineTransform xf = round % 2 == 0 ? AffineTransform::identity(4) : placement(rng, true);
    const std::vector<double> h = heights(model, normal, xf);
    check_sweep(compiled, normal, dense(h), xf, counts);
    check_sweep(compiled, normal, through_vertices(rng, h), xf, counts);
  }
  CHECK(counts.layers - counts.general - counts.empty > 2000);
}

TEST_CASE("sweep: one Slicer kept over several models, sweeps and slices mixed",
          "[slicer][sweep]") {
  // The sweep keeps per-model tables in its Slicer (and in its helper Slicers for threads):
  // sweeping another model, then the first again, slicing in between, must give every layer as
  // a fresh Slicer's slice() does.
  std::mt19937 rng(7001);
  const Complex a = load_model("120-cell");
  const Complex b = load_model("duoprism:12,9");
  const SliceModel ca(a, SliceModelOptions::unclustered());
  const SliceModel cb(b, SliceModelOptions::unclustered());
  Slicer kept;
  std::vector<SliceBuffers> layers;
  SliceBuffers between;
  for (int round = 0; round < 6; ++round) {
    INFO("round " << round);
    const bool first = round % 2 == 0;
    const Complex& model = first ? a : b;
    const SliceModel& compiled = first ? ca : cb;
    const Eigen::VectorXd normal = test::random_unit(rng, 4);
    const AffineTransform xf =
        round >= 4 ? placement(rng, round == 5) : AffineTransform::identity(4);
    const std::vector<double> h = heights(model, normal, xf);
    const std::vector<double> d = round % 3 == 2 ? sparse(rng, h) : dense(h);
    kept.sweep(compiled, normal, d, xf, layers, 1 + static_cast<unsigned>((round / 2) % 2));
    REQUIRE(layers.size() == d.size());
    Slicer fresh;
    SliceBuffers one;
    for (std::size_t k = 0; k < d.size(); ++k) {
      fresh.slice(compiled, Hyperplane::from(normal, d[k]), xf, one);
      const std::string why = difference(layers[k], one);
      if (!why.empty()) FAIL("layer " << k << " (offset " << d[k] << "): " << why);
    }
    // A slice of the other model through the same Slicer between two sweeps.
    const SliceModel& other = first ? cb : ca;
    kept.slice(other, Hyperplane::from(normal, 0.1), between);
    fresh.slice(other, Hyperplane::from(normal, 0.1), one);
    const std::string why = difference(between, one);
    if (!why.empty()) FAIL("slice between sweeps: " << why);
  }
}

TEST_CASE("sweep: layers whose crossings lie within the weld distance of a vertex",
          "[slicer][sweep]") {
  // A layer a little above or below a vertex (a few weld distances and less) has crossings the
  // fast path leaves to the general one: the sweep tests every crossing of a layer (two at a
  // time, and the last alone when their count is odd), so whichever crossing is too close,
  // the layer must be slice()'s general one; the layers between must be fast again. Each
  // sweep also runs alone on one such layer, and on pairs of them.
  std::mt19937 rng(20261206);
  Counts counts;
  std::size_t weld = 0;
  for (const std::string spec : {"24-cell", "120-cell", "600-cell", "duoprism:32,32"}) {
    const Complex model = load_model(spec);
    const SliceModel compiled(model, SliceModelOptions::unclustered());
    Slicer probe;  // (counts the layers the general path welds)
    SliceBuffers one;
    for (const bool mirrored : {false, true}) {
      INFO(spec << (mirrored ? ", mirrored" : ""));
      const AffineTransform xf = mirrored ? placement(rng, true) : AffineTransform::identity(4);
      const Eigen::VectorXd normal = test::random_unit(rng, 4);
      const std::vector<double> h = heights(model, normal, xf);
      const double span = h.back() - h.front();
      std::vector<double> d = dense(h);
      std::uniform_int_distribution<std::size_t> pick(0, h.size() - 1);
      for (int i = 0; i < 24; ++i) {
        const double x = h[pick(rng)];
        for (double k : {-3.0, -0.5, 0.5, 3.0, 100.0}) d.push_back(x + k * 1e-9 * span);
      }
      std::sort(d.begin(), d.end());
      check_sweep(compiled, normal, d, xf, counts);
      for (int i = 0; i < 8; ++i) {
        const double x = h[pick(rng)] + 0.5e-9 * span;
        check_sweep(compiled, normal, {x}, xf, counts);
        check_sweep(compiled, normal, {x, h[pick(rng)] - 0.5e-9 * span}, xf, counts);
      }
      for (double x : d) {
        probe.slice(compiled, Hyperplane::from(normal, x), xf, one);
        weld += one.fallback == FallbackReason::Weld;
      }
    }
  }
  CHECK(weld > 50);
  CHECK(counts.layers - counts.general - counts.empty > 3000);
}

TEST_CASE("sweep: a star polychoron, and the atlas's layers (every vertex height and between)",
          "[slicer][sweep]") {
  // The layers section_atlas sweeps: each distinct vertex height (a vertex on the plane: the
  // general path) and the midpoint above it (every layer passes vertices), on a convex model
  // and on a star polychoron whose faces and cells cross each other, placed, with a layer list
  // that is unsorted, repeats offsets and reaches beyond the model.
  std::mt19937 rng(20261206);
  Counts counts;
  for (const std::string spec : {"great grand stellated 120-cell", "24-cell"}) {
    INFO(spec);
    const Complex model = load_model(spec);
    const SliceModel compiled(model, SliceModelOptions::unclustered());
    const Eigen::VectorXd normal = test::random_unit(rng, 4);
    const AffineTransform xf = placement(rng, false);
    std::vector<double> h = heights(model, normal, xf);
    h.erase(std::unique(h.begin(), h.end()), h.end());
    std::vector<double> d;
    for (std::size_t i = 0; i < h.size(); ++i) {
      d.push_back(h[i]);
      if (i + 1 < h.size()) d.push_back(0.5 * h[i] + 0.5 * h[i + 1]);
    }
    if (d.size() > 96) d.resize(96);
    check_sweep(compiled, normal, d, xf, counts);
    const double span = h.back() - h.front();
    d.push_back(h.back() + 0.25 * span);
    d.push_back(h.front() - 0.25 * span);
    d.push_back(d[5]);
    std::shuffle(d.begin(), d.end(), rng);
    check_sweep(compiled, normal, d, xf, counts);
  }
  CHECK(counts.general > 0);
  CHECK(counts.empty >= 4);
  CHECK(counts.layers - counts.general - counts.empty > 50);
}
