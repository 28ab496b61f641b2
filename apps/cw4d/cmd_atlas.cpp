// cw4d atlas: the critical offsets of a model along a normal, and the section's f-vector on
// each interval between them (optionally a contact sheet of one section per interval).
#include <iostream>
#include <string>
#include <tuple>

#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/section_view.hpp"
#include "cw4d/section/atlas.hpp"

namespace cw4d::cli {

namespace {

/// More critical offsets than this (one cut each) are refused: about a minute of cutting.
constexpr std::size_t kMaxCriticalOffsets = 20000;

struct AtlasSettings {
  Placement placement;
  bool json = false;
  std::string output;  // -o sheet.png
  std::string size = "240x180";
  int columns = 0;
  bool edges = false;
};

std::string fvector_text(const std::vector<std::size_t>& f) {
  std::string s = "(";
  for (std::size_t i = 0; i < f.size(); ++i) s += (i ? ", " : "") + std::to_string(f[i]);
  return s + ")";
}

void run_atlas(AtlasSettings& s) {
  Placement& p = s.placement;
  p.parse("atlas");
  if (!s.output.empty() && lower_extension(s.output) != ".png")
    throw InputError("atlas draws its contact sheet as PNG: give -o NAME.png, not " +
                     quote_user_text(s.output));
  int width = 0, height = 0;
  if (!s.output.empty()) std::tie(width, height) = parse_image_size(s.size);
  const Input input = load_input(p);
  const Complex& model = *input.models().front();
  const int dim = input.dim();
  const AffineTransform place = p.model_to_world(dim);
  const Eigen::VectorXd normal = Eigen::Map<const Eigen::VectorXd>(p.normal.data(), dim);
  const std::size_t count = critical_offsets(model, normal, place).size();
  if (count > kMaxCriticalOffsets)
    throw InputError(p.input_label() + " has " + std::to_string(count) +
                     " critical offsets along this normal; atlas cuts at most " +
                     std::to_string(kMaxCriticalOffsets));
  if (!s.output.empty()) {
    if (dim != 4)
      throw InputError("atlas -o draws the sections of 4D models; " + p.input_label() +
                       " lives in R^" + std::to_string(dim));
    check_held_pixels(s.size, width, height, 2.0 * static_cast<double>(count));
  }
  AtlasOptions options;
  options.keep_sections = !s.output.empty();
  const Atlas atlas = section_atlas(model, normal, place, options);
  const std::vector<double> unit(atlas.normal.data(), atlas.normal.data() + dim);

  std::string wrote;
  if (!s.output.empty()) {
    if (atlas.intervals.empty())
      throw EmptySection(p.input_label() + " lies in one plane of this normal: no interval to " +
                         "draw; nothing written to " + quote_user_text(s.output));
    prepare_output_directory(s.output);
    render::SectionViewOptions o;
    o.raster.width = width;
    o.raster.height = height;
    o.edges = s.edges;
    o.source = &input.scene;
    o.frame = render::scene_frame(input.scene, HyperplaneFrame(p.plane(0.0)));
    std::vector<render::Image> cells;
    for (const Section& sec : atlas.sections)
      cells.push_back(render::render_section(sec, o, &model));
    render::write_png(s.output, render::contact_sheet(cells, s.columns), glm::vec3(1.0f));
    wrote = "wrote " + s.output + ": contact sheet of " + std::to_string(cells.size()) +
            " sections, one per interval, in order of offset";
  }

  if (s.json) {
    nlohmann::ordered_json j;
    j["model"] = p.model;
    j["normal"] = unit;
    j["tolerance"] = atlas.tolerance;
    j["critical_offsets"] = atlas.critical_offsets;
    j["critical_sections"] = nlohmann::ordered_json::array();
    for (const auto& c : atlas.critical) {
      nlohmann::ordered_json x = {
          {"offset", c.offset}, {"f_vector", c.fvector}, {"degenerate", true}};
      if (!c.contact.empty()) x["contact_f_vector"] = c.contact;
      j["critical_sections"].push_back(std::move(x));
    }
    j["intervals"] = nlohmann::ordered_json::array();
    for (const auto& i : atlas.intervals)
      j["intervals"].push_back({{"from", i.from},
                                {"to", i.to},
                                {"offset", i.section.offset},
                                {"f_vector", i.section.fvector}});
    if (!wrote.empty()) j["sheet"] = s.output;
    std::cout << j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << '\n';
    return;
  }
  std::cout << "atlas of " << p.input_label() << " along n = (" << join(unit, brief)
            << "): " << atlas.critical_offsets.size() << " critical offsets, "
            << atlas.intervals.size() << " intervals (heights within " << brief(atlas.tolerance)
            << " merged)\n";
  for (std::size_t k = 0; k < atlas.critical_offsets.size(); ++k) {
    const AtlasSection& c = atlas.critical[k];
    std::cout << "  d = " << brief(atlas.critical_offsets[k]) << "  passes a vertex: f-vector "
              << fvector_text(c.fvector);
    if (!c.contact.empty()) std::cout << ", touching the model in " << fvector_text(c.contact);
    std::cout << " (degenerate)\n";
    if (k < atlas.intervals.size()) {
      const auto& i = atlas.intervals[k];
      std::cout << "  " << brief(i.from) << " < d < " << brief(i.to) << "  f-vector "
                << fvector_text(i.section.fvector) << '\n';
    }
  }
  if (!wrote.empty()) std::cout << wrote << '\n';
}

}  // namespace

void add_atlas_command(CLI::App& app, Commands& commands) {
  auto s = std::make_shared<AtlasSettings>();
  auto* cmd = app.add_subcommand(
      "atlas",
      "List the critical offsets of a model along a normal and the section's f-vector on each "
      "interval between them.");
  s->placement.add_options(*cmd);
  cmd->remove_option(cmd->get_option("--scene"));
  cmd->get_option("MODEL")
      ->description("Built-in spec (see 'cw4d list') or a .4off/.off/.g4tf/.g4b file")
      ->required();
  cmd->add_flag("--json", s->json, "Print one JSON object instead of text");
  cmd->add_option("-o,--output", s->output,
                  "Also draw a contact sheet (PNG) of one section per interval, in order");
  cmd->add_option("--size", s->size, "-o: the size of each section's picture (default 240x180)")
      ->type_name("WxH");
  cmd->add_option("--columns", s->columns, "-o: pictures per row (default: about square)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--edges", s->edges, "-o: draw the sections' edges on top");
  cmd->footer(
      "The critical offsets are the heights n.x of the model's vertices along the unit normal\n"
      "(placed by --rotate/--translate as for 'slice'), sorted, with heights closer than 1e-9\n"
      "of the model's radius (its farthest vertex from the origin) merged into one. Between\n"
      "two consecutive ones the section's combinatorics do not change: each open interval is\n"
      "listed with the f-vector of its section (vertices, edges, faces of a 4D model's cut),\n"
      "cut at the interval's midpoint. The sections at the critical offsets themselves are\n"
      "listed too, flagged degenerate (the plane passes a vertex); where that section is\n"
      "empty, the plane only touches the model and the f-vector of what lies in the plane\n"
      "(a vertex (1, 0, 0), an edge (2, 1, 0), a square (4, 4, 1)) is given as the contact.\n"
      "JSON: {\"critical_offsets\": [...], \"critical_sections\": [{\"offset\", \"f_vector\",\n"
      "\"degenerate\", \"contact_f_vector\" (when empty)}], \"intervals\": [{\"from\", \"to\",\n"
      "\"offset\", \"f_vector\"}], ...}.\n"
      "At most 20000 critical offsets (one cut each).\n"
      "Examples:\n"
      "  cw4d atlas tesseract --normal 1,1,1,1\n"
      "  cw4d atlas 24-cell --normal 1,2,3,4 --json\n"
      "  cw4d atlas tesseract --normal 1,1,1,1 -o atlas.png\n"
      "Exit codes: see 'cw4d --help'.");
  commands.push_back({cmd, [s] { run_atlas(*s); }});
}

}  // namespace cw4d::cli
