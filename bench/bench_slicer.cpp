// The slicer's hot path (cw4d/section/slicer.hpp) against its own alternatives and against the
// machine, each figure a ratio of two benchmarks of the same run:
//
//  sweep/M/threads:T  one Slicer::sweep of 256 parallel layers (seeded generic normal, offsets
//                     evenly spaced over n.centre +- 0.9 radius), T threads;
//  slices/M           the same 256 planes by 256 Slicer::slice calls into 256 reused buffers
//                     (default options: cluster culling on).
//                     M = 120-cell, 600-cell, grid-1e4 (10^4 disjoint tesseracts, one Complex).
//  scene/1pct/cull, scene/1pct/nocull
//                     SceneSlicer::slice of a scene of 10^4 randomly turned tesseracts and
//                     24-cells (seeded) in the box [0,400]x[0,40]x[0,40]x[0,8], by a plane
//                     x ~ 200 that touches about 1 % of them, with and without culling;
//  scene/1pct/touched-only, scene/1pct/sphere-test
//                     references for the culled figure: only the touched objects cut by one
//                     Slicer (the work culling cannot avoid), and the bounding-sphere test of
//                     all 10^4 objects over a flat array (what a culling pass needs to cost);
//  scene/50pct/threads:T
//                     the same scene and a plane w ~ 4 that touches about 40 % of the objects.
//  big/slice/{nocull,cull}, big-nosolids/slice/{nocull,cull}
//                     a single Complex of 125,000 disjoint tesseracts (10^6 cells; with or
//                     without their rank-4 solids) compiled into a clustered SliceModel, cut
//                     by one generic plane through the middle; bytes/s = the input Complex's
//                     bytes (the target's figure), next to SliceModel::bytes() and the bytes
//                     an unculled slice must stream (positions, edge ids, cluster vertex lists).
//  big/vertex-pass    the least a first pass over the big model's vertices does (a plain dot
//                     product, the value and the side stored); bytes = the positions read.
//  memory/sum, memory/copy
//                     this machine's memory bandwidth, one thread: sum of a 1 GiB double array
//                     (8 accumulators), memcpy of 1 GiB (counted as 2 GiB moved, as STREAM).
//  torus/...          cw4d against CGAL::Polygon_mesh_slicer on a ~10^6-triangle torus
//                     (bench_slicer_cgal.cpp, the only file that includes CGAL).
//
// Single-thread ratios use CPU time; the thread ratios use wall-clock time. Nothing is asserted
// about time; a benchmark whose outputs disagree with the reference stops with an error.
//
//   bench_slicer [--benchmark_filter=REGEX] [--benchmark_min_time=SECONDS] ...
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench_models.hpp"
#include "bench_options.hpp"
#include "bench_ratios.hpp"
#include "bench_slicer_cgal.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/section/slicer.hpp"

