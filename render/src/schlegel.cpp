// Schlegel diagrams of 4D polytopes (see schlegel.hpp).
#include "cw4d/render/schlegel.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/render/color.hpp"

namespace cw4d::render {

namespace {

glm::vec3 to_glm(const Eigen::Vector3d& v) {
  return glm::vec3(static_cast<float>(v.x()), static_cast<float>(v.y()), static_cast<float>(v.z()));
}

// An orthonormal basis of the hyperplane orthogonal to the unit vector n, with det(n, B) > 0.
Eigen::Matrix<double, 4, 3> complement_basis(const Eigen::Vector4d& n) {
  const Eigen::MatrixXd column = n;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(column);
  const Eigen::Matrix4d Q = qr.householderQ() * Eigen::Matrix4d::Identity();
  Eigen::Matrix<double, 4, 3> B = Q.rightCols(3);
  Eigen::Matrix4d F;
  F.col(0) = n;
  F.rightCols(3) = B;
  if (F.determinant() < 0.0) B.col(2) *= -1.0;
  return B;
}

}  // namespace

Eigen::Vector3d SchlegelProjection::project(const Eigen::Vector4d& x) const {
  const double a = normal.dot(x - centre);
  const double s = (eye_height - cell_height) / (eye_height - a);
  const Eigen::Vector4d e = eye();
  return basis.transpose() * (e + s * (x - e) - centre);
}

SchlegelProjection schlegel_projection(const Complex& model, long long cell) {
  if (model.ambient_dim() != 4 || model.top_rank() < 3 || model.count(3) == 0)
    throw InputError("Schlegel diagrams need a closed 4D model with cells");
  const auto nc = static_cast<std::uint32_t>(model.count(3));
  if (cell < -1 || cell >= static_cast<long long>(nc))
    throw InputError("--cell " + std::to_string(cell) + ": the model has cells 0.." +
                     std::to_string(nc - 1));
  const auto& p = model.positions();
  SchlegelProjection v;
  v.centre = p.rowwise().mean();
  const double scale = position_scale(model);
  std::vector<Eigen::Vector4d> normals(nc);
  std::vector<double> heights(nc, -std::numeric_limits<double>::infinity());
  for (std::uint32_t c = 0; c < nc; ++c) {
    const Eigen::VectorXd a = facet_area_vector(model, c, scale);
    normals[c] = a.norm() > 0.0 ? Eigen::Vector4d(a.normalized()) : Eigen::Vector4d::Zero();
    for (const auto u : model.vertices_of(3, c))
      heights[c] = std::max(heights[c], normals[c].dot(p.col(u) - v.centre));
  }
  if (cell >= 0) {
    v.cell = static_cast<std::uint32_t>(cell);
  } else {
    for (std::uint32_t c = 1; c < nc; ++c)
      if (normals[c](3) > normals[v.cell](3) + 1e-12) v.cell = c;
  }
  v.normal = normals[v.cell];
  if (v.normal.norm() == 0.0)
    throw InputError("cell " + std::to_string(v.cell) + " is degenerate (no normal)");
  v.basis = complement_basis(v.normal);
  double top = 0.0;
  for (Eigen::Index i = 0; i < p.cols(); ++i)
    top = std::max(top, v.normal.dot(p.col(i) - v.centre));
  v.cell_height = heights[v.cell];
  if (!(top > 0.0))
    throw InputError("cell " + std::to_string(v.cell) + " does not face away from the centre");
  // The eye sees cell j from outside once h (n_j . N) > d_j: stay below the lowest such h.
  double upper = 2.0 * top;
  for (std::uint32_t c = 0; c < nc; ++c) {
    if (c == v.cell || !(heights[c] > 0.0)) continue;
    const double cosine = normals[c].dot(v.normal);
    if (cosine > 1e-12) upper = std::min(upper, heights[c] / cosine);
  }
  v.eye_height = upper > top ? top + 0.5 * (upper - top) : 1.25 * top;
  return v;
}

std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> schlegel_edges(
    const Complex& model, const SchlegelProjection& projection) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> out;
  out.reserve(model.count(1));
  for (std::uint32_t e = 0; e < model.count(1); ++e) {
    const auto [t, h] = model.edge(e);
    out.push_back({projection.project(model.position(t)), projection.project(model.position(h))});
  }
  return out;
}

