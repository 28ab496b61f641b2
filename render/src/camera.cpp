#include "cw4d/render/camera.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

#include "cw4d/complex/error.hpp"
#include "cw4d/render/tolerances.hpp"

namespace cw4d::render {

glm::vec3 View::to_viewer(const glm::vec3& p) const {
  if (orthographic) return -forward;
  const glm::vec3 d = eye - p;
  const float len = glm::length(d);
  return len > 0.0f ? d / len : -forward;
}

glm::vec3 Camera::forward() const {
  return glm::normalize(target - eye);
}

glm::vec3 Camera::right() const {
  return glm::normalize(glm::cross(forward(), up));
}

glm::mat4 Camera::view_matrix() const {
  return glm::lookAt(eye, target, up);
}

glm::mat4 Camera::projection_matrix(float aspect) const {
  if (projection == Projection::Orthographic) {
    const float h = 0.5f * ortho_height, w = h * aspect;
    return glm::ortho(-w, w, -h, h, near_plane, far_plane);
  }
  return glm::perspective(glm::radians(fov_y_degrees), aspect, near_plane, far_plane);
}

View Camera::view(float aspect) const {
  const glm::vec3 d = target - eye;
  if (!(glm::length(d) > 0.0f)) throw InputError("camera: the eye and the target coincide");
  if (!(glm::length(glm::cross(glm::normalize(d), glm::normalize(up))) > tol::up_parallel_sin))
    throw InputError("camera: the up vector is parallel to the viewing direction");
  if (!(aspect > 0.0f) || !std::isfinite(aspect))
    throw InputError("camera: aspect must be positive");
  if (!(far_plane > near_plane) || (projection == Projection::Perspective && !(near_plane > 0.0f)))
    throw InputError("camera: need 0 < near < far");
  if (projection == Projection::Perspective && !(fov_y_degrees > 0.0f && fov_y_degrees < 180.0f))
    throw InputError("camera: the field of view must lie in (0, 180) degrees");
  if (projection == Projection::Orthographic && !(ortho_height > 0.0f))
    throw InputError("camera: the orthographic height must be positive");
  View v;
  v.clip_from_world = projection_matrix(aspect) * view_matrix();
  v.eye = eye;
  v.forward = forward();
  v.orthographic = projection == Projection::Orthographic;
  return v;
}

Camera Camera::framing(const glm::vec3& centre, float radius, const glm::vec3& from, float aspect,
                       Projection projection, float fov_y_degrees, float margin,
                       const glm::vec3& up) {
  Camera c;
  radius = std::max(radius, 1e-6f);
  glm::vec3 dir = glm::length(from) > 0.0f ? glm::normalize(from) : glm::vec3(0, 0, 1);
  c.up = std::abs(dir.z) > 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
  if (glm::length(up) > 0.0f && glm::length(glm::cross(glm::normalize(up), dir)) > 0.05f) c.up = up;
  c.projection = projection;
  c.fov_y_degrees = fov_y_degrees;
  c.target = centre;
  const float r = radius * std::max(margin, 1.0f);
  if (projection == Projection::Orthographic) {
    c.ortho_height = 2.0f * r * std::max(1.0f, 1.0f / aspect);
    const float dist = 4.0f * r;
    c.eye = centre + dir * dist;
    c.near_plane = dist - 2.0f * r;
    c.far_plane = dist + 2.0f * r;
  } else {
    const float half_y = 0.5f * glm::radians(fov_y_degrees);
    const float half_x = std::atan(std::tan(half_y) * aspect);
    const float dist = r / std::sin(std::min(half_x, half_y));
    c.eye = centre + dir * dist;
    c.near_plane = std::max(dist - 2.0f * r, 0.01f * dist);
    c.far_plane = dist + 2.0f * r;
  }
  return c;
}

}  // namespace cw4d::render
