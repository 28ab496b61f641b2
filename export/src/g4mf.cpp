#include "cw4d/export/g4mf.hpp"

#include <algorithm>
#include <memory>

#include "cw4d/complex/error.hpp"

namespace cw4d {

std::vector<std::string> write_g4mf_model_file(const std::string& path, const Complex& model,
                                               G4mfWriteOptions options, bool uvw) {
  options.texture = nullptr;
  options.texture_dim = 0;
  const int n = model.ambient_dim();
  if (uvw && n >= 3 && model.top_rank() >= n - 1 && model.count(n - 1) > 0 &&
      model.has_facet_normals()) {
    auto maps = std::make_shared<std::vector<FacetTextureMap>>(facet_texture_maps(model));
    options.texture_dim = n - 1;
    options.texture = [maps, &model](std::uint32_t facet, std::uint32_t vertex, float* out) {
      const Eigen::VectorXd x = model.position(vertex);
      const Eigen::VectorXd t = (*maps)[facet](x);
      for (Eigen::Index i = 0; i < t.size(); ++i) out[i] = static_cast<float>(t(i));
    };
  }
  return write_g4mf_file(path, model, options);
}

std::vector<std::string> write_g4mf_section_file(const std::string& path, const Section& section,
                                                 G4mfWriteOptions options, const CornerUvw* uvw) {
  const Complex& c = section.complex;
  options.texture = nullptr;
  options.texture_dim = 0;
  const std::uint32_t nf = c.top_rank() >= 2 ? static_cast<std::uint32_t>(c.count(2)) : 0u;
  if (uvw && c.ambient_dim() == 3 && nf > 0) {
    if (uvw->offset.size() != nf + 1u)
      throw InputError("the texture coordinates do not belong to this section");
    // Corner j of face f is vertex face_cycle(f)[j]: a lookup per face.
    auto cycles = std::make_shared<std::vector<std::vector<std::uint32_t>>>(nf);
    for (std::uint32_t f = 0; f < nf; ++f) (*cycles)[f] = c.face_cycle(f);
    options.texture_dim = static_cast<int>(uvw->uvw.rows());
    options.texture = [cycles, uvw](std::uint32_t face, std::uint32_t vertex, float* out) {
      const auto& cycle = (*cycles)[face];
      const auto at = std::find(cycle.begin(), cycle.end(), vertex);
      if (at == cycle.end()) throw InputError("a face corner is not on its face's cycle");
      const auto col = uvw->uvw.col(uvw->offset[face] + (at - cycle.begin()));
      for (Eigen::Index i = 0; i < col.size(); ++i) out[i] = col(i);
    };
  }
  return write_g4mf_file(path, c, options);
}

}  // namespace cw4d
