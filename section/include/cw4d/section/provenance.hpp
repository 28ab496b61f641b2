#pragma once
// The one check that a section's provenance (Section::vertex_source, source, object_of_face)
// refers to the model(s) a reader is given. Every reader of provenance that also reads a model
// (texture coordinates, cell colors, 4D normals, exporters) calls check_provenance once, up
// front, before it indexes the model's arrays with the section's ids.
#include <cstdint>
#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/section/section.hpp"

namespace cw4d {

/// A cheap fingerprint of a model's shape: a hash of its dimension and f-vector (ranks 0 to
/// top), never 0. Computing it reads no array, so every section carries it at no cost; it tells
/// apart models whose ids would all be in range (the section of a tesseract given the 24-cell),
/// but not two models of the same f-vector (a model and its transformed copy, which is also
/// the one legitimate case: a section of a moved model drawn with the model's colors).
std::uint64_t model_fingerprint(const Complex& model);

/// The fingerprint of a section cut from `models` in order: model_fingerprint of a single
/// model, a hash of the objects' fingerprints in object order for a scene (section_scene).
/// \pre every pointer is non-null.
std::uint64_t models_fingerprint(const std::vector<const Complex*>& models);

/// Checks that `section` was cut from `models` (models[i] the model of scene object i when
/// section.object_of_face is set, else models[0] the model): the fingerprint (when the section
/// carries one), the dimension, every scene object id, and every model id of the provenance,
/// below its rank's count in the model of its object. A vertex source of rank 1 and element
/// no_index (a diagonal of a tetrahedralization) is accepted here; the readers that need a model
/// edge refuse it. Linear in the size of the section.
/// \throw InputError naming the first id out of range, e.g. "the section was not cut from this
/// model (cell id 812 >= 120 cells)", or the fingerprints that differ.
void check_provenance(const Section& section, const std::vector<const Complex*>& models);
void check_provenance(const Section& section, const Complex& model);

}  // namespace cw4d
