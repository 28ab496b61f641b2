#include "cw4d/render/section_view.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "cw4d/complex/error.hpp"
#include "cw4d/render/color.hpp"
#include "cw4d/section/provenance.hpp"
#include "cw4d/section/uvw.hpp"

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

// The world-space unit outward normal of 3-cell `cell` of a placed model: the model's facet
// normal through the inverse transpose of the placement.
glm::vec4 world_normal4(const SceneObject& obj, std::uint32_t cell) {
  const Complex& m = *obj.complex;
  if (!m.has_facet_normals() || cell >= m.facet_normals().cols() || m.ambient_dim() != 4)
    return glm::vec4(0.0f);
  const Eigen::VectorXd n =
      obj.transform.linear().inverse().transpose() * m.facet_normals().col(cell);
  const double len = n.norm();
  if (!(len > 0.0)) return glm::vec4(0.0f);
  return {static_cast<float>(n(0) / len), static_cast<float>(n(1) / len),
          static_cast<float>(n(2) / len), static_cast<float>(n(3) / len)};
}

glm::vec4 cell_color(const Complex* model, std::uint32_t cell) {
  if (model && model->colors(3).size() == model->count(3) && cell < model->count(3))
    return to_linear(model->colors(3)[cell]);
  return glm::vec4(palette_color(cell), 1.0f);
}

}  // namespace

TriangleMesh section_mesh(const Section& section, const Complex* model, const Scene& source,
                          const TextureAssignment* textures) {
  TriangleMesh mesh = section_mesh(section, model);
  const Complex& c = section.complex;
  if (mesh.vertices.empty()) return mesh;
  const std::size_t nf = c.count(2);
  if (section.source.size() <= 2 || section.source[2].size() != nf)
    throw InputError("4D light and textures need the section's provenance (cut it with section())");
  const bool per_object = section.object_of_face.size() == nf;
  std::vector<const Complex*> models;
  for (const auto& o : source.objects) models.push_back(o.complex.get());
  if (models.empty())
    throw InputError("4D light and textures need the scene the section came from");
  // The cell ids index the objects' models (normals, textures): they must be theirs.
  check_provenance(section, models);
  const bool textured = textures && !textures->empty();
  CornerUvw uvw;
  if (textured) uvw = section_uvw(section, models);
  // section_mesh emits, for every face with >= 3 corners in order, one vertex per corner.
  std::size_t v = 0;
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::size_t corners = c.face_cycle(f).size();
    if (corners < 3) continue;
    const std::uint32_t object = per_object ? section.object_of_face[f] : 0u;
    if (object >= source.objects.size())
      throw InputError("section face from scene object " + std::to_string(object) +
                       ", which the scene lacks");
    const std::uint32_t cell = section.source[2][f];
    const glm::vec4 n4 = world_normal4(source.objects[object], cell);
    const Texture3D* tex = textured ? textures->find(object, cell) : nullptr;
    for (std::size_t j = 0; j < corners; ++j, ++v) {
      Vertex& vert = mesh.vertices[v];
      vert.normal4 = n4;
      if (tex) {
        const auto col = uvw.uvw.col(uvw.offset[f] + j);
        vert.uvw = glm::vec3(col(0), col(1), col(2));
        vert.texture = tex;
      }
    }
  }
  return mesh;
}

TriangleMesh soup_mesh(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& normals,
                       const Eigen::Matrix3Xd& uvw, const std::vector<std::uint32_t>& cell,
                       const SceneObject& object, const TextureAssignment* textures) {
  const std::size_t nt = cell.size();
  if (positions.cols() != static_cast<Eigen::Index>(3 * nt) || normals.cols() != positions.cols() ||
      uvw.cols() != positions.cols())
    throw InputError("triangle soup: positions, normals and uvw need 3 columns per triangle");
  TriangleMesh mesh;
  mesh.vertices.reserve(3 * nt);
  mesh.triangles.reserve(nt);
  const bool textured = textures && !textures->empty();
  for (std::size_t i = 0; i < nt; ++i) {
    const glm::vec4 color = cell_color(object.complex.get(), cell[i]);
    const glm::vec4 n4 = world_normal4(object, cell[i]);
    const Texture3D* tex = textured ? textures->find(0, cell[i]) : nullptr;
    const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
    for (int k = 0; k < 3; ++k) {
      const Eigen::Index col = static_cast<Eigen::Index>(3 * i + k);
      Vertex v{to_glm(positions.col(col)), to_glm(normals.col(col)), color};
      v.normal4 = n4;
      if (tex) {
        v.uvw = to_glm(uvw.col(col));
        v.texture = tex;
      }
      mesh.vertices.push_back(v);
    }
    mesh.triangles.push_back({first, first + 1, first + 2});
  }
  return mesh;
}

