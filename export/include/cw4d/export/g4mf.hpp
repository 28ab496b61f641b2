#pragma once
// G4MF output (cw4d/complex/g4mf.hpp) of models and sections with their texture coordinates.
//
// A model is written as it is (its own coordinates, every rank, colors, facet normals) with, for
// each facet corner, the UVW of the facet's box map (facet_texture_maps, section/uvw.hpp): the
// map the tetrahedral mesh, the slicers and the exporters of sections use, so a G4MF consumer
// that cuts the model gets the textures cw4d's sections show.
//
// A section is written as the complex it is (in R^(n-1), the plane's orthonormal coordinates:
// see Section::frame), with its cell or object colors and its facet normals (the source cells'
// normals projected into the plane); for a 3D section, the UVW of every polygon corner (the
// texture coordinates of section_uvw or of the tetrahedral path).
#include <string>
#include <vector>

#include "cw4d/complex/g4mf.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/uvw.hpp"

namespace cw4d {

/// Writes `model` to `path` in `options.container` (options.texture is replaced: with the box
/// maps when `uvw`, else nothing). \return the files written (a .bin first for text_external).
/// \throw InputError (a model G4MF cannot hold; uvw without facet normals), IoError.
std::vector<std::string> write_g4mf_model_file(const std::string& path, const Complex& model,
                                               G4mfWriteOptions options, bool uvw = true);

/// Writes `section.complex` to `path`; `uvw`, when given, holds the corner texture coordinates of
/// its faces (section_uvw of this section, or the tetrahedral path's) and is written for a 3D
/// section. \return the files written. \throw InputError, IoError.
std::vector<std::string> write_g4mf_section_file(const std::string& path, const Section& section,
                                                 G4mfWriteOptions options,
                                                 const CornerUvw* uvw = nullptr);

}  // namespace cw4d
