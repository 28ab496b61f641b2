#pragma once
// Schlegel diagrams: a 4D polytope seen in perspective from a point just outside one of its
// cells, projected onto that cell's hyperplane (V. Schlegel, "Theorie der homogen
// zusammengesetzten Raumgebilde", 1883; the classic view of polymake and Stella4D). For a
// convex polytope the front cell is the outer boundary of the diagram and the images of the
// other cells tile it without overlap.
#include <Eigen/Core>
#include <glm/vec3.hpp>

#include <cstdint>
#include <utility>
#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/render/camera.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/raster.hpp"

namespace cw4d::render {

/// The perspective from eye = centre + eye_height * normal onto the front cell's hyperplane
/// normal . (x - centre) = cell_height, in the coordinates of `basis` (orthonormal, orthogonal
/// to normal) about the centre.
struct SchlegelProjection {
  Eigen::Vector4d centre = Eigen::Vector4d::Zero();   ///< mean of the vertices
  Eigen::Vector4d normal = Eigen::Vector4d::UnitW();  ///< the front cell's outward unit normal
  double cell_height = 1.0;                           ///< of the front cell above the centre
  double eye_height = 1.5;                            ///< > cell_height: just outside the cell
  std::uint32_t cell = 0;
  Eigen::Matrix<double, 4, 3> basis = Eigen::Matrix<double, 4, 3>::Identity();

  Eigen::Vector4d eye() const { return centre + eye_height * normal; }
  /// The 3D image of a point below the eye (normal . (x - centre) < eye_height).
  Eigen::Vector3d project(const Eigen::Vector4d& x) const;
};

/// The projection seen from just outside cell `cell` (-1: the cell whose outward normal has
/// the largest w component, the lowest id among equals): the eye halfway between the front
/// cell's hyperplane and the nearest hyperplane of another cell it would see from outside, so
/// that it sees no cell but the front one from outside.
/// \throw InputError when the model is not a closed 4D complex with cells, or `cell` is out of
///        range.
SchlegelProjection schlegel_projection(const Complex& model, long long cell = -1);

/// Every edge of the model, projected: (tail, head) per edge id.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> schlegel_edges(
    const Complex& model, const SchlegelProjection& projection);

struct SchlegelOptions {
  RasterOptions raster;
  /// The 3D camera looks at the diagram from this direction (diagram coordinates).
  glm::vec3 view_from{0.55f, 0.45f, 1.6f};
  Projection projection = Projection::Perspective;
  float line_width = 2.0f;
  /// Also draw the 2-faces, translucent, colored by their first cell.
  bool faces = false;
  float face_opacity = 0.22f;
  glm::vec3 background{1.0f};  ///< linear
};

/// The 3D camera of a Schlegel picture: framing the projected front cell.
Camera schlegel_camera(const Complex& model, const SchlegelProjection& projection,
                       const SchlegelOptions& options);

/// The picture: every edge projected, colored by its 4D distance from the eye (near warm, far
/// cool, as the 4D wireframe), with the translucent faces blended over what lies behind them
/// when `faces` is set, seen by schlegel_camera. \throw InputError for a model that is not 4D.
Image render_schlegel(const Complex& model, const SchlegelProjection& projection,
                      const SchlegelOptions& options);

}  // namespace cw4d::render
