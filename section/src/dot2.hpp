#pragma once
// The compensated plane value n.x - d shared by plane_value, the slicer and the sweep (private to
// section/, which is compiled with -ffp-contract=off so the operations below are never fused).
// The dot product is accumulated first and -d added last, so a sweep computes the vertex part
// once and finishes it for every plane offset with exactly the bits plane_value gives.
#include <cmath>

namespace cw4d::detail {

/// TwoProduct/TwoSum accumulation of sum_i n_i x_i (Ogita-Rump-Oishi Dot2): the exact sum is
/// hi + (lo + the rounding errors below the last ulp).
struct Dot2 {
  double hi = 0.0, lo = 0.0;
};

inline Dot2 dot2_partial(const double* n, const double* x, int size) {
  double p = 0.0, c = 0.0;
  for (int i = 0; i < size; ++i) {
    const double h = n[i] * x[i];
    const double r = std::fma(n[i], x[i], -h);  // exact: n_i x_i = h + r
    const double sum = p + h;
    const double z = sum - p;
    const double e = (p - (sum - z)) + (h - z);  // exact: p + h = sum + e
    p = sum;
    c += e + r;
  }
  return {p, c};
}

/// hi + lo - d with the last TwoSum carried: the plane value of the vertex for offset d.
inline double dot2_finish(Dot2 v, double d) {
  const double h = -d;
  const double sum = v.hi + h;
  const double z = sum - v.hi;
  const double e = (v.hi - (sum - z)) + (h - z);
  return sum + (v.lo + e);
}

}  // namespace cw4d::detail
