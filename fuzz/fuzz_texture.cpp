// libFuzzer target: the two readers behind `--texture volume:PATTERN` — the slice pattern
// parser and the PNG decoder — on arbitrary bytes.
//
// The input's first line is a slice pattern; the rest are the bytes of a PNG. A pattern that
// parses must name its slices as the pattern says (its text around one number), and decoding
// must either refuse the bytes with a ParseError or give an image within the texel budget whose
// pixels fill exactly width x height x channels bytes. Any other exception, sanitizer report,
// hang or runaway allocation is a finding.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "cw4d/complex/error.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/texture.hpp"

namespace {

// Far below the CLI's 2^26 texels: an instrumented decoder of a 64 Mi-texel image is slow.
constexpr std::uint64_t kMaxTexels = std::uint64_t{1} << 20;

void pattern(std::string_view text) {
  try {
    const cw4d::render::SlicePattern p = cw4d::render::parse_slice_pattern(text);
    for (const int i : {0, 7, 123456789}) {
      const std::string name = p.path(i);
      const std::string number = std::to_string(i);
      // prefix, the number padded to the width, suffix: nothing else.
      const std::size_t digits = std::max<std::size_t>(number.size(), p.width);
      if (name.size() != p.prefix.size() + digits + p.suffix.size()) __builtin_trap();
      if (name.compare(0, p.prefix.size(), p.prefix) != 0) __builtin_trap();
      if (name.compare(name.size() - p.suffix.size(), p.suffix.size(), p.suffix) != 0)
        __builtin_trap();
      if (name.compare(p.prefix.size() + digits - number.size(), number.size(), number) != 0)
        __builtin_trap();
    }
  } catch (const cw4d::InputError&) {
  }
}

void png(std::span<const unsigned char> bytes) {
  try {
    const cw4d::render::Image8 image = cw4d::render::decode_png(bytes, "fuzz.png", kMaxTexels);
    if (image.width < 1 || image.height < 1 || image.channels < 1 || image.channels > 4)
      __builtin_trap();
    const auto texels = static_cast<std::uint64_t>(image.width) * image.height;
    if (texels > kMaxTexels) __builtin_trap();
    if (image.bytes.size() != texels * image.channels) __builtin_trap();
    // The header read alone agrees with the decoder.
    const auto header = cw4d::render::png_header(bytes);
    if (!header || header->width != image.width || header->height != image.height) __builtin_trap();
  } catch (const cw4d::ParseError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::size_t eol = text.find('\n');
  pattern(text.substr(0, eol));
  if (eol != std::string_view::npos)
    png(std::span<const unsigned char>(data + eol + 1, size - eol - 1));
  return 0;
}
