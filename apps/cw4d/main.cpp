// The cw4d command line: one subcommand per cmd_<name>.cpp, registered below.
//
// Options are parsed into one settings struct per subcommand and checked before any model is
// loaded; every failure class maps to one documented exit code (kExitCodes in cli.cpp), and
// every error is a single "cw4d: error: ..." line on stderr.
#include <exception>
#include <iostream>

#include "cli.hpp"
#include "cw4d/tetrahedralize/hull.hpp"

namespace {

using cw4d::cli::Exit;

int fail(Exit code, const std::string& message) {
  std::cerr << "cw4d: error: " << cw4d::cli::one_line(message) << '\n';
  return static_cast<int>(code);
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = cw4d::cli;
  cw4d::register_hull_models();
  CLI::App app{"cw4d: 4D polytopes as CW complexes, cut by hyperplanes into 3D meshes.", "cw4d"};
  app.footer(cli::kExitCodes);
  app.require_subcommand(1);

  cli::Commands commands;
  cli::add_list_command(app, commands);
  cli::add_info_command(app, commands);
  cli::add_slice_command(app, commands);
  cli::add_sweep_command(app, commands);
  cli::add_render_command(app, commands);
  cli::add_tetrahedralize_command(app, commands);
  cli::add_convert_command(app, commands);
  cli::add_bench_command(app, commands);
  cli::add_view_command(app, commands);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help: print it to stdout
    return fail(Exit::usage, std::string(e.what()) + " (run 'cw4d --help')");
  }

  try {
    for (const auto& command : commands)
      if (*command.app) command.run();
  } catch (const cw4d::ParseError& e) {
    return fail(Exit::bad_input, e.what());
  } catch (const cw4d::InputError& e) {
    return fail(Exit::usage, e.what());
  } catch (const cw4d::TopologyError& e) {
    return fail(Exit::invalid_complex, e.what());
  } catch (const cw4d::IoError& e) {
    return fail(Exit::cannot_write, e.what());
  } catch (const cli::EmptySection& e) {
    return fail(Exit::empty_section, e.what());
  } catch (const std::exception& e) {
    return fail(Exit::internal, std::string("internal error: ") + e.what());
  }
  return static_cast<int>(Exit::ok);
}
