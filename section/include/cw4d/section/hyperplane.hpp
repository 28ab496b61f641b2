#pragma once
// Hyperplanes {x : n.x = d} with a unit normal, the one side classification function, and the
// orthonormal frame in which sections are expressed.
#include <Eigen/Core>

#include <cmath>
#include <cstdint>
#include <limits>

#include "cw4d/complex/tolerances.hpp"

namespace cw4d {

/// {x in R^n : normal . x = offset} with |normal| = 1, so offset is the signed distance of the
/// plane from the origin.
struct Hyperplane {
  Eigen::VectorXd normal;
  double offset = 0.0;

  /// The plane {x : (n/|n|) . x = d}: d is the signed distance from the origin along n/|n|.
  /// \throw InputError when n is zero or not finite, or d is not finite.
  static Hyperplane from(const Eigen::VectorXd& n, double d);
  int dim() const { return static_cast<int>(normal.size()); }
  double signed_distance(const Eigen::VectorXd& x) const { return normal.dot(x) - offset; }
};

enum class Side : std::int8_t { Negative = -1, On = 0, Positive = 1 };

/// n.x - d evaluated so that the result is the same on every machine and compiler: products are
/// split exactly with fma (TwoProduct), summed left to right with TwoSum error terms carried
/// (Ogita-Rump-Oishi Dot2), so the value is as accurate as a computation in twice the working
/// precision and its rounding never depends on vectorisation or FMA contraction (section/ is
/// also compiled with -ffp-contract=off). \pre n.size() == x.size().
double plane_value(const Eigen::VectorXd& n, double d, const double* x);

/// The single decision of which side of a plane a point lies on: On when
/// |signed_distance| <= tolerance. Every topological branch of the section uses this answer.
///
/// How the section's topological decisions are made (the same answer for the same input on
/// every machine):
///  - side of the plane: s = plane_value(...) (deterministic, near-exact; the slicer's fast path
///    uses the height n.x summed in a fixed order, minus d, whose error is below 5 ulps of the
///    scale), then this function with the tolerance of tolerances.hpp (plane_side_ulps), itself
///    computed deterministically. Outside the ON band the sign of s is the sign of the exact
///    n.x - d for the given doubles (the band exceeds either evaluation's error). Inside it the
///    vertex is ON, and ON vertices are resolved by symbolic perturbation: they count as Positive,
///    i.e. the plane is moved by -epsilon along n (the limit of generic planes), and only when that
///    leaves no section at all, as Negative (+epsilon), so a plane containing a facet returns that
///    facet.
///  - which cut points of a face pair up: the face's boundary chain on the cut line, ordered
///    along the line (stable sort by projection, ties in id order) and weighted by the running
///    winding number (section.cpp, emit_edges): purely a function of the decisions above and of
///    the double coordinates, with no tolerance.
///  - loop orientation: a loop's orientation is inherited from the signed boundary algebra (the
///    signs of the model's incidences), never measured; only the triangulation's hole
///    assignment measures areas (triangulate.hpp).
inline Side classify_side(double signed_distance, double tolerance) {
  if (signed_distance > tolerance) return Side::Positive;
  if (signed_distance < -tolerance) return Side::Negative;
  return Side::On;
}

/// The ON band classify_side is given for the plane n.x = d (model space) over vertices of
/// norm at most max_norm: tol::plane_side_ulps units of rounding of |n| max_norm + |d|, the
/// bound on the error of computing n.x - d. The one formula every section path uses.
inline double on_plane_tolerance(double normal_norm, double max_norm, double offset) {
  const double scale = normal_norm * max_norm + std::abs(offset);
  return tol::plane_side_ulps * std::numeric_limits<double>::epsilon() * scale;
}

/// Orthonormal basis (n x (n-1), one column per basis vector) of the hyperplane directions,
/// chosen deterministically: with j the last index of the largest |normal_j|, the columns are
/// the images of the other standard axes e_i (i != j, in increasing order) under the Householder
/// reflection that maps e_j to -sign(normal_j) * normal; the first column is then negated if
/// needed so that (b_1, ..., b_{n-1}, normal) is right-handed (det = +1). For normal = +e_n the
/// basis is (e_1, ..., e_{n-1}): cutting with w = d keeps x, y, z.
Eigen::MatrixXd hyperplane_basis(const Eigen::VectorXd& unit_normal);
/// The same basis written without allocating (for n <= 8) into `basis`, n x (n-1) column-major.
void hyperplane_basis(const double* unit_normal, int n, double* basis);

/// A hyperplane with its basis: section coordinates y of a point x of the plane are
/// y = basis^T (x - offset * normal), and x = offset * normal + basis * y.
struct HyperplaneFrame {
  Hyperplane plane;
  Eigen::MatrixXd basis;

  explicit HyperplaneFrame(const Hyperplane& p);
  HyperplaneFrame() = default;
  Eigen::VectorXd origin() const { return plane.offset * plane.normal; }
  Eigen::VectorXd to_plane(const Eigen::VectorXd& x) const {
    return basis.transpose() * (x - origin());
  }
  Eigen::VectorXd lift(const Eigen::VectorXd& y) const { return origin() + basis * y; }
};

}  // namespace cw4d
