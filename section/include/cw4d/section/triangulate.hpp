#pragma once
// Triangulation of the convex polygons of a section (or any complex's faces).
#include <array>
#include <cstdint>
#include <vector>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

struct Triangle {
  std::array<std::uint32_t, 3> v;  ///< vertex ids, in the face's orientation
  std::uint32_t face;              ///< the face it came from
};

/// Fan triangulation of every face from its first vertex (valid for convex faces): a k-gon
/// gives k - 2 triangles that keep the face's orientation.
std::vector<Triangle> fan_triangulate(const Complex& complex);

}  // namespace cw4d
