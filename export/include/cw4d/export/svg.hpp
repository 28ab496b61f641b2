#pragma once
// A vector picture of a 3D section: orthographic view, flat Lambert shading, back faces culled,
// faces drawn back to front (exact for convex sections; painter's order otherwise).
#include <Eigen/Core>

#include <string>

#include "cw4d/section/section.hpp"

namespace cw4d {

struct SvgOptions {
  int width = 640;
  int height = 480;
  /// Direction the camera looks from (towards the origin of the section's bounding box).
  Eigen::Vector3d view_from{2.0, 1.3, 1.0};
  /// Direction the light comes from.
  Eigen::Vector3d light_from{1.0, 2.0, 3.0};
  /// Draw the polygon outlines.
  bool edges = true;
};

/// SVG text of a section in R^3; faces take their color from complex.colors(2) when present
/// (alpha as fill-opacity), else a hue per source cell.
/// \throw InputError when the section is not 3-dimensional.
std::string svg_text(const Section& section, const SvgOptions& options = {});

/// Writes through a temporary file and a rename. \throw IoError, InputError.
void write_svg_file(const std::string& path, const Section& section,
                    const SvgOptions& options = {});

}  // namespace cw4d
