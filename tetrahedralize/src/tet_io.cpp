#include "cw4d/tetrahedralize/tet_io.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <sstream>
#include <vector>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/section/hyperplane.hpp"

namespace cw4d {

namespace {

static_assert(std::endian::native == std::endian::little,
              "the binary writers assume little endian");

std::string base64(const std::string& bytes) {
  static constexpr char table[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const std::uint32_t v = (static_cast<std::uint8_t>(bytes[i]) << 16) |
                            (static_cast<std::uint8_t>(bytes[i + 1]) << 8) |
                            static_cast<std::uint8_t>(bytes[i + 2]);
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += table[(v >> 6) & 63];
    out += table[v & 63];
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (rest == 2) v |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    out += table[(v >> 18) & 63];
    out += table[(v >> 12) & 63];
    out += rest == 2 ? table[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

template <class T>
void append_raw(std::string& s, T x) {
  char b[sizeof(T)];
  std::memcpy(b, &x, sizeof(T));
  s.append(b, sizeof(T));
}

// One DataArray of a .vtu file. `values` are written with the given VTK type.
template <class T>
void data_array(std::ostringstream& o, const char* type, const char* name, int components,
                const std::vector<T>& values, VtuEncoding enc) {
  o << "        <DataArray type=\"" << type << "\"";
  if (name) o << " Name=\"" << name << "\"";
  if (components > 1) o << " NumberOfComponents=\"" << components << "\"";
  if (enc == VtuEncoding::Ascii) {
    o << " format=\"ascii\">\n          ";
    for (std::size_t i = 0; i < values.size(); ++i) {
      o << values[i] << ((i + 1) % 12 == 0 && i + 1 < values.size() ? "\n          " : " ");
    }
    o << "\n        </DataArray>\n";
  } else {
    std::string raw;
    raw.reserve(values.size() * sizeof(T));
    for (const T& v : values) append_raw(raw, v);
    std::string head;
    append_raw(head, static_cast<std::uint64_t>(raw.size()));
    // VTK decodes the header and the data as separately padded base64 blocks.
    o << " format=\"binary\">\n          " << base64(head) << base64(raw)
      << "\n        </DataArray>\n";
  }
}

std::string lower_ext(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

std::string with_ext(const std::string& path, const std::string& ext) {
  return std::filesystem::path(path).replace_extension(ext).string();
}

// Writes two files: the first, then the second; removes the first when the second fails.
void write_pair(const std::string& first, const std::string& first_text, const std::string& second,
                const std::string& second_text) {
  write_file_atomically(first, first_text);
  try {
    write_file_atomically(second, second_text);
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(first, ec);
    throw;
  }
}

}  // namespace

Eigen::Vector3d SchlegelView::project(const Eigen::Vector4d& x) const {
  const double a = normal.dot(x - centre);
  const double s = eye_height / (eye_height - a);  // > 0 below the eye
  const Eigen::Vector4d e = eye();
  return basis.transpose() * (e + s * (x - e) - centre);
}

namespace {

// Height of each cell's hyperplane above the centre, n_j . (x - centre) over its corners (the
// largest, for cells that are not quite planar); -inf for cells without tetrahedra.
std::vector<double> cell_heights(const TetMesh& mesh, const Eigen::Vector4d& centre) {
  std::vector<double> d(mesh.cell_count(), -std::numeric_limits<double>::infinity());
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const std::uint32_t c = mesh.tet_cell[t];
    const Eigen::Vector4d n = mesh.cell_normals.col(c);
    for (int k = 0; k < 4; ++k) d[c] = std::max(d[c], n.dot(mesh.corner_position(t, k) - centre));
  }
  return d;
}

}  // namespace

bool SchlegelView::faces_eye(const TetMesh& mesh, std::uint32_t cell) const {
  return mesh.cell_normals.col(cell).dot(eye() - centre) > cell_heights(mesh, centre)[cell];
}

SchlegelView schlegel_view(const TetMesh& mesh) {
  if (mesh.size() == 0 || mesh.positions.cols() == 0)
    throw InputError("Schlegel view: the tetrahedral mesh is empty");
  SchlegelView v;
  v.centre = mesh.positions.rowwise().mean();
  const std::vector<double> d = cell_heights(mesh, v.centre);
  // The front cell: largest w component of the outward normal among the cells above the centre.
  bool found = false;
  for (std::uint32_t c = 0; c < d.size(); ++c) {
    if (!(d[c] > 0.0)) continue;
    if (!found || mesh.cell_normals(3, c) > mesh.cell_normals(3, v.front_cell)) v.front_cell = c;
    found = true;
  }
  if (!found) {  // no cell above the centre: take the highest one along its own normal
    for (std::uint32_t c = 0; c < d.size(); ++c)
      if (d[c] > d[v.front_cell]) v.front_cell = c;
  }
  v.normal = mesh.cell_normals.col(v.front_cell).normalized();
  // Everything must lie below the eye.
  double top = 0.0, radius = 0.0;
  for (Eigen::Index i = 0; i < mesh.positions.cols(); ++i) {
    top = std::max(top, v.normal.dot(mesh.positions.col(i) - v.centre));
    radius = std::max(radius, (mesh.positions.col(i) - v.centre).norm());
  }
  top = std::max(top, 1e-6 * radius);
  if (!(top > 0.0)) top = 1.0;
  // The eye sees cell j from outside once h (n_j . N) > d_j: stay below the lowest such h.
  double upper = 2.0 * top;
  for (std::uint32_t c = 0; c < d.size(); ++c) {
    if (c == v.front_cell || !(d[c] > 0.0)) continue;
    const double cosine = mesh.cell_normals.col(c).dot(v.normal);
    if (cosine > 0.0) upper = std::min(upper, d[c] / cosine);
  }
  v.eye_height = upper > top ? top + 0.5 * (upper - top) : 1.25 * top;
  v.basis = hyperplane_basis(v.normal);
  return v;
}

std::string vtu_text(const TetMesh& mesh, VtuEncoding enc) {
  const std::size_t nt = mesh.size();
  std::vector<double> points, pos4, nrm4, uvw;
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types, front;
  std::vector<std::int32_t> cells;
  points.reserve(12 * nt);
  const SchlegelView view = nt ? schlegel_view(mesh) : SchlegelView{};
  const std::vector<double> heights = cell_heights(mesh, view.centre);
  const Eigen::Vector4d eye = view.eye() - view.centre;
  for (std::size_t t = 0; t < nt; ++t) {
    const Eigen::Vector4d n = mesh.tet_normal(t);
    std::array<Eigen::Vector3d, 4> p;
    for (int k = 0; k < 4; ++k) p[k] = view.project(mesh.corner_position(t, k));
    // Corner order with a positive 3D volume (VTK's convention for VTK_TETRA).
    std::array<int, 4> order{0, 1, 2, 3};
    if ((p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) < 0.0) std::swap(order[1], order[2]);
    const std::uint32_t c = mesh.tet_cell[t];
    front.push_back(mesh.cell_normals.col(c).dot(eye) > heights[c] ? 1 : 0);
    for (int k : order) {
      const Eigen::Vector4d x = mesh.corner_position(t, k);
      const Eigen::Vector3d u = mesh.corner_uvw_of(t, k);
      for (int i = 0; i < 3; ++i) points.push_back(p[k](i));
      for (int i = 0; i < 4; ++i) pos4.push_back(x(i));
      for (int i = 0; i < 4; ++i) nrm4.push_back(n(i));
      for (int i = 0; i < 3; ++i) uvw.push_back(u(i));
      connectivity.push_back(static_cast<std::int64_t>(connectivity.size()));
    }
    offsets.push_back(static_cast<std::int64_t>(4 * (t + 1)));
    types.push_back(10);  // VTK_TETRA
    cells.push_back(static_cast<std::int32_t>(mesh.tet_cell[t]));
  }
  std::ostringstream o;
  o << std::setprecision(17);
  o << "<?xml version=\"1.0\"?>\n"
    << "<!-- cw4d tetrahedral mesh: 4 unshared corners per tetrahedron; points: the Schlegel "
       "diagram seen from "
    << view.eye().transpose() << " (front cell " << view.front_cell
    << "); point data position4, normal4 (outward 4D normal of the source cell), uvw; cell "
       "data cell (source 3-cell), front (1: a cell facing the eye) -->\n"
    << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\""
    << (enc == VtuEncoding::Base64 ? " header_type=\"UInt64\"" : "") << ">\n"
    << "  <UnstructuredGrid>\n"
    << "    <Piece NumberOfPoints=\"" << 4 * nt << "\" NumberOfCells=\"" << nt << "\">\n"
    << "      <PointData Scalars=\"\" Vectors=\"\">\n";
  data_array(o, "Float64", "position4", 4, pos4, enc);
  data_array(o, "Float64", "normal4", 4, nrm4, enc);
  data_array(o, "Float64", "uvw", 3, uvw, enc);
  o << "      </PointData>\n      <CellData>\n";
  data_array(o, "Int32", "cell", 1, cells, enc);
  if (enc == VtuEncoding::Ascii) {
    std::vector<int> f(front.begin(), front.end());  // print numbers, not characters
    data_array(o, "UInt8", "front", 1, f, enc);
  } else {
    data_array(o, "UInt8", "front", 1, front, enc);
  }
  o << "      </CellData>\n      <Points>\n";
  data_array(o, "Float64", "Points", 3, points, enc);
  o << "      </Points>\n      <Cells>\n";
  data_array(o, "Int64", "connectivity", 1, connectivity, enc);
  data_array(o, "Int64", "offsets", 1, offsets, enc);
  if (enc == VtuEncoding::Ascii) {
    std::vector<int> t(types.begin(), types.end());  // print numbers, not characters
    data_array(o, "UInt8", "types", 1, t, enc);
  } else {
    data_array(o, "UInt8", "types", 1, types, enc);
  }
  o << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  return o.str();
}

std::string tetgen_node_text(const TetMesh& mesh) {
  std::ostringstream o;
  o << std::setprecision(17);
  o << "# cw4d: vertices x y z, attribute w\n" << mesh.positions.cols() << " 3 1 0\n";
  for (Eigen::Index v = 0; v < mesh.positions.cols(); ++v) {
    const auto x = mesh.positions.col(v);
    o << v << ' ' << x(0) << ' ' << x(1) << ' ' << x(2) << ' ' << x(3) << '\n';
  }
  return o.str();
}

std::string tetgen_ele_text(const TetMesh& mesh) {
  std::ostringstream o;
  o << "# cw4d: tetrahedra (outward oriented in 4D), attribute: source cell\n"
    << mesh.size() << " 4 1\n";
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const auto& v = mesh.tets[t];
    o << t << ' ' << v[0] << ' ' << v[1] << ' ' << v[2] << ' ' << v[3] << ' ' << mesh.tet_cell[t]
      << '\n';
  }
  return o.str();
}

std::string fourdo_text(const TetMesh& mesh) {
  std::ostringstream o;
  o << std::setprecision(17);
  o << "4DO 1\n# cw4d tetrahedral mesh: " << mesh.positions.cols() << " vertices, " << mesh.size()
    << " tetrahedra, " << mesh.cell_count() << " cells\n";
  for (Eigen::Index v = 0; v < mesh.positions.cols(); ++v) {
    const auto x = mesh.positions.col(v);
    o << "v " << x(0) << ' ' << x(1) << ' ' << x(2) << ' ' << x(3) << '\n';
  }
  for (Eigen::Index c = 0; c < mesh.cell_normals.cols(); ++c) {
    const auto n = mesh.cell_normals.col(c);
    o << "vn " << n(0) << ' ' << n(1) << ' ' << n(2) << ' ' << n(3) << '\n';
  }
  for (Eigen::Index i = 0; i < mesh.corner_uvw.cols(); ++i) {
    const auto u = mesh.corner_uvw.col(i);
    o << "vt " << u(0) << ' ' << u(1) << ' ' << u(2) << '\n';
  }
  o << "tformat v/vn/vt\n";
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    o << 't';
    for (std::size_t k = 0; k < 4; ++k)
      o << ' ' << mesh.tets[t][k] << '/' << mesh.tet_cell[t] << '/' << 4 * t + k;
    o << '\n';
  }
  // Compound cells: the tetrahedra of each source cell (stored contiguously per cell).
  std::size_t t0 = 0;
  while (t0 < mesh.size()) {
    std::size_t t1 = t0;
    o << 'c';
    while (t1 < mesh.size() && mesh.tet_cell[t1] == mesh.tet_cell[t0]) o << ' ' << t1++;
    o << '\n';
    t0 = t1;
  }
  return o.str();
}

std::string gpu_buffer_bytes(const TetMesh& mesh) {
  std::string out;
  out.reserve(192 * mesh.size());
  for (std::size_t t = 0; t < mesh.size(); ++t) {
    const Eigen::Vector4d n = mesh.tet_normal(t);
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector4d x = mesh.corner_position(t, k);
      const Eigen::Vector3d u = mesh.corner_uvw_of(t, k);
      for (int i = 0; i < 4; ++i) append_raw(out, static_cast<float>(x(i)));
      for (int i = 0; i < 4; ++i) append_raw(out, static_cast<float>(n(i)));
      for (int i = 0; i < 3; ++i) append_raw(out, static_cast<float>(u(i)));
      append_raw(out, static_cast<float>(mesh.tet_cell[t]));
    }
  }
  return out;
}

std::string gpu_buffer_header(const TetMesh& mesh, const std::string& bin_name) {
  std::string escaped;
  for (char c : bin_name) {
    if (c == '"' || c == '\\') escaped += '\\';
    escaped += c;
  }
  std::ostringstream o;
  o << "{\n"
    << "  \"format\": \"cw4d-tet-gpu\",\n"
    << "  \"version\": 1,\n"
    << "  \"buffer\": \"" << escaped << "\",\n"
    << "  \"byte_order\": \"little\",\n"
    << "  \"tetrahedra\": " << mesh.size() << ",\n"
    << "  \"corners_per_tetrahedron\": 4,\n"
    << "  \"stride_bytes\": 48,\n"
    << "  \"byte_length\": " << 192 * mesh.size() << ",\n"
    << "  \"cells\": " << mesh.cell_count() << ",\n"
    << "  \"attributes\": [\n"
    << "    {\"name\": \"position\", \"type\": \"float32\", \"components\": 4, \"offset\": 0},\n"
    << "    {\"name\": \"normal\", \"type\": \"float32\", \"components\": 4, \"offset\": 16},\n"
    << "    {\"name\": \"uvw\", \"type\": \"float32\", \"components\": 4, \"offset\": 32, "
       "\"note\": \"u, v, w, source cell id\"}\n"
    << "  ]\n"
    << "}\n";
  return o.str();
}

G4mfSimplexMesh g4mf_simplex_mesh(const TetMesh& mesh, const std::vector<Rgba>& cell_colors) {
  // TetMesh orders corners by det(N, p1 - p0, p2 - p0, p3 - p0) > 0; G4MF (and godot-4d) take
  // perpendicular(p1 - p0, p2 - p0, p3 - p0) as the outward normal, and perpendicular(a, b, c)
  // . N = det(a, b, c, N) = -det(N, a, b, c): swapping the last two corners turns one order
  // into the other.
  constexpr int order[4] = {0, 1, 3, 2};
  G4mfSimplexMesh out;
  out.positions = mesh.positions;
  out.simplexes.reserve(4 * mesh.size());
  const bool uvw = mesh.corner_uvw.cols() == static_cast<Eigen::Index>(4 * mesh.size());
  if (uvw) out.corner_texture.resize(3, static_cast<Eigen::Index>(4 * mesh.size()));
  for (std::size_t t = 0; t < mesh.size(); ++t)
    for (int j = 0; j < 4; ++j) {
      out.simplexes.push_back(mesh.tets[t][static_cast<std::size_t>(order[j])]);
      if (uvw)
        out.corner_texture.col(static_cast<Eigen::Index>(4 * t) + j) =
            mesh.corner_uvw.col(static_cast<Eigen::Index>(4 * t) + order[j]).cast<float>();
    }
  out.simplex_cell = mesh.tet_cell;
  out.cell_normals = mesh.cell_normals;
  if (cell_colors.size() == mesh.cell_count()) out.cell_colors = cell_colors;
  return out;
}

bool is_tet_mesh_path(const std::string& path) {
  const std::string e = lower_ext(path);
  return e == ".vtu" || e == ".node" || e == ".ele" || e == ".4do" || e == ".bin" || e == ".json" ||
         e == ".g4tf" || e == ".g4b";
}

void write_tet_mesh(const std::string& path, const TetMesh& mesh, bool binary) {
  const std::string e = lower_ext(path);
  if (e == ".vtu") {
    write_file_atomically(path, vtu_text(mesh, binary ? VtuEncoding::Base64 : VtuEncoding::Ascii));
  } else if (e == ".node" || e == ".ele") {
    write_pair(with_ext(path, ".node"), tetgen_node_text(mesh), with_ext(path, ".ele"),
               tetgen_ele_text(mesh));
  } else if (e == ".4do") {
    write_file_atomically(path, fourdo_text(mesh));
  } else if (e == ".bin" || e == ".json") {
    const std::string bin = with_ext(path, ".bin");
    write_pair(bin, gpu_buffer_bytes(mesh), with_ext(path, ".json"),
               gpu_buffer_header(mesh, std::filesystem::path(bin).filename().string()));
  } else if (e == ".g4tf" || e == ".g4b") {
    G4mfWriteOptions options;
    options.container = e == ".g4b" ? G4mfContainer::binary : G4mfContainer::text_embedded;
    options.name = std::filesystem::path(path).stem().string();
    write_g4mf_simplex_file(path, g4mf_simplex_mesh(mesh), options);
  } else {
    throw InputError("cannot write a tetrahedral mesh as '" + path +
                     "': use .vtu, .node/.ele, .4do, .bin/.json or .g4tf/.g4b");
  }
}

}  // namespace cw4d
