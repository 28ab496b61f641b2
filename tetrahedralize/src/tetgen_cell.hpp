#pragma once
// TetGen (AGPL, fenced in this library) for one non-convex 3-cell of a 4D complex. Internal.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

struct TetgenCellResult {
  /// Tetrahedra as local ids: 0 .. vertices.size()-1 are the cell's vertices (in the order
  /// passed), higher ids are steiner[id - vertices.size()]. Orientation not normalized.
  std::vector<std::array<std::uint32_t, 4>> tets;
  /// Interior Steiner points TetGen added, lifted back into R^4 (they lie in the cell).
  std::vector<Eigen::Vector4d> steiner;
};

/// Tetrahedralizes the polyhedron bounded by `boundary` (triangles of model vertex ids, all
/// among `vertices`) in the cell's own frame (an orthonormal basis of the hyperplane with
/// normal `normal`), with TetGen's -pYQ: the boundary triangles are kept exactly.
/// \throw MeshingError naming the cell when TetGen fails (its exit code, never an exit).
TetgenCellResult tetgen_cell(const Complex& complex, std::uint32_t cell,
                             const std::vector<std::uint32_t>& vertices,
                             const std::vector<std::array<std::uint32_t, 3>>& boundary,
                             const Eigen::Vector4d& normal);

}  // namespace cw4d
