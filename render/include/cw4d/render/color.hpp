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

/// A user color (sRGB, straight alpha) as linear RGB with the same alpha.
glm::vec4 to_linear(const Rgba& srgb);
glm::vec3 to_linear(const glm::vec3& srgb);

/// A pastel hue per integer (golden-angle steps), linear RGB: the default color of cell `id`.
glm::vec3 palette_color(std::uint32_t id);

/// A depth-cue ramp, linear RGB: t = 0 (near) warm orange, t = 1 (far) cool blue.
glm::vec3 depth_cue_color(float t);

}  // namespace cw4d::render
