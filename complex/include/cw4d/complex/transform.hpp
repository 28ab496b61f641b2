#pragma once
// Affine transforms x -> A x + t of R^n, built from rotations in coordinate planes,
// translations and scales. Points are column vectors; (a * b)(x) = a(b(x)).
#include <Eigen/Core>

#include <string_view>
#include <utility>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

class AffineTransform {
 public:
  /// Identity of R^dim.
  explicit AffineTransform(int dim = 4);
  AffineTransform(Eigen::MatrixXd linear, Eigen::VectorXd translation);

  static AffineTransform identity(int dim) { return AffineTransform(dim); }
  /// Rotation by angle (radians) in the plane of axes i and j: e_i turns towards e_j.
  static AffineTransform rotation(int dim, int axis_i, int axis_j, double angle);
  static AffineTransform translation(const Eigen::VectorXd& t);
  static AffineTransform scale(int dim, double s);
  static AffineTransform scale(const Eigen::VectorXd& s);

  int dim() const { return static_cast<int>(linear_.rows()); }
  const Eigen::MatrixXd& linear() const { return linear_; }
  const Eigen::VectorXd& translation() const { return translation_; }

  Eigen::VectorXd apply(const Eigen::VectorXd& x) const { return linear_ * x + translation_; }
  AffineTransform inverse() const;
  bool is_identity() const;
  /// Composition: (a * b).apply(x) == a.apply(b.apply(x)).
  friend AffineTransform operator*(const AffineTransform& a, const AffineTransform& b);

 private:
  Eigen::MatrixXd linear_;
  Eigen::VectorXd translation_;
};

/// Axis letters of R^4 planes: "xy", "xz", "xw", "yz", "yw", "zw" (also "yx" etc., which turn
/// the other way). Returns the two axis indices.
/// \throw InputError for anything else.
std::pair<int, int> parse_rotation_plane(std::string_view name);

/// Applies a transform to a complex: positions, facet normals (inverse transpose), and the
/// orientation (facets flipped when the transform reverses orientation) so that the result
/// stays outward oriented.
/// \throw InputError when the transform's dimension differs or it is singular.
Complex transformed(const Complex& complex, const AffineTransform& transform);

}  // namespace cw4d
