#pragma once
// Shared pieces of the cw4d command line: exit codes, option parsing, loading and placing the
// input, and the registry of subcommands. Each subcommand lives in its own cmd_<name>.cpp and
// is added to the app by one add_<name>_command call in main.cpp.
//
// Every failure is an exception from complex/error.hpp (or EmptySection below); main() maps
// the exception class to one documented exit code and prints one "cw4d: error: ..." line.
#include <CLI/CLI.hpp>

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"

namespace cw4d::cli {

enum class Exit : int {
  ok = 0,
  usage = 1,            // bad command line, bad option value, unknown model spec
  bad_input = 2,        // an input file could not be parsed
  invalid_complex = 3,  // the model failed validation (or the library found broken topology)
  cannot_write = 4,     // the output could not be written
  empty_section = 5,    // the plane misses the model: nothing written
  internal = 6,         // anything unexpected (a bug, out of memory)
  check_failed = 7,     // cw4d check: at least one file failed
};

/// The exit-code table printed by `cw4d --help`.
extern const char* const kExitCodes;

/// cw4d check found a file that fails (the report says which and why).
class CheckFailed : public Error {
 public:
  using Error::Error;
};

/// The empty-section outcome, thrown so that main() maps it like every other failure.
class EmptySection : public Error {
 public:
  using Error::Error;
};

// --- text ------------------------------------------------------------------------------------

/// Newlines replaced by spaces (every error is one line).
std::string one_line(std::string s);
/// The longest error message printed (bytes); user text in messages is cut by quote_user_text
/// (cw4d/complex/text.hpp) well below it, so this only bounds what no quote caught.
inline constexpr std::size_t kMaxMessageBytes = 2000;
/// `message` cut to kMaxMessageBytes (on a UTF-8 boundary) with "... (N bytes)" when longer.
std::string bounded_message(const std::string& message);
/// Shortest round-trip text of a double (for file headers).
std::string exact(double v);
/// Six significant digits (for messages).
std::string brief(double v);
/// "a,b,c" with each value formatted by `fmt`.
std::string join(const std::vector<double>& values, std::string (*fmt)(double));
/// A finite number; `what` names the option in the error. \throw InputError
double parse_number(std::string_view text, const std::string& what);
/// "x,y,z,w" -> numbers (the count is checked against the model's dimension later).
std::vector<double> parse_vector(const std::string& text, const std::string& option);
/// "WIDTHxHEIGHT" (--size), each side 1..16384. \throw InputError
std::pair<int, int> parse_image_size(const std::string& text);
/// The most pixels a picture command (render, net) holds at once: linear RGBA floats of 16
/// bytes each, about 2.4 GB.
inline constexpr double kMaxHeldPixels = 1.5e8;
/// Refuses a picture of `size` (the --size text, width x height) held `images` times over
/// beyond kMaxHeldPixels; `fewer` says what else to reduce (" or fewer --layers"), if anything.
/// \throw InputError
void check_held_pixels(const std::string& size, int width, int height, double images,
                       const std::string& fewer = {});
/// The extension of `path`, lower case, with its dot ("" when none).
std::string lower_extension(const std::string& path);
bool is_off_extension(const std::string& ext);
/// "12 vertices, 18 edges, 8 faces"
std::string describe_counts(const Complex& c);
/// "vertex"/"vertices", "edge"/"edges", ... for rank 0..3, "rank-k element(s)" above.
std::string rank_name(int rank, std::size_t count);

/// A progress bar on stderr ("cw4d: sweep [####....] 12/64 layers"), drawn only when `wanted`
/// and stderr is a terminal; step() may be called from several threads.
class ProgressBar {
 public:
  /// `command` and `unit` name the bar ("sweep", "layers"); `total` is the count at the end.
  ProgressBar(std::string command, std::string unit, std::size_t total, bool wanted);
  /// Draws `done` of the total (a newline after the last).
  void step(std::size_t done);

