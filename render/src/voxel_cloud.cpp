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

Image render_voxel_cloud(const Scene& scene, const Eigen::VectorXd& normal, const CloudOptions& o) {
  if (scene.dim() != 4) throw InputError("voxel clouds need a 4D scene");
  if (o.layers < 1 || o.layers > 4096)
    throw InputError("the layer count must be 1..4096, not " + std::to_string(o.layers));
  const Hyperplane plane0 = Hyperplane::from(normal, 0.0);
  const HyperplaneFrame frame0(plane0);
  const auto [lo, hi] = scene_extent(scene, plane0.normal);
  const double extent = std::max(hi - lo, 1e-12);
  const double spacing = extent / o.layers;
  const FrameSphere sphere = scene_frame(scene, frame0);  // (y1, y2, y3) of the centre
  const float radius = std::max(sphere.radius, 1e-6f);
  const float s_centre = static_cast<float>(0.5 * (lo + hi));

  // The volume camera: orthographic, looking at (u, v, s) = (c1, c2, s_centre).
  RasterOptions ro = o.raster;
  ro.background = glm::vec4(0.0f);
  const float aspect = static_cast<float>(ro.width) / static_cast<float>(ro.height);
  const glm::vec3 volume_centre(sphere.centre.x, sphere.centre.y, s_centre);
  const Camera volume_cam = Camera::framing(volume_centre, radius, o.view_from, aspect,
                                            Projection::Orthographic, 30.0f, 1.05f);
  const glm::mat4 volume_clip = volume_cam.projection_matrix(aspect) * volume_cam.view_matrix();
  const glm::vec3 dir = glm::normalize(o.view_from);
  const double cos_theta = std::max(0.2, static_cast<double>(std::abs(dir.z)));
  const double path = spacing / cos_theta;

  // Within a layer: seen along -y3 from +y3; depth row maps y3 in [c3 - r, c3 + r] to clip z
  // in [1, -1] (larger y3 nearer).
  const glm::vec3 layer_forward(0.0f, 0.0f, -1.0f);
  Camera layer_cam;
  layer_cam.eye = sphere.centre + glm::vec3(0.0f, 0.0f, 4.0f * radius);
  layer_cam.target = sphere.centre;
  layer_cam.up = glm::vec3(0.0f, 1.0f, 0.0f);
  const Lighting lighting = Lighting::studio(layer_cam);

  std::vector<double> offsets = layer_offsets(lo, hi, o.layers);
  // Back to front: the viewer sits at +dir; layers with smaller s * dir.z are farther.
  if (dir.z < 0.0f) std::reverse(offsets.begin(), offsets.end());

  Image acc(ro.width, ro.height);
  for (double s : offsets) {
    Section section = section_scene(scene, Hyperplane::from(normal, s));
    if (section.empty()) continue;
    if (o.cell_palette) {
      auto& colors = section.complex.colors_mut(2);
      for (std::size_t f = 0; f < colors.size() && f < section.source[2].size(); ++f) {
        const glm::vec3 c = palette_color(section.source[2][f]);
        colors[f] = {linear_to_srgb(c.r), linear_to_srgb(c.g), linear_to_srgb(c.b), colors[f].a};
      }
    }
    TriangleMesh mesh = section_mesh(section);
    for (auto& v : mesh.vertices)
      v.color.a = corrected_opacity(v.color.a * o.opacity, path, extent);
    // Section coordinates y -> volume (u, v, s) = (y1, y2, s) for x and y, depth from y3.
    glm::mat4 place(0.0f);  // column-major: place[col][row]
    place[0][0] = 1.0f;
    place[1][1] = 1.0f;
    place[3][2] = static_cast<float>(s);
    place[3][3] = 1.0f;
    glm::mat4 clip = volume_clip * place;
    // Replace the depth row: z_clip = -(y3 - c3) / r (w stays 1: orthographic).
    for (int col = 0; col < 4; ++col) clip[col][2] = 0.0f;
    clip[2][2] = -1.0f / (1.02f * radius);
    clip[3][2] = sphere.centre.z / (1.02f * radius);
    View view;
    view.clip_from_world = clip;
    view.forward = layer_forward;
    view.orthographic = true;
    Rasterizer r(ro);
    r.draw(mesh, view, lighting);
    acc.composite_over(r.render());
  }
  if (o.flatten) acc.flatten(o.background);
  return acc;
}

}  // namespace cw4d::render
