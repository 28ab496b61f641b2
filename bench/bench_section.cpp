// Microseconds per hyperplane section (cw4d::section) of built-in 4D models, over fixed lists
// of 256 planes: generic random planes (random unit normal, offset uniform in +-0.9 max_radius,
// so most planes hit) and degenerate planes through model vertices (offset = n . v), either with
// a random normal ("vertex": usually one vertex on the plane) or with a normal from {-1,0,1}^4
// ("lattice": planes containing edges, faces and whole cells of the tesseract).
//
// One benchmark iteration is one slice; the planes are cycled. Counters are averages per slice:
// section faces, section vertices and the fraction of planes whose section is not empty.
// In console mode (the default) the program ends with time ratios measured in the same run.
//
//   bench_section [--benchmark_filter=REGEX] [--benchmark_min_time=SECONDS] ...
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

#include "bench_options.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"

namespace {

constexpr std::size_t kPlaneCount = 256;
constexpr std::uint32_t kSeed = 20240401u;
constexpr double kMinTime = 0.2;  // seconds per benchmark unless --benchmark_min_time is given

std::vector<cw4d::Hyperplane> generic_planes(const cw4d::Complex& model) {
  return cw4d::bench::generic_planes(model, kPlaneCount, kSeed);
}

enum class Degenerate { Vertex, Lattice };

std::vector<cw4d::Hyperplane> degenerate_planes(const cw4d::Complex& model, Degenerate kind) {
  std::mt19937 rng(kSeed + 1);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_int_distribution<int> trit(-1, 1);
  std::uniform_int_distribution<std::uint32_t> vertex(
      0, static_cast<std::uint32_t>(model.count(0) - 1));
  std::vector<cw4d::Hyperplane> planes;
  planes.reserve(kPlaneCount);
  while (planes.size() < kPlaneCount) {
    Eigen::VectorXd n(model.ambient_dim());
    for (int i = 0; i < n.size(); ++i)
      n[i] = kind == Degenerate::Vertex ? gauss(rng) : static_cast<double>(trit(rng));
    if (n.norm() < 1e-6) continue;
    n.normalize();
    const Eigen::VectorXd v = model.position(vertex(rng));
    planes.push_back(cw4d::Hyperplane::from(n, n.dot(v)));
  }
  return planes;
}

void run_slices(benchmark::State& state, const cw4d::Complex& model,
                const std::vector<cw4d::Hyperplane>& planes) {
  std::size_t i = 0;
  double faces = 0, vertices = 0, hits = 0;
  for (auto _ : state) {
    cw4d::Section s = cw4d::section(model, planes[i]);
    benchmark::DoNotOptimize(s);
    faces += static_cast<double>(s.complex.count(2));
    vertices += static_cast<double>(s.complex.count(0));
    hits += s.empty() ? 0.0 : 1.0;
    if (++i == planes.size()) i = 0;
  }
  state.counters["faces"] = benchmark::Counter(faces, benchmark::Counter::kAvgIterations);
  state.counters["verts"] = benchmark::Counter(vertices, benchmark::Counter::kAvgIterations);
  state.counters["hit"] = benchmark::Counter(hits, benchmark::Counter::kAvgIterations);
}

// self_intersects alone on precomputed sections (a convex model's sections take the full pass
// over every face pair; section() itself skips the test for certified convex models).
void run_self_intersects(benchmark::State& state, const std::vector<cw4d::Section>& sections) {
  std::size_t i = 0;
  double flagged = 0;
  for (auto _ : state) {
    const bool f = cw4d::self_intersects(sections[i].complex);
    benchmark::DoNotOptimize(f);
    flagged += f ? 1.0 : 0.0;
    if (++i == sections.size()) i = 0;
  }
  state.counters["flagged"] = benchmark::Counter(flagged, benchmark::Counter::kAvgIterations);
}

struct Case {
  std::string name;
  std::string model_spec;
  std::function<std::vector<cw4d::Hyperplane>(const cw4d::Complex&)> planes;
};

void register_cases(bool default_min_time) {
  const std::vector<Case> cases = {
      {"section/tesseract/generic", "tesseract", generic_planes},
      {"section/tesseract/degenerate_vertex", "tesseract",
       [](const cw4d::Complex& m) { return degenerate_planes(m, Degenerate::Vertex); }},
      {"section/tesseract/degenerate_lattice", "tesseract",
       [](const cw4d::Complex& m) { return degenerate_planes(m, Degenerate::Lattice); }},
      {"section/duoprism30x30/generic", "duoprism:30,30", generic_planes},
      {"section/duoprism30x30/degenerate_vertex", "duoprism:30,30",
       [](const cw4d::Complex& m) { return degenerate_planes(m, Degenerate::Vertex); }},
  };
  for (const Case& c : cases) {
    // Model and planes are built once, outside the timed loop, and live as long as the program.
    auto model = std::make_shared<cw4d::Complex>(cw4d::load_model(c.model_spec));
    auto planes = std::make_shared<std::vector<cw4d::Hyperplane>>(c.planes(*model));
    auto* b = benchmark::RegisterBenchmark(
        c.name.c_str(),
        [model, planes](benchmark::State& state) { run_slices(state, *model, *planes); });
    b->Unit(benchmark::kMicrosecond);
    // A per-benchmark MinTime would override the command line flag, so set it only by default.
    if (default_min_time) b->MinTime(kMinTime);
  }
  for (const char* spec : {"600-cell", "120-cell", "icosahedral 120-cell", "grand 600-cell"}) {
    const cw4d::Complex model = cw4d::load_model(spec);
    auto sections = std::make_shared<std::vector<cw4d::Section>>();
    for (const auto& plane : generic_planes(model)) {
      cw4d::Section s = cw4d::section(model, plane);
      if (!s.empty()) sections->push_back(std::move(s));
    }
    std::string name = std::string("self_intersects/") + spec + "/generic";
    std::replace(name.begin(), name.end(), ' ', '_');
    auto* b = benchmark::RegisterBenchmark(name.c_str(), [sections](benchmark::State& state) {
      run_self_intersects(state, *sections);
    });
    b->Unit(benchmark::kMicrosecond);
    if (default_min_time) b->MinTime(kMinTime);
  }
}

/// The console reporter, plus a summary of CPU time ratios between benchmarks of the same run
/// (CPU rather than wall time: single-threaded code on a possibly shared machine).
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  explicit RatioReporter(bool color) : ConsoleReporter(color ? OO_ColorTabular : OO_Tabular) {}

