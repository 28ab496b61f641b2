// The benchmarks bench/compare.sh runs from two builds (an older commit and the working tree)
// in alternating rounds. Only API that both have is used, so the same source is compiled
// against both; newer entry points are used where the headers announce them (feature macros).
//
// Per model (tesseract, 24-cell, 120-cell, 600-cell, duoprism:32,32, omnitruncated 120-cell):
//   slice     Slicer::slice over a fixed list of 256 generic planes (bench::generic_planes)
//   fixed     Slicer::slice with the plane n ~ (0.5377, 1.8339, -2.2588, 0.8622), offset
//             0.1 x circumradius
//   vertex    Slicer::slice with planes through a vertex (the degenerate, general path)
//   offsets   Slicer::slice into one SliceBuffers with the fixed normal and the sweep's 256
//             offsets (below) in turn: the planes bench/js/tet_slice.mjs times its port of
//             Tesserxel's tetrahedral kernel on (bench/js/compare_js.sh)
//   section   cw4d::section(model, plane) over the generic planes
//   tet       slice_tets over the model's tetrahedral mesh, the generic planes (into the indexed
//             TetSliceMesh where the headers have it, else the TetSection soup)
//   tet-soup  (newer trees only) the same into the TetSection soup
//   sweep     Slicer::sweep of 256 parallel layers (the fixed normal, offsets evenly spaced
//             inside +-0.95 circumradius), the time of the whole sweep
//   sweep-slices  the same 256 layers as 256 calls of Slicer::slice (same program, same run:
//             the sweep's own speed-up)
// And a scene (scene1pct/): 10^4 randomly turned tesseracts and 24-cells scattered in a box
// 400 x 40 x 40 x 8, the plane x ~ 200 touching about 1 % of them:
//   cull      SceneSlicer::slice of the whole scene into the same output
//   touched   SceneSlicer::slice of a scene of only the objects `cull` touched (the floor:
//             what `cull` costs beyond it is the culled objects' cost)
//   pairs     the two calls alternating (cull then touched, touched then cull, ...), each
//             timed: one line "ratio scene1pct/pairs <median> <lower quartile> <upper
//             quartile>" of cull/touched over blocks of 50 pairs (no drift between the two)
// Times are the thread's CPU time (CLOCK_THREAD_CPUTIME_ID), not wall-clock time.
// Output: one line per case, "case <name> <nanoseconds per operation> <units>" where units is
// what one operation processes (tetrahedra for tet), and "fallback" lines where supported.
//
//   bench_compare [--min-time SECONDS] [--filter SUBSTRING]
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench_options.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"

