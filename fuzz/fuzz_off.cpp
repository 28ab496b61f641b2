// libFuzzer target: the nOFF reader (read_off) on arbitrary bytes. Any exception other than
// cw4d::Error is a finding, as is every sanitizer report, crash, hang or runaway allocation.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/validate.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const cw4d::Complex c = cw4d::read_off(in, "fuzz.4off");
    // Whatever parses must also survive validation and writing back.
    const cw4d::ValidationReport report = cw4d::validate(c);
    if (report.ok()) {
      std::ostringstream out;
      cw4d::write_off(out, c);
    }
  } catch (const cw4d::Error&) {
  }
  return 0;
}
