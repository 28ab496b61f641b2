#include "cw4d/render/image.hpp"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <optional>
#include <vector>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/input_file.hpp"
#include "cw4d/render/color.hpp"

namespace {

// The most bytes one allocation of stb_image may take in the decode running on this thread
// (0 outside decode_png). stb_image trusts the header and lets the zlib stream grow its buffer
// up to 4 GiB; with this bound a stream that inflates beyond what the declared dimensions need
// fails as "out of memory" inside stb, which decode_png reports as an unreadable PNG.
thread_local std::size_t stbi_allocation_limit = 0;

void* stbi_bounded_malloc(std::size_t n) {
  return n <= stbi_allocation_limit ? std::malloc(n) : nullptr;
}

void* stbi_bounded_realloc(void* p, std::size_t n) {
  return n <= stbi_allocation_limit ? std::realloc(p, n) : nullptr;
}

// The PNG without its empty IDAT chunks, or nothing when it has none. An empty IDAT is legal
// and holds no data, but stb_image copies its zero bytes into a buffer it has not allocated yet
// (memcpy from a null pointer). Chunks are followed while their lengths fit in the bytes; the
// rest (a truncated or corrupt tail, for stb_image to refuse) is kept as it is, unless it
// starts as an empty IDAT.
std::optional<std::vector<unsigned char>> without_empty_idat(std::span<const unsigned char> b) {
  auto be32 = [&](std::size_t at) {
    return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) |
           (std::uint32_t{b[at + 2]} << 8) | std::uint32_t{b[at + 3]};
  };
  auto empty_idat = [&](std::size_t at) {
    return be32(at) == 0 && b[at + 4] == 'I' && b[at + 5] == 'D' && b[at + 6] == 'A' &&
           b[at + 7] == 'T';
  };
  auto next = [&](std::size_t at) -> std::size_t {  // the next chunk, or 0 past the last whole one
    return at + 12 <= b.size() && be32(at) <= b.size() - at - 12 ? at + 12 + be32(at) : 0;
  };
  // A tail that starts like an empty IDAT but is cut short of its CRC is dropped too (stb_image
  // reads its header before finding the end).
  auto empty_idat_tail = [&](std::size_t at) { return at + 8 <= b.size() && empty_idat(at); };
  bool any = false;
  std::size_t at = 8;
  for (; next(at) != 0; at = next(at)) any = any || empty_idat(at);
  if (!any && !empty_idat_tail(at)) return std::nullopt;
  std::vector<unsigned char> out(b.begin(), b.begin() + 8);
  for (at = 8; next(at) != 0; at = next(at))
    if (!empty_idat(at)) out.insert(out.end(), b.begin() + at, b.begin() + next(at));
  if (!empty_idat_tail(at)) out.insert(out.end(), b.begin() + std::min(at, b.size()), b.end());
  return out;
}

}  // namespace

// stb_image_write / stb_image (public domain, Debian's libstb-dev headers), compiled here with
// static linkage so no other translation unit sees their symbols.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wpedantic"
#endif
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb_image_write.h>
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_MALLOC(n) stbi_bounded_malloc(n)
#define STBI_REALLOC(p, n) stbi_bounded_realloc(p, n)
#define STBI_FREE(p) std::free(p)
#define STBI_ONLY_PNG
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace cw4d::render {

Image::Image(int w, int h, glm::vec4 fill)
    : width(w), height(h), pixels(static_cast<std::size_t>(w) * h, fill) {}

double Image::coverage() const {
  double sum = 0.0;
  for (const auto& p : pixels) sum += p.a;
  return sum;
}

void Image::composite_over(const Image& top, int x0, int y0) {
  for (int y = std::max(0, -y0); y < top.height && y + y0 < height; ++y)
    for (int x = std::max(0, -x0); x < top.width && x + x0 < width; ++x) {
      const glm::vec4& t = top.at(x, y);
      glm::vec4& d = at(x + x0, y + y0);
      d = t + (1.0f - t.a) * d;
    }
}

void Image::blit(const Image& src, int x0, int y0) {
  for (int y = std::max(0, -y0); y < src.height && y + y0 < height; ++y)
    for (int x = std::max(0, -x0); x < src.width && x + x0 < width; ++x)
      at(x + x0, y + y0) = src.at(x, y);
}

void Image::flatten(glm::vec3 background) {
  for (auto& p : pixels) p = glm::vec4(glm::vec3(p) + (1.0f - p.a) * background, 1.0f);
}

Image8 to_srgb8(const Image& image, glm::vec3 background, bool alpha) {
  Image8 out;
  out.width = image.width;
  out.height = image.height;
  out.channels = alpha ? 4 : 3;
  out.bytes.resize(image.pixels.size() * out.channels);
  const Srgb8Encoder& encode = Srgb8Encoder::instance();  // linear_to_srgb8, the same bytes
  std::size_t k = 0;
  for (const auto& p : image.pixels) {
    if (alpha) {
      // Premultiplied -> straight alpha before the transfer function.
      const float a = std::clamp(p.a, 0.0f, 1.0f);
      const glm::vec3 c = a > 0.0f ? glm::vec3(p) / a : glm::vec3(0.0f);
      for (int i = 0; i < 3; ++i) out.bytes[k++] = encode(c[i]);
      out.bytes[k++] = static_cast<std::uint8_t>(std::lround(a * 255.0f));
    } else {
      const glm::vec3 c = glm::vec3(p) + (1.0f - std::clamp(p.a, 0.0f, 1.0f)) * background;
      for (int i = 0; i < 3; ++i) out.bytes[k++] = encode(c[i]);
    }
  }
  return out;
}

namespace {

void append_bytes(void* context, void* data, int size) {
  static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                             static_cast<std::size_t>(size));
}

}  // namespace