namespace {

double g_min_time = 0.25;
const char* g_filter = nullptr;
std::atomic<std::size_t> g_sink{0};

// The calling thread's CPU time in seconds: time spent descheduled on a shared machine (other
// processes' builds) is not counted, which wall-clock time would add to either program.
double thread_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Runs op(i) for i = 0, 1, ... in batches until min_time of CPU time has passed; the CPU time
// per call.
double time_per_op(const std::function<void(std::size_t)>& op) {
  for (std::size_t i = 0; i < 4; ++i) op(i);  // warm the scratch
  std::size_t total = 0, batch = 1;
  double elapsed = 0.0;
  while (elapsed < g_min_time) {
    const double t0 = thread_seconds();
    for (std::size_t i = 0; i < batch; ++i) op(total + i);
    elapsed += thread_seconds() - t0;
    total += batch;
    if (batch < (1u << 20)) batch *= 2;
  }
  return elapsed * 1e9 / static_cast<double>(total);
}

void report(const std::string& name, double ns, double units) {
  std::printf("case %s %.6g %.6g\n", name.c_str(), ns, units);
  std::fflush(stdout);
}

bool wanted(const std::string& name) {
  return !g_filter || name.find(g_filter) != std::string::npos;
}

Eigen::VectorXd fixed_normal() {
  Eigen::VectorXd n(4);
  n << 0.5377, 1.8339, -2.2588, 0.8622;
  return n.normalized();
}

void run_model(const std::string& spec, const std::string& label, bool tets) {
  bool any = false;
  for (const char* kind : {"/slice", "/fixed", "/vertex", "/offsets", "/section", "/sweep", "/tet"})
    any |= wanted(label + kind);
  if (!any) return;
  const cw4d::Complex model = cw4d::load_model(spec);
  const cw4d::SliceModel compiled(model, cw4d::SliceModelOptions::unclustered());
  const std::vector<cw4d::Hyperplane> planes = cw4d::bench::generic_planes(model, 256, 20240401u);
  const double radius = cw4d::max_radius(model);
  const Eigen::VectorXd nf = fixed_normal();
  const cw4d::Hyperplane fixed{nf, 0.1 * radius};
  std::vector<cw4d::Hyperplane> through;  // planes through vertices (generic normals)
  for (std::size_t i = 0; i < 16; ++i) {
    const Eigen::VectorXd& n = planes[i].normal;
    const Eigen::VectorXd x =
        model.position(static_cast<std::uint32_t>((i * 7919) % model.count(0)));
    through.push_back({n, n.dot(x)});
  }
  cw4d::Slicer slicer;
  cw4d::SliceBuffers out;
  if (wanted(label + "/slice"))
    report(label + "/slice", time_per_op([&](std::size_t i) {
             slicer.slice(compiled, planes[i % planes.size()], out);
             g_sink += out.vertex_source.size();
           }),
           1);
  if (wanted(label + "/fixed"))
    report(label + "/fixed", time_per_op([&](std::size_t) {
             slicer.slice(compiled, fixed, out);
             g_sink += out.vertex_source.size();
           }),
           1);
  if (wanted(label + "/vertex"))
    report(label + "/vertex", time_per_op([&](std::size_t i) {
             slicer.slice(compiled, through[i % through.size()], out);
             g_sink += out.vertex_source.size();
           }),
           1);
  if (wanted(label + "/offsets")) {
    std::vector<cw4d::Hyperplane> layers;
    for (std::size_t i = 0; i < 256; ++i)
      layers.push_back(cw4d::Hyperplane::from(
          nf, radius * (-0.95 + 1.9 * (static_cast<double>(i) + 0.5) / 256.0)));
    report(label + "/offsets", time_per_op([&](std::size_t i) {
             slicer.slice(compiled, layers[i % layers.size()], out);
             g_sink += out.vertex_source.size();
           }),
           1);
  }
  if (wanted(label + "/section"))
    report(label + "/section", time_per_op([&](std::size_t i) {
             const cw4d::Section s = cw4d::section(model, planes[i % planes.size()]);
             g_sink += s.vertex_source.size();
           }),
           1);
  if (wanted(label + "/sweep")) {
    std::vector<double> offsets(256);
    for (std::size_t i = 0; i < offsets.size(); ++i)
      offsets[i] = radius * (-0.95 + 1.9 * (static_cast<double>(i) + 0.5) / 256.0);
    const cw4d::AffineTransform id = cw4d::AffineTransform::identity(4);
    std::vector<cw4d::SliceBuffers> layers;
    report(label + "/sweep", time_per_op([&](std::size_t) {
             slicer.sweep(compiled, nf, offsets, id, layers);
             g_sink += layers.size();
           }),
           256);
  }
  if (wanted(label + "/sweep-slices")) {
    std::vector<double> offsets(256);
    for (std::size_t i = 0; i < offsets.size(); ++i)
      offsets[i] = radius * (-0.95 + 1.9 * (static_cast<double>(i) + 0.5) / 256.0);
    std::vector<cw4d::SliceBuffers> layers(offsets.size());
    report(label + "/sweep-slices", time_per_op([&](std::size_t) {
             for (std::size_t i = 0; i < offsets.size(); ++i)
               slicer.slice(compiled, cw4d::Hyperplane::from(nf, offsets[i]), layers[i]);
             g_sink += layers.size();
           }),
           256);
  }
  if (tets && wanted(label + "/tet")) {
    const cw4d::TetMesh mesh = cw4d::tetrahedralize(model);
    // The indexed form (one vertex per crossing edge): the same triangles, normals, uvw and
    // provenance as the soup the older code writes (to_soup gives that soup; "tet-soup" times it).
    cw4d::TetSliceMesh tm;
    report(label + "/tet", time_per_op([&](std::size_t i) {
             cw4d::slice_tets(mesh, planes[i % planes.size()], tm);
             g_sink += tm.triangle_count();
           }),
           static_cast<double>(mesh.size()));
    cw4d::TetSection ts;
    report(label + "/tet-soup", time_per_op([&](std::size_t i) {
             cw4d::slice_tets(mesh, planes[i % planes.size()], ts);
             g_sink += ts.triangle_count();
           }),
           static_cast<double>(mesh.size()));
  }
  // Why slices of the generic planes and of the planes through vertices took the general path.
  std::size_t counts[cw4d::kFallbackReasonCount] = {};
  for (const auto& p : planes)
    slicer.slice(compiled, p, out), ++counts[static_cast<int>(out.fallback)];
  for (const auto& p : through)
    slicer.slice(compiled, p, out), ++counts[static_cast<int>(out.fallback)];
  std::printf("fallback %s", label.c_str());
  for (int r = 0; r < cw4d::kFallbackReasonCount; ++r)
    if (counts[r])
      std::printf(" %s=%zu", cw4d::to_string(static_cast<cw4d::FallbackReason>(r)), counts[r]);
  std::printf("\n");
}

// 10^4 tesseracts and 24-cells, each turned by six seeded plane rotations, scattered in a box.
cw4d::Scene scattered_scene(std::size_t count, const double box[4], std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto tesseract = std::make_shared<const cw4d::Complex>(cw4d::load_model("tesseract"));
  auto cell24 = std::make_shared<const cw4d::Complex>(cw4d::load_model("24-cell"));
  cw4d::Scene scene;
  for (std::size_t i = 0; i < count; ++i) {
    cw4d::SceneObject obj;
    obj.model = i % 3 == 2 ? "24-cell" : "tesseract";
    obj.complex = i % 3 == 2 ? cell24 : tesseract;
    cw4d::AffineTransform xf = cw4d::AffineTransform::identity(4);
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b)
        xf = cw4d::AffineTransform::rotation(4, a, b, 6.283185307179586 * unit(rng)) * xf;
    Eigen::VectorXd t(4);
    for (int a = 0; a < 4; ++a) t[a] = box[a] * unit(rng);
    obj.transform = cw4d::AffineTransform::translation(t) * xf;
    scene.objects.push_back(std::move(obj));
  }
  return scene;
}

