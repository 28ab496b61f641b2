// cw4d net: unfold the cells of a 4D polytope (the faces of a 3D one) into one cell's
// hyperplane and write the net like a section.
#include <iostream>
#include <tuple>

#include "cli.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/net.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/section_view.hpp"
#include "output.hpp"

namespace cw4d::cli {

namespace {

struct NetSettings {
  std::string model;
  std::string output;
  std::string format;
  long long root = -1;
  std::string tree = "auto";
  std::uint64_t seed = 1;
  std::string size = "800x600";
  bool no_edges = false;
};

// The net as a Section (what the writers and the section renderer take): its pieces' boundary
// elements name their model facet as a section's faces name their cell.
Section as_section(const Net& net) {
  Section sec;
  sec.complex = net.complex;
  const int m = net.complex.ambient_dim();
  sec.source.assign(m, {});
  sec.source[m - 1] = net.boundary_facet;
  return sec;
}

void run_net(NetSettings& s) {
  const bool png = lower_extension(s.output) == ".png";
  if (png && !s.format.empty() && s.format != "png")
    throw InputError("--format " + s.format + " contradicts the extension of '" + s.output +
                     "' (png)");
  if (!png && s.format == "png")
    throw InputError("--format png contradicts the extension of '" + s.output +
                     "': name the file .png or drop --format");
  const SectionFormat format = png ? SectionFormat::obj : choose_format(s.output, s.format);
  const NetTree tree = parse_net_tree(s.tree);
  render::RasterOptions raster;
  if (png) {
    std::tie(raster.width, raster.height) = parse_image_size(s.size);
    check_held_pixels(s.size, raster.width, raster.height, 1.0);
  }

  const Complex model = load(s.model);
  const int dim = model.ambient_dim();
  if (dim != 3 && dim != 4)
    throw InputError("net unfolds 3D and 4D models; model " + quote_user_text(s.model) +
                     " lives in R^" + std::to_string(dim));
  const std::string where =
      "the net of model " + quote_user_text(s.model) + " lives in R^" + std::to_string(dim - 1);
  if (dim == 3 && (png || format != SectionFormat::obj))
    throw InputError(std::string(png ? "png" : format_name(format)) +
                     " output holds 3D nets of 4D models; " + where + " (write .obj instead)");
  if (dim == 4 && !png) check_format(format, 4, where);
  require_valid(model, s.model);
  if (s.root >= static_cast<long long>(model.count(dim - 1)))
    throw InputError("--root " + std::to_string(s.root) + ": model " + quote_user_text(s.model) +
                     " has " + std::to_string(model.count(dim - 1)) + " " +
                     rank_name(dim - 1, model.count(dim - 1)) + ", numbered from 0");

  NetOptions opt;
  opt.root = s.root;
  opt.tree = tree;
  opt.seed = s.seed;
  const Net net = unfold(model, opt);
  const Section sec = as_section(net);

  prepare_output_directory(s.output);
  std::string written = s.output;
  if (png) {
    render::SectionViewOptions o;
    o.raster = raster;
    o.edges = !s.no_edges;
    render::write_png(s.output, render::render_section(sec, o, &model), glm::vec3(1.0f));
  } else {
    Input input;
    SceneObject obj;
    obj.model = s.model;
    obj.complex = std::make_shared<const Complex>(model);
    obj.transform = AffineTransform::identity(dim);
    input.scene.objects.push_back(std::move(obj));
    SectionOutput out;
    out.format = format;
    out.uvw = false;
    out.comment = "cw4d net of " + s.model + "\ntree: " + net_tree_name(net.tree) +
                  (net.tree == NetTree::Random ? " (seed " + std::to_string(net.seed) + ")" : "") +
                  ", root " + rank_name(dim - 1, 1) + " " + std::to_string(net.root);
    written = describe_files(write_section(s.output, sec, input, out));
  }

  const std::string pieces = rank_name(dim - 1, net.complex.count(dim - 1));
  std::cout << "wrote " << written << ": net of " << s.model << ", " << net.complex.count(dim - 1)
            << " " << pieces << " unfolded into the hyperplane of " << rank_name(dim - 1, 1) << " "
            << net.root << " (" << net_tree_name(net.tree) << " tree"
            << (net.tree == NetTree::Random ? ", seed " + std::to_string(net.seed) : "") << ", "
            << net.trees_tried << (net.trees_tried == 1 ? " tree" : " trees") << " tried), "
            << (dim == 4 ? "volume " : "area ") << brief(signed_volume(net.complex)) << ", "
            << (net.overlaps.empty() ? "no overlaps"
                                     : std::to_string(net.overlaps.size()) + " overlapping pairs")
            << '\n';
  if (!net.overlaps.empty()) {
    const auto [a, b] = net.overlaps.front();
    std::cerr << "cw4d: warning: the net overlaps itself: " << rank_name(dim - 1, 2) << " " << a
              << " and " << b << " overlap"
              << (net.overlaps.size() > 1
                      ? ", and " + std::to_string(net.overlaps.size() - 1) + " more pairs"
                      : std::string())
              << "; "
              << (tree == NetTree::Auto
                      ? "no tree without overlaps among the " + std::to_string(net.trees_tried) +
                            " tried (try another --root)"
                      : "try --tree auto")
              << '\n';
  }
}

}  // namespace

void add_net_command(CLI::App& app, Commands& commands) {
  auto s = std::make_shared<NetSettings>();
  auto* cmd = app.add_subcommand(
      "net", "Unfold a 4D polytope's cells (a 3D polytope's faces) into a net and write it.");
  cmd->add_option("MODEL", s->model,
                  "Built-in spec (see 'cw4d list') or a .4off/.off/.g4tf/.g4b file")
      ->required();
  cmd->add_option("-o,--output", s->output,
                  "Output file: .obj, .gltf, .glb, .ply, .stl, .svg, .png (a shaded picture), "
                  ".4off/.off/.noff or .g4tf/.g4b; a 3D model's net (polygons in the plane z = "
                  "0): .obj")
      ->required();
  cmd->add_option("--format", s->format,
                  "Force the output format instead of taking it from the extension")
      ->type_name("NAME");
  cmd->add_option("--root", s->root,
                  "The cell (face of a 3D model) whose hyperplane the net lies in (default: "
                  "cell 0, and with --tree auto the others after it)")
      ->type_name("CELL")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--tree", s->tree,
                  "Spanning tree of the cells: auto (default), bfs, dfs, greedy, random")
      ->check(CLI::IsMember({"auto", "bfs", "dfs", "greedy", "random"}));
  cmd->add_option("--seed", s->seed, "random: the seed of the tree (auto: of the first one)");
  cmd->add_option("--size", s->size, "png: image size in pixels (default 800x600)")
      ->type_name("WxH");
  cmd->add_flag("--no-edges", s->no_edges, "png: leave out the edge overlay");
  cmd->footer(
      "Each cell is rotated about the face it shares with its parent in a spanning tree of the\n"
      "cell-adjacency graph into the parent's hyperplane, on the far side of that face; the\n"
      "net is one closed solid per cell (cell colors kept), in an orthonormal frame of the\n"
      "root cell's hyperplane. Trees:\n"
      "  bfs     breadth first from the root (compact: the tesseract's cross of eight cubes)\n"
      "  dfs     depth first from the root (long chains)\n"
      "  greedy  breadth first, attaching a cell only where it overlaps nothing placed\n"
      "  random  a random spanning tree (--seed)\n"
      "  auto    the first tree without overlaps among bfs, greedy, dfs, a depth-first greedy\n"
      "          and 16 random trees from the root, then from up to 8 roots when --root is\n"
      "          not given\n"
      "Overlaps are decided exactly for convex cells (separating axes; touching cells do not\n"
      "overlap) and conservatively for non-convex ones. A net that overlaps is still written,\n"
      "with a warning on stderr.\n"
      "Examples:\n"
      "  cw4d net tesseract --tree bfs -o cross.obj\n"
      "  cw4d net 120-cell -o net.png\n"
      "Exit codes: see 'cw4d --help'.");
  commands.push_back({cmd, [s] { run_net(*s); }});
}

}  // namespace cw4d::cli
