// The cw4d command line: list built-in models, report on a model, slice it, convert it.
//
// Options are parsed into one settings struct per subcommand and checked before any model is
// loaded; every failure class maps to one documented exit code (see kExitCodes below), and
// every error is a single "cw4d: error: ..." line on stderr.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <ios>
#include <iostream>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/export/obj.hpp"
#include "cw4d/export/svg.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/scene_section.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/tetrahedralize/hull.hpp"

namespace {

namespace fs = std::filesystem;

enum class Exit : int {
  ok = 0,
  usage = 1,            // bad command line, bad option value, unknown model spec
  bad_input = 2,        // an input file could not be parsed
  invalid_complex = 3,  // the model failed validation (or the library found broken topology)
  cannot_write = 4,     // the output could not be written
  empty_section = 5,    // the plane misses the model: nothing written
  internal = 6,         // anything unexpected (a bug, out of memory)
};

constexpr const char* kExitCodes =
    "Exit codes:\n"
    "  0  success (info also exits 0 for an invalid model: it reports \"valid\": false)\n"
    "  1  usage error: bad option or value, unknown model spec\n"
    "  2  an input file cannot be read or parsed (message names file:line)\n"
    "  3  the model is not a valid complex (validation failed)\n"
    "  4  the output cannot be written (nothing is left half-written)\n"
    "  5  the section is empty: the plane misses the model, nothing is written\n"
    "  6  internal error (a bug in cw4d, or out of memory)\n"
    "Errors are printed as one line on stderr: \"cw4d: error: <message>\".";

// Thrown for the empty-section outcome so that main() maps it like every other failure.
class EmptySection : public cw4d::Error {
 public:
  using Error::Error;
};

// --- settings, one per subcommand ---------------------------------------------------------

struct InfoSettings {
  std::string model;
  bool json = false;
};

struct Rotation {
  std::string text;  // as given, for messages and the OBJ header
  int axis_i = 0, axis_j = 1;
  double degrees = 0.0;
};

enum class Format { obj, off, svg };

struct SliceSettings {
  std::string model;
  std::string scene;  // a scene file instead of a model (exactly one of the two is given)
  std::vector<double> normal;
  double offset = 0.0;
  std::vector<Rotation> rotations;  // applied in the order given
  std::vector<double> translate;    // empty = none
  bool triangulate = false;
  std::string output;
  Format format = Format::obj;
};

// slice's options as typed, before parse_slice_settings turns them into SliceSettings.
struct SliceArgs {
  std::string normal, translate;
  std::vector<std::string> rotate;
};

struct ConvertSettings {
  std::string model;
  std::string output;
};

// --- parsing helpers -----------------------------------------------------------------------

std::string one_line(std::string s) {
  for (auto& ch : s)
    if (ch == '\n' || ch == '\r') ch = ' ';
  return s;
}

// Shortest round-trip text of a double (for the OBJ header).
std::string exact(double v) {
  char buf[64];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, ptr);
}

// Six significant digits (for messages).
std::string brief(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

std::string join(const std::vector<double>& values, std::string (*fmt)(double)) {
  std::string out;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) out += ',';
    out += fmt(values[i]);
  }
  return out;
}

double parse_number(std::string_view text, const std::string& what) {
  // from_chars rejects a leading '+'; accept it since people type it.
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double v = 0.0;
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size())
    throw cw4d::InputError(what + ": '" + std::string(text) + "' is not a number");
  if (!std::isfinite(v))
    throw cw4d::InputError(what + ": '" + std::string(text) + "' is not finite");
  return v;
}

