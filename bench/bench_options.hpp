#pragma once
// What the bench programs read from Google Benchmark's own flags before handing them over: the
// ratio summaries need cw4d's console reporter, other output formats use the library's.
#include <unistd.h>

#include <string_view>

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

}  // namespace cw4d::bench
