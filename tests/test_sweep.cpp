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
#include <random>
#include <string>
#include <vector>

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

// 1024 layers evenly spaced across the model (and a little beyond), sorted.
std::vector<double> dense(const std::vector<double>& h) {
  const double lo = h.front(), hi = h.back(), pad = 0.02 * (hi - lo);
  std::vector<double> d(1024);
  for (std::size_t i = 0; i < d.size(); ++i)
    d[i] = lo - pad + (hi - lo + 2 * pad) * (static_cast<double>(i) + 0.5) / 1024.0;
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
  CHECK(counts.layers - counts.general - counts.empty > 50000);
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
  CHECK(counts.layers - counts.general - counts.empty > 4000);
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
