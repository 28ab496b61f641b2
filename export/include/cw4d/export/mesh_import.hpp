#pragma once
// Closed 3D polyhedra from ordinary mesh files (OBJ, OFF, PLY, STL) through OpenMesh's readers,
// the input of the model families extrude:FILE and spin:FILE,STEPS. OpenMesh stays inside
// export/'s sources: this header needs only complex/.
#include <string>
#include <vector>

#include "cw4d/complex/catalogue.hpp"
#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// Reads a closed polyhedron into a 3D complex (built with build_complex: outward oriented, with
/// facet normals, validated). The format follows the file extension (.obj, .off, .ply, .stl).
/// Polygonal faces stay polygons; a face whose vertices are not coplanar within
/// tol::planarity_rel * its size is fan-triangulated. Vertices with identical coordinates are
/// merged (STL has no shared vertices, and OpenMesh splits faces it cannot attach), and vertices
/// in no face are dropped. Coordinates pass through OpenMesh's readers, most of which read
/// single precision. Silences OpenMesh's own error stream while reading (not thread-safe).
/// \throw ParseError (FILE:0) when the file is missing, not a regular file, larger than
///        max_input_file_bytes, announces more elements than its size can hold, OpenMesh cannot
///        read it, or the faces do not bound a closed, valid polyhedron (open mesh, three faces on
///        one edge, ...).
Complex read_polyhedron(const std::string& path);

/// The model families of mesh files, for a Catalogue (default_catalogue() has them):
/// "extrude:FILE" (the 4D prism of height 2 over read_polyhedron(FILE)) and "spin:FILE,STEPS"
/// (make_spin of it).
std::vector<ModelFamily> mesh_file_families();

}  // namespace cw4d
