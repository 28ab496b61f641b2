#pragma once
// Independent oracles for section tests. None of them uses the section algorithm.
#include <Eigen/Core>

#include <vector>

#include "cw4d/complex/complex.hpp"

namespace cw4d::test {

/// (n-1)-volume of {x in solid : u . x = t} for a closed, outward complex in R^n and a unit u.
/// The solid is written as a signed sum of n-simplices (cones from the vertex centroid over the
/// facets' simplices); the cross-section volume of one simplex S is vol(S) * M(t), M the
/// normalized B-spline whose knots are the values u . vertex (Curry-Schoenberg), evaluated with
/// the de Boor-Cox recurrence. Right-continuous at knots; continuous where no n knots coincide.
double bspline_section_volume(const Complex& solid, const Eigen::VectorXd& u, double t);

/// Closed form for the cube [-1,1]^n cut by {u . x = t}, u a unit vector with no zero entry:
/// inclusion-exclusion over the vertices of the unit cube (a derivative of the cut volume).
double cube_section_volume(const Eigen::VectorXd& u, double t);

/// Normalized B-spline M(t | knots), integral 1 (knots need not be sorted).
double bspline(std::vector<double> knots, double t);

}  // namespace cw4d::test
