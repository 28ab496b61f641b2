// cw4d list, info and convert: the commands about models themselves.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/mass.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/export/g4mf.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"
#include "output.hpp"

namespace cw4d::cli {

void add_list_command(CLI::App& app, Commands& commands) {
  auto* cmd = app.add_subcommand("list", "Print every built-in model spec with a description.");
  commands.push_back({cmd, [] {
                        std::size_t width = 0;
                        for (const auto& b : builtin_list(default_catalogue()))
                          width = std::max(width, b.spec.size());
                        for (const auto& b : builtin_list(default_catalogue()))
                          std::cout << b.spec << std::string(width + 2 - b.spec.size(), ' ')
                                    << b.description << '\n';
                      }});
}

namespace {

struct InfoSettings {
  std::string model;
  bool json = false;
  std::string normal;  // --normal: also print the offsets where planes of it meet the model
};

void run_info(const InfoSettings& s) {
  std::vector<double> normal;
  if (!s.normal.empty()) {
    normal = parse_vector(s.normal, "--normal");  // refused before the model is built
    if (std::all_of(normal.begin(), normal.end(), [](double x) { return x == 0.0; }))
      throw InputError("--normal must not be the zero vector");
  }
  const Complex model = load(s.model);
  const ValidationReport report = validate(model);
  const int dim = model.ambient_dim();
  const auto fvec = model.fvector();
  std::vector<double> lo(dim, 0.0), hi(dim, 0.0);
  if (!model.empty()) {
    const Bounds b = bounds(model);
    for (int i = 0; i < dim; ++i) {
      lo[i] = b.min(i);
      hi[i] = b.max(i);
    }
  }
  // The enclosed volume only means something for a valid closed complex.
  // Measured on exactly rescaled positions, then scaled back: a volume beyond the range of a
  // double (coordinates near 1e308 in R^3, 1e77 in R^4, or 1e-80 in R^4) is said to be out of
  // range, not printed as nan, inf or 0.
  // (a plain double and a flag: GCC 12 at -O3 warns falsely that an optional<double> may be
  // read uninitialised here)
  double volume = 0.0;
  bool has_volume = false;
  const char* out_of_range = nullptr;
  if (report.ok()) {
    const double scale = position_scale(model);
    const double rescaled = signed_volume(model, scale);
    volume = std::ldexp(rescaled, -dim * std::ilogb(scale));
    if (!std::isfinite(volume))
      out_of_range = "beyond the range of a double (the coordinates are too large)";
    else if (volume == 0.0 && rescaled != 0.0)
      out_of_range = "below the range of a double (the coordinates are too small)";
    has_volume = !out_of_range;
  }
  // Mass properties of the solid (closed, valid models only; otherwise the reason).
  std::optional<MassProperties> mass;
  std::string no_mass = "the model is not a valid closed complex";
  if (report.ok()) {
    try {
      mass = mass_properties(model);
    } catch (const Error& e) {
      no_mass = e.what();
    }
  }
  std::optional<std::pair<double, double>> range;
  Eigen::VectorXd unit;
  if (!normal.empty()) {
    if (normal.size() != static_cast<std::size_t>(dim))
      throw InputError("--normal has " + std::to_string(normal.size()) + " components but model '" +
                       s.model + "' lives in R^" + std::to_string(dim) + ": give " +
                       std::to_string(dim) + " comma-separated numbers");
    unit = Hyperplane::from(Eigen::Map<const Eigen::VectorXd>(normal.data(), dim), 0.0).normal;
    if (!model.empty()) range = offset_interval(model, AffineTransform::identity(dim), unit);
  }

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
    j["volume"] = has_volume ? nlohmann::ordered_json(volume) : nlohmann::ordered_json(nullptr);
    if (mass) {
      std::vector<std::vector<double>> rows;
      for (int i = 0; i < dim; ++i)
        rows.emplace_back(mass->second_moment.row(i).begin(), mass->second_moment.row(i).end());
      j["mass"] = {{"hypervolume", mass->hypervolume},
                   {"boundary_volume", mass->boundary_volume},
                   {"centroid", std::vector<double>(mass->centroid.begin(), mass->centroid.end())},
                   {"second_moment", rows},
                   {"winding_weighted", mass->winding_weighted}};
    } else {
      j["mass"] = nullptr;
      j["mass_reason"] = no_mass;
    }
    if (range) {
      j["normal"] = std::vector<double>(unit.data(), unit.data() + unit.size());
      j["offsets"] = {{"min", range->first}, {"max", range->second}};
    }
    // A file name need not be UTF-8, which JSON demands: its stray bytes become U+FFFD.
    std::cout << j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << '\n';
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
            << "volume     "
            << (has_volume     ? brief(volume)
                : out_of_range ? out_of_range
                               : "n/a (invalid complex)")
            << '\n';
  if (mass) {
    std::vector<double> c(mass->centroid.begin(), mass->centroid.end());
    std::string rows;
    for (int i = 0; i < dim; ++i) {
      std::vector<double> row(mass->second_moment.row(i).begin(), mass->second_moment.row(i).end());
      rows += (i ? ", (" : "(") + join(row, brief) + ")";
    }
    std::cout << "boundary   " << brief(mass->boundary_volume) << " (" << dim - 1
              << "-volume of the facets)\n"
              << "centroid   (" << join(c, brief) << ")\n"
              << "moment     (" << rows << ")  (int x x^T over the solid, about the origin)\n";
    if (mass->winding_weighted)
      std::cout << "winding    the boundary winds more than once around some points (a star "
                   "model): volume, centroid and moment are weighted by the winding number\n";
  } else {
    std::cout << "mass       n/a (" << no_mass << ")\n";
  }
  if (range) {
    std::vector<double> u(unit.data(), unit.data() + unit.size());
    std::cout << "offsets    d from " << brief(range->first) << " to " << brief(range->second)
              << " along the unit normal (" << join(u, brief)
              << "): planes n.x = d with d in this range meet the model\n";
  }
}

struct ConvertSettings {
  std::string model;
  std::string output;
  std::string format;  // --format, empty: from the extension
  bool no_uvw = false;
};

void run_convert(const ConvertSettings& s) {
  // nOFF or G4MF, by --format or by the extension.
  const std::string ext = lower_extension(s.output);
  SectionFormat format = SectionFormat::off;
  if (s.format.empty()) {
    if (ext == ".g4tf")
      format = SectionFormat::g4tf;
    else if (ext == ".g4b")
      format = SectionFormat::g4b;
    else if (!is_off_extension(ext))
      throw InputError("cannot write " + quote_user_text(s.output) +
                       ": convert writes nOFF (.4off, .off, .noff) or G4MF (.g4tf, .g4b; "
                       "--format g4tf-bin puts the buffer of a .g4tf in a .bin)");
  } else {
    if (s.format != "4off" && s.format != "off" && s.format != "noff" && s.format != "g4tf" &&
        s.format != "g4tf-bin" && s.format != "g4b")
      throw InputError("--format " + quote_user_text(s.format) +
                       ": convert writes 4off, g4tf, g4tf-bin or g4b");
    format = choose_format(s.output, s.format);
  }
  if (format == SectionFormat::off && s.no_uvw)
    throw InputError("--no-uvw applies to G4MF output (nOFF holds no texture coordinates)");
  const Complex model = load(s.model);
  require_valid(model, s.model);
  prepare_output_directory(s.output);
  std::vector<std::string> files{s.output};
  if (format == SectionFormat::off) {
    write_off_file(s.output, model);
  } else {
    G4mfWriteOptions opt;
    opt.container = g4mf_container(format);
    opt.name = model_item_name(s.model);
    opt.description = "cw4d convert of " + s.model;
    files = write_g4mf_model_file(s.output, model, opt, !s.no_uvw);
  }
  std::cout << "wrote " << describe_files(files) << ": " << describe_counts(model) << '\n';
}

}  // namespace

void add_info_command(CLI::App& app, Commands& commands) {
  auto settings = std::make_shared<InfoSettings>();
  auto* cmd = app.add_subcommand(
      "info",
      "Report dimension, f-vector, validity, bounds, volume and mass properties of a model.");
  cmd->add_option("MODEL", settings->model,
                  "Built-in spec (see 'cw4d list') or a .4off/.off/.g4tf/.g4b file")
      ->required();
  cmd->add_flag("--json", settings->json, "Print one JSON object instead of text");
  cmd->add_option("--normal", settings->normal,
                  "Also print the range of offsets d for which the plane n.x = d (n normalized, "
                  "as slice takes it) meets the model")
      ->type_name("X,Y,Z,W");
  cmd->footer(
      "An invalid model is reported (\"valid\": false, with its issues), not an error: exit 0.\n"
      "The volume is null / n/a for an invalid model.\n"
      "Mass properties of the solid of density 1 (JSON \"mass\"): hypervolume, boundary_volume\n"
      "(the facets' (n-1)-volume), centroid and second_moment = int x x^T dV about the origin\n"
      "(an n x n matrix; about the centroid subtract hypervolume * c c^T), exact to rounding\n"
      "(signed simplices of the oriented boundary). A star model (the boundary winds more than\n"
      "once) gives winding-weighted values and \"winding_weighted\": true. A model that is not\n"
      "closed and valid has \"mass\": null and the reason in \"mass_reason\".\n"
      "Exit codes: see 'cw4d --help'.");
  commands.push_back({cmd, [settings] { run_info(*settings); }});
}

void add_convert_command(CLI::App& app, Commands& commands) {
  auto settings = std::make_shared<ConvertSettings>();
  auto* cmd = app.add_subcommand("convert", "Validate a model and write it as nOFF or G4MF.");
  cmd->add_option("MODEL", settings->model,
                  "Built-in spec (see 'cw4d list') or a .4off/.off/.g4tf/.g4b file")
      ->required();
  cmd->add_option("-o,--output", settings->output,
                  "Output file: .4off, .off or .noff (nOFF); .g4tf or .g4b (G4MF)")
      ->required();
  cmd->add_option("--format", settings->format,
                  "Force the format instead of taking it from the extension: 4off, g4tf, "
                  "g4tf-bin (a .g4tf whose buffer is a .bin beside it), g4b")
      ->type_name("NAME");
  cmd->add_flag("--no-uvw", settings->no_uvw,
                "G4MF: leave out the texture coordinates of the facet corners");
  cmd->footer(
      "The three nOFF extensions write nOFF (\"4OFF\" for 4D models, \"OFF\" for 3D ones).\n"
      "G4MF (godot-4d's Good 4D Model Format): .g4tf is JSON with the buffer embedded\n"
      "(base64), --format g4tf-bin puts it in NAME.bin beside the .g4tf, .g4b is binary.\n"
      "One mesh: float64 vertices, the edges, faces as edge cycles, cells as face lists\n"
      "(ordered so that G4MF's first-two-members rule gives cw4d's orientation), colors,\n"
      "facet normals and each facet's box-mapped UVW per corner (docs/formats.md).\n"
      "Missing parent directories of the output are created.\n"
      "Exit codes: see 'cw4d --help'.");
  commands.push_back({cmd, [settings] { run_convert(*settings); }});
}

}  // namespace cw4d::cli
