#pragma once
// A console reporter that ends a run with ratios of the benchmarks of that same run, each next
// to its target (on a shared machine only ratios taken side by side are stated).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace cw4d::bench {

/// Seconds per iteration (wall and main-thread CPU) and the counters of one benchmark.
struct Measured {
  double real = 0.0, cpu = 0.0;
  std::map<std::string, double> counters;
};
using Measurements = std::map<std::string, Measured>;  // by benchmark name

struct RatioLine {
  std::string label;   ///< what is compared
  std::string target;  ///< the issue's target, as text
  /// The figure, or nothing when a benchmark it needs did not run.
  std::function<std::optional<double>(const Measurements&)> value;
  std::function<bool(double)> met;  ///< empty: a figure without a target
  std::string format = "%.2fx";     ///< printf format of the figure
  double scale = 1.0;               ///< the figure is printed times this
};

/// time(a) / time(b), CPU or wall clock.
inline std::function<std::optional<double>(const Measurements&)> time_ratio(std::string a,
                                                                            std::string b,
                                                                            bool wall = false) {
  return
      [a = std::move(a), b = std::move(b), wall](const Measurements& m) -> std::optional<double> {
        const auto ia = m.find(a), ib = m.find(b);
        if (ia == m.end() || ib == m.end()) return std::nullopt;
        const double ta = wall ? ia->second.real : ia->second.cpu;
        const double tb = wall ? ib->second.real : ib->second.cpu;
        return tb > 0.0 ? std::optional<double>(ta / tb) : std::nullopt;
      };
}

class RatioReporter : public benchmark::ConsoleReporter {
 public:
  RatioReporter(bool color, std::vector<RatioLine> lines, std::string title)
      : ConsoleReporter(color ? OO_ColorTabular : OO_Tabular),
        lines_(std::move(lines)),
        title_(std::move(title)) {}

  void ReportRuns(const std::vector<Run>& reports) override {
    ConsoleReporter::ReportRuns(reports);
    for (const Run& run : reports) {
      if (run.error_occurred) continue;
      if (run.run_type != Run::RT_Iteration && run.aggregate_name != "mean") continue;
      const double unit = benchmark::GetTimeUnitMultiplier(run.time_unit);
      Measured& m = runs_[run.run_name.function_name];
      m.real = run.GetAdjustedRealTime() / unit;
      m.cpu = run.GetAdjustedCPUTime() / unit;
      for (const auto& [name, counter] : run.counters) m.counters[name] = counter.value;
    }
  }

  void Finalize() override {
    ConsoleReporter::Finalize();
    std::printf("\n%s\n", title_.c_str());
    for (const RatioLine& line : lines_) {
      const std::optional<double> v = line.value(runs_);
      if (!v) continue;
      char figure[64];
      std::snprintf(figure, sizeof figure, line.format.c_str(), *v * line.scale);
      std::printf("  %-64s %12s   %-10s %s\n", line.label.c_str(), figure, line.target.c_str(),
                  !line.met      ? ""
                  : line.met(*v) ? "met"
                                 : "NOT met");
    }
    std::fflush(stdout);
  }

 private:
  std::vector<RatioLine> lines_;
  std::string title_;
  Measurements runs_;
};

}  // namespace cw4d::bench
