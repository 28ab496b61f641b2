#pragma once
// Mass properties of the solid a closed, outward-oriented complex bounds: its n-volume, the
// (n-1)-volume of its boundary, its centroid and its second-moment matrix, in any dimension
// n >= 2 (R^3 and R^4 above all).
//
// Method: the oriented boundary is cut into signed simplices (each facet coned from its first
// vertex over its ridges, recursively, with the incidence signs: for_each_simplex in
// geometry.hpp), and each is coned from one fixed point, the mean of the vertices (which keeps
// the cancellation between positive and negative cones small). Each cone is a signed
// n-simplex with a closed-form integral, summed in coordinates relative to that point:
//   volume      V   = det(y_1, ..., y_n) / n!                     (y_i = v_i - apex)
//   first moment     int y dV      = V (y_1 + ... + y_n) / (n + 1)
//   second moment    int y y^T dV  = V / ((n+1)(n+2)) (sum_i y_i y_i^T + s s^T), s = sum_i y_i
// so the results are exact up to rounding, for convex and non-convex solids alike.
//
// Self-intersecting boundaries (the star polytopes) bound a chain, not a set: every value is
// then the integral weighted by the winding number (a region wound twice counts twice), which
// is what `winding_weighted` reports (see MassProperties).
#include <Eigen/Core>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

struct MassProperties {
  int dim = 0;               ///< the ambient dimension n
  double hypervolume = 0.0;  ///< n-volume of the solid (signed: positive for outward facets)
  /// (n-1)-volume of the boundary: the sum of the facets' volumes (each facet measured as its
  /// own oriented chain; a facet that is a star polytope counts its winding-weighted volume).
  double boundary_volume = 0.0;
  /// The centre of mass of the solid of density 1, (1/V) int x dV (n entries).
  Eigen::VectorXd centroid;
  /// The second-moment matrix about the origin of the model's coordinates, int x x^T dV over
  /// the solid (n x n, symmetric): the inertia of a uniform solid of density 1. About the
  /// centroid it is second_moment - hypervolume * centroid * centroid^T; the inertia tensor of
  /// mechanics in R^3 is trace(M) I - M.
  Eigen::MatrixXd second_moment;
  /// True when the boundary was seen to wind around some point other than 0 or 1 times (a
  /// self-intersecting star model): every value above is then weighted by the winding number
  /// (density). Decided by the winding number at sample points: the vertex mean and points
  /// just inside up to 32 facets (ray casting along a fixed generic direction); a
  /// self-intersection none of them sees is not flagged.
  bool winding_weighted = false;
};

/// The mass properties of the solid bounded by a closed complex in R^n (n >= 2): its facets
/// (rank n-1) outward oriented, every ridge in exactly two facets with opposite signs. The
/// model is expected to pass validate(); this call checks its tables (check_tables) and that
/// the facets close up, and refuses anything else.
/// \throw InputError for a complex with no facets, a dimension below 2, non-finite
///        coordinates or a result beyond the range of a double
/// \throw TopologyError when the facets do not close up (an open model), naming the ridge
MassProperties mass_properties(const Complex& complex);

/// The winding number of the oriented closed boundary of `complex` around `point` (ray
/// casting along a fixed generic direction): 1 inside a solid bounded by outward facets, 0
/// outside, the density inside a star polytope. A point within rounding of the boundary may
/// get either neighbouring value.
int winding_number(const Complex& complex, const Eigen::VectorXd& point);

}  // namespace cw4d
