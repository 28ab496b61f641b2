#pragma once
// Writing a section in the format its output path asks for (slice and sweep).
#include <string>
#include <vector>

#include "cli.hpp"
#include "cw4d/complex/g4mf.hpp"
#include "cw4d/export/mesh.hpp"
#include "cw4d/section/uvw.hpp"

namespace cw4d::cli {

enum class SectionFormat { obj, gltf, glb, ply, stl, svg, off, g4tf, g4tf_bin, g4b };

/// "obj", "gltf", ...
const char* format_name(SectionFormat f);
/// "obj, gltf, glb, ply, stl, svg, 4off, g4tf, g4tf-bin, g4b (...)" for help texts and errors.
std::string supported_formats();
/// True for the three G4MF formats.
bool is_g4mf(SectionFormat f);
/// The G4MF container of a G4MF format.
G4mfContainer g4mf_container(SectionFormat f);
/// The format named by --format (when not empty), else by the extension of `path` (.g4tf is
/// g4tf, the buffer embedded; --format g4tf-bin writes it beside the .g4tf as a .bin).
/// \throw InputError naming the supported formats.
SectionFormat choose_format(const std::string& path, const std::string& forced);
/// The usual file extension (".obj", ".4off", ...).
std::string format_extension(SectionFormat f);
/// The checks of a format against the input: mesh formats hold sections of 4D models (OBJ also
/// of 3D ones), nOFF of 4D..10D ones, G4MF of 3D..17D ones. \throw InputError
void check_format(SectionFormat f, int dim, const std::string& where);

struct SectionOutput {
  SectionFormat format = SectionFormat::obj;
  bool triangulate = false;  ///< OBJ: triangles instead of polygons
  bool uvw = true;           ///< OBJ, glTF and G4MF: texture coordinates
  std::string comment;       ///< OBJ header, glTF and G4MF asset description
  /// OBJ and glTF: these texture coordinates instead of section_uvw's (the tetrahedral path's
  /// sections carry their own); null: section_uvw.
  const CornerUvw* corner_uvw = nullptr;
};

/// Writes `sec` (cut from `input`) to `path`, through temporary files and renames.
/// \return the files written, e.g. {"a.obj", "a.mtl"}.
std::vector<std::string> write_section(const std::string& path, const Section& sec,
                                       const Input& input, const SectionOutput& out);

/// The name G4MF items are given for a model spec: the spec, or a file's stem.
std::string model_item_name(const std::string& spec);

/// "a.obj and a.mtl"
std::string describe_files(const std::vector<std::string>& files);

/// The glTF meshes of one section (per object), with UVW when asked.
std::vector<TriangleMesh> section_meshes(const Section& sec, const Input& input, bool uvw,
                                         const CornerUvw* corner_uvw = nullptr);

}  // namespace cw4d::cli
