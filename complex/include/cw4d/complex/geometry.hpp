#pragma once
// Measures of complexes: simplicial decompositions, oriented facet normals, volumes, bounds.
#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <span>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// Calls f(vertices, sign) for the oriented k-simplices (k + 1 vertex ids) of a decomposition of
/// element i of rank k (k >= 1): faces fan out from their first vertex, higher elements cone
/// from their first vertex over the simplices of the boundary elements that do not contain it
/// (the others would give flat cones). The signed sum of the simplices is the element as a chain.
void for_each_simplex(const Complex& complex, int rank, std::uint32_t i,
                      const std::function<void(std::span<const std::uint32_t>, int)>& f);

/// Oriented (k)-volume vector of a facet of a complex in R^(k+1): its direction is the outward
/// normal implied by the facet's orientation (Stokes convention), its length the facet volume.
/// The positions are multiplied by `scale` first (see position_scale).
Eigen::VectorXd facet_area_vector(const Complex& complex, std::uint32_t facet, double scale = 1.0);

/// A power of two s such that s * positions lies in [2^-60, 2^60] in magnitude (1 when it
/// already does, or when every coordinate is 0 or not finite). Multiplying by it is exact, so
/// decisions made on the scaled positions (orientation signs, normal directions, degeneracy)
/// do not depend on the model's units: volumes of coordinates near 1e200 or 1e-200 would
/// overflow or underflow in R^4 otherwise.
double position_scale(const Complex& complex);

/// Generalized cross product of n-1 vectors in R^n: X with X . y = det(u_1, ..., u_{n-1}, y).
Eigen::VectorXd generalized_cross(const Eigen::MatrixXd& u);

/// Signed n-volume enclosed by the facets of a closed complex in R^n (positive when outward).
/// The positions are multiplied by `scale` first (the result is the volume times scale^n).
/// `magnitude`, when given, receives the sum of the absolute volumes of the simplices summed
/// (the size of the rounding error of the result is about 1e-16 times it).
double signed_volume(const Complex& complex, double scale = 1.0, double* magnitude = nullptr);

/// k-volume of element i of rank k (sum of its simplices, measured in their own span).
double element_volume(const Complex& complex, int rank, std::uint32_t i);

/// Axis-aligned bounds, each a column vector of ambient_dim entries.
struct Bounds {
  Eigen::VectorXd min, max;
};
Bounds bounds(const Complex& complex);

/// Largest distance of a vertex from the origin.
double max_radius(const Complex& complex);

}  // namespace cw4d