// The output of SceneSlicer::slice: the touched objects' sections.
using SceneOutput = cw4d::SceneSlice;
std::size_t entries(const SceneOutput& out) {
  return out.buffers.size();
}

void run_scene() {
  if (!wanted("scene1pct/cull") && !wanted("scene1pct/touched") && !wanted("scene1pct/pairs"))
    return;
  const double box[4] = {400, 40, 40, 8};
  const cw4d::Scene scene = scattered_scene(10000, box, 20240401u);
  Eigen::VectorXd n(4);
  n << 1.0, 0.01, 0.02, 0.015;
  const cw4d::Hyperplane plane = cw4d::Hyperplane::from(n, 200.0);
  cw4d::SceneSlicer all(scene);
  SceneOutput out;
  all.slice(plane, out);
  // The objects SceneSlicer's sphere test keeps (rigid placements: the radius is the model's),
  // computed here so that both builds get the same scene.
  cw4d::Scene touched;
  const cw4d::SliceModel tesseract(*scene.objects[0].complex), cell24(*scene.objects[2].complex);
  for (const cw4d::SceneObject& obj : scene.objects) {
    const cw4d::SliceModel& m = obj.complex == scene.objects[0].complex ? tesseract : cell24;
    const Eigen::VectorXd c = obj.transform.apply(m.centre());
    const double reach =
        m.radius() + cw4d::tol::bounding_sphere_margin_rel * (m.radius() + c.norm());
    if (!(std::abs(plane.signed_distance(c)) > reach)) touched.objects.push_back(obj);
  }
  if (touched.objects.size() != all.touched()) std::fprintf(stderr, "scene: touched differ\n");
  cw4d::SceneSlicer few(touched);
  SceneOutput out_few;
  if (wanted("scene1pct/cull"))
    report("scene1pct/cull", time_per_op([&](std::size_t) {
             all.slice(plane, out);
             g_sink += entries(out);
           }),
           static_cast<double>(all.touched()));
  if (wanted("scene1pct/touched"))
    report("scene1pct/touched", time_per_op([&](std::size_t) {
             few.slice(plane, out_few);
             g_sink += entries(out_few);
           }),
           static_cast<double>(touched.objects.size()));
  if (wanted("scene1pct/pairs")) {
    std::vector<double> ratios;
    double cull = 0.0, floor = 0.0;
    const double start = thread_seconds();
    for (std::size_t k = 0; ratios.size() < 9 || thread_seconds() - start < 2 * g_min_time; ++k) {
      const bool first = k % 2 == 0;
      const double a = thread_seconds();
      first ? all.slice(plane, out) : few.slice(plane, out_few);
      const double b = thread_seconds();
      first ? few.slice(plane, out_few) : all.slice(plane, out);
      const double c = thread_seconds();
      cull += first ? b - a : c - b;
      floor += first ? c - b : b - a;
      if (k % 50 == 49) ratios.push_back(cull / floor), cull = floor = 0.0;
    }
    std::sort(ratios.begin(), ratios.end());
    const std::size_t m = ratios.size();
    std::printf("ratio scene1pct/pairs %.4f %.4f %.4f\n", ratios[m / 2], ratios[m / 4],
                ratios[3 * m / 4]);
  }
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--min-time") && i + 1 < argc) {
      g_min_time = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--filter") && i + 1 < argc) {
      g_filter = argv[++i];
    } else {
      std::fprintf(stderr, "usage: bench_compare [--min-time SECONDS] [--filter SUBSTRING]\n");
      return 2;
    }
  }
  run_model("tesseract", "tesseract", true);
  run_model("24-cell", "24-cell", true);
  run_model("120-cell", "120-cell", true);
  run_model("600-cell", "600-cell", true);
  run_model("duoprism:32,32", "duoprism32", true);
  run_model("omnitruncated 120-cell", "omni120", false);
  run_scene();
  return g_sink.load() == 0xdeadbeef ? 1 : 0;
}
