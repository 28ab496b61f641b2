#include "cw4d/section/scene_section.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

#include "cw4d/complex/error.hpp"
#include "cw4d/section/provenance.hpp"
#include "cw4d/section/slicer.hpp"

namespace cw4d {

std::vector<Section> section_objects(const Scene& scene, const Hyperplane& plane) {
  const int dim = scene.dim();
  if (!scene.objects.empty() && plane.dim() != dim)
    throw InputError("hyperplane in R^" + std::to_string(plane.dim()) + " for a scene in R^" +
                     std::to_string(dim));
  // Compiled without clusters, so that each piece is exactly section() of its object; objects
  // whose bounding sphere misses the plane are culled (their empty piece is the same).
  SceneSlicer slicer(scene, SliceModelOptions::unclustered());
  SceneSlice cut;
  slicer.slice(plane, cut);
  return to_sections(cut, scene.objects.size());
}

Section merge_sections(const Scene& scene, const std::vector<Section>& pieces) {
  assert(pieces.size() == scene.objects.size());
  Section out;
  if (pieces.empty()) return out;
  const int dim = pieces.front().complex.ambient_dim();  // the section's, one less than models'
  out.frame = pieces.front().frame;
  out.complex = Complex(dim);
  std::vector<const Complex*> models;
  for (const SceneObject& o : scene.objects) models.push_back(o.complex.get());
  out.source_fingerprint = models_fingerprint(models);
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
  assert(out.complex.well_formed() && out.vertex_source.size() == out.complex.count(0));
  assert(out.object_of_face.size() == out.complex.count(2));
  return out;
}

Section section_scene(const Scene& scene, const Hyperplane& plane) {
  return merge_sections(scene, section_objects(scene, plane));
}

}  // namespace cw4d
