// libFuzzer target: the model-spec parser (model_family, load_model) on arbitrary text.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 64) return 0;
  const std::string spec(reinterpret_cast<const char*>(data), size);
  // No files (a spec that is not a built-in is a path: the fuzzer must not open the machine's
  // files), no number above 5 and at most two ':' (one operator around one parametric model).
  // The library rejects huge models, but the largest ones it accepts take seconds per input
  // under the sanitizers: building cube:7 decomposes its 6-cube facets into 6! * 2^6 simplices
  // each for the normals, and ditorus:...,64 has 262144 cells.
  if (spec.find('/') != std::string::npos) return 0;
  if (std::count(spec.begin(), spec.end(), ':') > 2) return 0;
  int number = 0;
  for (char ch : spec) {
    number = (ch >= '0' && ch <= '9') ? std::min(number * 10 + (ch - '0'), 1000) : 0;
    if (number > 5) return 0;
  }
  try {
    (void)cw4d::model_family(spec);
    if (!cw4d::is_builtin_spec(spec)) return 0;  // a file name: not this target's business
    // Building is the target; validating the result (covered by the tests) would make the
    // largest accepted models, e.g. orthoplex:9 with its 8-dimensional facets, take seconds.
    const cw4d::Complex c = cw4d::load_model(spec);
    (void)c.fvector();
  } catch (const cw4d::Error&) {
  }
  return 0;
}
