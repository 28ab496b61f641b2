// cw4d sweep: N parallel sections, written as numbered files or as one animated glTF.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "cli.hpp"
#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/export/gltf.hpp"
#include "cw4d/section/slicer.hpp"
#include "output.hpp"

namespace cw4d::cli {

namespace {

namespace fs = std::filesystem;

struct SweepSettings {
  Placement placement;
  double from = 0.0, to = 0.0;
  int layers = 0;
  double seconds = 0.1;
  bool no_uvw = false;
  bool quiet = false;
  std::string format;
  std::string output;
};

// Where layer i goes when the sweep is written as one file per layer.
struct LayerFiles {
  fs::path directory;
  std::string stem;  // "layer" or the stem of the path given
  std::string extension;
  int digits = 3;
  std::string path(int i) const {
    std::string number = std::to_string(i);
    if (static_cast<int>(number.size()) < digits)
      number.insert(0, static_cast<std::size_t>(digits) - number.size(), '0');
    return (directory / (stem + "_" + number + extension)).string();
  }
};

void run_sweep(SweepSettings& s) {
  Placement& p = s.placement;
  p.parse("sweep");
  if (!std::isfinite(s.from) || !std::isfinite(s.to))
    throw InputError("--from and --to must be finite numbers");
  if (s.layers < 1 || s.layers > 100000)
    throw InputError("--layers " + std::to_string(s.layers) + ": give 1 to 100000 layers");
  if (s.layers > 1 && s.from == s.to)
    throw InputError("--from and --to are equal: " + std::to_string(s.layers) +
                     " layers would all be the same section");
  if (!(s.seconds > 0.0) || !std::isfinite(s.seconds))
    throw InputError("--seconds must be a positive number");

  // One glTF file with a node per layer, or one file per layer.
  const std::string ext = lower_extension(s.output);
  const bool one_file = s.format.empty() ? (ext == ".glb" || ext == ".gltf")
                                         : (s.format == "glb" || s.format == "gltf") &&
                                               (ext == ".glb" || ext == ".gltf");
  SectionOutput out;
  LayerFiles layer;
  if (one_file) {
    out.format = choose_format(s.output, s.format);
  } else if (ext.empty()) {
    out.format = choose_format("", s.format.empty() ? "obj" : s.format);
    // "layers/" names the folder "layers" (its staging folder and the final rename need the
    // folder's own name, which a trailing separator hides).
    layer.directory = fs::path(s.output);
    while (!layer.directory.has_filename() && layer.directory.has_relative_path())
      layer.directory = layer.directory.parent_path();
    layer.stem = "layer";
    layer.extension = format_extension(out.format);
  } else {
    out.format = choose_format(s.output, s.format);
    layer.directory = fs::path(s.output).parent_path();
    layer.stem = fs::path(s.output).stem().string();
    layer.extension = fs::path(s.output).extension().string();
  }
  layer.digits = std::max(3, static_cast<int>(std::to_string(s.layers - 1).size()));
  out.uvw = !s.no_uvw;

  const Input input = load_input(p);
  check_format(out.format, input.dim(),
               p.input_label() + " lives in R^" + std::to_string(input.dim()));

  // Layer files are written into a hidden staging folder beside their destination and moved
  // into place only when the whole sweep succeeded, by the rule every output follows
  // (atomic_file.hpp): an error, SIGINT or SIGTERM leaves no layer behind.
  const fs::path destination = layer.directory;
  std::optional<StagedFiles> staging;
  const bool new_folder = !one_file && ext.empty() && !fs::exists(fs::symlink_status(destination));
  if (!one_file) {
    const fs::path home = new_folder ? destination.parent_path() : destination;
    prepare_output_directory((home.empty() ? fs::path(".") : home / "x").string());
    staging.emplace(home.string(), new_folder ? destination.filename().string() : layer.stem);
    layer.directory = fs::path(staging->staged(""));
  }
  const auto drop_staging = [&] {
    if (staging) staging->discard();
  };

  ProgressBar progress("sweep", "layers", static_cast<std::size_t>(s.layers), !s.quiet);
  std::vector<GltfNode> nodes;
  std::vector<int> empty;
  std::vector<std::string> written;  // per layer file, for the summary
  std::vector<std::string> files;    // every file written, companions included
  std::size_t polygons = 0;
  progress.step(0);
  auto offset = [&](int i) {
    return s.layers == 1 ? s.from : s.from + (s.to - s.from) * i / (s.layers - 1);
  };
  // A single model is cut by one-pass sweeps of up to kChunk layers at a time, on every core
  // (slicer.hpp); each layer is exactly one section() with that plane (the sweep gets the raw
  // normal, which it normalises as Hyperplane::from does). Scenes are cut layer by layer.
  constexpr int kChunk = 256;
  std::optional<SliceModel> compiled;
  Slicer slicer;
  std::vector<SliceBuffers> swept;
  std::vector<double> offsets;
  // Brought near unit length by a power of two (exact, and what Hyperplane::from does), so that
  // its length cannot overflow or underflow.
  Eigen::VectorXd raw_normal = Eigen::Map<const Eigen::VectorXd>(
      p.normal.data(), static_cast<Eigen::Index>(p.normal.size()));
  const int e = std::ilogb(raw_normal.cwiseAbs().maxCoeff());
  raw_normal = raw_normal.unaryExpr([e](double x) { return std::scalbn(x, -e); }).eval();
  if (!input.is_scene)
    compiled.emplace(*input.scene.objects.front().complex, SliceModelOptions::unclustered());
  auto layer_section = [&](int i) {
    if (input.is_scene) return cut(input, p.plane(offset(i))).section;
    if (i % kChunk == 0) {
      offsets.clear();
      for (int k = i; k < std::min(s.layers, i + kChunk); ++k) offsets.push_back(offset(k));
      slicer.sweep(*compiled, raw_normal, offsets, input.scene.objects.front().transform, swept, 0);
    }
    return to_section(swept[i % kChunk]);
  };
  try {
    for (int i = 0; i < s.layers; ++i) {
      const double d = offset(i);
      const Section sec = layer_section(i);
      if (sec.empty()) {
        empty.push_back(i);
      } else {
        polygons += sec.complex.count(2);
        const std::string name = "layer " + std::to_string(i) + " d=" + brief(d);
        if (one_file) {
          GltfNode node;
          node.name = name;
          node.meshes = section_meshes(sec, input, out.uvw);
          nodes.push_back(std::move(node));
        } else {
          out.comment = "cw4d sweep of " + (input.is_scene ? "scene " + p.scene : p.model) + ", " +
                        name + "\nplane: n=(" + join(p.normal, exact) + "), d=" + exact(d) +
                        " (world space, n normalized)";
          if (!input.is_scene)
            out.comment += "\nmodel-to-world:" + p.transform_text() + " (in this order)";
          const auto layer_files = write_section(layer.path(i), sec, input, out);
          files.insert(files.end(), layer_files.begin(), layer_files.end());
          written.push_back(layer_files.front());
        }
      }
      progress.step(i + 1);
    }
  } catch (...) {
    // A failed sweep leaves none of its layers behind (files of earlier runs stay as they were).
    drop_staging();
    throw;
  }
  const std::string range = "d from " + brief(s.from) + " to " + brief(s.to);
  if (static_cast<int>(empty.size()) == s.layers) {
    drop_staging();
    throw EmptySection("every layer of the sweep (" + range + ") misses " + p.input_label() +
                       " (it meets " + offset_range(input, p.plane(0.0)) +
                       "); nothing written to " + quote_user_text(s.output));
  }
  if (!one_file) {
    // Into place: the staging folder becomes the new folder, or its files move one by one.
    if (new_folder) {
      staging->commit_as_folder(destination.string());
    } else {
      std::vector<std::string> names;
      for (const auto& f : files) names.push_back(fs::path(f).filename().string());
      staging->commit(names);
    }
    for (auto& w : written) w = (destination / fs::path(w).filename()).string();
  }
  if (one_file) {
    GltfOptions opt;
    opt.binary = out.format == SectionFormat::glb;
    opt.seconds_per_node = s.seconds;
    opt.description = "cw4d sweep of " + (input.is_scene ? "scene " + p.scene : p.model) +
                      ": planes n=(" + join(p.normal, exact) + "), " + range + ", " +
                      std::to_string(s.layers) + " layers";
    prepare_output_directory(s.output);
    write_gltf_file(s.output, nodes, opt);
    written.push_back(opt.binary ? s.output
                                 : s.output + " and " +
                                       fs::path(s.output).replace_extension(".bin").string());
  }
  const int full = s.layers - static_cast<int>(empty.size());
  std::cout << "wrote " << (one_file ? written.front() : std::to_string(written.size()) + " files")
            << ": " << full << " of " << s.layers << " layers, " << polygons << " polygons ("
            << (input.is_scene ? "scene " + p.scene : p.model) << ", " << range << ")\n";
  if (!one_file) std::cout << "  first " << written.front() << ", last " << written.back() << '\n';
  if (!empty.empty()) {
    std::cout << "  empty layers (not written):";
    for (int i : empty)
      std::cout << ' ' << i << " (d="
                << brief(s.layers == 1 ? s.from : s.from + (s.to - s.from) * i / (s.layers - 1))
                << ")";
    std::cout << '\n';
  }
}

}  // namespace

void add_sweep_command(CLI::App& app, Commands& commands) {
  auto s = std::make_shared<SweepSettings>();
  auto* cmd = app.add_subcommand(
      "sweep", "Cut a model with N parallel planes n.x = d, d from D0 to D1, and write them all.");
  s->placement.add_options(*cmd);
  cmd->add_option("--from", s->from, "Offset d of the first plane")->type_name("D0")->required();
  cmd->add_option("--to", s->to, "Offset d of the last plane")->type_name("D1")->required();
  cmd->add_option("--layers", s->layers, "Number of planes, evenly spaced from D0 to D1")
      ->type_name("N")
      ->required();
  cmd->add_option("--seconds", s->seconds,
                  "glTF: seconds each layer is shown by the animation (default 0.1)")
      ->type_name("S");
  cmd->add_option("--format", s->format,
                  "Format of the per-layer files (default: from the extension, else obj): obj, "
                  "gltf, glb, ply, stl, svg, 4off, g4tf, g4tf-bin, g4b")
      ->type_name("NAME");
  cmd->add_flag("--no-uvw", s->no_uvw, "Leave out the texture coordinates");
  cmd->add_flag("-q,--quiet", s->quiet, "No progress bar");
  cmd->add_option("-o,--output", s->output,
                  "A .glb/.gltf file (one node per layer, animated), a folder (layer_000.obj, "
                  "...), or a file name to number (out/s.ply -> out/s_000.ply, ...)")
      ->required();
  cmd->footer(
      "Layer i is cut at d = D0 + (D1 - D0) i / (N - 1). The model is placed as for 'slice'.\n"
      "Layers the planes miss are listed and not written; if every layer misses, nothing is\n"
      "written and the exit code is 5. A progress bar is drawn on stderr when it is a terminal.\n"
      "The .glb/.gltf holds one top-level node per non-empty layer (named \"layer i d=...\") and\n"
      "an animation \"sweep\" that shows one layer at a time (scale 1 while shown, else 0).\n"
      "Exit codes: see 'cw4d --help'.");
  commands.push_back({cmd, [s] { run_sweep(*s); }});
}

}  // namespace cw4d::cli
