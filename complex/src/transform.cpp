#include "cw4d/complex/transform.hpp"

#include <Eigen/LU>

#include <cmath>
#include <string>

#include "cw4d/complex/error.hpp"

namespace cw4d {

AffineTransform::AffineTransform(int dim)
    : linear_(Eigen::MatrixXd::Identity(dim, dim)), translation_(Eigen::VectorXd::Zero(dim)) {}

AffineTransform::AffineTransform(Eigen::MatrixXd linear, Eigen::VectorXd translation)
    : linear_(std::move(linear)), translation_(std::move(translation)) {
  if (linear_.rows() != linear_.cols() || linear_.rows() != translation_.size())
    throw InputError("AffineTransform: linear part must be square and match the translation");
}

AffineTransform AffineTransform::rotation(int dim, int i, int j, double angle) {
  if (i < 0 || j < 0 || i >= dim || j >= dim || i == j)
    throw InputError("rotation plane axes " + std::to_string(i) + "," + std::to_string(j) +
                     " are not two distinct axes of R^" + std::to_string(dim));
  AffineTransform r(dim);
  const double c = std::cos(angle), s = std::sin(angle);
  r.linear_(i, i) = c;
  r.linear_(j, j) = c;
  r.linear_(j, i) = s;
  r.linear_(i, j) = -s;
  return r;
}

AffineTransform AffineTransform::translation(const Eigen::VectorXd& t) {
  AffineTransform r(static_cast<int>(t.size()));
  r.translation_ = t;
  return r;
}

AffineTransform AffineTransform::scale(int dim, double s) {
  return scale(Eigen::VectorXd::Constant(dim, s));
}

AffineTransform AffineTransform::scale(const Eigen::VectorXd& s) {
  AffineTransform r(static_cast<int>(s.size()));
  r.linear_ = s.asDiagonal();
  return r;
}

AffineTransform AffineTransform::inverse() const {
  Eigen::FullPivLU<Eigen::MatrixXd> lu(linear_);
  if (!lu.isInvertible()) throw InputError("AffineTransform: the linear part is singular");
  Eigen::MatrixXd inv = lu.inverse();
  return AffineTransform(inv, -inv * translation_);
}

bool AffineTransform::is_identity() const {
  return linear_.isIdentity(0.0) && translation_.isZero(0.0);
}

AffineTransform operator*(const AffineTransform& a, const AffineTransform& b) {
  if (a.dim() != b.dim()) throw InputError("AffineTransform: composing different dimensions");
  return AffineTransform(a.linear_ * b.linear_, a.linear_ * b.translation_ + a.translation_);
}

std::pair<int, int> parse_rotation_plane(std::string_view name) {
  auto axis = [&](char ch) -> int {
    switch (ch) {
      case 'x':
      case 'X':
        return 0;
      case 'y':
      case 'Y':
        return 1;
      case 'z':
      case 'Z':
        return 2;
      case 'w':
      case 'W':
        return 3;
      default:
        return -1;
    }
  };
  if (name.size() == 2) {
    const int a = axis(name[0]), b = axis(name[1]);
    if (a >= 0 && b >= 0 && a != b) return {a, b};
  }
  throw InputError("unknown rotation plane '" + std::string(name) +
                   "' (use two of the axes x, y, z, w: xy xz xw yz yw zw)");
}

Complex transformed(const Complex& complex, const AffineTransform& t) {
  if (t.dim() != complex.ambient_dim())
    throw InputError("transform of R^" + std::to_string(t.dim()) + " applied to a complex in R^" +
                     std::to_string(complex.ambient_dim()));
  Eigen::FullPivLU<Eigen::MatrixXd> lu(t.linear());
  if (!lu.isInvertible()) throw InputError("transform is singular");
  Complex out = complex;
  Eigen::MatrixXd p = (t.linear() * complex.positions()).colwise() + t.translation();
  out.set_positions(std::move(p));
  if (complex.has_facet_normals()) {
    Eigen::MatrixXd n = lu.inverse().transpose() * complex.facet_normals();
    for (Eigen::Index i = 0; i < n.cols(); ++i) {
      const double len = n.col(i).norm();
      if (len > 0) n.col(i) /= len;
    }
    out.set_facet_normals(std::move(n));
  }
  if (lu.determinant() < 0.0) {
    const int fr = complex.facet_rank();
    if (fr >= 1)
      for (std::uint32_t f = 0; f < out.count(fr); ++f) out.flip(fr, f);
  }
  return out;
}

}  // namespace cw4d
