// Part d of bench_slicer: the same plane through the same ~10^6-triangle torus (708 x 708 x 2
// triangles, bench_models.hpp) by cw4d's Slicer (a closed Complex in R^3 with outward facet
// normals and one rank-3 solid, so the section is a set of polygons = closed loops) and by
// CGAL::Polygon_mesh_slicer over a CGAL::Surface_mesh<Epick::Point_3> with the same triangles
// (closed polylines). Before timing, the outputs are compared: as many closed polylines as
// polygons (without the solid: as connected components of the section edges), no open
// polyline, as many points (a closed polyline repeats its first point) and the same total
// length to 1e-9.
//
//  torus/cw/slice                 Slicer::slice, SliceModel (clustered) and buffers reused
//  torus/cw/construct+slice       SliceModel + Slicer + SliceBuffers made, then one slice
//  torus/cw-nosolid/slice         the torus without its solid: section edges only (the loops
//                                 are implied by the edges but not chained into polygons)
//  torus/cgal/slice               the slicer (and its AABB tree of edges) reused
//  torus/cgal/construct+slice     Polygon_mesh_slicer made (its tree is built by the first
//                                 query, i.e. inside this benchmark), then one slice
#include "bench_slicer_cgal.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_slicer.h>
#include <CGAL/Surface_mesh.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "bench_models.hpp"
#include "cw4d/section/slicer.hpp"

namespace cw4d::bench {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using CgalSlicer = CGAL::Polygon_mesh_slicer<Mesh, K>;
using Polylines = std::vector<std::vector<K::Point_3>>;

constexpr int kGrid = 708;  // 708 x 708 x 2 = 1,002,528 triangles

struct TorusCase {
  Torus torus, open;  // with and without the rank-3 solid
  Mesh mesh;
  std::unique_ptr<SliceModel> model, open_model;
};

const TorusCase& torus_case() {
  static const std::unique_ptr<TorusCase> c = [] {
    auto t = std::make_unique<TorusCase>();
    t->torus = make_torus(kGrid, kGrid, true);
    t->open = make_torus(kGrid, kGrid, false);
    std::vector<Mesh::Vertex_index> v;
    v.reserve(t->torus.points.size());
    for (const auto& p : t->torus.points)
      v.push_back(t->mesh.add_vertex(K::Point_3(p.x(), p.y(), p.z())));
    for (const auto& f : t->torus.tris) t->mesh.add_face(v[f[0]], v[f[1]], v[f[2]]);
    t->model = std::make_unique<SliceModel>(t->torus.complex);
    t->open_model = std::make_unique<SliceModel>(t->open.complex);
    return t;
  }();
  return *c;
}

Hyperplane torus_plane() {
  return Hyperplane::from(Eigen::Vector3d(0.05, 0.03, 1.0), 0.1);
}

K::Plane_3 cgal_plane(const Hyperplane& p) {
  return K::Plane_3(p.normal[0], p.normal[1], p.normal[2], -p.offset);
}

// "" when the two sections agree, else what differs.
std::string compare(const SliceBuffers& ours, const Polylines& theirs) {
  std::size_t closed = 0, open = 0, points = 0;
  double length = 0.0;
  for (const auto& pl : theirs) {
    const bool c = pl.size() > 1 && pl.front() == pl.back();
    (c ? closed : open) += 1;
    points += c ? pl.size() - 1 : pl.size();
    for (std::size_t i = 1; i < pl.size(); ++i)
      length += std::sqrt(CGAL::squared_distance(pl[i - 1], pl[i]));
  }
  double our_length = 0.0;
  const Incidence& edges = ours.boundary[0];
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto ids = edges.ids(e);
    const double dx = ours.coords[2 * ids[1]] - ours.coords[2 * ids[0]];
    const double dy = ours.coords[2 * ids[1] + 1] - ours.coords[2 * ids[0] + 1];
    our_length += std::hypot(dx, dy);
  }
  // Our loops: the polygons, or (no solid, so no polygons) the components of the edge graph.
  std::size_t loops = ours.count(2);
  if (ours.boundary.size() < 2) {
    std::vector<std::uint32_t> root(ours.count(0));
    for (std::uint32_t v = 0; v < root.size(); ++v) root[v] = v;
    const auto find = [&](std::uint32_t v) {
      while (root[v] != v) v = root[v] = root[root[v]];
      return v;
    };
    for (std::size_t e = 0; e < edges.size(); ++e)
      root[find(edges.ids(e)[0])] = find(edges.ids(e)[1]);
    loops = 0;
    for (std::uint32_t v = 0; v < root.size(); ++v) loops += find(v) == v;
  }
  std::string why;
  if (ours.general) why += " general path;";
  if (open != 0) why += " open CGAL polylines;";
  if (closed != loops)
    why += " loops " + std::to_string(loops) + " vs " + std::to_string(closed) + ";";
  if (points != ours.count(0))
    why += " points " + std::to_string(ours.count(0)) + " vs " + std::to_string(points) + ";";
  if (std::abs(length - our_length) > 1e-9 * length) why += " lengths differ;";
  return why;
}

