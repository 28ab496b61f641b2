#pragma once
// Small helpers for writing vectors and angles in tests.
#include <Eigen/Core>

#include <initializer_list>
#include <numbers>

namespace cw4d::test {

inline Eigen::VectorXd vec(std::initializer_list<double> xs) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(xs.size()));
  Eigen::Index i = 0;
  for (double x : xs) v(i++) = x;
  return v;
}

inline double radians(double degrees) {
  return degrees * std::numbers::pi / 180.0;
}

}  // namespace cw4d::test
