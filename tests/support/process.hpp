#pragma once
// Running programs from tests: the cw4d binary, and the independent readers (assimp, node).
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "support/temp_dir.hpp"

namespace cw4d::test {

/// `s` in single quotes for /bin/sh.
inline std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char ch : s) out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return out + "'";
}

struct Result {
  int code = -1;  ///< exit status, -1 when killed by a signal
  std::string out, err;
};

/// Runs `program args...` inside `dir` through /bin/sh; stdout and stderr are captured.
inline Result run_program(const TempDir& dir, const std::string& program,
                          const std::vector<std::string>& args) {
  const std::filesystem::path out = dir / ".stdout", err = dir / ".stderr";
  std::string cmd = "cd " + shell_quote(dir.path().string()) + " && " + shell_quote(program);
  for (const auto& a : args) cmd += ' ' + shell_quote(a);
  cmd += " >" + shell_quote(out.string()) + " 2>" + shell_quote(err.string()) + " </dev/null";
  const int status = std::system(cmd.c_str());
  Result r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

}  // namespace cw4d::test
