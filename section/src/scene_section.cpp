#include "cw4d/section/scene_section.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>
#include <unordered_map>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/tolerances.hpp"

namespace cw4d {

namespace {

struct Sphere {
  Eigen::VectorXd centre;
  double radius = 0.0;
};

// Centre of the bounding box and the farthest vertex from it (not the smallest sphere, but
// close and one pass).
Sphere bounding_sphere(const Complex& c) {
  const auto& p = c.positions();
  Sphere s;
  s.centre = Eigen::VectorXd::Zero(c.ambient_dim());
  if (p.cols() == 0) return s;
  s.centre = 0.5 * (p.rowwise().minCoeff() + p.rowwise().maxCoeff());
  s.radius = (p.colwise() - s.centre).colwise().norm().maxCoeff();
  return s;
}

// What section() returns when the plane misses the model.
Section empty_section(int dim, const Hyperplane& plane) {
  Section s;
  s.complex = Complex(dim - 1);
  s.complex.set_positions(Eigen::MatrixXd(dim - 1, 0));
  s.frame = HyperplaneFrame(plane);
  s.source.resize(1);
  return s;
}

}  // namespace

std::vector<Section> section_objects(const Scene& scene, const Hyperplane& plane) {
  const int dim = scene.dim();
  if (!scene.objects.empty() && plane.dim() != dim)
    throw InputError("hyperplane in R^" + std::to_string(plane.dim()) + " for a scene in R^" +
                     std::to_string(dim));
  std::unordered_map<const Complex*, Sphere> spheres;  // models are shared between objects
  std::vector<Section> pieces;
  pieces.reserve(scene.objects.size());
  for (const SceneObject& obj : scene.objects) {
    const Complex& model = *obj.complex;
    auto it = spheres.find(&model);
    if (it == spheres.end()) it = spheres.emplace(&model, bounding_sphere(model)).first;
    // The sphere in the world: centre moved, radius stretched by the largest singular value.
    const Eigen::VectorXd centre = obj.transform.apply(it->second.centre);
    const double stretch =
        Eigen::JacobiSVD<Eigen::MatrixXd>(obj.transform.linear()).singularValues()(0);
    const double radius = stretch * it->second.radius;
    const double margin = tol::bounding_sphere_margin_rel * (radius + centre.norm());
    if (std::abs(plane.signed_distance(centre)) > radius + margin)
      pieces.push_back(empty_section(dim, plane));
    else
      pieces.push_back(section(model, plane, obj.transform));
  }
  return pieces;
}

Section merge_sections(const Scene& scene, const std::vector<Section>& pieces) {
  assert(pieces.size() == scene.objects.size());
  Section out;
  if (pieces.empty()) return out;
  const int dim = pieces.front().complex.ambient_dim();  // the section's, one less than models'
  out.frame = pieces.front().frame;
  out.complex = Complex(dim);
  out.source.resize(1);

  int top = 0;
  Eigen::Index nv = 0;
  for (const Section& p : pieces) {
    top = std::max(top, p.complex.top_rank());
    nv += p.complex.positions().cols();
  }
  if (top >= 1) out.complex.boundary_mut(top);
  out.source.resize(top + 1);

  Eigen::MatrixXd positions(dim, nv);
  const int facet_rank = dim - 1;
  bool normals_ok = facet_rank >= 1;
  std::size_t nfacets = 0;
  for (const Section& p : pieces) {
    const std::size_t nf = p.complex.count(facet_rank);
    nfacets += nf;
    normals_ok = normals_ok && (nf == 0 || p.complex.has_facet_normals());
  }
  Eigen::MatrixXd normals(dim, normals_ok ? static_cast<Eigen::Index>(nfacets) : 0);

  std::vector<std::uint32_t> base(top + 1, 0);  // elements of each rank merged so far
  std::vector<std::uint32_t> ids;
  std::vector<Rgba>* colors = top >= 2 ? &out.complex.colors_mut(2) : nullptr;
  Eigen::Index next_normal = 0;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const Section& p = pieces[i];
    const Complex& c = p.complex;
    const Eigen::Index pv = c.positions().cols();
    positions.middleCols(base[0], pv) = c.positions();
    out.vertex_source.insert(out.vertex_source.end(), p.vertex_source.begin(),
                             p.vertex_source.end());
    for (int r = 1; r <= c.top_rank(); ++r) {
      const Incidence& table = c.boundary(r);
      Incidence& dst = out.complex.boundary_mut(r);
      for (std::uint32_t x = 0; x < table.size(); ++x) {
        const auto row = table.ids(x);
        ids.assign(row.begin(), row.end());
        for (auto& id : ids) id += base[r - 1];
        dst.add_row(ids, table.signs(x));
      }
      if (r < static_cast<int>(p.source.size()))
        out.source[r].insert(out.source[r].end(), p.source[r].begin(), p.source[r].end());
    }
    const std::size_t faces = c.count(2);
    out.object_of_face.insert(out.object_of_face.end(), faces, static_cast<std::uint32_t>(i));
    if (colors) {
      const bool have_cells = p.source.size() > 2 && p.source[2].size() == faces;
      for (std::uint32_t f = 0; f < faces; ++f)
        colors->push_back(have_cells ? scene.objects[i].color_of_cell(p.source[2][f])
                                     : scene.objects[i].color);
    }
    if (normals_ok && c.count(facet_rank) > 0) {
      const Eigen::Index nf = static_cast<Eigen::Index>(c.count(facet_rank));
      normals.middleCols(next_normal, nf) = c.facet_normals();
      next_normal += nf;
    }
    for (int r = 0; r <= c.top_rank(); ++r) base[r] += static_cast<std::uint32_t>(c.count(r));
  }
  out.complex.set_positions(std::move(positions));
  if (normals_ok && nfacets > 0) out.complex.set_facet_normals(std::move(normals));
  return out;
}

Section section_scene(const Scene& scene, const Hyperplane& plane) {
  return merge_sections(scene, section_objects(scene, plane));
}

}  // namespace cw4d
