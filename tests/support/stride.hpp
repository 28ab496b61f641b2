#pragma once
// How many of the items of a long loop over files or models a test takes: every one in the
// normal suite, every fourth when CW4D_STRESS_FRACTION (a number in (0, 1)) asks for less. The
// sanitizer suite sets it: there each item costs about ten times as much, the paths the items
// take repeat from one to the next, and the normal suite has compared every one.
#include <cstddef>
#include <cstdlib>

namespace cw4d::test {

inline std::size_t loop_stride() {
  const char* env = std::getenv("CW4D_STRESS_FRACTION");
  const double f = env ? std::atof(env) : 1.0;
  return f > 0.0 && f < 1.0 ? 4 : 1;
}

/// The number of items of `count` a loop with `stride` takes (0, stride, 2 stride, ...).
inline std::size_t strided_count(std::size_t count, std::size_t stride) {
  return (count + stride - 1) / stride;
}

}  // namespace cw4d::test
