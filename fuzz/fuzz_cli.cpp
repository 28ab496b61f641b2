// libFuzzer target: the whole command line. An input is an argument vector, the arguments
// separated by NUL bytes (argv[0] is supplied), run through cw4d::cli::run exactly as main()
// does. What must hold: no crash, no sanitizer report, and the exit code is one of docs/cli.md's
// table other than 6 (an internal error is a bug). Every run happens in one scratch directory
// that holds a few small inputs (a.4off: the 5-cell, b.off: a cube, s.json: a scene, p.txt:
// the tesseract's vertices) and is emptied and refilled before each run; arguments containing
// '/' are not run, so a path names at most the parent of that directory (".."), which is the
// scratch folder's own root, emptied too (and removed at exit). Sizes are bounded: at most 32
// arguments and 512 bytes, and no integer in an argument above 8 (exponents, decimals and the
// names "N-cell" excepted), and `render` draws at most 160x120 pixels per picture (a --size is
// added where the input gives none): what cw4d's own limits let through takes seconds in a release
// build but ~10x that instrumented (a contact sheet of 64 layers of 800x600 pixels; info cube:8,
// 0.4 s released, 9-15 s here), so the fuzzer keeps to the inputs that finish well within its
// timeout.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <streambuf>
#include <string>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/off_io.hpp"
#include "run.hpp"

namespace {

namespace fs = std::filesystem;

fs::path home, root, scratch;         // scratch = root/w, the working directory
std::string five_cell_off, cube_off;  // written by the library's own nOFF writer

std::string off_text(const char* spec) {
  std::ostringstream out;
  cw4d::write_off(out, cw4d::load_model(spec));
  return out.str();
}

class NullBuffer : public std::streambuf {
 protected:
  int overflow(int c) override { return c; }
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
};

void refill() {
  for (const auto& entry : fs::directory_iterator(root))
    if (entry.path() != scratch) fs::remove_all(entry.path());
  for (const auto& entry : fs::directory_iterator(scratch)) fs::remove_all(entry.path());
  std::ofstream(scratch / "a.4off") << five_cell_off;
  std::ofstream(scratch / "b.off") << cube_off;
  std::ofstream(scratch / "s.json")
      << R"({"objects": [{"model": "tesseract", "scale": 0.5, "color": "#ff8000"},)"
      << R"( {"model": "a.4off", "translate": [1, 0, 0, 0]}]})" << '\n';
  std::ofstream p(scratch / "p.txt");
  for (int i = 0; i < 16; ++i)
    p << (i & 1 ? 1 : -1) << ' ' << (i & 2 ? 1 : -1) << ' ' << (i & 4 ? 1 : -1) << ' '
      << (i & 8 ? 1 : -1) << '\n';
}

// Integers above 8 (a digit run not after '.', 'e' or 'E', nor a polychoron's "N-cell"), '/'
// anywhere.
bool acceptable(const std::string& arg) {
  if (arg.find('/') != std::string::npos) return false;
  for (std::size_t i = 0; i < arg.size();) {
    if (!(arg[i] >= '0' && arg[i] <= '9')) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < arg.size() && arg[j] >= '0' && arg[j] <= '9') ++j;
    std::size_t k = i;
    while (k > 0 && (arg[k - 1] == '+' || arg[k - 1] == '-')) --k;
    const bool fraction_or_exponent =
        k > 0 && (arg[k - 1] == '.' || arg[k - 1] == 'e' || arg[k - 1] == 'E');
    const bool cell_name = arg.compare(j, 5, "-cell") == 0;  // 24-cell, 120-cell, ...
    if (!fraction_or_exponent && !cell_name && (j - i > 2 || std::stoi(arg.substr(i, j - i)) > 8))
      return false;
    if (fraction_or_exponent && j - i > 17) return false;
    i = j;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  char name[] = "/tmp/cw4d-fuzz-cli-XXXXXX";
  if (!::mkdtemp(name)) std::abort();
  root = name;
  scratch = root / "w";
  fs::create_directory(scratch);
  std::atexit([] {
    std::error_code ignored;
    fs::current_path(home, ignored);
    fs::remove_all(root, ignored);
  });
  five_cell_off = off_text("5-cell");
  cube_off = off_text("cube:3");
  // The working directory is the scratch folder only while a command runs: libFuzzer reads
  // and writes its corpus folders, given relative to where it was started, in between.
  home = fs::current_path();
  // The command's own output is not the fuzzer's: stdout goes nowhere, std::cerr too (libFuzzer
  // reports on the C stderr, which stays).
  static NullBuffer null;
  std::cout.rdbuf(&null);
  std::cerr.rdbuf(&null);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0 || size > 512) return 0;
  std::vector<std::string> args{"cw4d"};
  std::string current;
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == 0) {
      args.push_back(current);
      current.clear();
    } else {
      current += static_cast<char>(data[i]);
    }
  }
  args.push_back(current);
  if (args.size() > 33) return 0;
  for (const std::string& a : args)
    if (!acceptable(a)) return 0;
  // bench measures for seconds by design; it is not an input handler.
  if (args.size() > 1 && args[1] == "bench") return 0;
  // A picture is at most 160x120 pixels unless the input chose a --size (of integers <= 8).
  if (args.size() > 1 && args[1] == "render") {
    bool sized = false;
    for (const std::string& a : args) sized = sized || a.rfind("--size", 0) == 0;
    if (!sized) {
      args.push_back("--size");
      args.push_back("160x120");
    }
  }
  refill();
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  fs::current_path(scratch);
  const int code = cw4d::cli::run(static_cast<int>(args.size()), argv.data());
  fs::current_path(home);
  if (code < 0 || code > 7 || code == 6) {
    std::fprintf(stderr, "fuzz_cli: exit code %d\n", code);
    std::abort();
  }
  return 0;
}
