// Shared pieces of the cw4d command line (see cli.hpp).
#include "cli.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <ios>
#include <limits>
#include <numbers>
#include <tuple>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/placement.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/section/scene_section.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"

namespace cw4d::cli {

namespace fs = std::filesystem;

const char* const kExitCodes =
    "Exit codes:\n"
    "  0  success (info also exits 0 for an invalid model: it reports \"valid\": false)\n"
    "  1  usage error: bad option or value, unknown model spec\n"
    "  2  an input file cannot be read or parsed (message names file:line; G4MF: file:0 and\n"
    "     the part of the file)\n"
    "  3  the model is not a valid complex (validation failed)\n"
    "  4  the output cannot be written (nothing is left half-written)\n"
    "  5  the section is empty: the plane misses the model, nothing is written\n"
    "  6  internal error (a bug in cw4d, or out of memory)\n"
    "  7  check: at least one file failed (the report says which and why)\n"
    "Errors are printed as one line on stderr: \"cw4d: error: <message>\".";

// --- text ------------------------------------------------------------------------------------

std::string one_line(std::string s) {
  for (auto& ch : s)
    if (ch == '\n' || ch == '\r') ch = ' ';
  return s;
}

std::string bounded_message(const std::string& message) {
  if (message.size() <= kMaxMessageBytes) return message;
  std::size_t end = kMaxMessageBytes;
  while (end > 0 && (static_cast<unsigned char>(message[end]) & 0xC0) == 0x80) --end;
  return message.substr(0, end) + "... (" + std::to_string(message.size()) + " bytes)";
}

std::string exact(double v) {
  char buf[64];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, ptr);
}

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
    throw InputError(what + ": " + quote_user_text(std::string(text)) + " is not a number");
  if (!std::isfinite(v))
    throw InputError(what + ": " + quote_user_text(std::string(text)) + " is not finite");
  return v;
}

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

void check_held_pixels(const std::string& size, int width, int height, double images,
                       const std::string& fewer) {
  const double held = static_cast<double>(width) * height * images;
  if (held > kMaxHeldPixels)
    throw InputError(
        "--size " + quote_user_text(size) + " would hold " +
        std::to_string(static_cast<long long>(std::min(held, 9e18))) + " pixels in memory (" +
        std::to_string(static_cast<long long>(std::min(held * 16 / 1e6, 9e18))) +
        " MB); cw4d holds at most " + std::to_string(static_cast<long long>(kMaxHeldPixels)) +
        ": give a smaller --size" + fewer);
}

std::pair<int, int> parse_image_size(const std::string& text) {
  // Parsed with from_chars rather than sscanf("%dx%d"), whose %d is undefined for a number
  // beyond int (glibc wraps 4294967297 to 1) and which skips leading spaces and signs.
  auto side = [&](std::string_view digits) {
    int v = 0;
    const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v);
    const bool ok = !digits.empty() && digits.front() != '-' && ec == std::errc() &&
                    ptr == digits.data() + digits.size() && v >= 1 && v <= 16384;
    return ok ? v : 0;
  };
  const auto x = text.find('x');
  const int w = x == std::string::npos ? 0 : side(std::string_view(text).substr(0, x));
  const int h = x == std::string::npos ? 0 : side(std::string_view(text).substr(x + 1));
  if (w == 0 || h == 0)
    throw InputError("--size must be WIDTHxHEIGHT with sides 1..16384, not " +
                     quote_user_text(text));
  return {w, h};
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (auto& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

bool is_off_extension(const std::string& ext) {
  return ext == ".4off" || ext == ".off" || ext == ".noff";
}

std::string rank_name(int rank, std::size_t count) {
  static const char* singular[] = {"vertex", "edge", "face", "cell"};
  static const char* plural[] = {"vertices", "edges", "faces", "cells"};
  if (rank < 4) return count == 1 ? singular[rank] : plural[rank];
  return "rank-" + std::to_string(rank) + (count == 1 ? " element" : " elements");
}

std::string describe_counts(const Complex& c) {
  std::string out;
  const auto f = c.fvector();
  for (std::size_t k = 0; k < f.size(); ++k) {
    if (k) out += ", ";
    out += std::to_string(f[k]) + " " + rank_name(static_cast<int>(k), f[k]);
  }
  return out;
}

ProgressBar::ProgressBar(std::string command, std::string unit, std::size_t total, bool wanted)
    : command_(std::move(command)),
      unit_(std::move(unit)),
      total_(total),
      enabled_(wanted && ::isatty(2) != 0) {}

void ProgressBar::step(std::size_t done) {
  if (!enabled_) return;
  std::lock_guard lock(mutex_);
  constexpr std::size_t width = 40;
  const std::size_t filled = total_ ? std::min(done, total_) * width / total_ : width;
  std::fprintf(stderr, "\rcw4d: %s [%s%s] %zu/%zu %s", command_.c_str(),
               std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), done,
               total_, unit_.c_str());
  if (done == total_) std::fputc('\n', stderr);
  std::fflush(stderr);
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& names) {
  const std::string guess = closest_name(word, names);
  return guess.empty() ? std::string() : "; did you mean " + quote_user_text(guess) + "?";
}

