#pragma once
// Every tolerance cw4d uses, in one place. All are relative to a scale stated per constant.

namespace cw4d::tol {

/// A vertex is ON a hyperplane when its signed value s = n.x - d lies within the rounding error
/// of computing it: |s| <= plane_side_ulps * epsilon * (|n| * max_i |x_i| + |d|) (n, d in model
/// space). Used only by cw4d::classify_side, the one function every topological decision of the
/// section uses. Deliberately tight: a wider band would snap vertices of cells that are almost
/// parallel to the plane, moving their cut polygons far off the plane of the cell.
inline constexpr double plane_side_ulps = 64.0;

/// A crossing point that lies within weld_rel * (the model's bounding-box diagonal) of an end of
/// its edge merges into that end's section vertex, so nearly degenerate planes give no
/// near-duplicate vertices; the collapsed pieces cancel as chains.
inline constexpr double weld_rel = 1e-9;

/// A model facet whose unit normal, moved into the section's frame and projected onto the
/// plane, is shorter than near_parallel_normal is nearly parallel to the plane: its section
/// facet's normal is taken from the section's own geometry (its area vector) instead, by
/// section() and by the slicer (which leaves such slices to the general path).
inline constexpr double near_parallel_normal = 1e-9;

/// Self-intersection test of a section (cw4d::self_intersects): a boundary edge pierces another
/// face only when its ends lie farther than self_intersection_rel * (bounding-box diagonal) on
/// both sides of that face's plane, so faces that merely touch are not reported. Two faces
/// sharing two vertices cross along the segment between them only when its midpoint lies that
/// far inside each (or on an edge of it) and their unit normals' cross product exceeds it.
inline constexpr double self_intersection_rel = 1e-9;

/// A facet is planar when every vertex lies within planarity_rel * (facet diameter) of the
/// facet's best-fit hyperplane (validate()).
inline constexpr double planarity_rel = 1e-6;

/// A facet normal or simplex volume whose magnitude is below degenerate_rel * scale^k is
/// treated as zero (degenerate) when orienting.
inline constexpr double degenerate_rel = 1e-12;

/// Wythoff construction: orbit points within wythoff_same_vertex_rel * circumradius are one
/// vertex. Rounding in -cos(pi/m) makes a vertex reached by k reflections drift by about
/// k * m * 1e-16 (relative; measured 3e-9 for m = 10000), while distinct vertices are at least
/// ~pi / m apart.
inline constexpr double wythoff_same_vertex_rel = 1e-7;

/// A Coxeter diagram's Gram matrix counts as positive definite (a finite group) when its smallest
/// eigenvalue exceeds this. Affine groups give 0 (numerically ~1e-16); the smallest finite value,
/// I2(10000), is about 5e-8.
inline constexpr double wythoff_positive_definite_min = 1e-12;

/// Scenes: an object is not cut when the plane's distance from its bounding sphere's centre
/// exceeds the radius by more than bounding_sphere_margin_rel * (radius + |centre|). Skipping
/// is only a shortcut, so the margin errs towards cutting (the section decides exactly).
inline constexpr double bounding_sphere_margin_rel = 1e-9;

/// Convex hulls (tetrahedralize/hull): a point within hull_coplanar_rel * R of a hull facet's
/// hyperplane lies on that facet, and points closer than that to each other are one point, where
/// R is the radius of the point set about its centroid. Golden-ratio coordinates computed in
/// double are off by ~1e-15 R; the flattest genuine dihedral in the built-in hulls (glome:R,24)
/// bends by a sagitta above 1e-4 R.
inline constexpr double hull_coplanar_rel = 1e-9;

/// Parametric UVW (tetrahedralize/tet_mesh.hpp): an angle about an axis is undefined for a point
/// within uvw_axis_rel * R of that axis (R: the shape's radius); such a corner takes the mean
/// angle of the other corners of its tetrahedron. Grid points off the axis are >= R sin(pi/4N).
inline constexpr double uvw_axis_rel = 1e-9;

}  // namespace cw4d::tol
