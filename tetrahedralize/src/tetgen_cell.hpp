#pragma once
// TetGen (AGPL, fenced in cw4d_tetrahedralize) for one non-convex 3-cell of a 4D complex.
// Internal: the NonConvexCellMesher of tetrahedralize().
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"

namespace cw4d {

using TetgenCellResult = CellTets;

/// Tetrahedralizes the polyhedron bounded by `boundary` (triangles of model vertex ids, all
/// among `vertices`) in the cell's own frame (an orthonormal basis of the hyperplane with
/// normal `normal`), with TetGen's -pYQ: the boundary triangles are kept exactly.
/// \throw MeshingError naming the cell when TetGen fails (its exit code, never an exit).
TetgenCellResult tetgen_cell(const Complex& complex, std::uint32_t cell,
                             const std::vector<std::uint32_t>& vertices,
                             const std::vector<std::array<std::uint32_t, 3>>& boundary,
                             const Eigen::Vector4d& normal);

}  // namespace cw4d
