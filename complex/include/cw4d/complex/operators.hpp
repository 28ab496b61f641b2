#pragma once
// Operators that make new closed complexes from closed complexes (pyramid, prism, polar dual,
// solid of revolution) and convex polytopal approximations of round shapes.
//
// Every result is built through build_complex (outward oriented, facet normals) and checked with
// validate(); a result that does not validate throws TopologyError. Inputs must be closed
// complexes that validate (InputError otherwise).
#include "cw4d/complex/complex.hpp"

namespace cw4d {

/// The pyramid over a closed complex in R^n: a closed complex in R^(n+1) whose base is the
/// solid of `base` at last coordinate 0 (it becomes a facet) and whose apex is (vertex centroid
/// of base, height); every element of the base is coned to the apex. Volume = base volume *
/// height / (n + 1). Works for n >= 1.
/// \throw InputError when base does not validate as closed or height is 0 or not finite.
Complex make_pyramid(const Complex& base, double height);

/// base x [-height/2, height/2] (the segment is the last coordinate). make_prism(p, 2) is the
/// spec prism:MODEL. \throw InputError when height <= 0 or not finite.
Complex make_prism(const Complex& base, double height);

/// Polar dual of a convex polytope in R^n (n >= 2) w.r.t. the sphere of `radius` centred at the
/// vertex centroid c: facet F (outward unit normal N, distance d > 0 from c) becomes the vertex
/// c + radius^2 / d * N, and an element of rank k becomes one of rank n - 1 - k. Rank-2 elements
/// of the dual are the cycles of facets around an element of rank n - 3, ordered by walking
/// facet-ridge adjacency. With the same centre, the dual of the dual is the original.
/// \throw InputError when the complex does not validate as closed, is not convex (a vertex more
///        than tol::planarity_rel * diameter outside a facet hyperplane), or radius <= 0.
Complex make_dual(const Complex& convex, double radius = 1.0);
/// make_dual with radius sqrt(R * d_min) (R: largest vertex distance from the vertex centroid,
/// d_min: smallest facet distance), so that the dual has the same circumradius about that centre;
/// for a regular polytope the dual of this dual is the original. What dual:MODEL builds.
Complex make_dual_same_size(const Complex& convex);

/// Uniform N-gonal antiprism in R^3 (N >= 3), edge 2, centred at the origin, axis z: two
/// N-gons of circumradius 1 / sin(pi/N) at z = +-h/2, turned by pi/N, with h^2 = 4 -
/// 1 / cos^2(pi/2N). N = 3 is the octahedron. f-vector (2N, 4N, 2N + 2).
Complex make_antiprism(int n);

/// Regular N-gon of circumradius r in the plane (N >= 3).
Complex make_round_polygon(double r, int n);

/// Polyhedral sphere of radius r in R^3 (a "UV sphere"): N >= 3 segments around the z axis and
/// M = max(2, N / 2) bands from pole to pole; vertices on the sphere at polar angles pi j / M and
/// azimuths 2 pi k / N. Faces are triangles at the poles and isosceles trapezoids (planar)
/// elsewhere; all vertices lie on the sphere and every face is a face of their convex hull, so
/// the polyhedron is convex. Refining N by a factor 2 keeps every vertex, so the volume grows
/// monotonically towards 4/3 pi r^3.
Complex make_uv_sphere(double r, int n);

/// N-gon of circumradius r (xy) x segment [-r, r] (z): a convex cylinder in R^3.
Complex make_cylinder(double r, int n);
/// N-gon x N-gon, both of circumradius r: the duocylinder approximation (volume -> pi^2 r^4).
Complex make_duocylinder(double r, int n);
/// N-gon of circumradius r x the square [-r, r]^2: the cubinder (volume -> 4 pi r^4).
Complex make_cubinder(double r, int n);
/// make_uv_sphere(r, n) x segment [-r, r]: the spherinder (volume -> 8/3 pi r^4).
Complex make_spherinder(double r, int n);

/// make_pyramid(base, h) with h half the largest side of base's bounding box (the radius r of
/// sphere:r,N and cylinder:r,N): cone:sphere is the spherone, cone:cylinder the cylindrone.
Complex make_cone(const Complex& base);

/// Polytopal solid of revolution in R^4 of a closed polyhedron P in R^3 lying in x >= 0: each
/// point (x, y, z) of P sweeps the regular `steps`-gon (x cos t, y, z, x sin t), t = 2 pi k /
/// steps, i.e. P turns in the (x, w) plane around the yz plane. Each face F of P and each step
/// give one 3-cell (planar: it lies in a hyperplane), bounded by the copies of F at both ends of
/// the step and one trapezoid per edge of F (planar: two sides are parallel). Vertices with
/// x = 0 stay single, faces lying in x = 0 vanish (they are inside the solid). P touching x = 0
/// only in a vertex or an edge gives a pinched (but still closed) complex.
/// Volume = 2 * area(unit steps-gon) * integral of x over P (-> 2 pi integral of x, Pappus).
/// \throw InputError when P does not validate as a closed 3D complex, has a vertex with x < 0
///        (beyond tol::planarity_rel * its diameter), or steps < 3.
Complex make_spin(const Complex& polyhedron, int steps);

/// True when every vertex lies on the inner side of every facet hyperplane, within
/// tol::planarity_rel * (bounding-box diagonal). Needs facet normals.
bool is_convex(const Complex& complex);

}  // namespace cw4d
