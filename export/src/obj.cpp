#include "cw4d/export/obj.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/section/triangulate.hpp"

namespace cw4d {

namespace {

void number(std::string& out, double v) {
  char buf[64];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  out.push_back(' ');
  out.append(buf, ptr);
}

// Colors are floats: their shortest form, not that of the double they widen to.
void number(std::string& out, float v) {
  char buf[64];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  out.push_back(' ');
  out.append(buf, ptr);
}

// Distinct face colors in order of first use, and each face's index among them.
struct Materials {
  std::vector<Rgba> colors;
  std::vector<std::uint32_t> of_face;
};

Materials materials(const Complex& c) {
  Materials m;
  const std::size_t nf = c.top_rank() >= 2 ? c.count(2) : 0;
  const auto& colors = c.colors(2);
  if (nf == 0 || colors.size() != nf) return m;
  for (const Rgba& col : colors) {
    auto it = std::find(m.colors.begin(), m.colors.end(), col);
    if (it == m.colors.end()) it = m.colors.insert(m.colors.end(), col);
    m.of_face.push_back(static_cast<std::uint32_t>(it - m.colors.begin()));
  }
  return m;
}

// group_of_face: a label per face ("cell_3"); a new `g` line starts where the label changes.
// holes: per face, the faces that are holes in it (section_holes); empty for none. A face with
// holes is written as the triangles of ear_clip_triangulate (OBJ polygons have no holes), and
// the hole faces themselves are not written.
// object_of_face: the scene object of each face (Section::object_of_face, contiguous per
// object) or null; an `o object_<i>` line starts each object, so importers that make one
// object per `o` (Blender) keep the scene's objects apart.
std::string write(const Complex& c, const std::vector<std::string>* group_of_face,
                  const ObjOptions& opt, const std::vector<std::vector<std::uint32_t>>& holes = {},
                  const std::vector<std::uint32_t>* object_of_face = nullptr) {
  const int dim = c.ambient_dim();
  if (dim != 2 && dim != 3)
    throw InputError("OBJ holds 3D geometry; this complex lives in R^" + std::to_string(dim) +
                     " (write .4off instead)");
  std::string out;
  if (!opt.comment.empty()) {
    std::size_t start = 0;
    while (start <= opt.comment.size()) {
      std::size_t end = opt.comment.find('\n', start);
      if (end == std::string::npos) end = opt.comment.size();
      out += "# " + opt.comment.substr(start, end - start) + "\n";
      start = end + 1;
    }
  }
  const auto& p = c.positions();
  for (Eigen::Index v = 0; v < p.cols(); ++v) {
    out += 'v';
    for (int i = 0; i < 3; ++i) number(out, i < dim ? p(i, v) : 0.0);
    out += '\n';
  }
  const std::size_t nf = c.top_rank() >= 2 ? c.count(2) : 0;
  const bool normals = dim == 3 && c.has_facet_normals() && nf > 0;
  if (normals) {
    for (std::uint32_t f = 0; f < nf; ++f) {
      out += "vn";
      for (int i = 0; i < 3; ++i) number(out, c.facet_normals()(i, f));
      out += '\n';
    }
  }
  if (nf == 0) {
    // A section of a 3D model is a polygon outline: its edges as OBJ line elements.
    for (std::uint32_t e = 0; e < (c.top_rank() >= 1 ? c.count(1) : 0); ++e) {
      const auto ends = c.edge(e);
      out += "l " + std::to_string(ends[0] + 1) + ' ' + std::to_string(ends[1] + 1) + '\n';
    }
    return out;
  }
  const bool uvw = opt.uvw != nullptr;
  if (uvw) {
    if (opt.uvw->offset.size() != nf + 1 || opt.uvw->uvw.cols() != opt.uvw->offset[nf])
      throw InputError("OBJ: the texture coordinates do not belong to this complex");
    for (Eigen::Index k = 0; k < opt.uvw->uvw.cols(); ++k) {
      out += "vt";
      for (Eigen::Index i = 0; i < opt.uvw->uvw.rows(); ++i) number(out, opt.uvw->uvw(i, k));
      out += '\n';
    }
  }
  const Materials mats = opt.material_library.empty() ? Materials{} : materials(c);
  if (!mats.colors.empty()) out += "mtllib " + opt.material_library + "\n";
  const std::string* current_group = nullptr;
  std::uint32_t current_material = no_index;
  // Corner j of face f (its position in face_cycle(f)) is vertex v.
  auto corner = [&](std::uint32_t v, std::uint32_t f, std::size_t j) {
    out += ' ' + std::to_string(v + 1);
    if (uvw) out += '/' + std::to_string(opt.uvw->offset[f] + j + 1);
    if (normals) out += (uvw ? "/" : "//") + std::to_string(f + 1);
  };
  // Faces written as triangles: all with --triangulate, else those with holes.
  std::vector<bool> is_hole(nf, false), as_triangles(nf, opt.triangulate);
  bool any_holes = false;
  for (std::uint32_t f = 0; f < holes.size(); ++f)
    for (std::uint32_t h : holes[f]) is_hole[h] = as_triangles[f] = any_holes = true;
  std::vector<std::vector<Triangle>> triangles_of(nf);
  if (opt.triangulate || any_holes)
    for (const Triangle& t : ear_clip_triangulate(c, holes)) triangles_of[t.face].push_back(t);
  // The corner of triangle vertex v: in face f, else in one of its holes.
  auto triangle_corner = [&](std::uint32_t v, std::uint32_t f) {
    for (std::size_t k = 0; k <= (holes.empty() ? 0 : holes[f].size()); ++k) {
      const std::uint32_t g = k == 0 ? f : holes[f][k - 1];
      const auto cyc = c.face_cycle(g);
      const auto at = std::find(cyc.begin(), cyc.end(), v);
      if (at != cyc.end()) return corner(v, g, static_cast<std::size_t>(at - cyc.begin()));
    }
    throw InputError("OBJ: a triangle names a vertex outside its face");
  };
  std::uint32_t current_object = no_index;
  for (std::uint32_t f = 0; f < nf; ++f) {
    if (is_hole[f]) continue;
    if (object_of_face && (*object_of_face)[f] != current_object) {
      current_object = (*object_of_face)[f];
      std::string name = current_object < opt.object_names.size() ? opt.object_names[current_object]
                                                                  : std::string();
      for (char& ch : name)
        if (ch == '\n' || ch == '\r') ch = ' ';
      if (name.empty()) name = "object_" + std::to_string(current_object);
      out += "o " + name + "\n";
      current_group = nullptr;
      current_material = no_index;
    }
    if (group_of_face && opt.group_by_source &&
        (!current_group || (*group_of_face)[f] != *current_group)) {
      current_group = &(*group_of_face)[f];
      out += "g " + *current_group + "\n";
      current_material = no_index;  // some readers reset the material per group
    }
    if (!mats.colors.empty() && mats.of_face[f] != current_material) {
      current_material = mats.of_face[f];
      out += "usemtl color_" + std::to_string(current_material) + "\n";
    }
    const auto cyc = c.face_cycle(f);
    if (as_triangles[f]) {
      for (const Triangle& t : triangles_of[f]) {
        out += 'f';
        for (std::uint32_t v : t.v) triangle_corner(v, f);
        out += '\n';
      }
    } else {
      out += 'f';
      for (std::size_t j = 0; j < cyc.size(); ++j) corner(cyc[j], f, j);
      out += '\n';
    }
  }
  return out;
}

}  // namespace

std::string obj_text(const Complex& complex, const ObjOptions& options) {
  return write(complex, nullptr, options);
}

std::string obj_text(const Section& section, const ObjOptions& options) {
  const std::size_t nf = section.complex.count(2);
  if (section.source.size() <= 2 || section.source[2].size() != nf)
    return write(section.complex, nullptr, options);
  // Cell ids repeat between the objects of a scene, so their groups name the object too.
  const bool objects = section.object_of_face.size() == nf;
  std::vector<std::string> groups(nf);
  for (std::uint32_t f = 0; f < nf; ++f)
    groups[f] = (objects ? "object_" + std::to_string(section.object_of_face[f]) + "_" : "") +
                "cell_" + std::to_string(section.source[2][f]);
  return write(section.complex, &groups, options, section_holes(section),
               objects ? &section.object_of_face : nullptr);
}

std::string mtl_text(const Complex& complex) {
  const Materials mats = materials(complex);
  if (mats.colors.empty()) return {};
  std::string out = "# cw4d face colors\n";
  for (std::size_t k = 0; k < mats.colors.size(); ++k) {
    const Rgba& col = mats.colors[k];
    out += "\nnewmtl color_" + std::to_string(k) + "\nKd";
    number(out, col.r);
    number(out, col.g);
    number(out, col.b);
    out += "\nd";
    number(out, col.a);
    out += "\nillum 1\n";  // diffuse only
  }
  return out;
}

void write_obj_file(const std::string& path, const Section& section, const ObjOptions& options) {
  const std::string mtl = mtl_text(section.complex);
  if (mtl.empty()) {
    write_file_atomically(path, obj_text(section, options));
    return;
  }
  namespace fs = std::filesystem;
  const fs::path mtl_path = fs::path(path).replace_extension(".mtl");
  if (mtl_path == fs::path(path))
    throw InputError("cannot write " + quote_user_text(path) +
                     ": its materials would go to the same file");
  ObjOptions opt = options;
  opt.material_library = mtl_path.filename().string();
  const std::string obj = obj_text(section, opt);  // may throw: before anything is written
  write_files_atomically({{mtl_path.string(), mtl}, {path, obj}});
}

}  // namespace cw4d
