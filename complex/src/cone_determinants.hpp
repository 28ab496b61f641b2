#pragma once
// Shared by geometry.cpp and builder.cpp (not installed).
#include <Eigen/Core>

#include <cstdint>
#include <span>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// The sum over the oriented simplices of the given facets (rank n-1) of
/// det(scale p_0 - centre, ..., scale p_{n-1} - centre) for their vertices p_j: n! times the
/// signed volume of the cones from `centre` (in scaled coordinates) over them.
double facet_cone_determinants(const Complex& complex, std::span<const std::uint32_t> facets,
                               const Eigen::VectorXd& centre, double scale = 1.0);

}  // namespace cw4d
