// Peak memory of a 10^6-cell section: one Complex of 125,000 disjoint tesseracts
// (bench_models.hpp, with their rank-4 solids), compiled into a clustered SliceModel, cut once
// without culling by a generic plane through the middle (the plane of bench_slicer's
// big/slice/nocull). After each stage it prints VmRSS and VmHWM (/proc/self/status) and
// getrusage's ru_maxrss; the high-water mark VmHWM is reset (echo 5 > /proc/self/clear_refs)
// after the Complex is built, so the peaks of the later stages are theirs, not the builder's.
// The byte counts are the arrays' sizes: input = the Complex, SliceModel::bytes(), output = the
// SliceBuffers. No Google Benchmark: one run, one table.
//
//   bench_memory [--no-solids]
#include <sys/resource.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include "bench_models.hpp"
#include "cw4d/section/slicer.hpp"

namespace {

struct Status {
  double rss = 0, hwm = 0, maxrss = 0;  // MiB
};

Status status() {
  Status s;
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("VmRSS:", 0) == 0) s.rss = std::stod(line.substr(6)) / 1024.0;
    if (line.rfind("VmHWM:", 0) == 0) s.hwm = std::stod(line.substr(6)) / 1024.0;
  }
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  s.maxrss = static_cast<double>(u.ru_maxrss) / 1024.0;
  return s;
}

bool reset_hwm() {
  std::ofstream out("/proc/self/clear_refs");
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

void row(const char* stage, const Status& s) {
  std::printf("| %-34s | %9.1f | %9.1f | %9.1f |\n", stage, s.rss, s.hwm, s.maxrss);
}

double mib(std::size_t b) {
  return static_cast<double>(b) / (1024.0 * 1024.0);
}

}  // namespace

int main(int argc, char** argv) {
  const bool solids = !(argc > 1 && std::strcmp(argv[1], "--no-solids") == 0);
  std::printf("| stage | VmRSS MiB | VmHWM MiB | ru_maxrss MiB |\n| --- | ---: | ---: | ---: |\n");
  row("start", status());
  const cw4d::Complex model = cw4d::bench::tesseract_union({20, 25, 25, 10}, solids);
  const Status built = status();
  row("Complex built", built);
  const bool reset = reset_hwm();
  const Status base = status();
  row(reset ? "(VmHWM reset)" : "(VmHWM reset FAILED)", base);
  const cw4d::SliceModel compiled(model);
  const Status after_model = status();
  row("SliceModel compiled", after_model);
  const Eigen::VectorXd n = cw4d::bench::seeded_normal(4, 20240401u + 7);
  const cw4d::Hyperplane plane = cw4d::Hyperplane::from(n, n.dot(compiled.centre()) + 0.123);
  cw4d::Slicer slicer;
  cw4d::SliceBuffers out;
  cw4d::SliceOptions options;
  options.cull = false;
  slicer.slice(compiled, plane, out, options);
  const Status after_slice = status();
  row("sliced (unculled)", after_slice);
  slicer.slice(compiled, plane, out, options);
  row("sliced again (buffers reused)", status());

  const std::size_t input = cw4d::bench::complex_bytes(model), model_bytes = compiled.bytes(),
                    output = cw4d::bench::buffers_bytes(out);
  const double peak = after_slice.hwm - base.rss;
  std::printf("\ncells %zu, solids %zu, section polygons %zu, general path %d\n", model.count(3),
              model.count(4), out.count(2), static_cast<int>(out.general));
  std::printf("input (Complex arrays)      %9.1f MiB\n", mib(input));
  std::printf("SliceModel::bytes()         %9.1f MiB  (%.2fx input)\n", mib(model_bytes),
              static_cast<double>(model_bytes) / static_cast<double>(input));
  std::printf("output (SliceBuffers)       %9.1f MiB\n", mib(output));
  std::printf("RSS growth, SliceModel      %9.1f MiB\n", after_model.rss - base.rss);
  std::printf("RSS growth, Slicer + output %9.1f MiB\n", after_slice.rss - after_model.rss);
  std::printf(
      "peak increase over the built Complex (VmHWM after slice - VmRSS before compile)\n"
      "                            %9.1f MiB = %.2fx (input + output)\n",
      peak, peak / (mib(input) + mib(output)));
  return 0;
}
