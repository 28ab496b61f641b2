// Milliseconds to build models from their specs (load_model: construction, orientation, facet
// normals), with the model's size as counters. The omnitruncated 120-cell (wythoff:x5x3x3x,
// 14400 vertices) is the largest convex uniform polychoron.
//
//   bench_build [--benchmark_filter=REGEX] [--benchmark_min_time=SECONDS] ...
#include <benchmark/benchmark.h>

#include <string>

#include "cw4d/complex/builtins.hpp"

namespace {

void build(benchmark::State& state, const std::string& spec) {
  std::size_t vertices = 0, cells = 0;
  for (auto _ : state) {
    const cw4d::Complex c = cw4d::load_model(spec);
    vertices = c.count(0);
    cells = c.count(3);
    benchmark::DoNotOptimize(vertices);
  }
  state.counters["vertices"] = static_cast<double>(vertices);
  state.counters["cells"] = static_cast<double>(cells);
}

}  // namespace

BENCHMARK_CAPTURE(build, tesseract, std::string("tesseract"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(build, 24_cell, std::string("24-cell"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(build, 120_cell, std::string("120-cell"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(build, 600_cell, std::string("600-cell"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(build, omnitruncated_120_cell, std::string("wythoff:x5x3x3x"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(build, duoprism_100_100, std::string("duoprism:100,100"))
    ->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