std::vector<std::string> subcommand_names(CLI::App& app) {
  std::vector<std::string> names{"help"};
  for (const auto* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  return names;
}

// --- models and files ------------------------------------------------------------------------

// load_model reports unreadable files as ParseError, except read failures after a successful
// open (a directory given as the model), which libstdc++ raises as std::ios_base::failure.
Complex load(const std::string& spec) {
  try {
    return load_model(spec, default_catalogue());
  } catch (const std::ios_base::failure& e) {
    throw ParseError(spec, 0, std::string("cannot read: ") + e.what());
  }
}

// Invalid models stop every cutting command: a broken complex gives meaningless output.
void require_valid(const Complex& model, const std::string& spec) {
  const ValidationReport report = validate(model);
  if (report.ok()) return;
  const auto& first = report.issues.front();
  // A model read from an nOFF file: name the line of the first offending element.
  std::string where;
  if (!is_builtin_spec(spec, default_catalogue()) && is_off_extension(lower_extension(spec))) {
    OffLines lines;
    try {
      read_off_file(spec, &lines);
    } catch (const Error&) {
    }
    if (const std::size_t line = lines.line_of(first.rank, first.id))
      where = spec + ":" + std::to_string(line) + ": ";
  }
  throw TopologyError(
      first.rank, {first.id},
      where + "model " + quote_user_text(spec) + " is not a valid complex: " + report.summary());
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
    throw IoError("cannot write " + quote_user_text(path) + ": cannot create directory " +
                  quote_user_text(parent.string()) + (ec ? ": " + ec.message() : ""));
}

// --- placement -------------------------------------------------------------------------------

namespace {

Rotation parse_rotation(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos)
    throw InputError("--rotate " + quote_user_text(text) + ": expected PLANE:DEGREES, e.g. xw:30");
  Rotation r;
  r.text = text;
  std::tie(r.axis_i, r.axis_j) = parse_rotation_plane(text.substr(0, colon));
  r.degrees =
      parse_number(std::string_view(text).substr(colon + 1), "--rotate " + quote_user_text(text));
  // Whole turns removed exactly (fmod is exact), so that 1e308 degrees is a rotation like any
  // other instead of overflowing when turned into radians.
  r.degrees = std::fmod(r.degrees, 360.0);
  return r;
}

}  // namespace

void Placement::add_options(CLI::App& cmd) {
  cmd.add_option(
      "MODEL", model,
      "Built-in spec (see 'cw4d list') or a .4off/.off/.g4tf/.g4b file; or give --scene");
  cmd.add_option("--scene", scene,
                 "JSON scene file: several placed, colored models, cut together (instead of "
                 "MODEL; not with --rotate/--translate)")
      ->type_name("FILE");
  cmd.add_option("--normal", normal_text,
                 "Plane normal in world space, one component per model axis (x,y,z,w); "
                 "need not be unit length")
      ->type_name("X,Y,Z,W")
      ->required();
  cmd.add_option("--rotate", rotate_text,
                 "PLANE:DEGREES with PLANE one of xy xz xw yz yw zw; repeatable, the "
                 "first given is applied first")
      ->type_name("PLANE:DEG")
      ->allow_extra_args(false);
  cmd.add_option("--translate", translate_text, "Translation applied after the rotations")
      ->type_name("X,Y,Z,W");
}

void Placement::parse(const std::string& command) {
  if (!scene.empty() && !model.empty())
    throw InputError("give a MODEL or --scene, not both (" + quote_user_text(model) +
                     " and --scene " + scene + ")");
  if (scene.empty() && model.empty()) throw InputError(command + " needs a MODEL or --scene FILE");
  // A scene places its objects itself; a second transform on top would be ambiguous.
  if (!scene.empty() && (!rotate_text.empty() || !translate_text.empty()))
    throw InputError(std::string(rotate_text.empty() ? "--translate" : "--rotate") +
                     " contradicts --scene: the scene file places its objects "
                     "(use \"rotate\" / \"translate\" there)");
  normal = parse_vector(normal_text, "--normal");
  if (std::all_of(normal.begin(), normal.end(), [](double x) { return x == 0.0; }))
    throw InputError("--normal must not be the zero vector");
  translate.clear();
  if (!translate_text.empty()) translate = parse_vector(translate_text, "--translate");
  rotations.clear();
  for (const auto& r : rotate_text) rotations.push_back(parse_rotation(r));
}

std::string Placement::input_label() const {
  return scene.empty() ? "model " + quote_user_text(model) : "scene " + quote_user_text(scene);
}

