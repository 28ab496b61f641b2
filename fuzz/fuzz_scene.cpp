// libFuzzer target: the JSON scene reader (read_scene) on arbitrary bytes. Model files named in
// a scene are looked up relative to a directory that does not exist, and inputs that could name
// an absolute path are skipped: a fuzzer must not read the machine's files.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  // Keep every model spec small and file-free: no '/' except in "//" and "/* */" comments and no
  // escapes that could spell one ("\/", "\u002f").
  for (std::size_t i = 0; i < text.size(); ++i) {
    const bool comment = (i + 1 < text.size() && (text[i + 1] == '/' || text[i + 1] == '*')) ||
                         (i > 0 && (text[i - 1] == '/' || text[i - 1] == '*'));
    if (text[i] == '/' && !comment) return 0;
    if (text[i] == '\\' && i + 1 < text.size() && (text[i + 1] == '/' || text[i + 1] == 'u'))
      return 0;
  }
  // Numbers in model specs stay at most 5 (see fuzz_spec.cpp); other numbers (angles, colors)
  // are not limited by this: only the digits right after a ':' or ',' of a spec are.
  int number = 0;
  char before = ' ';
  for (char ch : text) {
    if (ch >= '0' && ch <= '9') {
      number = std::min(number * 10 + (ch - '0'), 1000);
      if ((before == ':' || before == ',') && number > 5) return 0;
    } else {
      number = 0;
      before = ch;
    }
  }
  std::istringstream in(text);
  try {
    const cw4d::Scene scene = cw4d::read_scene(in, "fuzz.json", "/nonexistent-cw4d-fuzz-dir");
    (void)scene.dim();
  } catch (const cw4d::Error&) {
  }
  return 0;
}
