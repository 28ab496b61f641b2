#pragma once
// Wavefront OBJ export of 3D (or 2D, padded with z = 0) complexes such as sections.
#include <string>

#include "cw4d/complex/complex.hpp"
#include "cw4d/section/section.hpp"

namespace cw4d {

struct ObjOptions {
  /// Fan-triangulate the (convex) polygons instead of writing them whole.
  bool triangulate = false;
  /// One `g` group per source cell (needs the section's provenance).
  bool group_by_source = true;
  /// Comment lines written at the top (each prefixed with "# ").
  std::string comment;
};

/// OBJ text of a complex's faces: `v` per vertex, `vn` per face (its facet normal, when the
/// complex has facet normals of rank 2), `f v//vn ...` per polygon or triangle. A complex
/// without faces (the polygon outline cut from a 3D model) is written as `l` line elements.
/// \throw InputError when the complex is not in R^2 or R^3.
std::string obj_text(const Complex& complex, const ObjOptions& options = {});
/// Same for a section, grouped per source cell ("g cell_<id>").
std::string obj_text(const Section& section, const ObjOptions& options = {});

/// Writes through a temporary file and a rename. \throw IoError, InputError.
void write_obj_file(const std::string& path, const Section& section, const ObjOptions& options = {});

}  // namespace cw4d
