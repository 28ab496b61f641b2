// cw4d tetrahedralize: the tetrahedral mesh of a 4D model (with normals and UVW) for GPU slicers.
#include <iostream>

#include "cli.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/tetrahedralize/tet_io.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "output.hpp"

namespace cw4d::cli {

namespace {

struct TetSettings {
  std::string model;
  std::string output;
  std::string uvw = "auto";
  bool binary = false;
  bool no_cube_split = false;
};

void run_tetrahedralize(const TetSettings& s) {
  if (!is_tet_mesh_path(s.output))
    throw InputError("cannot write a tetrahedral mesh as '" + s.output +
                     "': use .vtu, .node/.ele, .4do, .bin/.json or .g4tf/.g4b");
  if (s.binary && lower_extension(s.output) != ".vtu")
    throw InputError("--binary applies to .vtu output only");
  TetOptions options;
  options.five_tet_cubes = !s.no_cube_split;
  const auto parametric = uvw_mapping_for_spec(s.model);
  if (s.uvw == "param") {
    if (!parametric)
      throw InputError(
          "--uvw param needs a model with parameters (glome:R,N, spherinder:R,N, "
          "duocylinder:R,N), not '" +
          s.model + "'");
    options.uvw = *parametric;
  } else if (s.uvw == "auto" && parametric) {
    options.uvw = *parametric;
  }
  const Complex model = load(s.model);
  require_valid(model, s.model);
  if (model.ambient_dim() != 4)
    throw InputError("tetrahedralize needs a 4D model; " + quote_user_text(s.model) +
                     " lives in R^" + std::to_string(model.ambient_dim()));
  TetStats stats;
  const TetMesh mesh = tetrahedralize(model, options, &stats);
  prepare_output_directory(s.output);
  const std::string ext = lower_extension(s.output);
  if (ext == ".g4tf" || ext == ".g4b") {
    // G4MF: the model's cell colors go along, per tetrahedron.
    G4mfWriteOptions opt;
    opt.container = ext == ".g4b" ? G4mfContainer::binary : G4mfContainer::text_embedded;
    opt.name = model_item_name(s.model);
    opt.description = "cw4d tetrahedralize of " + s.model;
    write_g4mf_simplex_file(s.output, g4mf_simplex_mesh(mesh, model.colors(3)), opt);
  } else {
    write_tet_mesh(s.output, mesh, s.binary);
  }
  std::cout << "wrote " << s.output << ": " << mesh.size() << " tetrahedra, "
            << mesh.positions.cols() << " vertices, from " << model.count(3) << " cells ("
            << stats.coned_cells << " coned, " << stats.cube_split_cells << " cubes split in 5, "
            << stats.tetgen_cells << " by TetGen with " << stats.steiner_points
            << " interior Steiner points); uvw "
            << (options.uvw.kind == UvwMapping::Kind::CellBox ? "box per cell" : "parametric")
            << '\n';
}

}  // namespace

void add_tetrahedralize_command(CLI::App& app, Commands& commands) {
  auto s = std::make_shared<TetSettings>();
  auto* cmd = app.add_subcommand(
      "tetrahedralize", "Write the tetrahedral mesh of a 4D model (positions, normals, UVW).");
  cmd->add_option("MODEL", s->model, "Model spec or file (see 'cw4d list')")->required();
  cmd->add_option("-o,--output", s->output,
                  "Output file: .vtu, .node/.ele, .4do, .bin/.json or .g4tf/.g4b")
      ->required();
  cmd->add_option("--uvw", s->uvw,
                  "Texture coordinates: box (each cell's box mapped to [0,1]^3), param (the "
                  "parameters of glome/spherinder/duocylinder), auto (param when available)")
      ->check(CLI::IsMember({"auto", "box", "param"}));
  cmd->add_flag("--binary", s->binary, "Base64-encoded binary DataArrays in .vtu (else ASCII)");
  cmd->add_flag("--no-cube-split", s->no_cube_split, "Cone cubes into 6 tetrahedra instead of 5");
  cmd->footer(
      "Convex cells are coned from one vertex over the triangles of the faces away from it;\n"
      "every face is triangulated once for the whole model, so the mesh is conforming. Cubes\n"
      "split into 5 tetrahedra (tesseract: 40). Non-convex cells go through TetGen (no Steiner\n"
      "points on cell boundaries); a cell TetGen rejects exits 3 naming the cell.\n"
      "Formats (by extension):\n"
      "  .vtu        VTK XML unstructured grid (ParaView): 4 corners per tetrahedron, point data\n"
      "              position4, normal4, uvw; cell data cell (source 3-cell)\n"
      "  .node/.ele  TetGen files (both written): x y z + w attribute; tetrahedra + source cell\n"
      "  .4do        HoxelDraw 4D OBJ (v, vn per cell, vt per corner, t v/vn/vt, c per cell)\n"
      "  .bin/.json  GPU buffer (both written): per tetrahedron 4 x (position vec4, normal vec4,\n"
      "              uvw vec4 with the cell id in w), float32 little endian, 192 bytes; the\n"
      "              .json header describes the layout\n"
      "  .g4tf/.g4b  G4MF (godot-4d's tetrahedral mesh): simplexes, cell normals per corner,\n"
      "              UVW per corner, cell colors per simplex; the .g4tf embeds its buffer\n"
      "Exit codes: see 'cw4d --help'.");
  commands.push_back({cmd, [s] { run_tetrahedralize(*s); }});
}

}  // namespace cw4d::cli