 private:
  std::string command_, unit_;
  std::size_t total_;
  bool enabled_;
  std::mutex mutex_;
};

/// "; did you mean 'slice'?" for the closest of `names` (closest_name), or "".
std::string did_you_mean(const std::string& word, const std::vector<std::string>& names);
/// The names of the app's subcommands.
std::vector<std::string> subcommand_names(CLI::App& app);

// --- models and files ------------------------------------------------------------------------

/// load_model, with read failures after a successful open (a directory) as ParseError.
Complex load(const std::string& spec);
/// \throw TopologyError naming the first issue when the model does not validate.
void require_valid(const Complex& model, const std::string& spec);
/// Creates the missing parent directories of an output path. \throw IoError
void prepare_output_directory(const std::string& path);

// --- where the input is and how it is cut ------------------------------------------------------

struct Rotation {
  std::string text;  // as given, for messages and file headers
  int axis_i = 0, axis_j = 1;
  double degrees = 0.0;
};

/// The options shared by the commands that cut something (slice, sweep, render): a MODEL or
/// --scene FILE, the plane normal, and the model's placement.
struct Placement {
  std::string model;
  std::string scene;  // exactly one of model and scene is given
  std::vector<double> normal;
  std::vector<Rotation> rotations;  // applied in the order given
  std::vector<double> translate;    // empty = none

  // As typed, before parse() turns them into the fields above.
  std::string normal_text, translate_text;
  std::vector<std::string> rotate_text;

  /// Adds MODEL, --scene, --normal, --rotate and --translate to `cmd`.
  void add_options(CLI::App& cmd);
  /// The checks that need no model; `command` names the subcommand in messages.
  /// \throw InputError
  void parse(const std::string& command);
  /// The checks against the input's dimension (an empty `normal`, one the command defaults
  /// itself, is not checked). \throw InputError
  void check_dimension(int dim) const;
  /// x_world = R_k ... R_1 x_model + t.
  AffineTransform model_to_world(int dim) const;
  /// " rotate xw:30; translate (1,0,0,0)" or " identity" (for file headers).
  std::string transform_text() const;
  /// "model 'tesseract'" or "scene 'a.json'".
  std::string input_label() const;
  /// The world-space plane normal . x = offset.
  Hyperplane plane(double offset) const;
};

/// The loaded, validated input of a cutting command: a scene, or a single model placed by the
/// command line's transform (then `scene` holds that one object, uncolored).
struct Input {
  Scene scene;
  bool is_scene = false;
  int dim() const { return scene.dim(); }
  /// Models in object order (for provenance: section.source refers to their ids).
  std::vector<const Complex*> models() const;
  /// Display names of the objects ("left", "object 1 (tesseract)", or the model spec).
  std::vector<std::string> object_names() const;
};

/// Loads the model or scene, checks the placement against its dimension and validates every
/// model once. \throw ParseError, InputError, TopologyError
Input load_input(const Placement& placement);

/// The offsets d for which the plane normal . x = d meets the input (its world-space vertices):
/// "d from -2 to 2 along n=(0,0,0,1)", for messages and `cw4d info --normal`.
std::string offset_range(const Input& input, const Hyperplane& plane);
/// The same for one model in its own coordinates.
std::pair<double, double> offset_interval(const Complex& model, const AffineTransform& to_world,
                                          const Eigen::VectorXd& unit_normal);

/// The section of the input.
struct Cut {
  /// For a scene the merged, colored section of all objects; for a single model its section.
  Section section;
  /// For a scene the section of each object (entry i for object i); empty for a single model.
  std::vector<Section> pieces;
};
Cut cut(const Input& input, const Hyperplane& plane);

// --- subcommands ---------------------------------------------------------------------------------

/// A registered subcommand: its CLI11 app and what to run when it was chosen.
struct Command {
  CLI::App* app = nullptr;
  std::function<void()> run;
};
using Commands = std::vector<Command>;

void add_list_command(CLI::App& app, Commands& commands);
void add_info_command(CLI::App& app, Commands& commands);
void add_convert_command(CLI::App& app, Commands& commands);
void add_slice_command(CLI::App& app, Commands& commands);
void add_net_command(CLI::App& app, Commands& commands);
void add_sweep_command(CLI::App& app, Commands& commands);
void add_render_command(CLI::App& app, Commands& commands);
void add_tetrahedralize_command(CLI::App& app, Commands& commands);
void add_bench_command(CLI::App& app, Commands& commands);
void add_view_command(CLI::App& app, Commands& commands);
void add_atlas_command(CLI::App& app, Commands& commands);
void add_check_command(CLI::App& app, Commands& commands);

}  // namespace cw4d::cli
