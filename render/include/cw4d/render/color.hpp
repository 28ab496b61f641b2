#pragma once
// Color spaces of the renderer. Every color a user writes (scene files, "#ff8000", cell colors)
// is sRGB; shading, blending and anti-aliasing happen on linear values; PNG pixels are sRGB
// again. Keeping the two apart is what makes the output gamma-correct.
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>

#include "cw4d/complex/complex.hpp"

namespace cw4d::render {

/// sRGB transfer function (IEC 61966-2-1), one component in [0, 1].
float srgb_to_linear(float c);
float linear_to_srgb(float c);
/// Linear [0, 1] -> 8-bit sRGB (clamped, rounded).
std::uint8_t linear_to_srgb8(float c);

/// linear_to_srgb8 without the power, the same byte for every float: the byte steps up at 255
/// thresholds, found by bisection on linear_to_srgb8 itself once per process; a table indexed
/// by a float's leading bits (bits >> 15) gives the byte at the start of its bucket and at most
/// max_steps comparisons with the next thresholds correct it. Valid because linear_to_srgb8 is
/// monotone; that is checked when the table is built over 64 floats either side of every
/// threshold (where an error of the power could break it), and where it fails `exact` is
/// false and operator() calls linear_to_srgb8.
struct Srgb8Encoder {
  static constexpr int kShift = 15;
  static constexpr std::uint32_t kOne = 0x3F800000u;  ///< the bits of 1.0f
  /// threshold[k] (k = 1..255): the bits of the least float in [0, 1] whose byte is >= k;
  /// threshold[0] = 0, threshold[256] = INT32_MAX (never reached).
  std::uint32_t threshold[257] = {};
  /// Per bucket b = bits >> kShift of c in [0, 1]: the byte of its first float (kOne >> kShift
  /// + 1 entries, then 3 bytes of padding for 32-bit gathers).
  std::uint8_t start[(kOne >> kShift) + 4] = {};
  int max_steps = 0;  ///< thresholds strictly inside one bucket, at most
  bool exact = false;

  static const Srgb8Encoder& instance();
  std::uint8_t operator()(float c) const;
};

/// A user color (sRGB, straight alpha) as linear RGB with the same alpha.
glm::vec4 to_linear(const Rgba& srgb);
glm::vec3 to_linear(const glm::vec3& srgb);

/// A pastel hue per integer (golden-angle steps), linear RGB: the default color of cell `id`.
glm::vec3 palette_color(std::uint32_t id);

/// A depth-cue ramp, linear RGB: t = 0 (near) warm orange, t = 1 (far) cool blue.
glm::vec3 depth_cue_color(float t);

}  // namespace cw4d::render
