#pragma once
// Wavefront OBJ export of 3D (or 2D, padded with z = 0) complexes such as sections. Face colors
// (complex.colors(2), e.g. from a scene) go to a companion .mtl file: one material per distinct
// color, "color_<k>" numbered in order of first use, with `Kd r g b` and `d opacity`. Kd holds
// the colour's sRGB-encoded components as given (as hex colours and the scene file write them),
// which is how three.js's MTLLoader reads them; Blender's importer takes them as linear, so
// colours look lighter there. The section of a scene starts each object with `o object_<i>`.
#include <string>
#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/uvw.hpp"

namespace cw4d {

struct ObjOptions {
  /// Triangulate the polygons (ear clipping, so non-convex ones too) instead of writing them
  /// whole. Polygons with holes (a section's loops inside another loop of the same cell) are
  /// always written as triangles, since OBJ polygons cannot have holes.
  bool triangulate = false;
  /// One `g` group per source cell (needs the section's provenance).
  bool group_by_source = true;
  /// Comment lines written at the top (each prefixed with "# ").
  std::string comment;
  /// File name of the material library: when set and the faces have colors, the OBJ says
  /// `mtllib <name>` and `usemtl color_<k>` before the faces of each color (see mtl_text).
  std::string material_library;
  /// Texture coordinates per face corner (section_uvw of the same section): written as
  /// `vt u v w` per corner and referenced as `f v/vt/vn`. Not owned; null for none.
  const CornerUvw* uvw = nullptr;
  /// Names of a scene's objects for the `o` lines (by object index); an object without a name
  /// here is written as `o object_<i>`.
  std::vector<std::string> object_names;
};

/// OBJ text of a complex's faces: `v` per vertex, `vn` per face (its facet normal, when the
/// complex has facet normals of rank 2), `f v//vn ...` per polygon or triangle. A complex
/// without faces (the polygon outline cut from a 3D model) is written as `l` line elements.
/// \throw InputError when the complex is not in R^2 or R^3.
std::string obj_text(const Complex& complex, const ObjOptions& options = {});
/// Same for a section, grouped per source cell ("g cell_<id>", or "g object_<i>_cell_<id>" for
/// a scene's section).
std::string obj_text(const Section& section, const ObjOptions& options = {});

/// MTL text of the face colors of a complex (one `newmtl color_<k>` per distinct color, in the
/// order obj_text uses them); empty when the faces have no colors.
std::string mtl_text(const Complex& complex);

/// Writes through a temporary file and a rename. When the faces have colors, the materials go
/// to the same path with the extension .mtl, written first (and removed again if the OBJ cannot
/// be written); options.material_library is then set to its file name.
/// \throw IoError, InputError.
void write_obj_file(const std::string& path, const Section& section,
                    const ObjOptions& options = {});

}  // namespace cw4d