void Placement::check_dimension(int dim) const {
  const std::string where = input_label() + " lives in R^" + std::to_string(dim);
  if (!normal.empty() && normal.size() != static_cast<std::size_t>(dim))
    throw InputError("--normal has " + std::to_string(normal.size()) + " components but " + where +
                     ": give " + std::to_string(dim) + " comma-separated numbers");
  if (!translate.empty() && translate.size() != static_cast<std::size_t>(dim))
    throw InputError("--translate has " + std::to_string(translate.size()) + " components but " +
                     where);
  for (const auto& r : rotations)
    if (r.axis_i >= dim || r.axis_j >= dim)
      throw InputError("--rotate " + r.text + ": " + where + ", which has no such axis");
}

AffineTransform Placement::model_to_world(int dim) const {
  AffineTransform m = AffineTransform::identity(dim);
  for (const auto& r : rotations)
    m = AffineTransform::rotation(dim, r.axis_i, r.axis_j, r.degrees * std::numbers::pi / 180.0) *
        m;
  if (!translate.empty())
    m = AffineTransform::translation(Eigen::Map<const Eigen::VectorXd>(translate.data(), dim)) * m;
  return m;
}

std::string Placement::transform_text() const {
  std::string text;
  for (const auto& r : rotations) text += " rotate " + r.text + ";";
  if (!translate.empty()) text += " translate (" + join(translate, exact) + ");";
  if (text.empty()) text = " identity;";
  text.pop_back();
  return text;
}

Hyperplane Placement::plane(double offset) const {
  return Hyperplane::from(
      Eigen::Map<const Eigen::VectorXd>(normal.data(), static_cast<Eigen::Index>(normal.size())),
      offset);
}

// --- input -----------------------------------------------------------------------------------

std::vector<const Complex*> Input::models() const {
  std::vector<const Complex*> out;
  for (const auto& obj : scene.objects) out.push_back(obj.complex.get());
  return out;
}

std::vector<std::string> Input::object_names() const {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& obj = scene.objects[i];
    if (!is_scene)
      out.push_back(obj.model);
    else if (!obj.name.empty())
      out.push_back(obj.name);
    else
      out.push_back("object " + std::to_string(i) + " (" + quote_user_text(obj.model) + ")");
  }
  return out;
}

Input load_input(const Placement& placement) {
  Input in;
  if (!placement.scene.empty()) {
    in.is_scene = true;
    in.scene = read_scene_file(placement.scene, default_catalogue());
  } else {
    auto model = std::make_shared<const Complex>(load(placement.model));
    SceneObject obj;
    obj.model = placement.model;
    obj.complex = model;
    obj.transform = AffineTransform::identity(model->ambient_dim());
    in.scene.objects.push_back(std::move(obj));
  }
  const int dim = in.dim();
  placement.check_dimension(dim);
  if (!in.is_scene) in.scene.objects.front().transform = placement.model_to_world(dim);
  // Placed coordinates beyond what doubles cut (a scene scale of 1e155, a file in units of
  // 1e200) are refused instead of answering "the plane misses": the library's one check.
  for (std::size_t i = 0; i < in.scene.objects.size(); ++i) {
    const SceneObject& obj = in.scene.objects[i];
    check_placement(*obj.complex, obj.transform,
                    in.is_scene
                        ? "object " + std::to_string(i) + " (" + quote_user_text(obj.model) +
                              ") of scene " + quote_user_text(placement.scene)
                        : "model " + quote_user_text(obj.model));
  }
  std::vector<const Complex*> checked;  // objects share models: validate each once
  for (const auto& obj : in.scene.objects) {
    if (std::find(checked.begin(), checked.end(), obj.complex.get()) != checked.end()) continue;
    require_valid(*obj.complex, obj.model);
    checked.push_back(obj.complex.get());
  }
  return in;
}

std::pair<double, double> offset_interval(const Complex& model, const AffineTransform& to_world,
                                          const Eigen::VectorXd& unit_normal) {
  // n . (L x + t) = (L^T n) . x + n . t
  const Eigen::VectorXd m = to_world.linear().transpose() * unit_normal;
  const double shift = unit_normal.dot(to_world.translation());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const auto& p = model.positions();
  for (Eigen::Index v = 0; v < p.cols(); ++v) {
    const double h = m.dot(p.col(v)) + shift;
    lo = std::min(lo, h);
    hi = std::max(hi, h);
  }
  return {lo, hi};
}

std::string offset_range(const Input& input, const Hyperplane& plane) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& obj : input.scene.objects) {
    const auto [a, b] = offset_interval(*obj.complex, obj.transform, plane.normal);
    lo = std::min(lo, a);
    hi = std::max(hi, b);
  }
  std::vector<double> n(plane.normal.data(), plane.normal.data() + plane.normal.size());
  return "d from " + brief(lo) + " to " + brief(hi) + " along the unit normal (" + join(n, brief) +
         ")";
}

Cut cut(const Input& input, const Hyperplane& plane) {
  Cut out;
  if (input.is_scene) {
    out.pieces = section_objects(input.scene, plane);
    out.section = merge_sections(input.scene, out.pieces);
  } else {
    const SceneObject& obj = input.scene.objects.front();
    out.section = section(*obj.complex, plane, obj.transform);
  }
  return out;
}

}  // namespace cw4d::cli
