#include "cw4d/render/color.hpp"

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>

namespace cw4d::render {

float srgb_to_linear(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float c) {
  c = std::clamp(c, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

std::uint8_t linear_to_srgb8(float c) {
  return static_cast<std::uint8_t>(std::lround(linear_to_srgb(c) * 255.0f));
}

namespace {

float float_of(std::uint32_t bits) {
  return std::bit_cast<float>(bits);
}

}  // namespace

const Srgb8Encoder& Srgb8Encoder::instance() {
  static const Srgb8Encoder e = [] {
    Srgb8Encoder t;
    auto byte = [](std::uint32_t bits) { return linear_to_srgb8(float_of(bits)); };
    t.exact = byte(0) == 0 && byte(kOne) == 255;
    t.threshold[0] = 0;
    t.threshold[256] = INT32_MAX;
    for (int k = 1; k <= 255; ++k) {  // the least bits in (0, kOne] with byte >= k
      std::uint32_t lo = 0, hi = kOne;
      while (hi - lo > 1) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        (byte(mid) >= k ? hi : lo) = mid;
      }
      t.threshold[k] = hi;
      // Monotone around the step: below it bytes < k, from it on >= k.
      for (std::uint32_t d = 1; d <= 64 && t.exact; ++d) {
        if (hi >= d && byte(hi - d) >= k) t.exact = false;
        if (hi + d - 1 <= kOne && byte(hi + d - 1) < k) t.exact = false;
      }
      if (t.threshold[k] < t.threshold[k - 1]) t.exact = false;
    }
    int k = 0;
    for (std::uint32_t b = 0; b <= (kOne >> kShift); ++b) {
      const std::uint32_t first = b << kShift, last = first + ((1u << kShift) - 1);
      while (k < 255 && t.threshold[k + 1] <= first) ++k;
      t.start[b] = static_cast<std::uint8_t>(k);
      int steps = 0;
      while (k + steps < 255 && t.threshold[k + steps + 1] <= last) ++steps;
      t.max_steps = std::max(t.max_steps, steps);
    }
    return t;
  }();
  return e;
}

std::uint8_t Srgb8Encoder::operator()(float c) const {
  if (!exact || c != c) return linear_to_srgb8(c);
  if (!(c > 0.0f)) return 0;
  if (c >= 1.0f) return 255;
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(c);
  int k = start[bits >> kShift];
  while (bits >= threshold[k + 1]) ++k;
  return static_cast<std::uint8_t>(k);
}

glm::vec4 to_linear(const Rgba& c) {
  return {srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b),
          std::clamp(c.a, 0.0f, 1.0f)};
}

glm::vec3 to_linear(const glm::vec3& c) {
  return {srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b)};
}

glm::vec3 palette_color(std::uint32_t id) {
  const float h = std::fmod(static_cast<float>(id) * 0.618033988749895f, 1.0f) * 6.0f;
  const float x = 1.0f - std::abs(std::fmod(h, 2.0f) - 1.0f);
  glm::vec3 rgb;
  switch (static_cast<int>(h)) {
    case 0:
      rgb = {1, x, 0};
      break;
    case 1:
      rgb = {x, 1, 0};
      break;
    case 2:
      rgb = {0, 1, x};
      break;
    case 3:
      rgb = {0, x, 1};
      break;
    case 4:
      rgb = {x, 0, 1};
      break;
    default:
      rgb = {1, 0, x};
      break;
  }
  return to_linear(glm::vec3(0.3f) + 0.65f * rgb);  // pastel (sRGB), so shading stays visible
}

glm::vec3 depth_cue_color(float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  // Interpolated in sRGB (perceptually even), returned linear.
  const glm::vec3 near{1.0f, 0.55f, 0.1f}, mid{0.85f, 0.85f, 0.85f}, far{0.2f, 0.4f, 1.0f};
  const glm::vec3 s = t < 0.5f ? near + (mid - near) * (2 * t) : mid + (far - mid) * (2 * t - 1);
  return to_linear(s);
}

}  // namespace cw4d::render
