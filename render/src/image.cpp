#include "cw4d/render/image.hpp"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/render/color.hpp"

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

Image8 read_png(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ParseError(path, 0, "cannot open the PNG file");
  std::ostringstream s;
  s << in.rdbuf();
  const std::string data = s.str();
  int w = 0, h = 0, n = 0;
  stbi_uc* pixels = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(data.data()),
                                          static_cast<int>(data.size()), &w, &h, &n, 0);
  if (!pixels) throw ParseError(path, 0, "not a readable PNG");
  Image8 out;
  out.width = w;
  out.height = h;
  out.channels = n;
  out.bytes.assign(pixels, pixels + static_cast<std::size_t>(w) * h * n);
  stbi_image_free(pixels);
  return out;
}

}  // namespace cw4d::render
