#include "cw4d/render/voxel_cloud.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

#include "cw4d/complex/error.hpp"
#include "cw4d/render/color.hpp"
#include "cw4d/render/section_view.hpp"
#include "cw4d/section/scene_section.hpp"

namespace cw4d::render {

float corrected_opacity(float alpha, double path, double reference) {
  alpha = std::clamp(alpha, 0.0f, 1.0f);
  if (alpha >= 1.0f) return 1.0f;
  if (!(reference > 0.0)) return alpha;
  return static_cast<float>(1.0 - std::pow(1.0 - alpha, path / reference));
}

int cloud_stack_axis(const glm::vec3& view_from, int requested) {
  if (requested >= 0 && requested <= 2) return requested;
  const glm::vec3 a = glm::abs(view_from);
  // Ties go to s (the layering of the 4D offset), then v.
  if (a.z >= a.x && a.z >= a.y) return 2;
  return a.y >= a.x ? 1 : 0;
}

Image render_voxel_cloud(const Scene& scene, const Eigen::VectorXd& normal, const CloudOptions& o) {
  if (scene.dim() != 4) throw InputError("voxel clouds need a 4D scene");
  if (o.layers < 1 || o.layers > 4096)
    throw InputError("the layer count must be 1..4096, not " + std::to_string(o.layers));
  if (o.stack_axis < -1 || o.stack_axis > 2)
    throw InputError("the stack axis must be -1 (from the view), 0 (u), 1 (v) or 2 (s)");
  const Hyperplane plane0 = Hyperplane::from(normal, 0.0);
  const HyperplaneFrame frame0(plane0);
  const auto [lo, hi] = scene_extent(scene, plane0.normal);
  const double extent = std::max(hi - lo, 1e-12);         // the reference depth D0
  const FrameSphere sphere = scene_frame(scene, frame0);  // (y1, y2, y3) of the centre
  const float radius = std::max(sphere.radius, 1e-6f);
  const float s_centre = static_cast<float>(0.5 * (lo + hi));

  // The volume camera: orthographic, looking at (u, v, s) = (c1, c2, s_centre).
  RasterOptions ro = o.raster;
  ro.background = glm::vec4(0.0f);
  const float aspect = static_cast<float>(ro.width) / static_cast<float>(ro.height);
  const glm::vec3 volume_centre(sphere.centre.x, sphere.centre.y, s_centre);
  const Camera volume_cam = o.camera ? *o.camera
                                     : Camera::framing(volume_centre, radius, o.view_from, aspect,
                                                       Projection::Orthographic, 30.0f, 1.05f);
  const glm::mat4 volume_clip = volume_cam.projection_matrix(aspect) * volume_cam.view_matrix();
  const glm::vec3 dir = glm::normalize(volume_cam.eye - volume_cam.target);

  // The volume's axes in 4D: u = b1 . x, v = b2 . x, s = n . x; each layer picture shows the
  // surface seen along -b3 (the largest b3 . x). A stack along axis k cuts the scene with the
  // hyperplanes a_k . x = c: a point (u, v, s) of the volume is the same line {b3 varies} of
  // 4D whichever axis is stacked, so only the sampling changes with k.
  const int k = cloud_stack_axis(dir, o.stack_axis);
  const Eigen::Vector4d b1 = frame0.basis.col(0), b2 = frame0.basis.col(1),
                        b3 = frame0.basis.col(2), n = plane0.normal;
  const Eigen::Vector4d axis = k == 0 ? b1 : k == 1 ? b2 : n;
  const auto [klo, khi] = scene_extent(scene, axis);
  const double spacing = std::max(khi - klo, 1e-12) / o.layers;
  // Light crossing one layer at angle theta to its normal travels spacing / cos(theta); the
  // stack axis is the one most aligned with the view, so cos(theta) >= 1/sqrt(3) unless fixed.
  const double cos_theta = std::max(0.2, static_cast<double>(std::abs(dir[k])));
  const double path = spacing / cos_theta;

  // Light: the studio rig of a camera looking along -b3 at the layer, lifted to 4D, each face
  // lit by its cell's 4D normal, so every stack axis shades a point alike.
  Camera layer_cam;
  layer_cam.eye = sphere.centre + glm::vec3(0.0f, 0.0f, 4.0f * radius);
  layer_cam.target = sphere.centre;
  layer_cam.up = glm::vec3(0.0f, 1.0f, 0.0f);
  const Lighting studio = Lighting::studio(layer_cam);
  Lighting lighting = studio;
  lighting.lights.clear();
  lighting.four_d = true;
  for (const Light& l : studio.lights) {
    if (l.kind != Light::Kind::Directional) continue;
    const Eigen::Vector4d d = frame0.basis * Eigen::Vector3d(l.vector.x, l.vector.y, l.vector.z);
    Light4 l4;
    l4.vector = glm::vec4(static_cast<float>(d(0)), static_cast<float>(d(1)),
                          static_cast<float>(d(2)), static_cast<float>(d(3)));
    l4.color = l.color;
    lighting.lights4.push_back(l4);
  }

  std::vector<double> offsets = layer_offsets(klo, khi, o.layers);
  // Back to front: the viewer sits at +dir; layers with smaller c * dir[k] are farther.
  if (dir[k] < 0.0f) std::reverse(offsets.begin(), offsets.end());

  Image acc(ro.width, ro.height);
  for (double c : offsets) {
    const Hyperplane plane = Hyperplane::from(axis, c);
    Section section = section_scene(scene, plane);
    if (section.empty()) continue;
    if (o.cell_palette) {
      auto& colors = section.complex.colors_mut(2);
      for (std::size_t f = 0; f < colors.size() && f < section.source[2].size(); ++f) {
        const glm::vec3 pc = palette_color(section.source[2][f]);
        colors[f] = {linear_to_srgb(pc.r), linear_to_srgb(pc.g), linear_to_srgb(pc.b), colors[f].a};
      }
    }
    TriangleMesh mesh = section_mesh(section, nullptr, scene, nullptr);
    for (auto& v : mesh.vertices)
      v.color.a = corrected_opacity(v.color.a * o.opacity, path, extent);
    // Section coordinates y -> world x = origin + B y -> (u, v, s, depth = b3 . x).
    const HyperplaneFrame& f = section.frame;
    const Eigen::Vector4d origin = f.origin();
    Eigen::Matrix4d to_volume = Eigen::Matrix4d::Zero();  // rows u, v, s, depth
    const Eigen::Vector4d rows[4] = {b1, b2, n, b3};
    for (int r = 0; r < 4; ++r) {
      to_volume.block<1, 3>(r, 0) = rows[r].transpose() * f.basis;
      to_volume(r, 3) = rows[r].dot(origin);
    }
    glm::mat4 place(0.0f);  // column-major: place[col][row]; (u, v, s, 1)
    for (int col = 0; col < 4; ++col)
      for (int r = 0; r < 3; ++r) place[col][r] = static_cast<float>(to_volume(r, col));
    place[3][3] = 1.0f;
    glm::mat4 clip = volume_clip * place;
    // Replace the depth row: z_clip = -(depth - c3) / r (w stays 1: orthographic).
    const float zs = -1.0f / (1.02f * radius);
    for (int col = 0; col < 4; ++col) clip[col][2] = zs * static_cast<float>(to_volume(3, col));
    clip[3][2] += sphere.centre.z / (1.02f * radius);
    View view;
    view.clip_from_world = clip;
    // Forward (section coordinates): -b3 expressed in the layer's frame (b3 lies in it).
    const Eigen::Vector3d fwd = -(f.basis.transpose() * b3);
    view.forward = glm::vec3(static_cast<float>(fwd(0)), static_cast<float>(fwd(1)),
                             static_cast<float>(fwd(2)));
    view.orthographic = true;
    lighting.origin4 = glm::vec4(static_cast<float>(origin(0)), static_cast<float>(origin(1)),
                                 static_cast<float>(origin(2)), static_cast<float>(origin(3)));
    for (int col = 0; col < 3; ++col)
      for (int r = 0; r < 4; ++r) lighting.basis4[col][r] = static_cast<float>(f.basis(r, col));
    Rasterizer r(ro);
    r.draw(mesh, view, lighting);
    acc.composite_over(r.render());
  }
  if (o.flatten) acc.flatten(o.background);
  return acc;
}

Image render_cloud_stereo_pair(const Scene& scene, const Eigen::VectorXd& normal,
                               const CloudOptions& o, float angle_degrees) {
  // Two orthographic views of the volume turned by -/+ angle/2 about the camera's up axis
  // (parallel projection has no eye offset, only a change of direction).
  if (scene.dim() != 4) throw InputError("voxel clouds need a 4D scene");
  const Hyperplane plane0 = Hyperplane::from(normal, 0.0);
  const auto [lo, hi] = scene_extent(scene, plane0.normal);
  const FrameSphere sphere = scene_frame(scene, HyperplaneFrame(plane0));
  const float aspect = static_cast<float>(o.raster.width) / static_cast<float>(o.raster.height);
  const glm::vec3 centre(sphere.centre.x, sphere.centre.y, static_cast<float>(0.5 * (lo + hi)));
  const Camera mid = Camera::framing(centre, std::max(sphere.radius, 1e-6f), o.view_from, aspect,
                                     Projection::Orthographic, 30.0f, 1.05f);
  const glm::vec3 up = glm::normalize(glm::cross(mid.right(), mid.forward()));
  Image pair(2 * o.raster.width, o.raster.height, glm::vec4(o.background, 1.0f));
  for (int side = 0; side < 2; ++side) {
    const float a = glm::radians((side == 0 ? -0.5f : 0.5f) * angle_degrees);
    const glm::mat4 turn = glm::rotate(glm::mat4(1.0f), a, up);
    Camera cam = mid;
    cam.eye = mid.target + glm::vec3(turn * glm::vec4(mid.eye - mid.target, 0.0f));
    cam.up = up;
    CloudOptions one = o;
    one.camera = &cam;
    one.flatten = true;
    pair.blit(render_voxel_cloud(scene, normal, one), side * o.raster.width, 0);
  }
  return pair;
}

}  // namespace cw4d::render
