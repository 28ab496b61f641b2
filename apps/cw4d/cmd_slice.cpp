// cw4d slice: cut a model or a scene with one hyperplane and write the section.
#include <iostream>

#include "cli.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/section/triangulate.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"
#include "output.hpp"

namespace cw4d::cli {

namespace {

struct SliceSettings {
  Placement placement;
  double offset = 0.0;
  bool triangulate = false;
  bool no_uvw = false;
  std::string format;         // --format, empty: from the extension
  std::string method = "cw";  // --method cw | tet
  std::string output;
};

void run_slice(SliceSettings& s) {
  s.placement.parse("slice");
  SectionOutput out;
  out.format = choose_format(s.output, s.format);
  out.triangulate = s.triangulate;
  out.uvw = !s.no_uvw;
  if (s.triangulate && out.format != SectionFormat::obj)
    throw InputError(
        "--triangulate applies to .obj output only (the other mesh formats are "
        "triangles already)");
  const Placement& p = s.placement;
  const Input input = load_input(p);
  check_format(out.format, input.dim(),
               p.input_label() + " lives in R^" + std::to_string(input.dim()));

  Cut cut_result;
  CornerUvw tet_uvw;
  if (s.method == "tet") {
    // The tetrahedral path: tetrahedralize the model, cut every tetrahedron; the texture
    // coordinates travel with the tetrahedra (interpolated along the cut edges).
    if (input.is_scene) throw InputError("--method tet cuts a single model, not a --scene");
    if (input.dim() != 4) throw InputError("--method tet needs a 4D model");
    const Complex& model = *input.models().front();
    TetSlicer slicer(TetSliceOptions{out.uvw});  // (--no-uvw: none computed)
    const TetSection ts =
        slicer.slice(tetrahedralize(model), p.plane(s.offset), p.model_to_world(4));
    cut_result.section = to_section(ts, model);
    if (out.uvw && !ts.empty()) {
      tet_uvw = tet_section_uvw(ts, cut_result.section);
      out.corner_uvw = &tet_uvw;
    }
  } else {
    cut_result = cut(input, p.plane(s.offset));
  }
  const Section& sec = cut_result.section;
  const std::string cut_text = "n=(" + join(p.normal, brief) + "), d=" + brief(s.offset);
  if (sec.empty())
    throw EmptySection("the plane " + cut_text +
                       (input.is_scene ? " misses every object of " : " misses ") +
                       p.input_label() + " (it meets " + offset_range(input, p.plane(s.offset)) +
                       "); nothing written to " + quote_user_text(s.output));

  out.comment = "cw4d slice of " + (input.is_scene ? "scene " + p.scene : p.model) +
                "\nplane: n=(" + join(p.normal, exact) + "), d=" + exact(s.offset) +
                " (world space, n normalized)";
  if (!input.is_scene) out.comment += "\nmodel-to-world:" + p.transform_text() + " (in this order)";
  const std::string written = describe_files(write_section(s.output, sec, input, out));

  std::string extra;
  if (s.triangulate)
    extra = " as " + std::to_string(triangulate_section(sec).size()) + " triangles";
  std::cout << "wrote " << written << ": " << describe_counts(sec.complex) << extra << ", volume "
            << brief(signed_volume(sec.complex));
  if (!input.is_scene) {
    std::cout << " (" << p.model << " cut by " << cut_text << ")\n";
    return;
  }
  std::cout << " (scene " << p.scene << ", " << input.scene.objects.size() << " objects, cut by "
            << cut_text << ")\n";
  const auto names = input.object_names();
  for (std::size_t i = 0; i < cut_result.pieces.size(); ++i) {
    const SceneObject& obj = input.scene.objects[i];
    const Complex& c = cut_result.pieces[i].complex;
    std::cout << "  object " << i << (obj.name.empty() ? "" : " '" + obj.name + "'") << " ("
              << obj.model << "): ";
    if (cut_result.pieces[i].empty())
      std::cout << "missed by the plane\n";
    else
      std::cout << describe_counts(c) << ", volume " << brief(signed_volume(c)) << '\n';
  }
}

}  // namespace

void add_slice_command(CLI::App& app, Commands& commands) {
  auto s = std::make_shared<SliceSettings>();
  auto* cmd =
      app.add_subcommand("slice", "Cut a model with the hyperplane n.x = d and write the section.");
  s->placement.add_options(*cmd);
  cmd->add_option("--offset", s->offset,
                  "Signed distance d of the plane from the origin along the unit normal")
      ->type_name("D")
      ->required();
  cmd->add_flag("--triangulate", s->triangulate,
                "Triangulate the polygons (OBJ only; polygons with holes always are)");
  cmd->add_option("--method", s->method,
                  "cw: the layered CW-complex section (polygons); tet: tetrahedralize the model "
                  "and cut each tetrahedron (triangles; UVW interpolated along the cut edges)")
      ->check(CLI::IsMember({"cw", "tet"}));
  cmd->add_flag(
      "--no-uvw", s->no_uvw,
      "Leave out the texture coordinates (OBJ vt, glTF TEXCOORD_0/_UVW, G4MF textureMap)");
  cmd->add_option("--format", s->format,
                  "Force the output format instead of taking it from the extension: obj, gltf, "
                  "glb, ply, stl, svg, 4off, g4tf, g4tf-bin, g4b")
      ->type_name("NAME");
  cmd->add_option("-o,--output", s->output,
                  "Output file: .obj, .gltf, .glb, .ply, .stl, .svg (a shaded picture), "
                  ".4off/.off/.noff, or .g4tf/.g4b (G4MF)")
      ->required();
  cmd->footer(
      "The model is placed by x_world = R_k ... R_1 x_model + t (R_1 = first --rotate) and cut\n"
      "in world space; a model in R^n takes n components in --normal and --translate.\n"
      "The output format follows the extension (or --format):\n"
      "  .obj   Wavefront: polygons with per-polygon normals, `vt u v w` texture coordinates,\n"
      "         a `g` group per source cell, a .mtl of the same name for colors; the outline\n"
      "         as line elements for a 3D model\n"
      "  .gltf  glTF 2.0 JSON with a .bin of the same name; .glb: one binary glTF file.\n"
      "         POSITION, NORMAL, COLOR_0 (cell colors), TEXCOORD_0 (u,v), _UVW, _CELL_ID;\n"
      "         one node per scene object\n"
      "  .ply   binary PLY, triangles with per-vertex colors; .stl: binary STL triangles\n"
      "  .svg   a flat-shaded picture of a 4D model's section\n"
      "  .4off/.off/.noff  the section as an nOFF complex\n"
      "  .g4tf  G4MF (godot-4d): the section as a 3D mesh with its topology (faces as edge\n"
      "         cycles), colors, normals and UVW, the buffer embedded (--format g4tf-bin: in a\n"
      "         .bin beside it); .g4b: binary G4MF\n"
      "Missing parent directories of the output are created.\n"
      "An empty section (the plane misses the model) writes nothing and exits 5.\n"
      "With --scene FILE every object of the scene is placed by its own transform and cut by the\n"
      "same plane; the pieces are written as one mesh with the objects' colors and a line per\n"
      "object is printed. Scene format, e.g.:\n"
      "  {\"objects\": [{\"model\": \"tesseract\", \"rotate\": [[\"xw\", 30]],\n"
      "                \"translate\": [1, 0, 0, 0], \"scale\": 0.5, \"color\": \"#ff8000\",\n"
      "                \"opacity\": 0.5, \"cell_colors\": {\"3\": [0, 0, 1]}, \"name\": \"a\"}]}\n"
      "(degrees; scale, then rotations in order, then translation; model paths are relative to\n"
      "the scene file). A malformed scene exits 2 naming file:line.\n"
      "Exit codes: see 'cw4d --help'.");
  commands.push_back({cmd, [s] { run_slice(*s); }});
}

}  // namespace cw4d::cli
