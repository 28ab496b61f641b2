#pragma once
// Voxel clouds ([wxyhly 2024] "体素云渲染"; slice stacking as in [Ikits et al. 2004]): many
// parallel sections of a scene, each drawn as one layer of a 3D "voxel picture", composited back to
// front.
//
// The volume has coordinates (u, v, s): (u, v) are the first two axes of the hyperplane basis
// and s = n . x is the layer offset; a point of the volume shows the scene's surface seen
// along the third basis axis b3 at (u, v, s). An orthographic 3D camera views the volume from
// `view_from`, and layers are blended "over" each other from the farthest to the nearest. The
// layers are stacked along the volume axis most aligned with the view (as texture-based volume
// rendering re-slices: [Ikits et al. 2004]): stacked along s a layer is the section at s; along
// u it is the section b1 . x = u, and so on; each is seen along b3 as a flat picture, and
// shaded in 4D (Blinn-Phong with the cells' 4D normals and the studio lights lifted into the
// base hyperplane), so the stack axis changes only where the volume is sampled.
//
// Opacity correction: an object's opacity alpha is the opacity of the cloud's whole depth seen
// face-on (the reference thickness D0 = the extent along n). Light crossing one layer of
// spacing d at angle theta to the layer normal travels D = d / cos(theta), so every layer uses
// alpha' = 1 - (1 - alpha)^(D / D0): the picture does not change with the number of layers,
// and grows denser when the volume is seen at a grazing angle.
#include <Eigen/Core>
#include <glm/vec3.hpp>

#include "cw4d/complex/scene.hpp"
#include "cw4d/render/camera.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/raster.hpp"

namespace cw4d::render {

struct CloudOptions {
  RasterOptions raster;
  int layers = 64;
  /// Multiplies every object's opacity (a single model's opacity is 1).
  float opacity = 0.97f;
  /// Direction the volume (u, v, s) is seen from.
  glm::vec3 view_from{0.3f, -0.6f, 1.0f};
  glm::vec3 background{1.0f};  ///< linear
  /// Color every face by a palette hue of its source cell (keeping the object's opacity)
  /// instead of the scene's colors: for single, uncolored models.
  bool cell_palette = false;
  /// false: keep the composite over a transparent background (premultiplied alpha).
  bool flatten = true;
  /// The axis of the volume the layers are stacked along: -1 the one most aligned with the
  /// view (layers never seen edge-on: no stripes at grazing views), 0 u, 1 v, 2 s.
  int stack_axis = -1;
  /// The volume camera (orthographic); null: framing the volume from view_from.
  const Camera* camera = nullptr;
};

/// The stack axis render_voxel_cloud uses for a view direction (requested: CloudOptions).
int cloud_stack_axis(const glm::vec3& view_from, int requested = -1);

/// Side-by-side stereo pair of the cloud (left eye left, 2 * width wide): the volume seen from
/// two directions turned by -/+ angle/2 about the camera's up axis.
Image render_cloud_stereo_pair(const Scene& scene, const Eigen::VectorXd& normal,
                               const CloudOptions& options, float angle_degrees = 6.0f);

/// alpha' = 1 - (1 - alpha)^(path / reference): the opacity of a slab of thickness `path` for a
/// material whose slab of thickness `reference` has opacity alpha.
float corrected_opacity(float alpha, double path, double reference);

/// The cloud picture. \throw InputError for a scene that is not 4-dimensional, a zero normal
///        or a layer count outside 1..4096.
Image render_voxel_cloud(const Scene& scene, const Eigen::VectorXd& normal,
                         const CloudOptions& options);

}  // namespace cw4d::render
