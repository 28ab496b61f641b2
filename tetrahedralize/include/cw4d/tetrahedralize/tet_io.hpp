#pragma once
// Writers of tetrahedral meshes (TetMesh). Every file goes through a temporary file and a rename
// (write_file_atomically); a writer of two files removes the first when the second fails.
//
// Formats:
//  * .vtu  VTK XML UnstructuredGrid (ParaView, VTK's vtkXMLUnstructuredGridReader). Corners are
//          not shared (4 points per tetrahedron) so that per-corner data stays exact. Points are
//          (x, y, z); point data "position4" (x, y, z, w), "normal4" (the cell's outward 4D
//          normal), "uvw"; cell data "cell" (source 3-cell id, Int32). Cell type 10 (VTK_TETRA).
//          ASCII or base64 binary (header UInt64, little endian) DataArrays.
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
#include <string>

#include "cw4d/tetrahedralize/tet_mesh.hpp"

namespace cw4d {

enum class VtuEncoding { Ascii, Base64 };

std::string vtu_text(const TetMesh& mesh, VtuEncoding encoding = VtuEncoding::Ascii);
std::string tetgen_node_text(const TetMesh& mesh);
std::string tetgen_ele_text(const TetMesh& mesh);
std::string fourdo_text(const TetMesh& mesh);
/// The interleaved buffer (192 bytes per tetrahedron) and its JSON header naming `bin_name`.
std::string gpu_buffer_bytes(const TetMesh& mesh);
std::string gpu_buffer_header(const TetMesh& mesh, const std::string& bin_name);

/// The tetrahedral formats write_tet_mesh knows, by extension.
bool is_tet_mesh_path(const std::string& path);

/// Writes a mesh in the format of the path's extension: .vtu (ASCII unless `binary`), .node or
/// .ele (both files, same stem), .4do, .bin or .json (both files, same stem).
/// \throw InputError for another extension; IoError when a file cannot be written.
void write_tet_mesh(const std::string& path, const TetMesh& mesh, bool binary = false);

}  // namespace cw4d
