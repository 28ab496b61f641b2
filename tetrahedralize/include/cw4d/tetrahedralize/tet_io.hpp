#pragma once
// Writers of tetrahedral meshes (TetMesh). Every file goes through a temporary file and a rename
// (write_file_atomically); a writer of two files removes the first when the second fails.
//
// Formats:
//  * .vtu  VTK XML UnstructuredGrid (ParaView, VTK's vtkXMLUnstructuredGridReader). Corners are
//          not shared (4 points per tetrahedron) so that per-corner data stays exact. Points are
//          the 3D Schlegel diagram of the mesh (schlegel_view below), so that a 3D viewer shows
//          the cells side by side rather than the overlapping xyz shadow of the 4D points; each
//          tetrahedron's corners are listed so that its 3D volume is positive. Point data
//          "position4" (x, y, z, w), "normal4" (the cell's outward 4D normal), "uvw"; cell data
//          "cell" (source 3-cell id, Int32) and "front" (UInt8, 1 for the tetrahedra of the cells
//          facing the eye, whose image encloses the others: threshold it away to see inside).
//          Cell type 10 (VTK_TETRA). ASCII or base64 binary (header UInt64, little endian).
//  * .node + .ele  TetGen's formats (0-based): .node holds the shared vertices as x y z with w as
//          the one point attribute; .ele the tetrahedra with the source cell as region attribute.
//  * .4do  the HoxelDraw 4D OBJ format (4DO spec v1): `4DO 1`, `v x y z w` per shared vertex,
//          `vn` per source cell, `vt u v w` per corner, `tformat v/vn/vt`, `t v/vn/vt x4` per
//          tetrahedron (zero-based indices), then one `c` record per source cell listing its
//          tetrahedra.
//  * .bin + .json  interleaved GPU buffer: per tetrahedron 4 corners, per corner 12 float32
//          (little endian): position vec4, normal vec4, uvw vec4 with the source cell id in the
//          fourth uvw component (exact below 2^24); stride 48 bytes, 192 bytes per tetrahedron.
//          The .json header names the layout, the counts and the .bin file.
//  * .g4tf / .g4b  G4MF (cw4d/complex/g4mf.hpp), godot-4d's tetrahedral mesh: the shared
//          vertices (float64), `simplexes` (each tetrahedron's corners 0, 1, 3, 2: G4MF takes
//          perpendicular(p1 - p0, p2 - p0, p3 - p0) as the outward normal, the opposite of the
//          Stokes order of TetMesh), the cells' normals per corner and per simplex, UVW per corner
//          (float32), and, from the CLI, the cells' colors per simplex; a .g4tf embeds its
//          buffer.
#include <Eigen/Core>

#include <cstdint>
#include <string>

#include "cw4d/complex/g4mf.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"

namespace cw4d {

/// The perspective from which .vtu files draw a 4D mesh in 3D: the Schlegel diagram. The eye is
/// on the outward normal N of the front cell (the cell whose normal has the largest w, lowest id
/// on ties), just outside it: at centre + h N with h halfway between the front cell's height
/// above the centre and the nearest height at which the eye would see a second cell from the
/// front (at most twice the front cell's height). Each point x is projected along the ray from
/// the eye onto the hyperplane through the centre orthogonal to N, and expressed in
/// hyperplane_basis(N) (for N = +w: x, y, z). For a convex polytope the images of the other
/// cells tile the image of the front cell without overlap; for other models it is a perspective
/// view (cells may overlap).
struct SchlegelView {
  Eigen::Vector4d centre = Eigen::Vector4d::Zero();   ///< mean of the mesh's points
  Eigen::Vector4d normal = Eigen::Vector4d::UnitW();  ///< N, the front cell's outward normal
  double eye_height = 1.0;                            ///< h
  std::uint32_t front_cell = 0;
  Eigen::Matrix<double, 4, 3> basis = Eigen::Matrix<double, 4, 3>::Identity();

  Eigen::Vector4d eye() const { return centre + eye_height * normal; }
  /// The 3D image of a point lying below the eye (N.(x - centre) < h).
  Eigen::Vector3d project(const Eigen::Vector4d& x) const;
  /// Whether the eye sees cell `cell` (outward normal n, at height d above the centre) from its
  /// outer side: n.(eye - centre) > d. Exactly the front cell for a convex polytope.
  bool faces_eye(const TetMesh& mesh, std::uint32_t cell) const;
};

/// The Schlegel view of a mesh (see SchlegelView). 	hrow InputError for an empty mesh.
SchlegelView schlegel_view(const TetMesh& mesh);

enum class VtuEncoding { Ascii, Base64 };

std::string vtu_text(const TetMesh& mesh, VtuEncoding encoding = VtuEncoding::Ascii);
std::string tetgen_node_text(const TetMesh& mesh);
std::string tetgen_ele_text(const TetMesh& mesh);
std::string fourdo_text(const TetMesh& mesh);
/// The interleaved buffer (192 bytes per tetrahedron) and its JSON header naming `bin_name`.
std::string gpu_buffer_bytes(const TetMesh& mesh);
std::string gpu_buffer_header(const TetMesh& mesh, const std::string& bin_name);

/// The tetrahedra as a G4MF simplex mesh (corners reordered as above); `cell_colors`, one per
/// model cell, are kept when there is one per cell.
G4mfSimplexMesh g4mf_simplex_mesh(const TetMesh& mesh, const std::vector<Rgba>& cell_colors = {});

/// The tetrahedral formats write_tet_mesh knows, by extension.
bool is_tet_mesh_path(const std::string& path);

/// Writes a mesh in the format of the path's extension: .vtu (ASCII unless `binary`), .node or
/// .ele (both files, same stem), .4do, .bin or .json (both files, same stem), .g4tf or .g4b.
/// \throw InputError for another extension; IoError when a file cannot be written.
void write_tet_mesh(const std::string& path, const TetMesh& mesh, bool binary = false);

}  // namespace cw4d
