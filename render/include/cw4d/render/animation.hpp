#pragma once
// Animated pictures: a sequence of equally sized frames as an animated WebP, encoded by
// libwebp's animation encoder (WebPAnimEncoder of libwebpmux, Debian's libwebp-dev).
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

/// The bytes of an animated WebP of `frames` (8-bit sRGB, 3 or 4 channels, all the same size).
/// \throw InputError for no frames, frames of different sizes or bad options; Error when the
///        encoder fails.
std::string encode_webp_animation(const std::vector<Image8>& frames,
                                  const AnimationOptions& options = {});

/// Writes it through a temporary file and a rename (nothing half-written on failure).
void write_webp_animation(const std::string& path, const std::vector<Image8>& frames,
                          const AnimationOptions& options = {});

}  // namespace cw4d::render