// "x,y,z,w" -> numbers (the count is checked against the model's dimension later).
std::vector<double> parse_vector(const std::string& text, const std::string& option) {
  std::vector<double> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    out.push_back(parse_number(std::string_view(text).substr(start, comma - start),
                               option + " component " + std::to_string(out.size() + 1)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

Rotation parse_rotation(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos)
    throw cw4d::InputError("--rotate '" + text + "': expected PLANE:DEGREES, e.g. xw:30");
  Rotation r;
  r.text = text;
  std::tie(r.axis_i, r.axis_j) = cw4d::parse_rotation_plane(text.substr(0, colon));
  r.degrees = parse_number(std::string_view(text).substr(colon + 1), "--rotate '" + text + "'");
  return r;
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

bool is_off_extension(const std::string& ext) {
  return ext == ".4off" || ext == ".off" || ext == ".noff";
}

// --- shared steps --------------------------------------------------------------------------

std::string rank_name(int rank, std::size_t count) {
  static const char* singular[] = {"vertex", "edge", "face", "cell"};
  static const char* plural[] = {"vertices", "edges", "faces", "cells"};
  if (rank < 4) return count == 1 ? singular[rank] : plural[rank];
  return "rank-" + std::to_string(rank) + (count == 1 ? " element" : " elements");
}

// "12 vertices, 18 edges, 8 faces"
std::string describe_counts(const cw4d::Complex& c) {
  std::string out;
  const auto f = c.fvector();
  for (std::size_t k = 0; k < f.size(); ++k) {
    if (k) out += ", ";
    out += std::to_string(f[k]) + " " + rank_name(static_cast<int>(k), f[k]);
  }
  return out;
}

// load_model reports unreadable files as ParseError, except read failures after a successful
// open (a directory given as the model), which libstdc++ raises as std::ios_base::failure.
cw4d::Complex load(const std::string& spec) {
  try {
    return cw4d::load_model(spec);
  } catch (const std::ios_base::failure& e) {
    throw cw4d::ParseError(spec, 0, std::string("cannot read: ") + e.what());
  }
}

// Invalid models stop slice and convert: a broken complex gives meaningless sections/files.
void require_valid(const cw4d::Complex& model, const std::string& spec) {
  const cw4d::ValidationReport report = cw4d::validate(model);
  if (report.ok()) return;
  const auto& first = report.issues.front();
  throw cw4d::TopologyError(first.rank, {first.id},
                            "model '" + spec + "' is not a valid complex: " + report.summary());
}

// Creating missing parent directories is a convenience (documented in --help); failing to
// create them is a write failure like any other.
void prepare_output_directory(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  if (parent.empty()) return;
  std::error_code ec;
  if (fs::is_directory(parent, ec)) return;
  fs::create_directories(parent, ec);
  if (ec || !fs::is_directory(parent))
    throw cw4d::IoError("cannot write '" + path + "': cannot create directory '" + parent.string() +
                        "'" + (ec ? ": " + ec.message() : ""));
}

// --- subcommands ---------------------------------------------------------------------------

void run_list() {
  std::size_t width = 0;
  for (const auto& b : cw4d::builtin_list()) width = std::max(width, b.spec.size());
  for (const auto& b : cw4d::builtin_list())
    std::cout << b.spec << std::string(width + 2 - b.spec.size(), ' ') << b.description << '\n';
}

void run_info(const InfoSettings& s) {
  const cw4d::Complex model = load(s.model);
  const cw4d::ValidationReport report = cw4d::validate(model);
  const int dim = model.ambient_dim();
  const auto fvec = model.fvector();
  std::vector<double> lo(dim, 0.0), hi(dim, 0.0);
  if (!model.empty()) {
    const cw4d::Bounds b = cw4d::bounds(model);
    for (int i = 0; i < dim; ++i) {
      lo[i] = b.min(i);
      hi[i] = b.max(i);
    }
  }
  // The enclosed volume only means something for a valid closed complex.
  std::optional<double> volume;
  if (report.ok()) volume = cw4d::signed_volume(model);

  if (s.json) {
    nlohmann::ordered_json j;
    j["model"] = s.model;
    j["dimension"] = dim;
    j["fvector"] = fvec;
    j["valid"] = report.ok();
    j["summary"] = report.summary();
    j["issues"] = nlohmann::ordered_json::array();
    for (const auto& issue : report.issues) j["issues"].push_back(issue.what);
    j["bounds"] = {{"min", lo}, {"max", hi}};
    j["volume"] = volume ? nlohmann::ordered_json(*volume) : nlohmann::ordered_json(nullptr);
    std::cout << j.dump(2) << '\n';
    return;
  }
  std::string counts, names;
  for (std::size_t k = 0; k < fvec.size(); ++k) {
    if (k) counts += ", ", names += ", ";
    counts += std::to_string(fvec[k]);
    names += rank_name(static_cast<int>(k), 2);
  }
  std::cout << "model      " << s.model << '\n'
            << "dimension  " << dim << '\n'
            << "f-vector   (" << counts << ")  [" << names << "]\n"
            << "valid      " << (report.ok() ? "yes" : "no: " + report.summary()) << '\n'
            << "bounds     min (" << join(lo, brief) << ")  max (" << join(hi, brief) << ")\n"
            << "volume     " << (volume ? brief(*volume) : "n/a (invalid complex)") << '\n';
}

// Checks that need the model's dimension.
void check_against_model(const SliceSettings& s, int dim) {
  const std::string where = (s.scene.empty() ? "model '" + s.model : "scene '" + s.scene) +
                            "' lives in R^" + std::to_string(dim);
  if (s.normal.size() != static_cast<std::size_t>(dim))
    throw cw4d::InputError("--normal has " + std::to_string(s.normal.size()) + " components but " +
                           where + ": give " + std::to_string(dim) + " comma-separated numbers");
  if (!s.translate.empty() && s.translate.size() != static_cast<std::size_t>(dim))
    throw cw4d::InputError("--translate has " + std::to_string(s.translate.size()) +
                           " components but " + where);
  for (const auto& r : s.rotations)
    if (r.axis_i >= dim || r.axis_j >= dim)
      throw cw4d::InputError("--rotate " + r.text + ": " + where + ", which has no such axis");
  // The section lives in R^(dim-1); each writer holds only some dimensions.
  // A 3D model's section is a polygon outline: an OBJ of `l` line elements.
  if (s.format == Format::obj && dim != 4 && dim != 3)
    throw cw4d::InputError("OBJ output holds sections of 3D and 4D models; " + where +
                           (dim > 4 ? " (write .4off instead)" : ""));
  if (s.format == Format::svg && dim != 4)
    throw cw4d::InputError("SVG pictures show 3D sections of 4D models; " + where);
  if (s.format == Format::off && (dim < 4 || dim > 10))
    throw cw4d::InputError("nOFF holds sections of 4D..10D models; " + where +
                           " (write .obj instead)");
}

cw4d::AffineTransform model_to_world(const SliceSettings& s, int dim) {
  cw4d::AffineTransform m = cw4d::AffineTransform::identity(dim);
  for (const auto& r : s.rotations)
    m = cw4d::AffineTransform::rotation(dim, r.axis_i, r.axis_j,
                                        r.degrees * std::numbers::pi / 180.0) *
        m;
  if (!s.translate.empty())
    m = cw4d::AffineTransform::translation(
            Eigen::Map<const Eigen::VectorXd>(s.translate.data(), dim)) *
        m;
  return m;
}

// "object 1 'left' (tesseract)"
std::string object_label(const cw4d::SceneObject& obj, std::size_t i) {
  return "object " + std::to_string(i) + (obj.name.empty() ? "" : " '" + obj.name + "'") + " (" +
         obj.model + ")";
}

void run_slice_scene(const SliceSettings& s) {
  const cw4d::Scene scene = cw4d::read_scene_file(s.scene);
  const int dim = scene.dim();
  check_against_model(s, dim);
  std::vector<const cw4d::Complex*> checked;  // objects share models: validate each once
  for (const auto& obj : scene.objects) {
    if (std::find(checked.begin(), checked.end(), obj.complex.get()) != checked.end()) continue;
    require_valid(*obj.complex, obj.model);
    checked.push_back(obj.complex.get());
  }
  const cw4d::Hyperplane plane =
      cw4d::Hyperplane::from(Eigen::Map<const Eigen::VectorXd>(s.normal.data(), dim), s.offset);
  const std::vector<cw4d::Section> pieces = cw4d::section_objects(scene, plane);
  const cw4d::Section sec = cw4d::merge_sections(scene, pieces);
  const std::string cut = "n=(" + join(s.normal, brief) + "), d=" + brief(s.offset);
  if (sec.empty())
    throw EmptySection("the plane " + cut + " misses every object of scene '" + s.scene +
                       "'; nothing written to '" + s.output + "'");

  prepare_output_directory(s.output);
  std::string written = s.output;
  if (s.format == Format::obj) {
    cw4d::ObjOptions opt;
    opt.triangulate = s.triangulate;
    opt.comment = "cw4d slice of scene " + s.scene + "\nplane: n=(" + join(s.normal, exact) +
                  "), d=" + exact(s.offset) + " (world space, n normalized)";
    cw4d::write_obj_file(s.output, sec, opt);
    if (!cw4d::mtl_text(sec.complex).empty())
      written += " and " + fs::path(s.output).replace_extension(".mtl").string();
  } else if (s.format == Format::svg) {
    cw4d::write_svg_file(s.output, sec);
  } else {
    cw4d::write_off_file(s.output, sec.complex);
  }
  std::cout << "wrote " << written << ": " << describe_counts(sec.complex) << ", volume "
            << brief(cw4d::signed_volume(sec.complex)) << " (scene " << s.scene << ", "
            << scene.objects.size() << " objects, cut by " << cut << ")\n";
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const cw4d::Complex& c = pieces[i].complex;
    std::cout << "  " << object_label(scene.objects[i], i) << ": ";
    if (pieces[i].empty())
      std::cout << "missed by the plane\n";
    else
      std::cout << describe_counts(c) << ", volume " << brief(cw4d::signed_volume(c)) << '\n';
  }
}

void run_slice(const SliceSettings& s) {
  if (!s.scene.empty()) return run_slice_scene(s);
  const cw4d::Complex model = load(s.model);
  const int dim = model.ambient_dim();
  check_against_model(s, dim);
  require_valid(model, s.model);

  const cw4d::AffineTransform xf = model_to_world(s, dim);
  const cw4d::Hyperplane plane =
      cw4d::Hyperplane::from(Eigen::Map<const Eigen::VectorXd>(s.normal.data(), dim), s.offset);
  const cw4d::Section sec = cw4d::section(model, plane, xf);

  std::string transform_text;
  for (const auto& r : s.rotations) transform_text += " rotate " + r.text + ";";
  if (!s.translate.empty()) transform_text += " translate (" + join(s.translate, exact) + ");";
  if (transform_text.empty()) transform_text = " identity;";
  transform_text.pop_back();
  const std::string cut = "n=(" + join(s.normal, brief) + "), d=" + brief(s.offset);

  if (sec.empty())
    throw EmptySection("the plane " + cut + " misses model '" + s.model +
                       "'; nothing written to '" + s.output + "'");

  prepare_output_directory(s.output);
  std::string extra;
  if (s.format == Format::obj) {
    cw4d::ObjOptions opt;
    opt.triangulate = s.triangulate;
    opt.comment = "cw4d slice of " + s.model + "\nplane: n=(" + join(s.normal, exact) +
                  "), d=" + exact(s.offset) + " (world space, n normalized)\n" +
                  "model-to-world:" + transform_text + " (in this order)";
    cw4d::write_obj_file(s.output, sec, opt);
    if (s.triangulate) {
      std::size_t triangles = 0;
      for (std::uint32_t f = 0; f < sec.complex.count(2); ++f)
        triangles += sec.complex.face_cycle(f).size() - 2;
      extra = " as " + std::to_string(triangles) + " triangles";
    }
  } else if (s.format == Format::svg) {
    cw4d::write_svg_file(s.output, sec);
  } else {
    cw4d::write_off_file(s.output, sec.complex);
  }
  std::cout << "wrote " << s.output << ": " << describe_counts(sec.complex) << extra << ", volume "
            << brief(cw4d::signed_volume(sec.complex)) << " (" << s.model << " cut by " << cut
            << ")\n";
}

void run_convert(const ConvertSettings& s) {
  const cw4d::Complex model = load(s.model);
  require_valid(model, s.model);
  prepare_output_directory(s.output);
  cw4d::write_off_file(s.output, model);
  std::cout << "wrote " << s.output << ": " << describe_counts(model) << '\n';
}

// Everything that can be checked without the model is checked here, before loading it.
void parse_slice_settings(const SliceArgs& args, SliceSettings& s) {
  if (!s.scene.empty() && !s.model.empty())
    throw cw4d::InputError("give a MODEL or --scene, not both ('" + s.model + "' and --scene " +
                           s.scene + ")");
  if (s.scene.empty() && s.model.empty())
    throw cw4d::InputError("slice needs a MODEL or --scene FILE");
  // A scene places its objects itself; a second transform on top would be ambiguous.
  if (!s.scene.empty() && (!args.rotate.empty() || !args.translate.empty()))
    throw cw4d::InputError(std::string(args.rotate.empty() ? "--translate" : "--rotate") +
                           " contradicts --scene: the scene file places its objects "
                           "(use \"rotate\" / \"translate\" there)");
  s.normal = parse_vector(args.normal, "--normal");
  bool all_zero = true;
  for (double x : s.normal) all_zero = all_zero && x == 0.0;
  if (all_zero) throw cw4d::InputError("--normal must not be the zero vector");
  if (!args.translate.empty()) s.translate = parse_vector(args.translate, "--translate");
  for (const auto& r : args.rotate) s.rotations.push_back(parse_rotation(r));
  const std::string ext = lower_extension(s.output);
  if (ext == ".obj")
    s.format = Format::obj;
  else if (is_off_extension(ext))
    s.format = Format::off;
  else if (ext == ".svg")
    s.format = Format::svg;
  else
    throw cw4d::InputError("cannot tell the format of '" + s.output +
                           "': supported extensions are .obj, .svg, .4off, .off, .noff");
  if (s.triangulate && s.format != Format::obj)
    throw cw4d::InputError("--triangulate applies to .obj output only");
}

void check_convert_settings(const ConvertSettings& s) {
  if (!is_off_extension(lower_extension(s.output)))
    throw cw4d::InputError("cannot write '" + s.output +
                           "': convert writes nOFF, use a .4off, .off or .noff extension");
}

int fail(Exit code, const std::string& message) {
  std::cerr << "cw4d: error: " << one_line(message) << '\n';
  return static_cast<int>(code);
}

}  // namespace

int main(int argc, char** argv) {
  cw4d::register_hull_models();
  CLI::App app{"cw4d: 4D polytopes as CW complexes, cut by hyperplanes into 3D meshes.", "cw4d"};
  app.footer(kExitCodes);
  app.require_subcommand(1);

  // list
  auto* list = app.add_subcommand("list", "Print every built-in model spec with a description.");

  // info
  InfoSettings info;
  auto* info_cmd = app.add_subcommand(
      "info", "Report dimension, f-vector, validity, bounds and volume of a model.");
  info_cmd->add_option("MODEL", info.model, "Built-in spec (see 'cw4d list') or a .4off/.off file")
      ->required();
  info_cmd->add_flag("--json", info.json, "Print one JSON object instead of text");
  info_cmd->footer(
      "An invalid model is reported (\"valid\": false, with its issues), not an error: exit 0.\n"
      "The volume is null / n/a for an invalid model. Exit codes: see 'cw4d --help'.");

  // slice
  SliceSettings slice;
  SliceArgs slice_args;
  auto* slice_cmd =
      app.add_subcommand("slice", "Cut a model with the hyperplane n.x = d and write the section.");
  slice_cmd->add_option("MODEL", slice.model,
                        "Built-in spec (see 'cw4d list') or a .4off/.off file; or give --scene");
  slice_cmd
      ->add_option("--scene", slice.scene,
                   "JSON scene file: several placed, colored models, cut together (instead of "
                   "MODEL; not with --rotate/--translate)")
      ->type_name("FILE");
  slice_cmd
      ->add_option("--normal", slice_args.normal,
                   "Plane normal in world space, one component per model axis (x,y,z,w); "
                   "need not be unit length")
      ->type_name("X,Y,Z,W")
      ->required();
  slice_cmd
      ->add_option("--offset", slice.offset,
                   "Signed distance d of the plane from the origin along the unit normal")
      ->type_name("D")
      ->required();
  slice_cmd
      ->add_option("--rotate", slice_args.rotate,
                   "PLANE:DEGREES with PLANE one of xy xz xw yz yw zw; repeatable, the "
                   "first given is applied first")
      ->type_name("PLANE:DEG")
      ->allow_extra_args(false);
  slice_cmd
      ->add_option("--translate", slice_args.translate, "Translation applied after the rotations")
      ->type_name("X,Y,Z,W");
  slice_cmd->add_flag("--triangulate", slice.triangulate,
                      "Fan-triangulate the polygons (OBJ only)");
  slice_cmd->add_option("-o,--output", slice.output,
                        "Output file: .obj, .svg (a shaded picture), or .4off/.off/.noff")
      ->required();
  slice_cmd->footer(
      "The model is placed by x_world = R_k ... R_1 x_model + t (R_1 = first --rotate) and cut\n"
      "in world space; a model in R^n takes n components in --normal and --translate.\n"
      "The output format follows the extension: .obj (Wavefront, a 3D mesh; the outline as\n"
      "line elements for a 3D model), .svg (a flat-shaded picture of a 4D model's section),\n"
      ".4off/.off/.noff (the section as an nOFF complex). Missing parent directories of the output are created.\n"
      "An empty section (the plane misses the model) writes nothing and exits 5.\n"
      "With --scene FILE every object of the scene is placed by its own transform and cut by the\n"
      "same plane; the pieces are written as one mesh with the objects' colors (.obj gets a\n"
      ".mtl of the same name, .svg and nOFF carry the face colors) and a line per object is\n"
      "printed. Scene format, e.g.:\n"
      "  {\"objects\": [{\"model\": \"tesseract\", \"rotate\": [[\"xw\", 30]],\n"
      "                \"translate\": [1, 0, 0, 0], \"scale\": 0.5, \"color\": \"#ff8000\",\n"
      "                \"opacity\": 0.5, \"cell_colors\": {\"3\": [0, 0, 1]}, \"name\": \"a\"}]}\n"
      "(degrees; scale, then rotations in order, then translation; model paths are relative to\n"
      "the scene file). A malformed scene exits 2 naming file:line.\n"
      "Exit codes: see 'cw4d --help'.");

  // convert
  ConvertSettings convert;
  auto* convert_cmd = app.add_subcommand("convert", "Validate a model and write it as nOFF.");
  convert_cmd
      ->add_option("MODEL", convert.model, "Built-in spec (see 'cw4d list') or a .4off/.off file")
      ->required();
  convert_cmd->add_option("-o,--output", convert.output, "Output file: .4off, .off or .noff")
      ->required();
  convert_cmd->footer(
      "All three extensions write nOFF (\"4OFF\" for 4D models, \"OFF\" for 3D ones).\n"
      "Missing parent directories of the output are created.\n"
      "Exit codes: see 'cw4d --help'.");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help: print it to stdout
    return fail(Exit::usage, std::string(e.what()) + " (run 'cw4d --help')");
  }

  try {
    if (*slice_cmd) {
      parse_slice_settings(slice_args, slice);
      run_slice(slice);
    } else if (*convert_cmd) {
      check_convert_settings(convert);
      run_convert(convert);
    } else if (*info_cmd) {
      run_info(info);
    } else if (*list) {
      run_list();
    }
  } catch (const cw4d::ParseError& e) {
    return fail(Exit::bad_input, e.what());
  } catch (const cw4d::InputError& e) {
    return fail(Exit::usage, e.what());
  } catch (const cw4d::TopologyError& e) {
    return fail(Exit::invalid_complex, e.what());
  } catch (const cw4d::IoError& e) {
    return fail(Exit::cannot_write, e.what());
  } catch (const EmptySection& e) {
    return fail(Exit::empty_section, e.what());
  } catch (const std::exception& e) {
    return fail(Exit::internal, std::string("internal error: ") + e.what());
  }
  return static_cast<int>(Exit::ok);
}
