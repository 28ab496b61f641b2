#pragma once
// What the bench programs read from Google Benchmark's own flags before handing them over: the
// ratio summaries need cw4d's console reporter, other output formats use the library's.
#include <unistd.h>

#include <cstdint>
#include <random>
#include <string_view>
#include <vector>

#include <Eigen/Dense>

#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/section/hyperplane.hpp"

namespace cw4d::bench {

struct BenchOptions {
  bool console = true;           ///< no --benchmark_format other than console
  bool color = false;            ///< --benchmark_color, default: stdout is a terminal
  bool default_min_time = true;  ///< no --benchmark_min_time given
};

inline BenchOptions scan_options(int argc, char** argv) {
  BenchOptions o;
  o.color = isatty(STDOUT_FILENO) != 0;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg.starts_with("--benchmark_format=") && arg != "--benchmark_format=console")
      o.console = false;
    if (arg.starts_with("--benchmark_min_time=")) o.default_min_time = false;
    if (arg.starts_with("--benchmark_color=")) {
      const std::string_view v = arg.substr(arg.find('=') + 1);
      o.color = v == "true" || v == "yes" || v == "1" || (v == "auto" && o.color);
    }
  }
  return o;
}

/// `count` generic planes for a model, the same list in every bench program: normals uniform on
/// the sphere, offsets uniform in +-0.9 of the model's radius, from a fixed seed.
inline std::vector<Hyperplane> generic_planes(const Complex& model, std::size_t count = 256,
                                              std::uint32_t seed = 20240401u) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double r = 0.9 * max_radius(model);
  std::uniform_real_distribution<double> offset(-r, r);
  std::vector<Hyperplane> planes;
  planes.reserve(count);
  while (planes.size() < count) {
    Eigen::VectorXd n(model.ambient_dim());
    for (int i = 0; i < n.size(); ++i) n[i] = gauss(rng);
    if (n.norm() < 1e-6) continue;
    planes.push_back(Hyperplane::from(n, offset(rng)));
  }
  return planes;
}

}  // namespace cw4d::bench
