#include "cw4d/export/obj.hpp"

#include <charconv>
#include <string>
#include <vector>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/error.hpp"

namespace cw4d {

namespace {

void number(std::string& out, double v) {
  char buf[64];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  out.push_back(' ');
  out.append(buf, ptr);
}

std::string write(const Complex& c, const std::vector<std::uint32_t>* group_of_face,
                  const ObjOptions& opt) {
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
  std::uint32_t current_group = 0xffffffffu;
  auto corner = [&](std::uint32_t v, std::uint32_t f) {
    out += ' ' + std::to_string(v + 1);
    if (normals) out += "//" + std::to_string(f + 1);
  };
  for (std::uint32_t f = 0; f < nf; ++f) {
    if (group_of_face && opt.group_by_source && (*group_of_face)[f] != current_group) {
      current_group = (*group_of_face)[f];
      out += "g cell_" + std::to_string(current_group) + "\n";
    }
    const auto cyc = c.face_cycle(f);
    if (opt.triangulate) {
      for (std::size_t k = 1; k + 1 < cyc.size(); ++k) {
        out += 'f';
        corner(cyc[0], f);
        corner(cyc[k], f);
        corner(cyc[k + 1], f);
        out += '\n';
      }
    } else {
      out += 'f';
      for (auto v : cyc) corner(v, f);
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
  const std::vector<std::uint32_t>* groups =
      section.source.size() > 2 && section.source[2].size() == section.complex.count(2)
          ? &section.source[2]
          : nullptr;
  return write(section.complex, groups, options);
}

void write_obj_file(const std::string& path, const Section& section, const ObjOptions& options) {
  write_file_atomically(path, obj_text(section, options));
}

}  // namespace cw4d
