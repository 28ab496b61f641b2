#pragma once
// The 3D camera: look-at placement, perspective or orthographic projection, OpenGL clip-space
// conventions (right-handed view space looking down -z, clip z in [-w, w]).
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace cw4d::render {

enum class Projection { Perspective, Orthographic };

/// What the rasterizer needs of a view: the clip transform and where the viewer is (for
/// specular highlights and two-sided lighting).
struct View {
  glm::mat4 clip_from_world{1.0f};
  glm::vec3 eye{0.0f};                   ///< perspective: the eye point
  glm::vec3 forward{0.0f, 0.0f, -1.0f};  ///< unit viewing direction
  bool orthographic = false;
  /// Unit vector from a world point towards the viewer.
  glm::vec3 to_viewer(const glm::vec3& p) const;
};

struct Camera {
  glm::vec3 eye{0.0f, 0.0f, 5.0f};
  glm::vec3 target{0.0f};
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  Projection projection = Projection::Perspective;
  float fov_y_degrees = 35.0f;  ///< perspective: full vertical field of view
  float ortho_height = 2.0f;    ///< orthographic: full height of the view in world units
  float near_plane = 0.05f;
  float far_plane = 100.0f;

  glm::vec3 forward() const;
  glm::vec3 right() const;  ///< unit, perpendicular to forward and up
  glm::mat4 view_matrix() const;
  glm::mat4 projection_matrix(float aspect) const;
  /// \throw InputError when eye == target, up is parallel to the view direction, the planes
  ///        are not 0 < near < far (perspective), or aspect/fov/height are not positive.
  View view(float aspect) const;

  /// A camera looking at the sphere (centre, radius) from the direction `from` (any length),
  /// so that the sphere fills the smaller image side up to `margin` (>= 1).
  /// Up is `up` when given (non-zero, not parallel to `from`), else +z unless `from` is
  /// (almost) parallel to it, then +y.
  static Camera framing(const glm::vec3& centre, float radius, const glm::vec3& from, float aspect,
                        Projection projection, float fov_y_degrees = 35.0f, float margin = 1.08f,
                        const glm::vec3& up = glm::vec3(0.0f));
};

}  // namespace cw4d::render
