#pragma once
// Triangle meshes for the exporters that want GPU-style vertex arrays (glTF, PLY, STL).
//
// A section's polygons are triangulated (section/triangulate.hpp) and their corners become
// mesh vertices of their own, so that every vertex carries its polygon's flat normal, color,
// texture coordinate and source cell. `section_vertex` remembers which section vertex a mesh
// vertex copies, so writers that want shared vertices (PLY) can weld them again.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "cw4d/section/section.hpp"
#include "cw4d/section/uvw.hpp"

namespace cw4d {

struct TriangleMesh {
  /// The scene object's name (or the model's spec for a single model).
  std::string name;
  /// The scene object the mesh was cut from (0 for a single model).
  std::uint32_t object = 0;
  Eigen::Matrix3Xf position;
  /// Unit outward normals (the polygon's).
  Eigen::Matrix3Xf normal;
  /// RGBA in [0, 1] as the complex stores colors (r, g, b sRGB-encoded, like hex colors; alpha
  /// linear); no columns when the section's faces have no colors.
  Eigen::Matrix4Xf color;
  /// Texture coordinates u, v, w; no columns when none were asked for.
  Eigen::Matrix3Xf uvw;
  /// The model cell each vertex was cut from.
  std::vector<std::uint32_t> cell;
  /// The section vertex each mesh vertex copies.
  std::vector<std::uint32_t> section_vertex;
  /// Three vertex ids per triangle, counter-clockwise seen from outside.
  std::vector<std::uint32_t> triangles;

  std::size_t vertex_count() const { return cell.size(); }
  std::size_t triangle_count() const { return triangles.size() / 3; }
};

/// The triangle meshes of a section in R^3: one per scene object the plane meets (in object
/// order, named by `object_names[object]`), or one for a single model's section (named
/// object_names[0] when given). `uvw`, when not null, must come from section_uvw of the same
/// section. Sections without faces give no meshes.
/// \throw InputError when the section does not live in R^3 or has no provenance.
std::vector<TriangleMesh> triangle_meshes(const Section& section,
                                          const std::vector<std::string>& object_names = {},
                                          const CornerUvw* uvw = nullptr);

}  // namespace cw4d
