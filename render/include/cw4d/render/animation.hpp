#pragma once
// Animated pictures: a sequence of equally sized frames as an animated WebP, encoded by
// libwebp's animation encoder (WebPAnimEncoder of libwebpmux, Debian's libwebp-dev), or as an
// animated GIF through giflib (Debian's libgif-dev: each frame median-cut to its own 256-color
// table by GifQuantizeBuffer, the delay in hundredths of a second, the NETSCAPE2.0 loop block).
#include <memory>
#include <string>
#include <vector>

#include "cw4d/render/image.hpp"

namespace cw4d::render {

struct AnimationOptions {
  int frame_ms = 80;      ///< how long each frame shows, 1..60000
  bool lossless = false;  ///< true: every frame exact (larger files)
  float quality = 82.0f;  ///< lossy: 0..100
  int loop_count = 0;     ///< 0: repeat forever
};

/// An animation encoded frame by frame, so that no caller holds all its frames: each add()
/// encodes one frame (WebP: into libwebp's encoder, which keeps only compressed frames and the
/// previous canvas; GIF: straight into the file's bytes) and finish() returns the file.
class AnimationEncoder {
 public:
  enum class Format { WebP, Gif };
  /// \throw InputError for sides out of range (WebP 1..16383, GIF 1..65535) or bad options;
  ///        Error when the encoder cannot start.
  AnimationEncoder(Format format, int width, int height, const AnimationOptions& options = {});
  ~AnimationEncoder();
  AnimationEncoder(const AnimationEncoder&) = delete;
  AnimationEncoder& operator=(const AnimationEncoder&) = delete;

  /// Encodes the next frame (8-bit sRGB, 3 or 4 channels, the encoder's size).
  /// \throw InputError for a frame of another size or layout; Error when encoding fails.
  void add(const Image8& frame);
  /// The frames added so far.
  int frames() const { return frames_; }
  /// The file's bytes; the encoder takes no more frames.
  /// \throw InputError when no frame was added; Error when assembling fails.
  std::string finish();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int frames_ = 0;
};

/// The bytes of an animated WebP of `frames` (8-bit sRGB, 3 or 4 channels, all the same size).
/// \throw InputError for no frames, frames of different sizes or bad options; Error when the
///        encoder fails.
std::string encode_webp_animation(const std::vector<Image8>& frames,
                                  const AnimationOptions& options = {});

/// Writes it through a temporary file and a rename (nothing half-written on failure).
void write_webp_animation(const std::string& path, const std::vector<Image8>& frames,
                          const AnimationOptions& options = {});

/// The bytes of an animated GIF of `frames` (8-bit sRGB, 3 or 4 channels, all the same size;
/// alpha is dropped). frame_ms is rounded to hundredths of a second (at least 1); lossless and
/// quality do not apply (GIF has 256 colors per frame).
/// \throw InputError as encode_webp_animation (GIF sides up to 65535); Error when giflib fails.
std::string encode_gif_animation(const std::vector<Image8>& frames,
                                 const AnimationOptions& options = {});

/// Writes it through a temporary file and a rename (nothing half-written on failure).
void write_gif_animation(const std::string& path, const std::vector<Image8>& frames,
                         const AnimationOptions& options = {});

}  // namespace cw4d::render
