// libFuzzer target: the G4MF reader (read_g4mf) on arbitrary bytes, .g4tf text and .g4b binary
// alike (the "G4MF" magic decides). External buffer files are not read. Any exception other than
// cw4d::Error is a finding, as is every sanitizer report, crash, hang or runaway allocation.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/g4mf.hpp"
#include "cw4d/complex/validate.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  cw4d::G4mfReadOptions options;
  options.allow_external = false;
  try {
    const cw4d::Complex c = cw4d::read_g4mf(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.g4tf", options);
    // Whatever reads must also survive validation, and a valid model writing and reading back.
    const cw4d::ValidationReport report = cw4d::validate(c);
    if (report.ok()) {
      cw4d::G4mfWriteOptions write;
      write.container = cw4d::G4mfContainer::binary;
      const cw4d::Complex back = cw4d::read_g4mf(cw4d::g4mf_files(c, write).main, "copy.g4b");
      if (back.fvector() != c.fvector()) __builtin_trap();
    }
  } catch (const cw4d::Error&) {
  }
  return 0;
}
