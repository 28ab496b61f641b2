// The two section paths side by side: the CW-complex section on its hot path (one SliceModel
// compiled once, SliceModelOptions::unclustered(), one Slicer and one SliceBuffers reused for
// every slice: polygons) and the tetrahedral slicer (cw4d::slice_tets over a TetMesh made once),
// on the 120-cell, the 600-cell and the 32,32-duoprism, over the same fixed list of 256 generic
// planes (random unit normal from a seeded std::mt19937, offset uniform in +-0.9 max_radius). One
// iteration is one slice; the planes are cycled. `tet/*` is the returning slice_tets (a new
// TetSection per call), `tet-slicer/*` a caller-owned TetSlicer into one reused TetSliceMesh (the
// steady path, printed as nanoseconds per tetrahedron at the end), `tet-slicer-nouvw/*` the same
// with TetSliceOptions::uvw off. Counter `tris` is the average
// number of triangles per slice: for the CW path SliceBuffers::fan_triangles() (the k - 2 triangles
// of each k-gon, what a fan triangulation sends to a GPU), for the tet path the triangles it emits.
// `section/*` is the convenience call cw4d::section(model, plane) (a Section with its own Complex
// per call), for reference; `tetrahedralize/*` times building the mesh itself (once per model). In
// console mode the program ends with the tet/CW ratios of time and triangles of this run.
//
//   bench_tet [--benchmark_filter=REGEX] [--benchmark_min_time=SECONDS] ...
#include <benchmark/benchmark.h>

#include <cstdio>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

#include "bench_options.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"

namespace {

constexpr std::size_t kPlaneCount = 256;
constexpr std::uint32_t kSeed = 20240401u;
constexpr double kMinTime = 0.3;

std::vector<cw4d::Hyperplane> generic_planes(const cw4d::Complex& model) {
  return cw4d::bench::generic_planes(model, kPlaneCount, kSeed);
}

struct Model {
  std::string name;
  cw4d::Complex complex;
  std::unique_ptr<cw4d::SliceModel> compiled;  // refers to complex
  cw4d::TetMesh mesh;
  std::vector<cw4d::Hyperplane> planes;
  double cw_tris = 0, tet_tris = 0;  // per slice, averaged over exactly the 256 planes
};

void cw_slices(benchmark::State& state, const Model& m) {
  cw4d::Slicer slicer;
  cw4d::SliceBuffers out;
  std::size_t i = 0;
  double tris = 0;
  for (auto _ : state) {
    slicer.slice(*m.compiled, m.planes[i], out);
    benchmark::DoNotOptimize(out.coords.data());
    tris += static_cast<double>(out.fan_triangles());
    if (++i == m.planes.size()) i = 0;
  }
  state.counters["tris"] = benchmark::Counter(tris, benchmark::Counter::kAvgIterations);
  state.counters["fast"] =
      static_cast<double>(slicer.fast_slices()) / static_cast<double>(state.iterations());
}

void section_slices(benchmark::State& state, const Model& m) {
  std::size_t i = 0;
  double tris = 0;
  for (auto _ : state) {
    cw4d::Section s = cw4d::section(m.complex, m.planes[i]);
    benchmark::DoNotOptimize(s);
    for (std::uint32_t f = 0; f < s.complex.count(2); ++f)
      tris += static_cast<double>(s.complex.boundary(2).row_size(f) - 2);
    if (++i == m.planes.size()) i = 0;
  }
  state.counters["tris"] = benchmark::Counter(tris, benchmark::Counter::kAvgIterations);
}

void tet_slices(benchmark::State& state, const Model& m) {
  std::size_t i = 0;
  double tris = 0;
  for (auto _ : state) {
    cw4d::TetSection s = cw4d::slice_tets(m.mesh, m.planes[i]);
    benchmark::DoNotOptimize(s);
    tris += static_cast<double>(s.triangle_count());
    if (++i == m.planes.size()) i = 0;
  }
  state.counters["tris"] = benchmark::Counter(tris, benchmark::Counter::kAvgIterations);
}

// The steady path: a caller-owned TetSlicer into one reused TetSliceMesh (indexed, welded).
// Counter `ns/tet`: CPU nanoseconds per tetrahedron of the mesh.
void tet_slicer_slices(benchmark::State& state, const Model& m, bool uvw) {
  cw4d::TetSlicer slicer(cw4d::TetSliceOptions{uvw});
  cw4d::TetSliceMesh out;
  std::size_t i = 0;
  double tris = 0;
  for (auto _ : state) {
    slicer.slice(m.mesh, m.planes[i], out);
    benchmark::DoNotOptimize(out.triangles.data());
    tris += static_cast<double>(out.triangle_count());
    if (++i == m.planes.size()) i = 0;
  }
  state.counters["tris"] = benchmark::Counter(tris, benchmark::Counter::kAvgIterations);
  state.counters["tets"] = static_cast<double>(m.mesh.size());
}

void build_mesh(benchmark::State& state, const Model& m) {
  for (auto _ : state) {
    cw4d::TetMesh mesh = cw4d::tetrahedralize(m.complex);
    benchmark::DoNotOptimize(mesh);
  }
  state.counters["tets"] = static_cast<double>(m.mesh.size());
}

std::vector<std::shared_ptr<Model>> register_cases(bool default_min_time) {
  std::vector<std::shared_ptr<Model>> models;
  for (std::string spec : {"120-cell", "600-cell", "duoprism:32,32"}) {
    auto m = std::make_shared<Model>();
    m->name = spec;
    m->complex = cw4d::load_model(spec);
    m->compiled =
        std::make_unique<cw4d::SliceModel>(m->complex, cw4d::SliceModelOptions::unclustered());
    m->mesh = cw4d::tetrahedralize(m->complex);
    m->planes = generic_planes(m->complex);
    cw4d::Slicer slicer;
    cw4d::SliceBuffers out;
    for (const auto& plane : m->planes) {
      slicer.slice(*m->compiled, plane, out);
      m->cw_tris += static_cast<double>(out.fan_triangles());
      m->tet_tris += static_cast<double>(cw4d::slice_tets(m->mesh, plane).triangle_count());
    }
    m->cw_tris /= static_cast<double>(m->planes.size());
    m->tet_tris /= static_cast<double>(m->planes.size());
    models.push_back(m);
    const std::vector<std::pair<std::string, void (*)(benchmark::State&, const Model&)>> runs = {
        {"cw/" + spec, cw_slices},
        {"tet/" + spec, tet_slices},
        {"tet-slicer/" + spec,
         [](benchmark::State& st, const Model& mm) { tet_slicer_slices(st, mm, true); }},
        {"tet-slicer-nouvw/" + spec,
         [](benchmark::State& st, const Model& mm) { tet_slicer_slices(st, mm, false); }},
        {"section/" + spec, section_slices},
        {"tetrahedralize/" + spec, build_mesh}};
    for (const auto& [name, fn] : runs) {
      auto* b = benchmark::RegisterBenchmark(name.c_str(),
                                             [m, fn = fn](benchmark::State& s) { fn(s, *m); });
      b->Unit(benchmark::kMicrosecond);
      if (default_min_time) b->MinTime(kMinTime);
    }
  }
  return models;
}

/// The console reporter plus the tet/CW ratios (CPU time per slice, triangles per slice).
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  RatioReporter(bool color, std::vector<std::shared_ptr<Model>> models)
      : ConsoleReporter(color ? OO_ColorTabular : OO_Tabular), models_(std::move(models)) {}

