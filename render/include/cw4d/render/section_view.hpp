#pragma once
// Pictures of 3D sections: shaded cell colors, an optional edge overlay, stereo pairs (the eye
// shifted inside the hyperplane, [wxyhly 2024] "裸眼3D"), and contact sheets of sweeps.
#include <Eigen/Core>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <vector>

#include "cw4d/complex/scene.hpp"
#include "cw4d/render/camera.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/raster.hpp"
#include "cw4d/render/texture.hpp"
#include "cw4d/section/section.hpp"

namespace cw4d::render {

/// A sphere in the section's 3D coordinates, used to frame the camera.
struct FrameSphere {
  glm::vec3 centre{0.0f};
  float radius = 0.0f;  ///< <= 0: not set
};

/// Mesh of a 3D section: every face fan-triangulated (faces are convex) with its own flat
/// normal (the projected facet normal, else the face's Newell normal) and color: the section's
/// face colors (complex.colors(2), set for scenes), else the model's 3-cell colors
/// (model->colors(3) through section.source), else a palette hue per source cell.
/// \throw InputError when the section is not 3-dimensional.
TriangleMesh section_mesh(const Section& section, const Complex* model = nullptr);

/// As section_mesh, decorated from `source`, the scene the section was cut from (a single
/// model's section: a scene of that one object): every vertex gets its face's 4D normal (the
/// source cell's outward normal placed in the world, unit), and every face with a texture in
/// `textures` its texture and each corner's UVW (section_uvw). `textures` must outlive the
/// mesh's rendering. 	hrow InputError as section_mesh and section_uvw.
TriangleMesh section_mesh(const Section& section, const Complex* model, const Scene& source,
                          const TextureAssignment* textures);

/// The mesh of a triangle soup cut from one placed model (the tetrahedral slicer's output):
/// triangle i has corners 3i..3i+2 of positions, normals (3D) and uvw, and came from 3-cell
/// cell[i] of object.complex; colors as section_mesh (the object's cell colors when the model
/// has them, else a palette hue per cell), normal4 and textures as the decorated section_mesh.
TriangleMesh soup_mesh(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& normals,
                       const Eigen::Matrix3Xd& uvw, const std::vector<std::uint32_t>& cell,
                       const SceneObject& object, const TextureAssignment* textures);

/// The section's edges as lines of one color (linear RGB, alpha).
std::vector<LineSegment> section_edges(const Section& section, glm::vec4 color);

/// The smallest-box-centred sphere around the section's vertices (radius 0 when empty).
FrameSphere bounding_frame(const Section& section);
/// A sphere around every object of a scene (its model's vertices, placed), expressed in the
/// coordinates of `frame`: one framing for every layer of a sweep.
FrameSphere scene_frame(const Scene& scene, const HyperplaneFrame& frame);

struct SectionViewOptions {
  RasterOptions raster;
  Projection projection = Projection::Perspective;
  float fov_y_degrees = 30.0f;
  /// Direction (section coordinates) the camera looks from, towards the frame's centre.
  glm::vec3 view_from{2.0f, 1.3f, 1.0f};
  /// What to frame; radius <= 0: the section's own bounds.
  FrameSphere frame;
  bool edges = false;
  glm::vec4 edge_color{0.015f, 0.015f, 0.02f, 1.0f};  ///< linear
  float edge_width = 1.5f;
  bool cull_back_faces = false;
  glm::vec3 background{1.0f};  ///< linear RGB
  /// The scene the section was cut from (a single model: the scene of that object). Needed
  /// for textures and 4D light; null: neither.
  const Scene* source = nullptr;
  TextureAssignment textures;
  /// false: lights in the section's 3D space (Lighting::studio); true: lights in 4D and each
  /// face lit by its cell's 4D normal, so turning the model in 4D changes the light.
  bool light_4d = false;
  /// The 4D lights (world space); empty: default_lights4 of the camera and hyperplane.
  std::vector<Light4> lights4;
};

/// The 4D counterpart of Lighting::studio: the studio's key and fill directions lifted into
/// the hyperplane and tilted 40 degrees out of it along +n (the key) and -n (the fill).
std::vector<Light4> default_lights4(const Camera& camera, const HyperplaneFrame& frame);

/// The lighting a section picture uses: studio(camera), in 4D when options.light_4d.
Lighting section_lighting(const Camera& camera, const HyperplaneFrame& frame,
                          const SectionViewOptions& options);

/// The smallest-box-centred sphere around a mesh's vertices.
FrameSphere bounding_frame(const TriangleMesh& mesh);

/// Draws a section mesh (and `edges`, when options.edges) as render_section does.
Image render_mesh(const TriangleMesh& mesh, const std::vector<LineSegment>& edges,
                  const HyperplaneFrame& frame, const SectionViewOptions& options,
                  const Camera& camera, bool flatten = true);

/// The camera a section picture uses (exposed for tests and stereo pairs).
Camera section_camera(const Section& section, const SectionViewOptions& options);

/// A shaded picture of a 3D section (opaque faces first, translucent ones blended back to front),
/// flattened onto the background. An empty section gives the bare background.
/// \throw InputError as section_mesh and Rasterizer.
Image render_section(const Section& section, const SectionViewOptions& options,
                     const Complex* model = nullptr);
/// As render_section with a given camera; with a transparent background when `flatten` is false.
Image render_section(const Section& section, const SectionViewOptions& options,
                     const Camera& camera, const Complex* model = nullptr, bool flatten = true);

/// Side-by-side stereo pair (left eye's view on the left, 2 * width wide): both eyes in the
/// section's hyperplane, shifted by -/+ separation/2 along the camera's right axis, looking in
/// the same direction. separation <= 0: 6% of the framed diameter.
Image render_stereo_pair(const Section& section, const SectionViewOptions& options,
                         float separation = 0.0f, const Complex* model = nullptr);

/// A grid of equally sized images, `columns` wide (<= 0: about square), separated by `gap`
/// pixels of `gap_color` (linear, opaque). \throw InputError when the images differ in size.
Image contact_sheet(const std::vector<Image>& cells, int columns = 0, int gap = 4,
                    glm::vec3 gap_color = glm::vec3(0.8f));

/// n offsets evenly spaced inside (lo, hi): the centres of n equal slabs.
std::vector<double> layer_offsets(double lo, double hi, int n);
/// The interval of n . x over every object of a scene (its placed vertices).
std::pair<double, double> scene_extent(const Scene& scene, const Eigen::VectorXd& unit_normal);

}  // namespace cw4d::render