TriangleMesh section_mesh(const Section& section, const Complex* model) {
  require_3d(section);
  const Complex& c = section.complex;
  TriangleMesh mesh;
  if (c.empty() || c.top_rank() < 2) return mesh;
  const std::size_t nf = c.count(2);
  const auto& face_colors = c.colors(2);
  const bool have_face_colors = face_colors.size() == nf;
  const bool have_source = section.source.size() > 2 && section.source[2].size() == nf;
  // The cell ids index the model's colors: refuse a model the section was not cut from.
  if (model) check_provenance(section, *model);
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

FrameSphere bounding_frame(const TriangleMesh& mesh) {
  FrameSphere s;
  if (mesh.vertices.empty()) return s;
  glm::vec3 lo = mesh.vertices.front().position, hi = lo;
  for (const auto& v : mesh.vertices) {
    lo = glm::min(lo, v.position);
    hi = glm::max(hi, v.position);
  }
  s.centre = 0.5f * (lo + hi);
  for (const auto& v : mesh.vertices)
    s.radius = std::max(s.radius, glm::length(v.position - s.centre));
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

std::vector<Light4> default_lights4(const Camera& camera, const HyperplaneFrame& frame) {
  const Lighting studio = Lighting::studio(camera);
  const Eigen::VectorXd& n = frame.plane.normal;
  std::vector<Light4> out;
  const double tilt = 40.0 * std::numbers::pi / 180.0;
  for (std::size_t i = 0; i < 2 && i < studio.lights.size(); ++i) {
    const glm::vec3 l = studio.lights[i].vector;
    const Eigen::VectorXd in_plane = frame.basis * Eigen::Vector3d(l.x, l.y, l.z);
    const Eigen::VectorXd d =
        std::cos(tilt) * in_plane.normalized() + (i == 0 ? 1.0 : -1.0) * std::sin(tilt) * n;
    Light4 light;
    light.vector = {static_cast<float>(d(0)), static_cast<float>(d(1)), static_cast<float>(d(2)),
                    static_cast<float>(d(3))};
    light.color = studio.lights[i].color;
    out.push_back(light);
  }
  return out;
}

Lighting section_lighting(const Camera& camera, const HyperplaneFrame& frame,
                          const SectionViewOptions& o) {
  Lighting lighting = Lighting::studio(camera);
  if (!o.light_4d) return lighting;
  if (frame.basis.rows() != 4 || frame.basis.cols() != 3)
    throw InputError("4D light needs the section of a 4D model");
  lighting.four_d = true;
  lighting.lights.clear();
  lighting.lights4 = o.lights4.empty() ? default_lights4(camera, frame) : o.lights4;
  const Eigen::VectorXd origin = frame.origin();
  lighting.origin4 = {static_cast<float>(origin(0)), static_cast<float>(origin(1)),
                      static_cast<float>(origin(2)), static_cast<float>(origin(3))};
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 4; ++r) lighting.basis4[c][r] = static_cast<float>(frame.basis(r, c));
  return lighting;
}

Image render_mesh(const TriangleMesh& mesh, const std::vector<LineSegment>& edges,
                  const HyperplaneFrame& frame, const SectionViewOptions& o, const Camera& camera,
                  bool flatten) {
  RasterOptions ro = o.raster;
  ro.background = glm::vec4(0.0f);
  Rasterizer r(ro);
  const View view = camera.view(r.aspect());
  const Lighting lighting = section_lighting(camera, frame, o);
  // Opaque faces first with depth writes, then translucent ones blended back to front.
  TriangleMesh opaque, translucent;
  opaque.vertices = translucent.vertices = mesh.vertices;
  for (const auto& t : mesh.triangles)
    (mesh.vertices[t[0]].color.a >= 1.0f ? opaque : translucent).triangles.push_back(t);
  DrawOptions d;
  d.cull_back_faces = o.cull_back_faces;
  if (!opaque.triangles.empty()) r.draw(opaque, view, lighting, d);
  if (o.edges && !edges.empty()) {
    DrawOptions e;
    e.shading = Shading::Unlit;
    e.line_width = o.edge_width;
    const float dist = glm::length(camera.eye - camera.target);
    e.pull_toward_viewer =
        2e-3f * (camera.projection == Projection::Orthographic ? camera.ortho_height : dist);
    r.draw_lines(edges, view, e);
  }
  if (!translucent.triangles.empty()) {
    d.blend = Blend::Over;
    r.draw(translucent, view, lighting, d);
  }
  Image img = r.render();
  if (flatten) img.flatten(o.background);
  return img;
}

Image render_section(const Section& section, const SectionViewOptions& o, const Camera& camera,
                     const Complex* model, bool flatten) {
  if (!o.source && (o.light_4d || !o.textures.empty()))
    throw InputError("4D light and textures need the scene the section was cut from (source)");
  const bool decorate = o.source && (o.light_4d || !o.textures.empty());
  const TriangleMesh mesh = decorate ? section_mesh(section, model, *o.source, &o.textures)
                                     : section_mesh(section, model);
  const std::vector<LineSegment> edges =
      o.edges ? section_edges(section, o.edge_color) : std::vector<LineSegment>{};
  return render_mesh(mesh, edges, section.frame, o, camera, flatten);
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
