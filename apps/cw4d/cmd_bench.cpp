// cw4d bench: how fast the section is on this machine, as ratios measured side by side.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <iostream>
#include <random>
#include <thread>

#include "cli.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/section/slicer.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"

namespace cw4d::cli {

namespace {

struct BenchSettings {
  std::string model = "120-cell";
  int layers = 256;
  double seconds = 0.3;
  unsigned threads = 0;
};

using Clock = std::chrono::steady_clock;

// Keeps a result alive so the timed call is not optimised away.
void benchmark_sink(std::size_t value) {
  static volatile std::size_t sink = 0;
  sink = sink + value;
}

// Seconds per call of each function, measured in alternating rounds (A B A B ...) so that both
// see the same machine load; the median round of each is kept.
std::vector<double> per_call(const std::vector<std::function<void()>>& fns, double budget) {
  constexpr int kRounds = 5;
  std::vector<std::vector<double>> rounds(fns.size());
  for (int r = 0; r < kRounds; ++r)
    for (std::size_t i = 0; i < fns.size(); ++i) {
      fns[i]();  // warm
      std::size_t calls = 0;
      const auto t0 = Clock::now();
      double elapsed = 0.0;
      do {
        fns[i]();
        ++calls;
        elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
      } while (elapsed < budget / (kRounds * fns.size()));
      rounds[i].push_back(elapsed / static_cast<double>(calls));
    }
  std::vector<double> out;
  for (auto& v : rounds) {
    std::sort(v.begin(), v.end());
    out.push_back(v[v.size() / 2]);
  }
  return out;
}

void run_bench(const BenchSettings& s) {
  if (s.layers < 2 || s.layers > 100000) throw InputError("--layers: give 2 to 100000 layers");
  if (!(s.seconds > 0.0) || s.seconds > 600.0) throw InputError("--seconds: give 0 to 600 seconds");
  const Complex model = load(s.model);
  require_valid(model, s.model);
  if (model.ambient_dim() != 4)
    throw InputError("bench needs a 4D model; " + quote_user_text(s.model) + " lives in R^" +
                     std::to_string(model.ambient_dim()));
  const unsigned threads =
      s.threads ? s.threads : std::max(1u, std::thread::hardware_concurrency());
  const SliceModel compiled(model, SliceModelOptions::unclustered());
  if (!compiled.fast())
    std::cout << "note: '" << s.model << "' takes the general path (see slicer.hpp)\n";
  // 256 generic planes: seeded random unit normals, offsets within 0.9 of the radius.
  std::mt19937 rng(20240401u);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  std::vector<Hyperplane> planes;
  for (int i = 0; i < 256; ++i) {
    Eigen::VectorXd n(4);
    for (int j = 0; j < 4; ++j) n[j] = g(rng);
    planes.push_back(Hyperplane::from(n, u(rng) * compiled.radius()));
  }
  const TetMesh mesh = tetrahedralize(model);
  // The tetrahedral slicer on its steady path, as the hot path: a TetSlicer into one reused
  // TetSliceMesh.
  TetSlicer tet_slicer;
  TetSliceMesh tet_out;
  Slicer slicer;
  SliceBuffers out;
  double cw_tris = 0, tet_tris = 0;
  for (const auto& p : planes) {
    slicer.slice(compiled, p, out);
    cw_tris += static_cast<double>(out.fan_triangles());
    tet_slicer.slice(mesh, p, tet_out);
    tet_tris += static_cast<double>(tet_out.triangle_count());
  }
  std::size_t next = 0;
  auto hot = [&] { slicer.slice(compiled, planes[next++ % planes.size()], out); };
  auto tet = [&] {
    tet_slicer.slice(mesh, planes[next++ % planes.size()], tet_out);
    benchmark_sink(tet_out.tet.size());
  };
  auto plain = [&] {
    benchmark_sink(section(model, planes[next++ % planes.size()]).complex.count(0));
  };
  const auto t1 = per_call({hot, tet, plain}, s.seconds);
  const double n = static_cast<double>(planes.size());
  std::printf("%s, %d layers, one thread unless stated; times are medians of alternating rounds\n",
              s.model.c_str(), s.layers);
  std::printf("  slice, hot path (Slicer)      %9.2f us   %7.1f triangles\n", t1[0] * 1e6,
              cw_tris / n);
  std::printf(
      "  slice, tetrahedral path       %9.2f us   %7.1f triangles   tet/CW time %.2fx, triangles "
      "%.2fx\n",
      t1[1] * 1e6, tet_tris / n, t1[1] / t1[0], tet_tris / cw_tris);
  std::printf("  slice, section() (allocates)  %9.2f us                     section()/hot %.2fx\n",
              t1[2] * 1e6, t1[2] / t1[0]);
  // A sweep against the same layers one slice at a time, and on every core.
  Eigen::VectorXd normal = planes[0].normal;
  std::vector<double> offsets(s.layers);
  for (int i = 0; i < s.layers; ++i)
    offsets[i] = compiled.radius() * (-1.0 + 2.0 * (i + 0.5) / s.layers);
  // Both sides keep all layers (a buffer each), as a caller that wants the sweep does.
  std::vector<SliceBuffers> layers, separate(offsets.size());
  const AffineTransform identity = AffineTransform::identity(4);
  auto sweep1 = [&] { slicer.sweep(compiled, normal, offsets, identity, layers, 1); };
  auto sweepT = [&] { slicer.sweep(compiled, normal, offsets, identity, layers, threads); };
  auto singles = [&] {
    for (std::size_t i = 0; i < offsets.size(); ++i)
      slicer.slice(compiled, Hyperplane::from(normal, offsets[i]), separate[i]);
  };
  const auto t2 = per_call({sweep1, singles, sweepT}, s.seconds);
  std::printf("  sweep of %d layers, one pass  %9.2f ms\n", s.layers, t2[0] * 1e3);
  std::printf("  the same layers as slices     %9.2f ms                     slices/sweep %.2fx\n",
              t2[1] * 1e3, t2[1] / t2[0]);
  std::printf("  the sweep on %u threads        %9.2f ms                     speedup %.2fx\n",
              threads, t2[2] * 1e3, t2[0] / t2[2]);
}

}  // namespace

void add_bench_command(CLI::App& app, Commands& commands) {
  auto s = std::make_shared<BenchSettings>();
  auto* cmd = app.add_subcommand(
      "bench", "Measure the section's speed on this machine (ratios measured side by side).");
  cmd->add_option("MODEL", s->model, "4D model spec or file (default 120-cell)");
  cmd->add_option("--layers", s->layers, "Layers of the sweep (default 256)");
  cmd->add_option("--seconds", s->seconds, "Time budget per comparison (default 0.3)");
  cmd->add_option("--threads", s->threads, "Threads for the sweep (default: every core)");
  cmd->footer(
      "Compares, over 256 seeded generic planes: the hot path (a compiled SliceModel and reused\n"
      "buffers) against the tetrahedral slicer and against section(); then one sweep of\n"
      "--layers parallel planes against the same layers cut one at a time, and on threads.\n"
      "The full benchmarks are bench/ (see bench/RESULTS.md).");
  commands.push_back({cmd, [s] { run_bench(*s); }});
}

}  // namespace cw4d::cli
