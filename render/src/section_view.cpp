#include "cw4d/render/section_view.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "cw4d/complex/error.hpp"
#include "cw4d/render/color.hpp"

namespace cw4d::render {

namespace {

glm::vec3 to_glm(const Eigen::Ref<const Eigen::VectorXd>& v) {
  return {static_cast<float>(v(0)), static_cast<float>(v(1)), static_cast<float>(v(2))};
}

void require_3d(const Section& section) {
  if (section.complex.ambient_dim() != 3)
    throw InputError("section pictures need a 3D section; this one lives in R^" +
                     std::to_string(section.complex.ambient_dim()));
}

// Positions of every object of a scene, placed in the world (one matrix per object).
template <class F>
void for_each_world_vertex_block(const Scene& scene, F&& f) {
  for (const SceneObject& obj : scene.objects) {
    const Eigen::MatrixXd world =
        (obj.transform.linear() * obj.complex->positions()).colwise() + obj.transform.translation();
    f(world);
  }
}

}  // namespace

TriangleMesh section_mesh(const Section& section, const Complex* model) {
  require_3d(section);
  const Complex& c = section.complex;
  TriangleMesh mesh;
  if (c.empty() || c.top_rank() < 2) return mesh;
  const std::size_t nf = c.count(2);
  const auto& face_colors = c.colors(2);
  const bool have_face_colors = face_colors.size() == nf;
  const bool have_source = section.source.size() > 2 && section.source[2].size() == nf;
  const bool have_cell_colors =
      model && have_source && model->colors(3).size() == model->count(3) && model->count(3) > 0;
  for (std::uint32_t f = 0; f < nf; ++f) {
    const auto cycle = c.face_cycle(f);
    if (cycle.size() < 3) continue;
    glm::vec3 normal(0.0f);
    if (c.has_facet_normals()) normal = to_glm(c.facet_normals().col(f));
    if (!(glm::dot(normal, normal) > 0.0f)) {  // Newell's normal of the polygon
      for (std::size_t i = 0; i < cycle.size(); ++i) {
        const glm::vec3 a = to_glm(c.position(cycle[i]));
        const glm::vec3 b = to_glm(c.position(cycle[(i + 1) % cycle.size()]));
        normal += glm::vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x),
                            (a.x - b.x) * (a.y + b.y));
      }
    }
    glm::vec4 color;
    if (have_face_colors) {
      color = to_linear(face_colors[f]);
    } else if (have_cell_colors) {
      color = to_linear(model->colors(3)[section.source[2][f]]);
    } else {
      color = glm::vec4(palette_color(have_source ? section.source[2][f] : f), 1.0f);
    }
    const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
    for (auto v : cycle) mesh.vertices.push_back({to_glm(c.position(v)), normal, color});
    for (std::uint32_t k = 1; k + 1 < cycle.size(); ++k)
      mesh.triangles.push_back({first, first + k, first + k + 1});
  }
  return mesh;
}

std::vector<LineSegment> section_edges(const Section& section, glm::vec4 color) {
  require_3d(section);
  std::vector<LineSegment> lines;
  const Complex& c = section.complex;
  if (c.top_rank() < 1) return lines;
  lines.reserve(c.count(1));
  for (std::uint32_t e = 0; e < c.count(1); ++e) {
    const auto [a, b] = c.edge(e);
    lines.push_back({to_glm(c.position(a)), to_glm(c.position(b)), color, color});
  }
  return lines;
}

FrameSphere bounding_frame(const Section& section) {
  require_3d(section);
  FrameSphere s;
  const auto& p = section.complex.positions();
  if (p.cols() == 0) return s;
  const Eigen::Vector3d centre = 0.5 * (p.rowwise().minCoeff() + p.rowwise().maxCoeff());
  s.centre = to_glm(centre);
  s.radius = static_cast<float>((p.colwise() - centre).colwise().norm().maxCoeff());
  return s;
}

FrameSphere scene_frame(const Scene& scene, const HyperplaneFrame& frame) {
  FrameSphere s;
  if (scene.objects.empty()) return s;
  const int dim = scene.dim();
  Eigen::VectorXd lo = Eigen::VectorXd::Constant(dim, std::numeric_limits<double>::infinity());
  Eigen::VectorXd hi = -lo;
  for_each_world_vertex_block(scene, [&](const Eigen::MatrixXd& w) {
    if (w.cols() == 0) return;
    lo = lo.cwiseMin(w.rowwise().minCoeff());
    hi = hi.cwiseMax(w.rowwise().maxCoeff());
  });
  if (!lo.allFinite()) return s;
  const Eigen::VectorXd centre = 0.5 * (lo + hi);
  double radius = 0.0;
  for_each_world_vertex_block(scene, [&](const Eigen::MatrixXd& w) {
    if (w.cols() > 0) radius = std::max(radius, (w.colwise() - centre).colwise().norm().maxCoeff());
  });
  const Eigen::VectorXd y = frame.basis.transpose() * centre;  // basis is orthogonal to n
  s.centre = to_glm(y);
  s.radius = static_cast<float>(radius);
  return s;
}

