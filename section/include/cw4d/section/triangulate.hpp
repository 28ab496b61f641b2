#pragma once
// Triangulation of the polygons of a section (or any complex's faces): fan triangulation for
// convex faces, ear clipping for non-convex faces and for polygons with holes.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

#include "cw4d/complex/complex.hpp"

namespace cw4d {

struct Section;

struct Triangle {
  std::array<std::uint32_t, 3> v;  ///< vertex ids, in the face's orientation
  std::uint32_t face;              ///< the face it came from
};

/// Fan triangulation of every face from its first vertex (valid for convex faces): a k-gon
/// gives k - 2 triangles that keep the face's orientation.
std::vector<Triangle> fan_triangulate(const Complex& complex);

/// Whether face f (a rank-2 element of a complex in R^2 or R^3) is a simple polygon: no vertex
/// visited twice and no two non-adjacent boundary edges meeting, measured in the plane of its
/// area vector. A face without a well-defined plane (zero area) is not simple.
bool is_simple_face(const Complex& complex, std::uint32_t f);

/// Ear clipping of one weakly simple polygon given by its 2D points (`points[i]` is the position
/// of vertex `ids[i]`), counter-clockwise or clockwise: appends k - 2 triangles in the loop's
/// orientation, tagged with `face`, to `out`. Straight angles give zero-area triangles (the
/// vertex stays, so neighbouring faces still share it). Returns false, leaving `out` unchanged,
/// when the polygon cannot be clipped (it is not simple); the caller decides what that means.
/// The one ear clipper of cw4d: the section's triangulation and the tetrahedral meshes use it.
bool ear_clip_polygon(std::vector<Eigen::Vector2d> points, std::vector<std::uint32_t> ids,
                      std::uint32_t face, std::vector<Triangle>& out);

/// Ear-clipping triangulation of every face of a complex in R^2 or R^3 (convex or not): a simple
/// k-gon gives k - 2 triangles with the face's orientation. The faces listed as holes of a face
/// in `holes` (holes[f]: faces lying inside face f, in its plane, oriented against it) are
/// bridged into it first, so the triangles cover f minus its holes, and the holes themselves
/// give no triangles. Faces that are not simple polygons (a self-intersecting section) and
/// polygons the ear clipper cannot finish are fan-triangulated: the triangles then sum to the
/// face as signed areas (the non-zero winding rule), which is still the right polygon soup.
/// \pre holes is empty or has one entry per face.
std::vector<Triangle> ear_clip_triangulate(
    const Complex& complex, const std::vector<std::vector<std::uint32_t>>& holes = {});

/// The holes of a section: the faces cut from one model cell (section.source[2], of one scene
/// object when object_of_face is set) lie in one
/// plane; a loop whose area vector points against the cell's outer loops is a hole, assigned to
/// the smallest outer loop of the same cell that contains it. Result: one entry per face.
std::vector<std::vector<std::uint32_t>> section_holes(const Section& section);

/// ear_clip_triangulate(section.complex, section_holes(section)).
std::vector<Triangle> triangulate_section(const Section& section);

}  // namespace cw4d
