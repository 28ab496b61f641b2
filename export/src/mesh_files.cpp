#include "cw4d/export/mesh_files.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <tuple>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/text.hpp"
#include "mute_openmesh.hpp"

namespace cw4d {

namespace {

struct Traits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3f;
  using Normal = OpenMesh::Vec3f;
  using Color = OpenMesh::Vec4uc;
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<Traits>;

using detail::MuteOpenMesh;

// A stored color component in [0, 1] (already sRGB-encoded) as a byte.
unsigned char byte(float c) {
  return static_cast<unsigned char>(std::lround(std::clamp(c, 0.0f, 1.0f) * 255.0f));
}

void require_triangles(const std::vector<TriangleMesh>& meshes, const char* format) {
  for (const auto& m : meshes)
    if (!m.triangles.empty()) return;
  throw InputError(std::string(format) + ": nothing to write (no triangles)");
}

std::string write_to_string(const TriMesh& mesh, const std::string& ext, OpenMesh::IO::Options opt,
                            const std::string& path) {
  MuteOpenMesh mute;
  std::ostringstream out(std::ios::binary);
  if (!OpenMesh::IO::write_mesh(mesh, out, ext, opt))
    throw IoError("cannot write " + quote_user_text(path) + ": OpenMesh's " + ext +
                  " writer failed");
  return out.str();
}

}  // namespace

void write_ply_file(const std::string& path, const std::vector<TriangleMesh>& meshes) {
  require_triangles(meshes, "PLY");
  TriMesh mesh;
  mesh.request_vertex_colors();
  const TriMesh::Color grey(200, 200, 200, 255);
  // Weld corners of one section vertex with one color (per object: ids restart per mesh).
  using Key = std::tuple<std::uint32_t, std::uint32_t, std::array<unsigned char, 4>>;
  std::map<Key, TriMesh::VertexHandle> welded;
  for (const TriangleMesh& m : meshes) {
    std::vector<TriMesh::VertexHandle> handle(m.vertex_count());
    for (std::size_t v = 0; v < m.vertex_count(); ++v) {
      TriMesh::Color col = grey;
      if (m.color.cols() > 0)
        col = TriMesh::Color(byte(m.color(0, v)), byte(m.color(1, v)), byte(m.color(2, v)),
                             byte(m.color(3, v)));
      const Key key{m.object, m.section_vertex[v], {col[0], col[1], col[2], col[3]}};
      auto [it, fresh] = welded.try_emplace(key);
      if (fresh) {
        it->second =
            mesh.add_vertex(TriMesh::Point(m.position(0, v), m.position(1, v), m.position(2, v)));
        mesh.set_color(it->second, col);
      }
      handle[v] = it->second;
    }
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
      std::array<TriMesh::VertexHandle, 3> h;
      for (int k = 0; k < 3; ++k) h[k] = handle[m.triangles[3 * t + k]];
      if (mesh.add_face(h[0], h[1], h[2]).is_valid()) continue;
      // A pinched section (two parts touching in a vertex) is not a manifold at that vertex;
      // the triangle is kept with vertices of its own there.
      for (auto& v : h) {
        const auto copy = mesh.add_vertex(mesh.point(v));
        mesh.set_color(copy, mesh.color(v));
        v = copy;
      }
      mesh.add_face(h[0], h[1], h[2]);
    }
  }
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::Binary | OpenMesh::IO::Options::LSB |
                              OpenMesh::IO::Options::VertexColor |
                              OpenMesh::IO::Options::ColorAlpha;
  write_file_atomically(path, write_to_string(mesh, ".ply", opt, path));
}

void write_stl_file(const std::string& path, const std::vector<TriangleMesh>& meshes) {
  require_triangles(meshes, "STL");
  TriMesh mesh;
  mesh.request_face_normals();
  for (const TriangleMesh& m : meshes) {
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
      std::array<TriMesh::VertexHandle, 3> h;
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t v = m.triangles[3 * t + k];
        h[k] =
            mesh.add_vertex(TriMesh::Point(m.position(0, v), m.position(1, v), m.position(2, v)));
      }
      const auto f = mesh.add_face(h[0], h[1], h[2]);
      const std::uint32_t v0 = m.triangles[3 * t];
      mesh.set_normal(f, TriMesh::Normal(m.normal(0, v0), m.normal(1, v0), m.normal(2, v0)));
    }
  }
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::Binary | OpenMesh::IO::Options::FaceNormal;
  write_file_atomically(path, write_to_string(mesh, ".stl", opt, path));
}

}  // namespace cw4d
