#include "cw4d/section/uvw.hpp"

#include <limits>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/index.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/provenance.hpp"

namespace cw4d {

std::vector<FacetTextureMap> facet_texture_maps(const Complex& model) {
  if (!model.has_facet_normals())
    throw InputError(
        "texture coordinates need the model's facet normals (build it with build_complex)");
  const int rank = model.facet_rank();
  const Eigen::Index n = model.ambient_dim();
  std::vector<FacetTextureMap> maps(model.count(rank));
  for (std::uint32_t f = 0; f < maps.size(); ++f) {
    const Eigen::MatrixXd basis = hyperplane_basis(model.facet_normals().col(f).normalized());
    Eigen::VectorXd lo = Eigen::VectorXd::Constant(n - 1, std::numeric_limits<double>::infinity());
    Eigen::VectorXd hi = -lo;
    for (std::uint32_t v : model.vertices_of(rank, f)) {
      const Eigen::VectorXd y = basis.transpose() * model.position(v);
      lo = lo.cwiseMin(y);
      hi = hi.cwiseMax(y);
    }
    // Rows basis_i^T / extent_i; the origin is the box's low corner lifted back (its component
    // along the normal does not matter: the rows are orthogonal to the normal).
    Eigen::VectorXd extent = hi - lo;
    for (Eigen::Index i = 0; i < extent.size(); ++i)
      if (!(extent(i) > 0.0)) extent(i) = 1.0;
    maps[f].to_uvw = extent.cwiseInverse().asDiagonal() * basis.transpose();
    maps[f].origin = basis * lo;
  }
  return maps;
}

CornerUvw section_uvw(const Section& section, const std::vector<const Complex*>& models) {
  const Complex& c = section.complex;
  const std::uint32_t nf = c.top_rank() >= 2 ? static_cast<std::uint32_t>(c.count(2)) : 0u;
  if (section.source.size() <= 2 || section.source[2].size() != nf ||
      section.vertex_source.size() != c.count(0))
    throw InputError(
        "texture coordinates of a section need its provenance (cut it with section())");
  // The ids below index the models' arrays: they must be the models' own.
  check_provenance(section, models);
  const bool per_object = section.object_of_face.size() == nf && nf > 0;
  std::vector<std::vector<FacetTextureMap>> maps(models.size());
  CornerUvw out;
  out.offset.assign(nf + 1, 0);
  for (std::uint32_t f = 0; f < nf; ++f)
    out.offset[f + 1] = out.offset[f] + static_cast<std::uint32_t>(c.face_cycle(f).size());
  out.uvw.resize(c.ambient_dim(), out.offset[nf]);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t object = per_object ? section.object_of_face[f] : 0u;
    if (object >= models.size() || models[object] == nullptr)
      throw InputError("texture coordinates: no model for scene object " + std::to_string(object));
    const Complex& model = *models[object];
    if (maps[object].empty()) maps[object] = facet_texture_maps(model);
    const FacetTextureMap& map = maps[object][section.source[2][f]];
    std::uint32_t k = out.offset[f];
    for (std::uint32_t v : c.face_cycle(f)) {
      const VertexSource& src = section.vertex_source[v];
      Eigen::VectorXd x;
      if (src.rank == 0) {
        x = model.position(src.element);
      } else {
        if (src.element == no_index)
          throw InputError(
              "texture coordinates: section vertex " + std::to_string(v) +
              " lies on no model edge (a tetrahedral cut: take its own texture coordinates)");
        const auto ends = model.edge(src.element);
        x = (1.0 - src.t) * model.position(ends[0]) + src.t * model.position(ends[1]);
      }
      out.uvw.col(k++) = map(x).cast<float>();
    }
  }
  return out;
}

}  // namespace cw4d
