#pragma once
// PLY and STL export of section meshes, written by OpenMesh's writers.
//
// PLY (binary little endian): float x, y, z per vertex with uchar red, green, blue, alpha (the
// source cell's color as stored, sRGB bytes; light grey when the section has no colors) and
// triangles.
// Corners of the same section vertex with the same color are welded again, so a one-colored
// section is a closed, watertight triangle mesh; vertices are split only where colors change.
// STL (binary): the triangles with their facet normals, no colors (STL has none).
#include <string>
#include <vector>

#include "cw4d/export/mesh.hpp"

namespace cw4d {

/// \throw InputError when there are no triangles, IoError when the file cannot be written.
void write_ply_file(const std::string& path, const std::vector<TriangleMesh>& meshes);
/// \throw InputError when there are no triangles, IoError when the file cannot be written.
void write_stl_file(const std::string& path, const std::vector<TriangleMesh>& meshes);

}  // namespace cw4d
