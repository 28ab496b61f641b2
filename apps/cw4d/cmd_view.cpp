// cw4d view: one self-contained HTML file (the viewer of web/, its WebAssembly core and scripts
// inlined) showing a model, to open from disk with no server.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <system_error>
#include <vector>

#include "cli.hpp"
#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/input_file.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/text.hpp"
#include "view_page.hpp"

// Where the viewer page is looked for (apps/CMakeLists.txt): CW4D_VIEW_INSTALL_DIR relative to
// the executable's directory (../share/cw4d in an installed prefix); CW4D_VIEW_BUILD_TEMPLATE (the
// web build's page) only when the executable is the one in CW4D_VIEW_BUILD_EXE_DIR.
#ifndef CW4D_VIEW_INSTALL_DIR
#define CW4D_VIEW_INSTALL_DIR "../share/cw4d"
#endif
#ifndef CW4D_VIEW_BUILD_TEMPLATE
#define CW4D_VIEW_BUILD_TEMPLATE ""
#endif
#ifndef CW4D_VIEW_BUILD_EXE_DIR
#define CW4D_VIEW_BUILD_EXE_DIR ""
#endif

namespace cw4d::cli {

namespace {

struct ViewSettings {
  Placement placement;
  double offset = 0.0;
  std::string output;
  std::string templ;  // --template; empty: found by find_template
};

constexpr std::string_view kPageName = "cw4d-view.html";

// The viewer page when no --template is given: relative to the running executable's folder
// (<exe dir>/../share/cw4d/cw4d-view.html, so an installed tree still works when moved), then
// the web build's page, but only for the executable of the build tree.
std::string find_template() {
  namespace fs = std::filesystem;
  std::vector<fs::path> looked;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec && exe.is_absolute()) {
    const fs::path dir = exe.parent_path();
    looked.push_back((dir / CW4D_VIEW_INSTALL_DIR / kPageName).lexically_normal());
    const fs::path build_dir = CW4D_VIEW_BUILD_EXE_DIR;
    if (!build_dir.empty() && !std::string_view(CW4D_VIEW_BUILD_TEMPLATE).empty() &&
        fs::equivalent(dir, build_dir, ec) && !ec)
      looked.emplace_back(CW4D_VIEW_BUILD_TEMPLATE);
  }
  for (const fs::path& path : looked)
    if (fs::is_regular_file(path, ec)) return path.string();
  std::string where;
  for (const fs::path& path : looked) where += (where.empty() ? "" : ", ") + path.string();
  where = where.empty() ? "the executable's own path is unknown" : "looked in " + where;
  throw InputError("the viewer page cw4d-view.html is missing (" + where +
                   "): build the web viewer (./setup.sh does, with emscripten), install it with "
                   "'cmake --install build', or give --template FILE");
}

void run_view(ViewSettings& s) {
  s.placement.parse("view");
  const Placement& p = s.placement;
  if (!p.scene.empty()) throw InputError("view shows one MODEL, not a --scene");
  if (!std::isfinite(s.offset)) throw InputError("--offset must be a finite number");
  if (lower_extension(s.output) != ".html" && lower_extension(s.output) != ".htm")
    throw InputError("-o: the view is an .html file, got " + quote_user_text(s.output));
  if (s.templ.empty()) s.templ = find_template();
  std::string templ;
  try {
    templ = read_input_file(s.templ);
  } catch (const ParseError& e) {
    // The reason as the reader gives it: missing, not a regular file (a FIFO), too large...
    throw InputError("cannot use the viewer page " + quote_user_text(s.templ) + ": " + e.message() +
                     "; build the web viewer (./setup.sh does, with emscripten) or give "
                     "--template FILE (build-web/web/site/cw4d-view.html)");
  }
  if (templ.find(kViewConfigMarker) == std::string::npos)
    throw InputError(quote_user_text(s.templ) +
                     " is not the viewer page (no configuration marker)");

  const Input input = load_input(p);
  if (input.dim() != 4)
    throw InputError("view shows 4D models; " + quote_user_text(p.model) + " lives in R^" +
                     std::to_string(input.dim()));
  // The model goes in as nOFF text with its placement applied, so the page shows exactly the
  // placed model (rotations in the order given) and needs neither the file nor the spec parser.
  const Complex placed = transformed(*input.models().front(), p.model_to_world(4));
  ViewPageOptions options;
  options.name = p.model + p.transform_text();
  options.normal = join(p.normal, exact);
  options.offset = exact(s.offset);
  const std::string page = view_page(templ, placed, options);
  prepare_output_directory(s.output);
  write_file_atomically(s.output, page);
  std::cout << "wrote " << s.output << ": " << p.model << " (" << describe_counts(placed)
            << "), plane n=(" << join(p.normal, brief) << "), d=" << brief(s.offset)
            << "; open it in a browser with WebGL2\n";
}

}  // namespace

void add_view_command(CLI::App& app, Commands& commands) {
  auto s = std::make_shared<ViewSettings>();
  auto* cmd = app.add_subcommand(
      "view", "Write one self-contained HTML viewer of a 4D model (opens from disk).");
  s->placement.add_options(*cmd);
  cmd->add_option("--offset", s->offset, "Initial offset d of the plane n.x = d (default 0)")
      ->type_name("D");
  cmd->add_option("-o,--output", s->output, "Output .html file")->required();
  cmd->add_option("--template", s->templ,
                  "The viewer page to fill (default: cw4d-view.html of the install, see below)")
      ->type_name("FILE");
  cmd->footer(
      "The page holds the model (as nOFF, placed by --rotate/--translate in the order given),\n"
      "the WebAssembly core and the viewer; it slices live in the browser. Controls: see the\n"
      "README.\n"
      "The page is filled from --template FILE; else from " CW4D_VIEW_INSTALL_DIR
      "/cw4d-view.html relative to\n"
      "this executable's folder (put there by 'cmake --install'; still found when the prefix is\n"
      "moved); else, for the executable of the build tree only, from the web build's site folder\n"
      "(CMake's CW4D_WEB_SITE_DIR, default build-web/web/site).\n"
      "The page may take at most 256 MiB: its size is bounded from the model before it is\n"
      "built, and a larger one is refused (exit 1). The model's name, normal and offset go into\n"
      "the page as JSON escaped for a <script> element (file names need not be UTF-8).\n"
      "Exit codes: see 'cw4d --help'.");
  commands.push_back({cmd, [s] { run_view(*s); }});
}

}  // namespace cw4d::cli
