#pragma once
// Non-convex round built-ins: the 3D torus and the 4D toratopes that are solids of revolution
// (make_spin) of a torus or a sphere. Every result is a closed, outward oriented complex with
// planar faces and flat cells (checked with validate()); none is convex.
//
//   spheritorus:R,r,N    (sqrt(x^2 + w^2) - R)^2 + y^2 + z^2 <= r^2        volume 8/3 pi^2 R r^3
//   torisphere:R,r,N     (sqrt(x^2 + y^2 + w^2) - R)^2 + z^2 <= r^2        4 pi^2 R^2 r^2 + pi^2
//   r^4 ditorus:R1,R2,r,N    (sqrt((sqrt(x^2 + w^2) - R1)^2 + y^2) - R2)^2 + z^2 <= r^2   4 pi^3 R1
//   R2 r^2 tiger:R1,R2,r,N      (sqrt(x^2 + w^2) - R1)^2 + (sqrt(y^2 + z^2) - R2)^2 <= r^2   4 pi^3
//   R1 R2 r^2
//
// N is the number of segments of every circle (the tube, the sweeps), 3..max_toratope_resolution;
// the polytopes are inscribed, so their volumes approach the values above from below.
#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// The finest toratope: at N = 64 the ditorus and the tiger have N^3 = 262144 cells and build
/// in about 4 s; the spheritorus and torisphere, N^3 / 2, in 2 s. (At 128, eight times the
/// cells, they took over a minute and 1.2 GB.)
inline constexpr int max_toratope_resolution = 64;

/// Torus of revolution about the z axis in R^3: tube circle of radius r (N segments) whose
/// centre runs on the circle of radius R > r (N segments). Faces are planar isosceles trapezoids.
/// \throw InputError for non-positive or non-finite radii, R <= r, or N
/// outside 3..max_toratope_resolution.
Complex make_torus(double major, double minor, int n);

/// \throw InputError for bad radii (see the table above: R > r > 0) or N
/// outside 3..max_toratope_resolution.
Complex make_spheritorus(double major, double minor, int n);
Complex make_torisphere(double major, double minor, int n);
/// \throw InputError unless R1 > R2 + r and R2 > r > 0, N in 3..128.
Complex make_ditorus(double r1, double r2, double minor, int n);
/// \throw InputError unless R1 > r, R2 > r, r > 0, N in 3..128.
Complex make_tiger(double r1, double r2, double minor, int n);

}  // namespace cw4d