std::string encode_png(const Image8& image) {
  if (image.width <= 0 || image.height <= 0)
    throw InputError("cannot encode an empty image as PNG");
  std::string out;
  const int ok =
      stbi_write_png_to_func(append_bytes, &out, image.width, image.height, image.channels,
                             image.bytes.data(), image.width * image.channels);
  if (!ok) throw Error("PNG encoding failed");
  return out;
}

void write_png(const std::string& path, const Image8& image) {
  write_file_atomically(path, encode_png(image));
}

void write_png(const std::string& path, const Image& image, glm::vec3 background) {
  write_png(path, to_srgb8(image, background));
}

std::optional<PngHeader> png_header(std::span<const unsigned char> b) {
  // The signature, then the IHDR chunk: length 13, "IHDR", width and height (big-endian),
  // bit depth, color type. Read here rather than by stb_image, which refuses dimensions it
  // cannot decode without saying what they are.
  static constexpr unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() < 26 || !std::equal(signature, signature + 8, b.begin())) return std::nullopt;
  auto be32 = [&](std::size_t at) {
    return (std::uint32_t{b[at]} << 24) | (std::uint32_t{b[at + 1]} << 16) |
           (std::uint32_t{b[at + 2]} << 8) | std::uint32_t{b[at + 3]};
  };
  if (be32(8) != 13 || b[12] != 'I' || b[13] != 'H' || b[14] != 'D' || b[15] != 'R')
    return std::nullopt;
  const std::uint32_t w = be32(16), h = be32(20);
  // The PNG specification bounds each side by 2^31 - 1.
  if (w == 0 || h == 0 || w > 0x7fffffffu || h > 0x7fffffffu) return std::nullopt;
  int channels = 0;
  switch (b[25]) {
    case 0:
      channels = 1;
      break;  // gray
    case 2:
      channels = 3;
      break;  // RGB
    case 3:
      channels = 3;
      break;  // palette (RGB, RGBA with a tRNS chunk)
    case 4:
      channels = 2;
      break;  // gray + alpha
    case 6:
      channels = 4;
      break;  // RGBA
    default:
      return std::nullopt;
  }
  return PngHeader{static_cast<int>(w), static_cast<int>(h), channels};
}

Image8 decode_png(std::span<const unsigned char> bytes, const std::string& name,
                  std::uint64_t max_texels) {
  max_texels = std::min(max_texels, max_png_texels);
  if (bytes.size() > max_png_file_bytes)
    throw ParseError(name, 0,
                     "PNG of " + std::to_string(bytes.size()) + " bytes is larger than the " +
                         std::to_string(max_png_file_bytes) + " bytes cw4d reads");
  const std::optional<PngHeader> header = png_header(bytes);
  if (!header) throw ParseError(name, 0, "not a PNG (no PNG signature and IHDR header)");
  const std::uint64_t texels = std::uint64_t(header->width) * std::uint64_t(header->height);
  if (texels > max_texels)
    throw ParseError(name, 0,
                     "PNG declares " + std::to_string(header->width) + "x" +
                         std::to_string(header->height) + " = " + std::to_string(texels) +
                         " texels, more than the " + std::to_string(max_texels) + " cw4d decodes");
  // What stb_image allocates for these dimensions: the compressed data (grown by doubling),
  // the inflated rows (up to 16-bit RGBA plus a filter byte per row) and the output; slack for
  // its tables.
  struct Limit {
    explicit Limit(std::size_t n) { stbi_allocation_limit = n; }
    ~Limit() { stbi_allocation_limit = 0; }
  } limit(2 * bytes.size() + 9 * static_cast<std::size_t>(texels) +
          static_cast<std::size_t>(header->height) + (std::size_t{1} << 20));
  const std::optional<std::vector<unsigned char>> filtered = without_empty_idat(bytes);
  if (filtered) bytes = *filtered;
  int w = 0, h = 0, n = 0;
  stbi_uc* pixels =
      stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &w, &h, &n, 0);
  if (!pixels) {
    const char* why = stbi_failure_reason();
    throw ParseError(
        name, 0, std::string("not a readable PNG") + (why ? std::string(" (") + why + ")" : ""));
  }
  struct Free {
    stbi_uc* p;
    ~Free() { stbi_image_free(p); }
  } release{pixels};
  if (static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h) > max_texels || n < 1 || n > 4)
    throw ParseError(name, 0, "not a readable PNG (its decoded size differs from its header)");
  Image8 out;
  out.width = w;
  out.height = h;
  out.channels = n;
  out.bytes.assign(pixels, pixels + static_cast<std::size_t>(w) * h * n);
  return out;
}

Image8 read_png(const std::string& path) {
  const std::string data = read_input_file(path, max_png_file_bytes);
  return decode_png(std::span(reinterpret_cast<const unsigned char*>(data.data()), data.size()),
                    path);
}

}  // namespace cw4d::render