  void ReportRuns(const std::vector<Run>& reports) override {
    ConsoleReporter::ReportRuns(reports);
    for (const Run& run : reports) {
      if (run.error_occurred) continue;
      const std::string& name = run.run_name.function_name;
      if (run.run_type == Run::RT_Iteration) {
        auto& [sum, n] = times_[name];
        sum += run.GetAdjustedCPUTime();
        n += 1;
      } else if (run.aggregate_name == "mean") {  // --benchmark_report_aggregates_only
        means_[name] = run.GetAdjustedCPUTime();
      }
    }
  }

  void Finalize() override {
    ConsoleReporter::Finalize();
    const std::array<std::array<const char*, 3>, 4> ratios = {{
        {"duoprism:30,30 vs tesseract, generic planes", "section/duoprism30x30/generic",
         "section/tesseract/generic"},
        {"tesseract, degenerate (vertex) vs generic", "section/tesseract/degenerate_vertex",
         "section/tesseract/generic"},
        {"tesseract, degenerate (lattice) vs generic", "section/tesseract/degenerate_lattice",
         "section/tesseract/generic"},
        {"duoprism:30,30, degenerate (vertex) vs generic",
         "section/duoprism30x30/degenerate_vertex", "section/duoprism30x30/generic"},
    }};
    bool header = false;
    for (const auto& [label, num, den] : ratios) {
      const double a = mean(num), b = mean(den);
      if (!(a > 0) || !(b > 0)) continue;  // filtered out
      if (!header) std::printf("\nCPU time per slice, ratios within this run:\n");
      header = true;
      std::printf("  %-48s %6.2fx\n", label, a / b);
    }
    std::fflush(stdout);
  }

 private:
  double mean(const std::string& name) const {
    if (auto m = means_.find(name); m != means_.end()) return m->second;
    auto it = times_.find(name);
    return it == times_.end() || it->second.second == 0 ? 0.0
                                                        : it->second.first / it->second.second;
  }
  std::map<std::string, std::pair<double, int>> times_;  // iteration runs: sum, count
  std::map<std::string, double> means_;                  // aggregate means
};

}  // namespace

int main(int argc, char** argv) {
  // The ratio summary needs our own console reporter; other formats use the library's.
  const auto [console, color, default_min_time] = cw4d::bench::scan_options(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  register_cases(default_min_time);
  if (console) {
    RatioReporter reporter(color);
    benchmark::RunSpecifiedBenchmarks(&reporter);
  } else {
    benchmark::RunSpecifiedBenchmarks();
  }
  benchmark::Shutdown();
  return 0;
}