void cw_slice(benchmark::State& state, bool solid) {
  const TorusCase& t = torus_case();
  const SliceModel& m = solid ? *t.model : *t.open_model;
  const Hyperplane plane = torus_plane();
  Slicer slicer;
  SliceBuffers out;
  slicer.slice(m, plane, out);
  Polylines ref;
  CgalSlicer(t.mesh)(cgal_plane(plane), std::back_inserter(ref));
  const std::string why = compare(out, ref);
  if (!why.empty()) {
    state.SkipWithError(("cw4d and CGAL disagree:" + why).c_str());
    return;
  }
  for (auto _ : state) {
    slicer.slice(m, plane, out);
    benchmark::DoNotOptimize(out.coords.data());
  }
  state.counters["faces"] = static_cast<double>(t.torus.tris.size());
  state.counters["points"] = static_cast<double>(out.count(0));
  state.counters["loops"] = static_cast<double>(out.count(2));
  state.counters["clusters"] = static_cast<double>(m.cluster_count());
}

void cw_construct_slice(benchmark::State& state) {
  const TorusCase& t = torus_case();
  const Hyperplane plane = torus_plane();
  for (auto _ : state) {
    const SliceModel m(t.torus.complex);
    Slicer slicer;
    SliceBuffers out;
    slicer.slice(m, plane, out);
    benchmark::DoNotOptimize(out.coords.data());
  }
}

void cgal_slice(benchmark::State& state) {
  const TorusCase& t = torus_case();
  const K::Plane_3 plane = cgal_plane(torus_plane());
  const CgalSlicer slicer(t.mesh);
  Polylines out;
  slicer(plane, std::back_inserter(out));
  for (auto _ : state) {
    out.clear();
    slicer(plane, std::back_inserter(out));
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["polylines"] = static_cast<double>(out.size());
}

void cgal_construct_slice(benchmark::State& state) {
  const TorusCase& t = torus_case();
  const K::Plane_3 plane = cgal_plane(torus_plane());
  for (auto _ : state) {
    const CgalSlicer slicer(t.mesh);
    Polylines out;
    slicer(plane, std::back_inserter(out));
    benchmark::DoNotOptimize(out.data());
  }
}

}  // namespace

void register_cgal_benchmarks(bool default_min_time, double min_time,
                              std::vector<RatioLine>& lines) {
  const auto add = [&](const char* name, void (*fn)(benchmark::State&)) {
    auto* b = benchmark::RegisterBenchmark(name, fn);
    b->Unit(benchmark::kMillisecond);
    if (default_min_time) b->MinTime(min_time);
  };
  add("torus/cw/slice", [](benchmark::State& s) { cw_slice(s, true); });
  add("torus/cw/construct+slice", cw_construct_slice);
  add("torus/cw-nosolid/slice", [](benchmark::State& s) { cw_slice(s, false); });
  add("torus/cgal/slice", cgal_slice);
  add("torus/cgal/construct+slice", cgal_construct_slice);
  const auto at_least_1 = [](double v) { return v >= 1.0; };
  lines.push_back({"d. torus 10^6 tris: CGAL slice / cw slice (both structures reused)", ">= 1x",
                   time_ratio("torus/cgal/slice", "torus/cw/slice"), at_least_1});
  lines.push_back({"d. (CGAL construct+slice / cw SliceModel construct+slice)", ">= 1x",
                   time_ratio("torus/cgal/construct+slice", "torus/cw/construct+slice"),
                   at_least_1});
  lines.push_back({"d. (CGAL slice / cw slice of the torus without its solid)", "",
                   time_ratio("torus/cgal/slice", "torus/cw-nosolid/slice"), nullptr});
}

}  // namespace cw4d::bench
