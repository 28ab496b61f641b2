// cw4d::cli::run, the whole command line as a function (main.cpp calls it; so does the
// libFuzzer target fuzz/fuzz_cli.cpp). One subcommand per cmd_<name>.cpp, registered below.
//
// Options are parsed into one settings struct per subcommand and checked before any model is
// loaded; every failure class maps to one documented exit code (kExitCodes in cli.cpp), and
// every error is a single "cw4d: error: ..." line on stderr.
#include <algorithm>
#include <exception>
#include <iostream>
#include <new>
#include <set>

#include "cli.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/text.hpp"
#include "run.hpp"

namespace {

using cw4d::cli::Exit;

int fail(Exit code, const std::string& message) {
  std::cerr << "cw4d: error: " << cw4d::cli::one_line(cw4d::cli::bounded_message(message)) << '\n';
  return static_cast<int>(code);
}

// The subcommand argv names when it is not an option ("" when it is an option or missing).
std::string first_word(int argc, char** argv) {
  return argc > 1 && argv[1][0] != '-' ? std::string(argv[1]) : std::string();
}

}  // namespace

int cw4d::cli::run(int argc, char** argv) {
  namespace cli = cw4d::cli;
  CLI::App app{"cw4d: 4D polytopes as CW complexes, cut by hyperplanes into 3D meshes.", "cw4d"};
  app.footer(cli::kExitCodes);
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("cw4d ") + CW4D_VERSION);

  cli::Commands commands;
  cli::add_list_command(app, commands);
  cli::add_info_command(app, commands);
  cli::add_slice_command(app, commands);
  cli::add_net_command(app, commands);
  cli::add_sweep_command(app, commands);
  cli::add_render_command(app, commands);
  cli::add_tetrahedralize_command(app, commands);
  cli::add_convert_command(app, commands);
  cli::add_atlas_command(app, commands);
  cli::add_bench_command(app, commands);
  cli::add_view_command(app, commands);
  cli::add_check_command(app, commands);
  bool strict = false;
  app.add_flag("--strict", strict,
               "Refuse nOFF files whose header counts disagree with their body (else they are "
               "read as the body stands, with a warning)");

  // "cw4d help [COMMAND]" is "cw4d [COMMAND] --help"; an unknown first word is a mistyped
  // subcommand, named as such (CLI11 would only say that a subcommand is required).
  const std::string word = first_word(argc, argv);
  if (word == "help") {
    if (argc == 2) {
      std::cout << app.help();
      return static_cast<int>(Exit::ok);
    }
    for (const auto* sub : app.get_subcommands({}))
      if (sub->get_name() == argv[2]) {
        std::cout << sub->help();
        return static_cast<int>(Exit::ok);
      }
    return fail(Exit::usage, "help: unknown subcommand " + quote_user_text(std::string(argv[2])) +
                                 cli::did_you_mean(argv[2], cli::subcommand_names(app)) +
                                 " (run 'cw4d help')");
  }
  if (!word.empty()) {
    const auto names = cli::subcommand_names(app);
    if (std::find(names.begin(), names.end(), word) == names.end())
      return fail(Exit::usage, "unknown subcommand " + quote_user_text(word) +
                                   cli::did_you_mean(word, names) + " (run 'cw4d help')");
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help: print it to stdout
    return fail(Exit::usage, std::string(e.what()) + " (run 'cw4d --help')");
  }

  cw4d::OffReadOptions off_options;
  off_options.strict = strict;
  // Once per file and problem, though a command may read a file more than once.
  off_options.warn = [printed = std::set<std::string>()](const std::string& warning) mutable {
    if (!printed.insert(warning).second) return;
    std::cerr << "cw4d: warning: " << cw4d::cli::one_line(cw4d::cli::bounded_message(warning))
              << '\n';
  };
  const cw4d::ScopedOffReadOptions scoped_off_options(off_options);
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
  } catch (const cli::CheckFailed& e) {
    return fail(Exit::check_failed, e.what());
  } catch (const cli::EmptySection& e) {
    return fail(Exit::empty_section, e.what());
  } catch (const std::bad_alloc&) {
    return fail(Exit::internal, "out of memory");
  } catch (const std::exception& e) {
    return fail(Exit::internal, std::string("internal error: ") + e.what());
  }
  return static_cast<int>(Exit::ok);
}
