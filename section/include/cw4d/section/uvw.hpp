#pragma once
// Default texture coordinates: each facet (3-cell of a 4D model) gets its own box mapping.
//
// The facet's points are written in the facet's own orthonormal frame (hyperplane_basis of its
// outward normal, so the frame is deterministic and right-handed with the normal), and the
// facet's bounding box in that frame is mapped onto [0,1]^(n-1). Every point of the facet then
// has a UVW (for n = 4) in [0,1]^3; a section vertex takes the UVW of its model position in the
// facet its polygon was cut from, so exporters, the tetrahedral mesh and the slicers agree.
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

#include "cw4d/complex/complex.hpp"
#include "cw4d/section/section.hpp"

namespace cw4d {

/// x (model space, on the facet) -> uvw = to_uvw * (x - origin), in [0,1]^(n-1) on the facet.
struct FacetTextureMap {
  Eigen::VectorXd origin;
  Eigen::MatrixXd to_uvw;  ///< (n-1) x n
  Eigen::VectorXd operator()(const Eigen::VectorXd& x) const { return to_uvw * (x - origin); }
};

/// One map per facet of `model`, in facet order.
/// \pre model.has_facet_normals() (built complexes have them).
/// \throw InputError when the model has no facet normals.
std::vector<FacetTextureMap> facet_texture_maps(const Complex& model);

/// Texture coordinates of every face corner of a section: corner j of face f (in the order of
/// face_cycle(f)) has uvw[offset[f] + j]. A corner takes the UVW of its model position in the
/// facet its face was cut from (section.source[2][f]), so UVW are continuous inside each cut
/// cell and jump across cells, like normals.
struct CornerUvw {
  std::vector<std::uint32_t> offset;  ///< count(2) + 1 entries
  Eigen::MatrixXf uvw;                ///< (n-1) x corners
};

/// `models[i]` is the model of scene object i (section.object_of_face), or models[0] the model
/// of a single model's section. The section must come from section()/section_scene() of them.
/// \throw InputError when the section has no provenance or a model is missing.
CornerUvw section_uvw(const Section& section, const std::vector<const Complex*>& models);

}  // namespace cw4d
