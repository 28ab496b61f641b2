// The two section paths side by side: the CW-complex section (cw4d::section, polygons) and the
// tetrahedral slicer (cw4d::slice_tets over a TetMesh made once), on the 120-cell and the
// 600-cell, over the same fixed list of 256 generic planes (random unit normal from a seeded
// std::mt19937, offset uniform in +-0.9 max_radius). One iteration is one slice; the planes are
// cycled. Counter `tris` is the average number of triangles per slice: for the CW path the
// k - 2 triangles of each k-gon (what a fan triangulation sends to a GPU), for the tet path the
// triangles it emits. `tetrahedralize/*` times building the mesh itself (once per model).
// In console mode the program ends with the tet/CW ratios of time and triangles of this run.
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
  cw4d::TetMesh mesh;
  std::vector<cw4d::Hyperplane> planes;
  double cw_tris = 0, tet_tris = 0;  // per slice, averaged over exactly the 256 planes
};

void cw_slices(benchmark::State& state, const Model& m) {
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

void build_mesh(benchmark::State& state, const Model& m) {
  for (auto _ : state) {
    cw4d::TetMesh mesh = cw4d::tetrahedralize(m.complex);
    benchmark::DoNotOptimize(mesh);
  }
  state.counters["tets"] = static_cast<double>(m.mesh.size());
}

std::vector<std::shared_ptr<Model>> register_cases(bool default_min_time) {
  std::vector<std::shared_ptr<Model>> models;
  for (std::string spec : {"120-cell", "600-cell"}) {
    auto m = std::make_shared<Model>();
    m->name = spec;
    m->complex = cw4d::load_model(spec);
    m->mesh = cw4d::tetrahedralize(m->complex);
    m->planes = generic_planes(m->complex);
    for (const auto& plane : m->planes) {
      const cw4d::Section s = cw4d::section(m->complex, plane);
      for (std::uint32_t f = 0; f < s.complex.count(2); ++f)
        m->cw_tris += static_cast<double>(s.complex.boundary(2).row_size(f) - 2);
      m->tet_tris += static_cast<double>(cw4d::slice_tets(m->mesh, plane).triangle_count());
    }
    m->cw_tris /= static_cast<double>(m->planes.size());
    m->tet_tris /= static_cast<double>(m->planes.size());
    models.push_back(m);
    const std::vector<std::pair<std::string, void (*)(benchmark::State&, const Model&)>> runs = {
        {"cw/" + spec, cw_slices},
        {"tet/" + spec, tet_slices},
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
            "\ntet path vs CW path, within this run (CPU time per slice; triangles per slice\n"
            "averaged over exactly the %zu planes):\n",
            kPlaneCount);
      header = true;
      std::printf(
          "  %-9s time %6.2fx (%.1f vs %.1f us)   triangles %5.2fx (%.1f vs %.1f), %zu "
          "tetrahedra\n",
          m->name.c_str(), cpu_[tet] / cpu_[cw], cpu_[tet], cpu_[cw], m->tet_tris / m->cw_tris,
          m->tet_tris, m->cw_tris, m->mesh.size());
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
