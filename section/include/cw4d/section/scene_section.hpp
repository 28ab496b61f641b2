#pragma once
// Cutting a whole scene with one world-space hyperplane.
#include <vector>

#include "cw4d/complex/scene.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"

namespace cw4d {

/// The section of each object (entry i for scene.objects[i]), all in the frame of `plane`.
/// Objects whose bounding sphere does not reach the plane are not cut: their entry is an empty
/// section (like the entry of an object the plane misses).
/// \throw InputError when the plane's dimension differs from the scene's.
std::vector<Section> section_objects(const Scene& scene, const Hyperplane& plane);

/// Merges the per-object sections of section_objects into one section: vertices, elements of
/// every rank, provenance and facet normals concatenated in object order (ids offset), with
/// object_of_face set and one color per face in complex.colors(2): the color of the source
/// 3-cell from the scene, else the object's color, alpha = opacity. Overlapping objects are
/// not united: the result is the union of closed surfaces, one (or none) per object.
/// \pre pieces.size() == scene.objects.size(), all cut by the same plane.
Section merge_sections(const Scene& scene, const std::vector<Section>& pieces);

/// merge_sections(scene, section_objects(scene, plane)).
Section section_scene(const Scene& scene, const Hyperplane& plane);

}  // namespace cw4d
