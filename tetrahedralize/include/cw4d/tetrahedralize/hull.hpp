#pragma once
// Convex hulls of point sets as CW complexes, and the model families built from them.
//
// The hull itself comes from CGAL's dD triangulation (GPL: fenced in this library, see
// docs/ARCHITECTURE.md); on top of it coplanar hull simplices are merged into true polygonal faces
// and polyhedral cells, so the result is the face lattice of the polytope, not a triangulation.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "cw4d/complex/catalogue.hpp"
#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// The boundary complex of the convex hull of points (dim x N, one column per point, dim 3 or 4).
/// Ranks 1 .. dim-1 are stored, built with build_complex
/// (outward oriented, facet normals). Faces are the hull's true polygons (vertex cycles ordered
/// around their centroid), higher ranks its true cells: hull simplices whose vertices lie within
/// tol::hull_coplanar_rel * (radius of the point set about its centroid) of one hyperplane are
/// one facet. Only vertices of the hull remain (renumbered in input order); interior points,
/// points inside a facet, face or edge, and duplicates (within the same tolerance) are dropped.
/// \throw InputError when dim is out of range, there are fewer than dim + 1 points, a
///        coordinate is not finite, or the points lie in a lower-dimensional flat.
Complex convex_hull(const Eigen::MatrixXd& points);

/// Reads a point file: one point per line, coordinates separated by whitespace and/or commas,
/// '#' starts a comment, blank lines are skipped; every point has the same dimension (3 or 4).
/// Returns dim x N.
/// \throw ParseError ("FILE:LINE: ...") for a bad number, a line of another dimension, a
///        dimension other than 3 or 4, or a file without points (line 0 when it cannot be read).
Eigen::MatrixXd read_point_file(const std::string& path);

/// The snub cube ("snic"): the orbit of one point under the rotation group of the cube, chosen
/// so that all edges are equal (Newton on the sphere); edge length 2, centred at the origin,
/// f-vector (24, 60, 38): 32 triangles and 6 squares. Chiral: one fixed hand.
Complex make_snub_cube();

/// The snub dodecahedron ("snid"), built like make_snub_cube from the icosahedral rotations;
/// edge length 2, f-vector (60, 150, 92): 80 triangles and 12 pentagons.
Complex make_snub_dodecahedron();

/// The snub 24-cell (Klitzing's s3s4o3o, "sadi"): the hull of the 96 even permutations of
/// (0, +-1, +-phi, +-phi^2); edge length 2, f-vector (96, 432, 480, 144).
Complex make_snub_24_cell();

/// The grand antiprism ("gap"): the hull of the 120 vertices of the 600-cell (circumradius 1)
/// without the two decagons on a pair of completely orthogonal great circles; f-vector
/// (100, 500, 720, 320).
Complex make_grand_antiprism();

/// The largest glome resolution: glome:1,12 (9254 vertices, 36329 cells) builds in about 3 s;
/// the hull's time grows as n^4 (glome:1,24, 16 times the points, took over a minute).
inline constexpr int max_glome_resolution = 12;

/// A convex polytope inscribed in the 3-sphere of radius r, resolution n (1 ..
/// max_glome_resolution): the hull of
/// a grid in Hopf coordinates x = r (cos a cos b, cos a sin b, sin a cos c, sin a sin c) with
/// a = (pi/2) i / n for i = 0..n, and on each torus max(3, ceil(4 n cos a)) angles b and
/// max(3, ceil(4 n sin a)) angles c (one c on the circle a = 0, one b on a = pi/2), every other
/// torus turned by half a step. Its volume tends to pi^2 r^4 / 2 (error O(1/n^2)).
/// \throw InputError for r <= 0 (or not finite) or n out of range.
Complex make_glome(double r, int n);

/// The hull-based model families, for a Catalogue (default_catalogue() has them): "hull:FILE",
/// "snub cube" (snub-cube, snic), "snub dodecahedron" (snub-dodecahedron, snid), "snub 24-cell"
/// (snub-24-cell, sadi), "grand antiprism" (gap) and "glome:R,N".
std::vector<ModelFamily> hull_families();

}  // namespace cw4d
