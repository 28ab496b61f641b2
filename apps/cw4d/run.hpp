#pragma once
// The cw4d command line as a function.

namespace cw4d::cli {

/// Parses argv (argv[0] is the program name) and runs the subcommand. Returns the exit code of the
/// table in docs/cli.md (0 to 6) and never calls exit(): every failure, out of memory included, is
/// caught and reported as one "cw4d: error: ..." line on stderr. \pre argv[argc] == nullptr.
int run(int argc, char** argv);

}  // namespace cw4d::cli
