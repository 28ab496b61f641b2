#pragma once
// Every tolerance of the renderer, in one place (the geometry's own are in
// complex/tolerances.hpp). Each is relative to the scale stated.

namespace cw4d::render::tol {

/// ConvexOccluder::from: a polytope is convex when no vertex lies farther than this times its
/// bounding radius outside a facet's hyperplane (planar facets of the built-ins are exact to
/// ~1e-15; a real dent is far larger).
inline constexpr double occluder_convex_rel = 1e-7;

/// An eye counts as in front of a facet only when its distance from the facet's hyperplane
/// exceeds this times (occluder radius + |eye| + |centre|): an eye in the plane of a facet sees
/// it edge-on, as a back facet.
inline constexpr double eye_facet_band_rel = 1e-12;

/// Default shrink of an occluder's shadow, relative to its radius, so that edges lying on its
/// own surface are not culled by rounding ([wxyhly 2024]: "待剔除面可以向内部缩进去一个很小的值").
inline constexpr double shadow_margin_rel = 1e-6;

/// Stereographic projection: points within this of the north pole (1 - w) are not projected.
inline constexpr double pole_gap = 1e-9;

/// Camera::view: the up vector must be at least this far (sine of the angle) from the viewing
/// direction.
inline constexpr float up_parallel_sin = 1e-6f;

/// Solid textures (texture.hpp): a sample within this fraction of one period below a lattice
/// plane of the pattern (a checker's cell wall, a grid line's edge, an image volume's repeat)
/// counts as on its upper side: the texture takes floor(p + tie), not floor(p). A section plane
/// that lies exactly on a lattice plane (w = 0 through the tesseract with any even checker)
/// gives every pixel the same UVW up to interpolation rounding, and floor(p) would pick either
/// side at random per pixel. The rasterizer interpolates UVW perspective-correctly in float
/// (raster.cpp: attributes times 1/w, barycentric weights, one division), a relative error of
/// a few float ulps, so |error| <~ 1e-6 |p| periods: 1e-3 clears it a hundredfold for
/// |p| = UVW * scale up to 10 (UVW in [0, 1] at every default scale) and tenfold up to 100,
/// while it moves a genuine boundary by 1e-3 of a period (under a tenth of a pixel unless one
/// period spans more than 100 pixels).
/// The discontinuity moves from p = k, where exact geometry lands, to p = k - tie, where
/// nothing in particular does ([Goldberg 1991] "What every computer scientist should know about
/// floating-point arithmetic": the rounding behind the jitter).
inline constexpr float texture_lattice_tie = 1e-3f;

}  // namespace cw4d::render::tol
