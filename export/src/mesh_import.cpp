#include "cw4d/export/mesh_import.hpp"

#include <Eigen/Geometry>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/input_file.hpp"
#include "cw4d/complex/operators.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "cw4d/complex/validate.hpp"
#include "mute_openmesh.hpp"

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

// OpenMesh reserves what a file's header announces before reading the elements. Refuse the
// counts the file is too short to hold (each vertex takes at least 6 bytes, "0 0 0\n" or
// more in binary; each face at least 1), so that a 100-byte file announcing 2e9 vertices is a
// parse error, not an exhausted memory.
void check_announced_counts(const std::string& path, std::uintmax_t size) {
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (head.substr(0, 3) == "\xEF\xBB\xBF") head.erase(0, 3);
  double vertices = 0, faces = 0;
  std::istringstream words(head);
  std::string word;
  const auto lower = [](std::string w) {
    for (auto& ch : w) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return w;
  };
  std::string ext = std::filesystem::path(path).extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  const bool is_stl = ext == ".stl";
  if (!(words >> word)) return;
  const std::string first = lower(word);
  if (first.size() >= 3 && first.substr(first.size() - 3) == "off") {
    // [ST][C][N][4][n]OFF [BINARY], comments, then "V F E".
    std::vector<double> counts;
    while (counts.size() < 2 && words >> word) {
      if (word[0] == '#') {
        std::getline(words, word);
        continue;
      }
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      if (*end != '\0') {
        if (counts.empty() && lower(word) == "binary") continue;
        return;  // OpenMesh will report it
      }
      counts.push_back(v);
    }
    if (counts.size() < 2) return;
    vertices = counts[0];
    faces = counts[1];
  } else if (first == "ply") {
    std::string line;
    std::istringstream lines(head);
    while (std::getline(lines, line) && lower(line).rfind("end_header", 0) != 0) {
      std::istringstream f(line);
      std::string element, kind;
      double n = 0;
      if (f >> element >> kind >> n && element == "element")
        (kind == "vertex" ? vertices : faces) += n;
    }
  } else if (is_stl && first != "solid" && size >= 84) {
    // Binary STL: an 80-byte header, a 32-bit triangle count, 50 bytes per triangle.
    const auto* b = reinterpret_cast<const unsigned char*>(head.data() + 80);
    if (head.size() >= 84)
      faces = static_cast<double>(static_cast<std::uint32_t>(b[0]) | std::uint32_t{b[1]} << 8 |
                                  std::uint32_t{b[2]} << 16 | std::uint32_t{b[3]} << 24);
    if (faces * 50 + 84 > static_cast<double>(size))
      throw ParseError(path, 0,
                       "announces " + std::to_string(static_cast<long long>(faces)) +
                           " triangles but the file has only " + std::to_string(size) + " bytes");
    return;
  }
  if (vertices * 6 + faces > static_cast<double>(size) || vertices < 0 || faces < 0)
    throw ParseError(path, 0,
                     "announces " +
                         std::to_string(static_cast<long long>(std::clamp(vertices, -9e18, 9e18))) +
                         " vertices and " +
                         std::to_string(static_cast<long long>(std::clamp(faces, -9e18, 9e18))) +
                         " faces but the file has only " + std::to_string(size) + " bytes");
}

// "FILE,STEPS" of spin: the path is everything before the last comma.
std::pair<std::string, int> parse_file_steps(std::string_view args, std::string_view spec) {
  const std::size_t comma = args.rfind(',');
  if (comma == std::string_view::npos || comma == 0)
    throw InputError("model spec " + quote_user_text(std::string(spec)) + " expects FILE,STEPS");
  return {std::string(args.substr(0, comma)), parse_ints(args.substr(comma + 1), spec, 1)[0]};
}

}  // namespace

std::vector<ModelFamily> mesh_file_families() {
  std::vector<ModelFamily> f;
  f.push_back(
      parametric_family("extrude", "extrude:FILE",
                        "4D prism (height 2) over a closed polyhedron read from an OBJ, OFF, "
                        "PLY or STL file",
                        [](const std::string&, std::string_view a) {
                          return make_prism(read_polyhedron(std::string(a)), 2.0);
                        }));
  f.push_back(
      parametric_family("spin", "spin:FILE,STEPS",
                        "4D solid of revolution of a closed polyhedron (OBJ/OFF/PLY/STL) lying "
                        "in x >= 0, turned in the xw plane around the yz plane in STEPS steps",
                        [](const std::string& spec, std::string_view a) {
                          const auto [file, steps] = parse_file_steps(a, spec);
                          return make_spin(read_polyhedron(file), steps);
                        }));
  return f;
}

Complex read_polyhedron(const std::string& path) {
  // Only regular files of bounded size reach OpenMesh (a FIFO would block it forever).
  const std::uintmax_t size = check_input_file(path);
  check_announced_counts(path, size);
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