Camera schlegel_camera(const Complex& model, const SchlegelProjection& projection,
                       const SchlegelOptions& options) {
  // The front cell's image holds the whole diagram (for a convex model); frame every vertex
  // anyway.
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  std::vector<Eigen::Vector3d> points;
  for (Eigen::Index i = 0; i < model.positions().cols(); ++i) {
    points.push_back(projection.project(model.positions().col(i)));
    lo = lo.cwiseMin(points.back());
    hi = hi.cwiseMax(points.back());
  }
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  double radius = 0.0;
  for (const auto& q : points) radius = std::max(radius, (q - centre).norm());
  const float aspect = static_cast<float>(options.raster.width) / options.raster.height;
  return Camera::framing(to_glm(centre), static_cast<float>(std::max(radius, 1e-30)),
                         options.view_from, aspect, options.projection, 30.0f, 1.04f,
                         glm::vec3(0, 1, 0));
}

Image render_schlegel(const Complex& model, const SchlegelProjection& projection,
                      const SchlegelOptions& o) {
  if (model.ambient_dim() != 4) throw InputError("Schlegel diagrams need a 4D model");
  RasterOptions ro = o.raster;
  ro.background = glm::vec4(0.0f);
  Rasterizer r(ro);
  const Camera cam = schlegel_camera(model, projection, o);
  const View view = cam.view(r.aspect());
  const auto& p = model.positions();
  // Depth cue by the 4D distance from the eye.
  const Eigen::Vector4d eye = projection.eye();
  double near = std::numeric_limits<double>::infinity(), far = -near;
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    const double d = (Eigen::Vector4d(p.col(i)) - eye).norm();
    near = std::min(near, d);
    far = std::max(far, d);
  }
  auto cue = [&](std::uint32_t vertex) {
    const double d = (Eigen::Vector4d(p.col(vertex)) - eye).norm();
    const double t = far > near ? (d - near) / (far - near) : 0.5;
    return glm::vec4(depth_cue_color(static_cast<float>(t)), 1.0f);
  };
  std::vector<LineSegment> lines;
  for (std::uint32_t e = 0; e < model.count(1); ++e) {
    const auto [t, h] = model.edge(e);
    lines.push_back({to_glm(projection.project(p.col(t))), to_glm(projection.project(p.col(h))),
                     cue(t), cue(h)});
  }
  DrawOptions d;
  d.line_width = o.line_width;
  r.draw_lines(lines, view, d);
  if (o.faces && model.top_rank() >= 2) {
    // Each face fan-triangulated, colored by the palette hue of its first cell.
    std::vector<std::uint32_t> cell_of_face(model.count(2), 0);
    if (model.top_rank() >= 3)
      for (std::uint32_t c = model.count(3); c-- > 0;)
        for (const auto f : model.boundary(3).ids(c)) cell_of_face[f] = c;
    TriangleMesh mesh;
    for (std::uint32_t f = 0; f < model.count(2); ++f) {
      const auto cyc = model.face_cycle(f);
      const glm::vec4 color(palette_color(cell_of_face[f]), o.face_opacity);
      const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
      for (const auto u : cyc)
        mesh.vertices.push_back({to_glm(projection.project(p.col(u))), glm::vec3(0.0f), color});
      for (std::uint32_t k = 1; k + 1 < cyc.size(); ++k)
        mesh.triangles.push_back({base, base + k, base + k + 1});
    }
    DrawOptions fd;
    fd.shading = Shading::Unlit;
    fd.blend = Blend::Over;
    r.draw(mesh, view, Lighting{}, fd);
  }
  Image img = r.render();
  img.flatten(o.background);
  return img;
}

}  // namespace cw4d::render