  void ReportRuns(const std::vector<Run>& reports) override {
    ConsoleReporter::ReportRuns(reports);
    for (const Run& run : reports) {
      if (run.error_occurred) continue;
      const std::string& name = run.run_name.function_name;
      if (run.run_type == Run::RT_Iteration || run.aggregate_name == "mean") {
        cpu_[name] = run.GetAdjustedCPUTime();
        if (auto it = run.counters.find("tris"); it != run.counters.end())
          tris_[name] = it->second.value;
      }
    }
  }

  void Finalize() override {
    ConsoleReporter::Finalize();
    bool header = false;
    for (const auto& m : models_) {
      const std::string cw = "cw/" + m->name, tet = "tet/" + m->name;
      if (!cpu_.count(cw) || !cpu_.count(tet)) continue;
      if (!header)
        std::printf(
            "\ntet path vs CW hot path (Slicer), within this run (CPU time per slice; triangles\n"
            "per slice averaged over exactly the %zu planes; targets: time >= 3x, triangles\n"
            ">= 3x):\n",
            kPlaneCount);
      header = true;
      const double time = cpu_[tet] / cpu_[cw], tris = m->tet_tris / m->cw_tris;
      std::printf(
          "  %-9s time %6.2fx (%.2f vs %.2f us) %-7s  triangles %5.2fx (%.1f vs %.1f) %-7s  %zu "
          "tetrahedra\n",
          m->name.c_str(), time, cpu_[tet], cpu_[cw], time >= 3.0 ? "met" : "NOT met", tris,
          m->tet_tris, m->cw_tris, tris >= 3.0 ? "met" : "NOT met", m->mesh.size());
      const std::string ts = "tet-slicer/" + m->name;
      if (cpu_.count(ts))
        std::printf(
            "  %-9s TetSlicer into a reused TetSliceMesh: %.2f us, %.2f ns per tetrahedron, "
            "%.2fx the hot CW slice\n",
            m->name.c_str(), cpu_[ts], cpu_[ts] * 1e3 / static_cast<double>(m->mesh.size()),
            cpu_[ts] / cpu_[cw]);
      const std::string tn = "tet-slicer-nouvw/" + m->name;
      if (cpu_.count(tn))
        std::printf("  %-9s the same without UVW: %.2f us, %.2f ns per tetrahedron\n",
                    m->name.c_str(), cpu_[tn],
                    cpu_[tn] * 1e3 / static_cast<double>(m->mesh.size()));
      const std::string sec = "section/" + m->name;
      if (cpu_.count(sec))
        std::printf("  %-9s section() / Slicer::slice: %.2fx (%.2f vs %.2f us)\n", m->name.c_str(),
                    cpu_[sec] / cpu_[cw], cpu_[sec], cpu_[cw]);
    }
    std::fflush(stdout);
  }

 private:
  std::vector<std::shared_ptr<Model>> models_;
  std::map<std::string, double> cpu_, tris_;
};

}  // namespace

int main(int argc, char** argv) {
  const auto [console, color, default_min_time] = cw4d::bench::scan_options(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  const auto models = register_cases(default_min_time);
  if (console) {
    RatioReporter reporter(color, models);
    benchmark::RunSpecifiedBenchmarks(&reporter);
  } else {
    benchmark::RunSpecifiedBenchmarks();
  }
  benchmark::Shutdown();
  return 0;
}
