#include "output.hpp"

#include <algorithm>
#include <array>
#include <filesystem>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/export/g4mf.hpp"
#include "cw4d/export/gltf.hpp"
#include "cw4d/export/mesh_files.hpp"
#include "cw4d/export/obj.hpp"
#include "cw4d/export/svg.hpp"
#include "cw4d/section/uvw.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"

namespace cw4d::cli {

namespace {

struct FormatEntry {
  SectionFormat format;
  const char* name;
  std::array<const char*, 3> extensions;  // the first is the usual one
};

constexpr FormatEntry kFormats[] = {
    {SectionFormat::obj, "obj", {".obj", nullptr, nullptr}},
    {SectionFormat::gltf, "gltf", {".gltf", nullptr, nullptr}},
    {SectionFormat::glb, "glb", {".glb", nullptr, nullptr}},
    {SectionFormat::ply, "ply", {".ply", nullptr, nullptr}},
    {SectionFormat::stl, "stl", {".stl", nullptr, nullptr}},
    {SectionFormat::svg, "svg", {".svg", nullptr, nullptr}},
    {SectionFormat::off, "4off", {".4off", ".off", ".noff"}},
    {SectionFormat::g4tf, "g4tf", {".g4tf", nullptr, nullptr}},
    {SectionFormat::g4tf_bin, "g4tf-bin", {".g4tf", nullptr, nullptr}},
    {SectionFormat::g4b, "g4b", {".g4b", nullptr, nullptr}},
};

const FormatEntry& entry(SectionFormat f) {
  for (const auto& e : kFormats)
    if (e.format == f) return e;
  return kFormats[0];
}

}  // namespace

const char* format_name(SectionFormat f) {
  return entry(f).name;
}

std::string format_extension(SectionFormat f) {
  return entry(f).extensions[0];
}

std::string supported_formats() {
  std::string out;
  for (const auto& e : kFormats) {
    if (!out.empty()) out += ", ";
    out += e.name;
  }
  return out + " (nOFF also as .off and .noff; g4tf-bin: a .g4tf with its buffer in a .bin)";
}

bool is_g4mf(SectionFormat f) {
  return f == SectionFormat::g4tf || f == SectionFormat::g4tf_bin || f == SectionFormat::g4b;
}

G4mfContainer g4mf_container(SectionFormat f) {
  return f == SectionFormat::g4b        ? G4mfContainer::binary
         : f == SectionFormat::g4tf_bin ? G4mfContainer::text_external
                                        : G4mfContainer::text_embedded;
}

SectionFormat choose_format(const std::string& path, const std::string& forced) {
  const std::string ext = lower_extension(path);
  const FormatEntry* by_extension = nullptr;
  for (const auto& e : kFormats)
    for (const char* x : e.extensions)
      if (x && ext == x && !by_extension) by_extension = &e;
  if (!forced.empty()) {
    for (const auto& e : kFormats)
      if (forced == e.name ||
          (e.format == SectionFormat::off && (forced == "off" || forced == "noff"))) {
        // An extension that names another format would mislead whoever opens the file (two
        // formats share .g4tf: the buffer embedded or beside it).
        const bool same_extension = std::any_of(e.extensions.begin(), e.extensions.end(),
                                                [&](const char* x) { return x && ext == x; });
        if (by_extension && by_extension->format != e.format && !same_extension)
          throw InputError("--format " + forced + " contradicts the extension of " +
                           quote_user_text(path) + " (" + by_extension->name +
                           "): name the file ." + std::string(e.extensions[0] + 1) +
                           " or drop --format");
        return e.format;
      }
    throw InputError("--format " + forced + ": unknown format; supported: " + supported_formats());
  }
  if (by_extension) return by_extension->format;
  throw InputError("cannot tell the format of " + quote_user_text(path) + " from its extension" +
                   (ext.empty() ? "" : " " + quote_user_text(ext)) +
                   ": supported: " + supported_formats() + "; or give --format");
}

void check_format(SectionFormat f, int dim, const std::string& where) {
  // The section lives in R^(dim-1); each writer holds only some dimensions. A 3D model's
  // section is a polygon outline: an OBJ of `l` line elements.
  switch (f) {
    case SectionFormat::obj:
      if (dim != 4 && dim != 3)
        throw InputError("OBJ output holds sections of 3D and 4D models; " + where +
                         (dim > 4 ? " (write .4off instead)" : ""));
      break;
    case SectionFormat::off:
      if (dim < 4 || dim > 10)
        throw InputError("nOFF holds sections of 4D..10D models; " + where +
                         " (write .obj instead)");
      break;
    case SectionFormat::svg:
      if (dim != 4) throw InputError("SVG pictures show 3D sections of 4D models; " + where);
      break;
    case SectionFormat::g4tf:
    case SectionFormat::g4tf_bin:
    case SectionFormat::g4b:
      if (dim < 3 || dim > 17)
        throw InputError("G4MF output holds sections of 3D..17D models; " + where);
      break;
    default:
      if (dim != 4)
        throw InputError(std::string(format_name(f)) + " output holds 3D sections of 4D models; " +
                         where);
  }
}

std::vector<TriangleMesh> section_meshes(const Section& sec, const Input& input, bool uvw,
                                         const CornerUvw* corner_uvw) {
  CornerUvw corners;
  if (uvw && !corner_uvw) corners = section_uvw(sec, input.models());
  return triangle_meshes(sec, input.object_names(),
                         uvw ? (corner_uvw ? corner_uvw : &corners) : nullptr);
}

std::string model_item_name(const std::string& spec) {
  if (is_builtin_spec(spec, default_catalogue())) return spec;
  return std::filesystem::path(spec).stem().string();
}

std::string describe_files(const std::vector<std::string>& files) {
  std::string out;
  for (std::size_t i = 0; i < files.size(); ++i) out += (i ? " and " : "") + files[i];
  return out;
}

std::vector<std::string> write_section(const std::string& path, const Section& sec,
                                       const Input& input, const SectionOutput& out) {
  namespace fs = std::filesystem;
  prepare_output_directory(path);
  switch (out.format) {
    case SectionFormat::obj: {
      ObjOptions opt;
      opt.triangulate = out.triangulate;
      opt.comment = out.comment;
      opt.object_names = input.object_names();
      CornerUvw corners;
      if (out.uvw && sec.complex.ambient_dim() == 3 && sec.complex.top_rank() >= 2) {
        if (!out.corner_uvw) corners = section_uvw(sec, input.models());
        opt.uvw = out.corner_uvw ? out.corner_uvw : &corners;
      }
      write_obj_file(path, sec, opt);
      if (!mtl_text(sec.complex).empty())
        return {path, fs::path(path).replace_extension(".mtl").string()};
      return {path};
    }
    case SectionFormat::gltf:
    case SectionFormat::glb: {
      GltfOptions opt;
      opt.binary = out.format == SectionFormat::glb;
      opt.description = out.comment;
      std::vector<GltfNode> nodes;
      for (auto& mesh : section_meshes(sec, input, out.uvw, out.corner_uvw)) {
        GltfNode node;
        node.name = mesh.name;
        node.meshes.push_back(std::move(mesh));
        nodes.push_back(std::move(node));
      }
      write_gltf_file(path, nodes, opt);
      if (opt.binary) return {path};
      return {path, fs::path(path).replace_extension(".bin").string()};
    }
    case SectionFormat::ply:
      write_ply_file(path, section_meshes(sec, input, false));
      return {path};
    case SectionFormat::stl:
      write_stl_file(path, section_meshes(sec, input, false));
      return {path};
    case SectionFormat::svg:
      write_svg_file(path, sec);
      return {path};
    case SectionFormat::off:
      write_off_file(path, sec.complex);
      return {path};
    case SectionFormat::g4tf:
    case SectionFormat::g4tf_bin:
    case SectionFormat::g4b: {
      G4mfWriteOptions opt;
      opt.container = g4mf_container(out.format);
      const auto names = input.object_names();
      opt.name =
          input.is_scene || names.empty() ? "section" : model_item_name(names.front()) + " section";
      opt.description = out.comment;
      CornerUvw corners;
      const CornerUvw* uvw = nullptr;
      if (out.uvw && sec.complex.ambient_dim() == 3 && sec.complex.top_rank() >= 2) {
        if (!out.corner_uvw) corners = section_uvw(sec, input.models());
        uvw = out.corner_uvw ? out.corner_uvw : &corners;
      }
      return write_g4mf_section_file(path, sec, opt, uvw);
    }
  }
  return {path};
}

}  // namespace cw4d::cli
