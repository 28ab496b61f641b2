#pragma once
// Part d of bench_slicer: cw4d's slicer against CGAL::Polygon_mesh_slicer on a triangulated
// torus of ~10^6 faces. Defined in bench_slicer_cgal.cpp, the only file that includes CGAL.
#include <vector>

#include "bench_ratios.hpp"

namespace cw4d::bench {

/// Registers torus/... benchmarks (MinTime(min_time) when default_min_time) and appends their
/// ratio lines.
void register_cgal_benchmarks(bool default_min_time, double min_time,
                              std::vector<RatioLine>& lines);

}  // namespace cw4d::bench