std::pair<double, double> scene_extent(const Scene& scene, const Eigen::VectorXd& n) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for_each_world_vertex_block(scene, [&](const Eigen::MatrixXd& w) {
    if (w.cols() == 0) return;
    const Eigen::RowVectorXd h = n.transpose() * w;
    lo = std::min(lo, h.minCoeff());
    hi = std::max(hi, h.maxCoeff());
  });
  return {lo, hi};
}

std::vector<double> layer_offsets(double lo, double hi, int n) {
  std::vector<double> out;
  for (int i = 0; i < n; ++i) out.push_back(lo + (hi - lo) * (i + 0.5) / n);
  return out;
}

Camera section_camera(const Section& section, const SectionViewOptions& o) {
  FrameSphere f = o.frame.radius > 0.0f ? o.frame : bounding_frame(section);
  if (!(f.radius > 0.0f)) f.radius = 1.0f;
  const float aspect = static_cast<float>(o.raster.width) / static_cast<float>(o.raster.height);
  return Camera::framing(f.centre, f.radius, o.view_from, aspect, o.projection, o.fov_y_degrees);
}

Image render_section(const Section& section, const SectionViewOptions& o, const Camera& camera,
                     const Complex* model, bool flatten) {
  RasterOptions ro = o.raster;
  ro.background = glm::vec4(0.0f);
  Rasterizer r(ro);
  const View view = camera.view(r.aspect());
  const Lighting lighting = Lighting::studio(camera);
  const TriangleMesh mesh = section_mesh(section, model);
  // Opaque faces first with depth writes, then translucent ones blended back to front.
  TriangleMesh opaque, translucent;
  opaque.vertices = translucent.vertices = mesh.vertices;
  for (const auto& t : mesh.triangles)
    (mesh.vertices[t[0]].color.a >= 1.0f ? opaque : translucent).triangles.push_back(t);
  DrawOptions d;
  d.cull_back_faces = o.cull_back_faces;
  if (!opaque.triangles.empty()) r.draw(opaque, view, lighting, d);
  if (o.edges) {
    DrawOptions e;
    e.shading = Shading::Unlit;
    e.line_width = o.edge_width;
    const float dist = glm::length(camera.eye - camera.target);
    e.pull_toward_viewer =
        2e-3f * (camera.projection == Projection::Orthographic ? camera.ortho_height : dist);
    r.draw_lines(section_edges(section, o.edge_color), view, e);
  }
  if (!translucent.triangles.empty()) {
    d.blend = Blend::Over;
    r.draw(translucent, view, lighting, d);
  }
  Image img = r.render();
  if (flatten) img.flatten(o.background);
  return img;
}

Image render_section(const Section& section, const SectionViewOptions& options,
                     const Complex* model) {
  return render_section(section, options, section_camera(section, options), model);
}

Image render_stereo_pair(const Section& section, const SectionViewOptions& o, float separation,
                         const Complex* model) {
  const Camera centre = section_camera(section, o);
  if (!(separation > 0.0f)) {
    const FrameSphere f = o.frame.radius > 0.0f ? o.frame : bounding_frame(section);
    separation = 0.06f * 2.0f * std::max(f.radius, 1e-6f);
  }
  // The eyes move inside the hyperplane: the section is the same for both, only the camera
  // shifts ([wxyhly 2024], 裸眼3D: cut first, then offset within the cut).
  const glm::vec3 shift = 0.5f * separation * centre.right();
  Camera left = centre, right = centre;
  left.eye -= shift;
  left.target -= shift;
  right.eye += shift;
  right.target += shift;
  const Image l = render_section(section, o, left, model);
  const Image r = render_section(section, o, right, model);
  Image pair(2 * l.width, l.height, glm::vec4(o.background, 1.0f));
  pair.blit(l, 0, 0);
  pair.blit(r, l.width, 0);
  return pair;
}

Image contact_sheet(const std::vector<Image>& cells, int columns, int gap, glm::vec3 gap_color) {
  if (cells.empty()) throw InputError("a contact sheet needs at least one image");
  const int w = cells.front().width, h = cells.front().height;
  for (const auto& c : cells)
    if (c.width != w || c.height != h) throw InputError("contact sheet images differ in size");
  const int n = static_cast<int>(cells.size());
  if (columns <= 0) columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  columns = std::min(columns, n);
  gap = std::max(gap, 0);
  const int rows = (n + columns - 1) / columns;
  Image sheet(columns * w + (columns + 1) * gap, rows * h + (rows + 1) * gap,
              glm::vec4(gap_color, 1.0f));
  for (int i = 0; i < n; ++i)
    sheet.blit(cells[i], gap + (i % columns) * (w + gap), gap + (i / columns) * (h + gap));
  return sheet;
}

}  // namespace cw4d::render
