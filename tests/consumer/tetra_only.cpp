// A client of cw4d::tetra alone (no CGAL, no TetGen): the tesseract [-1, 1]^4 is tetrahedralized
// (its eight cubes split into five tetrahedra each: 40) and the tetrahedra cut by w = 0.25 give
// the boundary of the cube [-1, 1]^3 (volume 8). Exit 0 when that holds.
#include <cmath>
#include <cstdio>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"

int main() {
  const cw4d::Complex tesseract = cw4d::load_model("tesseract");
  cw4d::TetStats stats;
  const cw4d::TetMesh mesh = cw4d::tetrahedralize_cells(tesseract, {}, {}, &stats);
  const cw4d::TetSection cut =
      cw4d::slice_tets(mesh, cw4d::Hyperplane::from(Eigen::Vector4d(0, 0, 0, 1), 0.25));
  const double volume = cut.volume();
  std::printf("tetrahedral section of the tesseract: %zu tetrahedra, volume %.12g\n", mesh.size(),
              volume);
  return mesh.size() == 40 && stats.skipped_cells == 0 && std::abs(volume - 8.0) < 1e-12 ? 0 : 1;
}
