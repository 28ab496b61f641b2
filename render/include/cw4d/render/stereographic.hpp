#pragma once
// Stereographic projection of a polytope's edges ([wxyhly 2024], "球极投影"): the polytope is
// scaled onto the unit 3-sphere about its centre (each edge becomes the great arc its points
// project radially to), then projected from the north pole (0, 0, 0, 1) to R^3 by (x, y, z, w) ->
// (x, y, z) / (1 - w). Edges are subdivided adaptively, so curves stay smooth where the projection
// stretches them near the pole, and drawn as lines or as thin tubes whose radius follows the
// projection's conformal factor 1 / (1 - w) (tubes of constant width on the sphere).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <glm/vec3.hpp>

#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/render/camera.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/raster.hpp"

namespace cw4d::render {

/// A projected, subdivided edge: points in R^3 and the w of their preimage on the sphere.
struct ProjectedCurve {
  std::uint32_t edge = 0;
  std::vector<Eigen::Vector3d> points;
  std::vector<double> w;
  bool starts_at_vertex = false;  ///< points.front() is the edge's tail (not a break)
  bool ends_at_vertex = false;    ///< points.back() is the edge's head
};

struct StereographicOptions {
  RasterOptions raster;
  /// Applied to the centred, unit-radius polytope before projecting (4 x 4 orthogonal):
  /// chooses which point of the polytope sits at the pole.
  Eigen::Matrix4d rotation = Eigen::Matrix4d::Identity();
  /// Before `rotation`: turn the polytope so that the centre of its facet 0 lies at the south
  /// pole (the middle of the picture) and the opposite side around the north pole.
  bool facet_at_south_pole = true;
  /// Longest projected chord of a subdivided edge, relative to the unit sphere's image radius.
  double max_chord = 0.03;
  /// Points farther than this from the origin after projection are dropped (the curve breaks).
  double clip_radius = 12.0;
  bool tubes = true;
  /// Tube radius on the sphere (radians of the unit 3-sphere).
  double tube_radius = 0.012;
  int tube_sides = 10;
  /// Also draw balls at the polytope's vertices (tubes only).
  bool vertex_balls = true;
  float line_width = 1.5f;
  glm::vec3 view_from{2.0f, 1.3f, 1.0f};
  Projection projection = Projection::Perspective;
  /// Radius of the region framed by the camera (in projected units).
  float view_radius = 2.2f;
  glm::vec3 background{1.0f};  ///< linear
};

/// The stereographic image of every edge of a 4D complex, subdivided (curves broken where they
/// come within 1e-9 of the pole or leave clip_radius). \throw InputError when not 4D.
std::vector<ProjectedCurve> stereographic_curves(const Complex& model,
                                                 const StereographicOptions& options);

/// Tube mesh around the curves (radius scaled by 1 / (1 - w)), colored along w.
TriangleMesh tube_mesh(const std::vector<ProjectedCurve>& curves,
                       const StereographicOptions& options);

/// The picture. \throw InputError when the model is not 4D.
Image render_stereographic(const Complex& model, const StereographicOptions& options);

}  // namespace cw4d::render
