#include "cw4d/complex/mesh_import.hpp"

#include <Eigen/Geometry>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <vector>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/detail/mute_openmesh.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/complex/validate.hpp"

namespace cw4d {

namespace {

struct Traits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
};
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<Traits>;

using detail::MuteOpenMesh;

bool is_planar(const Eigen::MatrixXd& pos, const std::vector<std::uint32_t>& cycle) {
  // Newell normal and centroid: robust for any simple polygon.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero(), centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d lo = pos.col(cycle[0]), hi = lo;
  for (std::size_t i = 0; i < cycle.size(); ++i) {
    const Eigen::Vector3d a = pos.col(cycle[i]), b = pos.col(cycle[(i + 1) % cycle.size()]);
    normal += (a - b).cross(a + b) * 0.5;
    centroid += a;
    lo = lo.cwiseMin(a);
    hi = hi.cwiseMax(a);
  }
  centroid /= static_cast<double>(cycle.size());
  const double size = (hi - lo).norm();
  if (normal.norm() <= tol::degenerate_rel * size * size) return false;
  normal.normalize();
  for (auto v : cycle)
    if (std::abs(normal.dot(pos.col(v) - centroid)) > tol::planarity_rel * size) return false;
  return true;
}

}  // namespace

Complex read_polyhedron(const std::string& path) {
  if (!std::ifstream(path, std::ios::binary)) throw IoError(path + ": cannot open file");
  PolyMesh mesh;
  bool read_ok = false;
  {
    MuteOpenMesh mute;
    OpenMesh::IO::Options options;
    read_ok = OpenMesh::IO::read_mesh(mesh, path, options);
  }
  if (!read_ok) throw ParseError(path, 0, "cannot read the mesh (unknown format or bad data)");
  if (mesh.n_faces() == 0) throw ParseError(path, 0, "the mesh has no faces");

  ComplexSoup soup;
  soup.ambient_dim = 3;
  std::map<std::array<double, 3>, std::uint32_t> index;  // merged vertices by exact position
  std::vector<std::array<double, 3>> points;
  for (const auto fh : mesh.faces()) {
    std::vector<std::uint32_t> cycle;
    for (const auto vh : mesh.fv_range(fh)) {
      const auto& p = mesh.point(vh);
      const std::array<double, 3> key{p[0], p[1], p[2]};
      const auto [it, added] = index.emplace(key, static_cast<std::uint32_t>(points.size()));
      if (added) points.push_back(key);
      cycle.push_back(it->second);
    }
    soup.faces.push_back(std::move(cycle));
  }
  soup.positions.resize(3, static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
    soup.positions.col(static_cast<Eigen::Index>(i)) << points[i][0], points[i][1], points[i][2];
  // Non-planar polygons would fail validation; a fan keeps the surface closed.
  std::vector<std::vector<std::uint32_t>> faces;
  for (auto& cycle : soup.faces) {
    if (cycle.size() <= 3 || is_planar(soup.positions, cycle)) {
      faces.push_back(std::move(cycle));
      continue;
    }
    for (std::size_t k = 1; k + 1 < cycle.size(); ++k)
      faces.push_back({cycle[0], cycle[k], cycle[k + 1]});
  }
  soup.faces = std::move(faces);

  Complex complex(3);
  try {
    complex = build_complex(soup);
  } catch (const TopologyError& e) {
    throw ParseError(path, 0, std::string("bad face: ") + e.what());
  }
  const ValidationReport report = validate(complex);
  if (!report.ok()) throw ParseError(path, 0, "not a closed polyhedron: " + report.summary());
  return complex;
}

}  // namespace cw4d