namespace {

using cw4d::bench::Measurements;
using cw4d::bench::RatioLine;
using cw4d::bench::time_ratio;

constexpr std::size_t kLayers = 256;
constexpr std::uint32_t kSeed = 20240401u;
constexpr double kMinTime = 0.3;

// --- models, built on first use (a filtered run builds only what it cuts) ---------------------

struct Compiled {
  cw4d::Complex complex;
  std::unique_ptr<cw4d::SliceModel> model;
};

const Compiled& compiled(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Compiled>> cache;
  auto& slot = cache[name];
  if (!slot) {
    slot = std::make_unique<Compiled>();
    if (name == "grid-1e4")
      slot->complex = cw4d::bench::tesseract_union({10, 10, 10, 10}, true);
    else if (name == "big")
      slot->complex = cw4d::bench::tesseract_union({20, 25, 25, 10}, true);
    else if (name == "big-nosolids")
      slot->complex = cw4d::bench::tesseract_union({20, 25, 25, 10}, false);
    else
      slot->complex = cw4d::load_model(name);
    slot->model = std::make_unique<cw4d::SliceModel>(slot->complex);
  }
  return *slot;
}

struct Layers {
  Eigen::VectorXd normal;
  std::vector<double> offsets;
  std::vector<cw4d::Hyperplane> planes;
};

Layers layers_for(const cw4d::SliceModel& m) {
  Layers l;
  l.normal = cw4d::bench::seeded_normal(4, kSeed);
  const double mid = l.normal.dot(m.centre()), half = 0.9 * m.radius();
  for (std::size_t i = 0; i < kLayers; ++i) {
    const double d = mid - half + 2.0 * half * (static_cast<double>(i) + 0.5) / kLayers;
    l.offsets.push_back(d);
    l.planes.push_back(cw4d::Hyperplane::from(l.normal, d));
  }
  return l;
}

double section_vertices(const std::vector<cw4d::SliceBuffers>& out) {
  double v = 0;
  for (const auto& b : out) v += static_cast<double>(b.count(0));
  return v / static_cast<double>(out.size());
}

// --- a. sweeps against single slices ----------------------------------------------------------

void sweep(benchmark::State& state, const std::string& name, unsigned threads) {
  const cw4d::SliceModel& m = *compiled(name).model;
  const Layers l = layers_for(m);
  const cw4d::AffineTransform id = cw4d::AffineTransform::identity(4);
  cw4d::Slicer slicer, single;
  std::vector<cw4d::SliceBuffers> out, ref(kLayers);
  slicer.sweep(m, l.normal, l.offsets, id, out, threads);
  for (std::size_t i = 0; i < kLayers; ++i) {
    single.slice(m, l.planes[i], ref[i]);
    if (ref[i].count(0) != out[i].count(0) || ref[i].count(2) != out[i].count(2) ||
        ref[i].coords != out[i].coords) {
      state.SkipWithError("sweep layer differs from slice()");
      return;
    }
  }
  const std::size_t fast0 = slicer.fast_slices();
  for (auto _ : state) {
    slicer.sweep(m, l.normal, l.offsets, id, out, threads);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["verts"] = section_vertices(out);
  state.counters["fast"] = static_cast<double>(slicer.fast_slices() - fast0) /
                           static_cast<double>(state.iterations() * kLayers);
}

void slices(benchmark::State& state, const std::string& name) {
  const cw4d::SliceModel& m = *compiled(name).model;
  const Layers l = layers_for(m);
  cw4d::Slicer slicer;
  std::vector<cw4d::SliceBuffers> out(kLayers);
  for (std::size_t i = 0; i < kLayers; ++i) slicer.slice(m, l.planes[i], out[i]);
  for (auto _ : state) {
    for (std::size_t i = 0; i < kLayers; ++i) slicer.slice(m, l.planes[i], out[i]);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["verts"] = section_vertices(out);
}

// --- b, e. scenes -----------------------------------------------------------------------------

const cw4d::Scene& scene() {
  static const cw4d::Scene s =
      cw4d::bench::scattered_scene(10000, Eigen::Vector4d(400, 40, 40, 8), kSeed);
  return s;
}

cw4d::Hyperplane scene_plane(bool many) {
  Eigen::VectorXd n(4);
  if (many)
    n << 0.01, 0.02, 0.015, 1.0;  // w ~ 4: about half of the objects
  else
    n << 1.0, 0.01, 0.02, 0.015;  // x ~ 200: about 1 %
  return cw4d::Hyperplane::from(n, many ? 4.0 : 200.0);
}

void scene_slice(benchmark::State& state, bool many, bool cull, unsigned threads) {
  cw4d::SceneSlicer slicer(scene());
  const cw4d::Hyperplane plane = scene_plane(many);
  cw4d::SliceOptions options;
  options.cull = cull;
  cw4d::SceneSlice out;
  slicer.slice(plane, out, threads, options);
  std::size_t hit = 0;
  for (const auto& b : out.buffers) hit += !b.empty();
  for (auto _ : state) {
    slicer.slice(plane, out, threads, options);
    benchmark::DoNotOptimize(out.buffers.data());
  }
  cw4d::SceneSlicer culling(scene());
  culling.slice(plane, out, 1);
  state.counters["touched"] =
      static_cast<double>(culling.touched()) / static_cast<double>(scene().objects.size());
  state.counters["hit"] = static_cast<double>(hit) / static_cast<double>(scene().objects.size());
}

// The floor of a culled scene slice: only the objects whose bounding sphere meets the plane,
// cut by one Slicer (SliceModels of the two distinct models), no pass over the others.
void scene_touched_only(benchmark::State& state) {
  const cw4d::Scene& sc = scene();
  const cw4d::Hyperplane plane = scene_plane(false);
  std::map<const cw4d::Complex*, std::unique_ptr<cw4d::SliceModel>> models;
  std::vector<std::size_t> touched;
  for (std::size_t i = 0; i < sc.objects.size(); ++i) {
    auto& m = models[sc.objects[i].complex.get()];
    if (!m) m = std::make_unique<cw4d::SliceModel>(*sc.objects[i].complex);
    // Rigid placements: the sphere keeps its radius.
    const Eigen::VectorXd c = sc.objects[i].transform.apply(m->centre());
    if (std::abs(plane.signed_distance(c)) <= m->radius() * (1.0 + 1e-9)) touched.push_back(i);
  }
  cw4d::Slicer slicer;
  std::vector<cw4d::SliceBuffers> out(touched.size());
  const auto run = [&] {
    for (std::size_t j = 0; j < touched.size(); ++j) {
      const cw4d::SceneObject& o = sc.objects[touched[j]];
      slicer.slice(*models[o.complex.get()], plane, o.transform, out[j]);
    }
  };
  run();
  for (auto _ : state) {
    run();
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["touched"] =
      static_cast<double>(touched.size()) / static_cast<double>(sc.objects.size());
}

// The culling test alone over flat (centre, radius) records.
void scene_sphere_test(benchmark::State& state) {
  const cw4d::Scene& sc = scene();
  const cw4d::Hyperplane plane = scene_plane(false);
  std::vector<std::array<double, 5>> spheres;
  for (const auto& o : sc.objects) {
    const cw4d::SliceModel m(*o.complex);
    const Eigen::VectorXd c = o.transform.apply(m.centre());
    spheres.push_back({c[0], c[1], c[2], c[3], m.radius()});
  }
  std::vector<char> hit(spheres.size());
  for (auto _ : state) {
    for (std::size_t i = 0; i < spheres.size(); ++i) {
      const auto& q = spheres[i];
      const double d = plane.normal[0] * q[0] + plane.normal[1] * q[1] + plane.normal[2] * q[2] +
                       plane.normal[3] * q[3] - plane.offset;
      hit[i] = std::abs(d) <= q[4];
    }
    benchmark::DoNotOptimize(hit.data());
  }
}

// --- c. a 10^6-cell model next to the memory bandwidth ---------------------------------------

cw4d::Hyperplane big_plane(const cw4d::SliceModel& m) {
  const Eigen::VectorXd n = cw4d::bench::seeded_normal(4, kSeed + 7);
  return cw4d::Hyperplane::from(n, n.dot(m.centre()) + 0.123);
}

// The bytes every unculled fast slice of a clustered SliceModel in R^4 reads whatever the
// output: the positions (n doubles per vertex; every cluster touched, the vertex pass runs over
// all vertices in order, not through the clusters' vertex lists), the edge table's endpoint ids
// (2 x uint32 per edge; the edge loop reads no offsets and no signs) and the clusters' edge
// ranges.
std::size_t stream_bytes(const cw4d::SliceModel& m) {
  const cw4d::Complex& c = m.complex();
  const std::size_t n = static_cast<std::size_t>(m.dim()), nv = c.count(0), ne = c.count(1),
                    nc = m.cluster_count();
  return nv * n * 8 + ne * 2 * 4 + (nc + 1) * 4;
}

void big_slice(benchmark::State& state, const std::string& name, bool cull) {
  const cw4d::SliceModel& m = *compiled(name).model;
  const cw4d::Hyperplane plane = big_plane(m);
  cw4d::SliceOptions options;
  options.cull = cull;
  cw4d::Slicer slicer;
  cw4d::SliceBuffers out;
  slicer.slice(m, plane, out, options);
  if (out.general) {
    state.SkipWithError("the plane took the general path");
    return;
  }
  for (auto _ : state) {
    slicer.slice(m, plane, out, options);
    benchmark::DoNotOptimize(out.coords.data());
  }
  const std::size_t stream = stream_bytes(m);
  if (m.cluster_count() < 2) {
    state.SkipWithError("the model is not clustered");
    return;
  }
  // bytes/s (SetBytesProcessed) and "bytes" count the input Complex, the scene's size (the
  // target's figure); "model_bytes" and "stream_bytes" are context (see register_all).
  const auto bytes = static_cast<double>(cw4d::bench::complex_bytes(m.complex()));
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes) * state.iterations());
  state.counters["bytes"] = bytes;
  state.counters["model_bytes"] = static_cast<double>(m.bytes());
  state.counters["stream_bytes"] = static_cast<double>(stream);
  state.counters["cells"] = static_cast<double>(m.complex().count(3));
  state.counters["polygons"] = static_cast<double>(out.count(2));
  state.counters["clusters"] = static_cast<double>(m.cluster_count());
}

// The least any slicer's first pass does, on the big model's 2 x 10^6 vertices: read the
// positions, a dot product with the normal, store the value and the side.
[[gnu::noinline]] void vertex_pass(const double* p, std::size_t nv, const double* n, double d,
                                   double* s, std::int8_t* side) {
  for (std::size_t v = 0; v < nv; ++v) {
    const double* x = p + 4 * v;
    const double value = n[0] * x[0] + n[1] * x[1] + n[2] * x[2] + n[3] * x[3] - d;
    s[v] = value;
    side[v] = static_cast<std::int8_t>(value > 1e-12 ? 1 : value < -1e-12 ? -1 : 0);
  }
}

void big_vertex_pass(benchmark::State& state) {
  const Compiled& c = compiled("big");
  const cw4d::Hyperplane plane = big_plane(*c.model);
  const std::size_t nv = c.complex.count(0);
  std::vector<double> s(nv);
  std::vector<std::int8_t> side(nv);
  for (auto _ : state) {
    vertex_pass(c.complex.positions().data(), nv, plane.normal.data(), plane.offset, s.data(),
                side.data());
    benchmark::DoNotOptimize(s.data());
  }
  state.counters["bytes"] = static_cast<double>(nv * 4 * sizeof(double));
  state.SetBytesProcessed(static_cast<std::int64_t>(nv * 4 * sizeof(double)) * state.iterations());
}

constexpr std::size_t kArrayBytes = std::size_t{1} << 30;

struct Arrays {
  std::vector<double> a, b;
  Arrays() : a(kArrayBytes / sizeof(double)), b(kArrayBytes / sizeof(double)) {
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = static_cast<double>(i & 1023) * 0.5;
    std::fill(b.begin(), b.end(), 1.0);
  }
};

Arrays& arrays() {
  static Arrays arr;
  return arr;
}

[[gnu::noinline]] double sum_array(const double* a, std::size_t n) {
  double s[8] = {};
  for (std::size_t i = 0; i + 8 <= n; i += 8)
    for (int k = 0; k < 8; ++k) s[k] += a[i + k];
  return ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
}

void memory_sum(benchmark::State& state) {
  const Arrays& arr = arrays();
  for (auto _ : state) {
    double s = sum_array(arr.a.data(), arr.a.size());
    benchmark::DoNotOptimize(s);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(kArrayBytes) * state.iterations());
  state.counters["bytes"] = static_cast<double>(kArrayBytes);
}

void memory_copy(benchmark::State& state) {
  Arrays& arr = arrays();
  for (auto _ : state) {
    std::memcpy(arr.b.data(), arr.a.data(), kArrayBytes);
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(2 * kArrayBytes) * state.iterations());
  state.counters["bytes"] = static_cast<double>(2 * kArrayBytes);
}

// --- registration and the ratios --------------------------------------------------------------

benchmark::internal::Benchmark* add(const std::string& name,
                                    std::function<void(benchmark::State&)> fn,
                                    bool default_min_time, bool wall = false) {
  auto* b = benchmark::RegisterBenchmark(name.c_str(), std::move(fn));
  b->Unit(benchmark::kMillisecond);
  if (default_min_time) b->MinTime(kMinTime);
  if (wall) b->UseRealTime();
  return b;
}

/// bytes/s of benchmark a over bytes/s of benchmark b (counter `bytes_a` of a, "bytes" of b,
/// per iteration, CPU time).
std::function<std::optional<double>(const Measurements&)> rate_ratio(
    std::string a, std::string b, std::string bytes_a = "bytes") {
  return [a = std::move(a), b = std::move(b),
          bytes_a = std::move(bytes_a)](const Measurements& m) -> std::optional<double> {
    const auto ia = m.find(a), ib = m.find(b);
    if (ia == m.end() || ib == m.end() || !ia->second.counters.count(bytes_a)) return std::nullopt;
    return (ia->second.counters.at(bytes_a) / ia->second.cpu) /
           (ib->second.counters.at("bytes") / ib->second.cpu);
  };
}

std::function<std::optional<double>(const Measurements&)> counter(std::string run, std::string c) {
  return [run = std::move(run), c = std::move(c)](const Measurements& m) -> std::optional<double> {
    const auto it = m.find(run);
    if (it == m.end() || !it->second.counters.count(c)) return std::nullopt;
    return it->second.counters.at(c);
  };
}

std::function<std::optional<double>(const Measurements&)> rate(std::string run,
                                                               std::string bytes = "bytes") {
  return [run = std::move(run),
          bytes = std::move(bytes)](const Measurements& m) -> std::optional<double> {
    const auto it = m.find(run);
    if (it == m.end() || !it->second.counters.count(bytes)) return std::nullopt;
    return it->second.counters.at(bytes) / it->second.cpu;
  };
}

std::vector<RatioLine> register_all(bool dmt) {
  std::vector<RatioLine> lines;
  const auto at_least = [](double x) { return [x](double v) { return v >= x; }; };
  const auto at_most = [](double x) { return [x](double v) { return v <= x; }; };
  // a, e: sweeps.
  for (const std::string name : {"120-cell", "600-cell", "grid-1e4"}) {
    add(
        "slices/" + name, [name](benchmark::State& s) { slices(s, name); }, dmt);
    add(
        "sweep/" + name + "/threads:1", [name](benchmark::State& s) { sweep(s, name, 1); }, dmt,
        true);
    add(
        "sweep/" + name + "/threads:2", [name](benchmark::State& s) { sweep(s, name, 2); }, dmt,
        true);
    lines.push_back({"a. 256 x slice() / one 256-layer sweep(), " + name, ">= 5x",
                     time_ratio("slices/" + name, "sweep/" + name + "/threads:1"), at_least(5.0)});
  }
  // b, e: scenes.
  add(
      "scene/1pct/cull", [](benchmark::State& s) { scene_slice(s, false, true, 1); }, dmt);
  add(
      "scene/1pct/nocull", [](benchmark::State& s) { scene_slice(s, false, false, 1); }, dmt);
  add("scene/1pct/touched-only", scene_touched_only, dmt);
  add("scene/1pct/sphere-test", scene_sphere_test, dmt);
  add(
      "scene/50pct/threads:1", [](benchmark::State& s) { scene_slice(s, true, true, 1); }, dmt,
      true);
  add(
      "scene/50pct/threads:2", [](benchmark::State& s) { scene_slice(s, true, true, 2); }, dmt,
      true);
  lines.push_back({"b. scene of 10^4 objects: culled / unculled time", "<= 3 %",
                   time_ratio("scene/1pct/cull", "scene/1pct/nocull"), at_most(0.03), "%.2f %%",
                   100});
  lines.push_back({"b. (objects the plane touches)", "~1 %", counter("scene/1pct/cull", "touched"),
                   nullptr, "%.2f %%", 100});
  lines.push_back({"b. (only the touched objects, one Slicer / unculled)", "",
                   time_ratio("scene/1pct/touched-only", "scene/1pct/nocull"), nullptr, "%.2f %%",
                   100});
  lines.push_back({"b. (sphere test of all objects, flat array / unculled)", "",
                   time_ratio("scene/1pct/sphere-test", "scene/1pct/nocull"), nullptr, "%.3f %%",
                   100});
  // c: the big model and the memory.
  for (const std::string name : {"big", "big-nosolids"}) {
    add(
        name + "/slice/nocull", [name](benchmark::State& s) { big_slice(s, name, false); }, dmt);
    add(
        name + "/slice/cull", [name](benchmark::State& s) { big_slice(s, name, true); }, dmt);
  }
  add("big/vertex-pass", big_vertex_pass, dmt);
  add("memory/sum", memory_sum, dmt);
  add("memory/copy", memory_copy, dmt);
  // The target's figure counts the scene's bytes, the input Complex: a size fixed by the input,
  // not by how the slicer lays out its compiled copy (SliceModel::bytes() grows with every
  // auxiliary array, which would raise the figure without a faster slice). The other two are
  // context: the compiled arrays, and the least an unculled slice must stream.
  lines.push_back({"c. 10^6 cells, unculled slice: Complex bytes/s / sum bandwidth", ">= 0.5x",
                   rate_ratio("big/slice/nocull", "memory/sum"), at_least(0.5)});
  lines.push_back({"c. (same, model without rank-4 solids)", ">= 0.5x",
                   rate_ratio("big-nosolids/slice/nocull", "memory/sum"), at_least(0.5)});
  lines.push_back({"c. (SliceModel::bytes()/s / sum)", "",
                   rate_ratio("big/slice/nocull", "memory/sum", "model_bytes"), nullptr});
  lines.push_back({"c. (streamed bytes/s / sum)", "",
                   rate_ratio("big/slice/nocull", "memory/sum", "stream_bytes"), nullptr});
  lines.push_back(
      {"c. (input Complex, MB)", "", counter("big/slice/nocull", "bytes"), nullptr, "%.1f", 1e-6});
  lines.push_back({"c. (SliceModel::bytes(), MB)", "", counter("big/slice/nocull", "model_bytes"),
                   nullptr, "%.1f", 1e-6});
  lines.push_back({"c. (streamed: positions + edge ids + cluster vertex lists, MB)", "",
                   counter("big/slice/nocull", "stream_bytes"), nullptr, "%.1f", 1e-6});
  lines.push_back({"c. (a bare vertex pass: positions bytes/s / sum)", "",
                   rate_ratio("big/vertex-pass", "memory/sum"), nullptr});
  lines.push_back({"c. (unculled slice time / bare vertex pass time)", "",
                   time_ratio("big/slice/nocull", "big/vertex-pass"), nullptr});
  lines.push_back(
      {"c. (unculled slice, Complex GB/s)", "", rate("big/slice/nocull"), nullptr, "%.2f", 1e-9});
  lines.push_back({"c. (sum of 1 GiB, GB/s)", "", rate("memory/sum"), nullptr, "%.2f", 1e-9});
  lines.push_back(
      {"c. (copy of 1 GiB, GB/s read + written)", "", rate("memory/copy"), nullptr, "%.2f", 1e-9});
  lines.push_back({"c. (culled / unculled time, same plane)", "",
                   time_ratio("big/slice/cull", "big/slice/nocull"), nullptr, "%.2f %%", 100});
  lines.push_back({"c. (same, model without rank-4 solids)", "",
                   time_ratio("big-nosolids/slice/cull", "big-nosolids/slice/nocull"), nullptr,
                   "%.2f %%", 100});
  // d: CGAL.
  cw4d::bench::register_cgal_benchmarks(dmt, kMinTime, lines);
  // e: threads (wall clock).
  lines.push_back({"e. scene, plane touching ~50 %: 1 thread / 2 threads (wall)", "(2 cores)",
                   time_ratio("scene/50pct/threads:1", "scene/50pct/threads:2", true), nullptr});
  for (const std::string name : {"120-cell", "600-cell", "grid-1e4"})
    lines.push_back(
        {"e. sweep " + name + ": 1 thread / 2 threads (wall)", "(2 cores)",
         time_ratio("sweep/" + name + "/threads:1", "sweep/" + name + "/threads:2", true),
         nullptr});
  return lines;
}

}  // namespace

int main(int argc, char** argv) {
  const auto [console, color, default_min_time] = cw4d::bench::scan_options(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  std::vector<RatioLine> lines = register_all(default_min_time);
  if (console) {
    cw4d::bench::RatioReporter reporter(color, std::move(lines),
                                        "Ratios within this run (against their targets):");
    benchmark::RunSpecifiedBenchmarks(&reporter);
  } else {
    benchmark::RunSpecifiedBenchmarks();
  }
  benchmark::Shutdown();
  return 0;
}
