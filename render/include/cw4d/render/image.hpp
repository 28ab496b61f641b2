#pragma once
// Images: the linear floating-point picture the rasterizer resolves to, its 8-bit sRGB form,
// and PNG files.
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace cw4d::render {

/// width x height pixels, row-major from the top-left; each pixel linear RGB premultiplied by
/// its alpha (coverage x opacity; 1 on an opaque background).
struct Image {
  int width = 0, height = 0;
  std::vector<glm::vec4> pixels;

  Image() = default;
  Image(int w, int h, glm::vec4 fill = glm::vec4(0.0f));
  glm::vec4& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const glm::vec4& at(int x, int y) const {
    return pixels[static_cast<std::size_t>(y) * width + x];
  }
  /// Sum of the alpha channel: the covered area in pixels when drawn over a transparent
  /// background with opaque colors.
  double coverage() const;
  /// Premultiplied "over": this = top + (1 - top.a) * this, pixel by pixel, with top placed at
  /// (x, y). Parts outside this image are dropped.
  void composite_over(const Image& top, int x = 0, int y = 0);
  /// Copies `src` into this image at (x, y) (clipped), replacing the pixels.
  void blit(const Image& src, int x, int y);
  /// Flattens onto an opaque background (linear RGB): every alpha becomes 1.
  void flatten(glm::vec3 background);
};

/// 8-bit sRGB, 3 channels (RGB) or 4 (RGBA, straight alpha), row-major from the top-left.
struct Image8 {
  int width = 0, height = 0, channels = 3;
  std::vector<std::uint8_t> bytes;
};

/// Encodes a linear image as 8-bit sRGB. With alpha = false the image is first flattened onto
/// `background` (linear RGB); with alpha = true the PNG keeps straight alpha.
Image8 to_srgb8(const Image& image, glm::vec3 background = glm::vec3(1.0f), bool alpha = false);

/// PNG bytes of an 8-bit image. \throw Error when encoding fails.
std::string encode_png(const Image8& image);

/// Writes a PNG through a temporary file and a rename (nothing half-written on failure).
/// \throw IoError naming the path, InputError for an empty image.
void write_png(const std::string& path, const Image8& image);
void write_png(const std::string& path, const Image& image, glm::vec3 background = glm::vec3(1.0f));

/// The largest PNG file read_png opens (256 MiB, an 8-bit RGBA image of max_png_texels stored
/// uncompressed): checked on the open file before reading.
inline constexpr std::uintmax_t max_png_file_bytes = std::uintmax_t{256} << 20;
/// The most texels (width x height) a PNG may declare to be decoded (2^26, 8192 x 8192):
/// checked on its header before anything is allocated for the pixels.
inline constexpr std::uint64_t max_png_texels = std::uint64_t{1} << 26;

/// What a PNG's header declares.
struct PngHeader {
  int width = 0, height = 0, channels = 0;
};

/// The header of PNG bytes, or nothing when they do not start like a PNG.
std::optional<PngHeader> png_header(std::span<const unsigned char> bytes);

/// Decodes PNG bytes to 8 bits per channel (1 gray, 2 gray + alpha, 3 RGB or 4 RGBA
/// channels, as stored). `name` names the source in errors. The header is read first: more
/// than `max_texels` texels (at most max_png_texels) are refused before decoding, and no
/// allocation of the decoder may exceed what those dimensions need, so a small file declaring
/// huge dimensions, or a compressed stream inflating far beyond them, fails cleanly.
/// \throw ParseError(name, 0, reason) for bytes that are not a readable PNG or beyond the limits.
Image8 decode_png(std::span<const unsigned char> bytes, const std::string& name = "PNG data",
                  std::uint64_t max_texels = max_png_texels);

/// Reads a PNG file (written by write_png, or a texture slice): a regular file of at most
/// max_png_file_bytes, decoded by decode_png.
/// \throw ParseError(path, 0, reason): missing, not a regular file (a FIFO, a device), too
///        large, not a readable PNG or beyond max_png_texels.
Image8 read_png(const std::string& path);

}  // namespace cw4d::render
