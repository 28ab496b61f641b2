#include "cw4d/export/mesh.hpp"

#include <algorithm>

#include "cw4d/complex/error.hpp"
#include "cw4d/section/triangulate.hpp"

namespace cw4d {

std::vector<TriangleMesh> triangle_meshes(const Section& section,
                                          const std::vector<std::string>& object_names,
                                          const CornerUvw* uvw) {
  const Complex& c = section.complex;
  if (c.ambient_dim() != 3)
    throw InputError("triangle meshes hold 3D sections; this one lives in R^" +
                     std::to_string(c.ambient_dim()));
  const std::uint32_t nf = c.top_rank() >= 2 ? static_cast<std::uint32_t>(c.count(2)) : 0u;
  if (nf == 0) return {};
  if (section.source.size() <= 2 || section.source[2].size() != nf || !c.has_facet_normals())
    throw InputError("a triangle mesh of a section needs its provenance and normals");
  if (uvw && uvw->offset.size() != nf + 1u)
    throw InputError("the texture coordinates do not belong to this section");
  const bool per_object = section.object_of_face.size() == nf;
  const auto& colors = c.colors(2);
  const bool colored = colors.size() == nf;

  // One mesh per object that has faces, in object order (its faces need not be contiguous).
  std::vector<std::uint32_t> object_of_face(nf, 0u);
  if (per_object) object_of_face = section.object_of_face;
  const std::uint32_t objects = *std::max_element(object_of_face.begin(), object_of_face.end()) + 1;
  std::vector<std::uint32_t> corners(objects, 0u);
  for (std::uint32_t f = 0; f < nf; ++f)
    corners[object_of_face[f]] += static_cast<std::uint32_t>(c.face_cycle(f).size());
  std::vector<std::uint32_t> mesh_of_object(objects, 0u);
  std::vector<TriangleMesh> meshes;
  for (std::uint32_t o = 0; o < objects; ++o) {
    if (corners[o] == 0) continue;
    mesh_of_object[o] = static_cast<std::uint32_t>(meshes.size());
    TriangleMesh& mesh = meshes.emplace_back();
    mesh.object = o;
    if (o < object_names.size()) mesh.name = object_names[o];
    const Eigen::Index n = corners[o];
    mesh.position.resize(3, n);
    mesh.normal.resize(3, n);
    if (colored) mesh.color.resize(4, n);
    if (uvw) mesh.uvw.resize(3, n);
    mesh.cell.reserve(n);
    mesh.section_vertex.reserve(n);
  }

  // Corners of each face, then its triangles in terms of them.
  std::vector<std::uint32_t> first_corner(nf);
  for (std::uint32_t f = 0; f < nf; ++f) {
    TriangleMesh& mesh = meshes[mesh_of_object[object_of_face[f]]];
    const auto cycle = c.face_cycle(f);
    const Eigen::Vector3f n = c.facet_normals().col(f).cast<float>().normalized();
    first_corner[f] = static_cast<std::uint32_t>(mesh.cell.size());
    for (std::size_t j = 0; j < cycle.size(); ++j) {
      const Eigen::Index k = static_cast<Eigen::Index>(mesh.cell.size());
      mesh.position.col(k) = c.position(cycle[j]).cast<float>();
      mesh.normal.col(k) = n;
      if (colored) mesh.color.col(k) << colors[f].r, colors[f].g, colors[f].b, colors[f].a;
      if (uvw) {
        const auto col = uvw->uvw.col(uvw->offset[f] + j);
        mesh.uvw.col(k) << col(0), col(1), col(2);
      }
      mesh.cell.push_back(section.source[2][f]);
      mesh.section_vertex.push_back(cycle[j]);
    }
  }
  // Non-convex polygons are ear-clipped, and holes (loops of the same cell inside another) are
  // bridged into their outer loop: a triangle may use corners of the face's holes.
  const std::vector<std::vector<std::uint32_t>> holes = section_holes(section);
  for (const Triangle& t : ear_clip_triangulate(c, holes)) {
    TriangleMesh& mesh = meshes[mesh_of_object[object_of_face[t.face]]];
    for (std::uint32_t v : t.v) {
      std::uint32_t corner = 0;
      bool found = false;
      const auto find_in = [&](std::uint32_t f) {
        const auto cycle = c.face_cycle(f);
        const auto at = std::find(cycle.begin(), cycle.end(), v);
        if (at == cycle.end()) return false;
        corner = first_corner[f] + static_cast<std::uint32_t>(at - cycle.begin());
        return true;
      };
      found = find_in(t.face);
      for (std::size_t h = 0; !found && h < holes[t.face].size(); ++h)
        found = find_in(holes[t.face][h]);
      if (!found) throw InputError("triangulation names a vertex outside its face");
      mesh.triangles.push_back(corner);
    }
  }
  return meshes;
}

}  // namespace cw4d
