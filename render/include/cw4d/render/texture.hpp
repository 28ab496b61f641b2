#pragma once
// Solid (3D) textures sampled through a section's UVW ([Peachey 1985] "Solid texturing of
// complex surfaces"; [Perlin 1985] "An image synthesizer"): every point of a cut cell carries
// the texture coordinates of its place in the 3-cell, so a section shows the inside of a
// textured 4D solid, and moving the hyperplane moves through the texture.
//
// Procedural textures modulate the cell's color (checker and grid darken part of it, wood and
// marble mix it with a darker shade); an image volume (a stack of PNG slices, filtered
// trilinearly) replaces it. UVW in [0, 1]^3 spans a cell's box (section/uvw.hpp); `scale`
// repeats the pattern that many times per unit of UVW.
//
// Lattice walls: with p = uvw * scale, the checker's cells, the grid's line edges and an image
// volume's repeats change where a coordinate of p (or p -/+ half a line width) crosses a whole
// number. Those walls are taken as floor(x + tie), tie = tol::texture_lattice_tie = 1e-3 of a
// period: a sample on a wall, or within the tie below it, belongs to the cell above it. A
// section lying exactly on a wall (the tesseract cut at w = 0 with checker:8 has p.z = 4 on
// its faces) then shows one side uniformly, not a per-pixel mix decided by interpolation
// rounding; a wall the section crosses stays where it is, to 1e-3 of a period. Wood's ring
// edges are curved surfaces (no section lies on one) and marble has no walls.
#include <glm/vec3.hpp>

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace cw4d::render {

/// The most texels an image volume holds over all its slices (2^25, 12 bytes each in memory):
/// every slice's header is checked against what is left before the slice is decoded.
inline constexpr std::uint64_t max_volume_texels = std::uint64_t{1} << 25;
/// The most slices a PATTERN names (numbers 0 .. max_volume_slices - 1).
inline constexpr int max_volume_slices = 4096;

/// A numbered file name of an image volume, "slices/z%03d.png": the text around exactly one
/// number, written in decimal and zero-padded to `width` digits (0: no padding).
struct SlicePattern {
  std::string prefix, suffix;
  int width = 0;
  /// The name of slice i >= 0 ("slices/z007.png").
  std::string path(int i) const;
};

/// Parses a slice pattern without handing it to printf: it holds exactly one "%d" or "%0Nd"
/// (N = 1..9), and "%%" for a literal percent sign; any other "%" is refused.
/// \throw InputError naming the pattern and what is wrong with it.
SlicePattern parse_slice_pattern(std::string_view pattern);

/// width x height x depth texels, linear RGB, x fastest; texel (i, j, k) sits at
/// uvw = ((i + 0.5) / width, (j + 0.5) / height, (k + 0.5) / depth).
struct ImageVolume {
  int width = 0, height = 0, depth = 0;
  std::vector<glm::vec3> texels;

  const glm::vec3& at(int i, int j, int k) const {
    return texels[(static_cast<std::size_t>(k) * height + j) * width + i];
  }
  /// Trilinear filtering, clamped to the edge texels (uvw outside [0, 1] repeats the border).
  glm::vec3 sample(glm::vec3 uvw) const;
  /// Slices in order (w = 0 first), each a PNG of the same size (gray, gray+alpha, RGB or
  /// RGBA; sRGB, alpha ignored); the PNG's top row is v = 1. Each slice is read by read_png's
  /// rules (a regular file within max_png_file_bytes and max_png_texels), and all together hold
  /// at most max_volume_texels. \throw InputError for no slices, slices of different sizes or
  /// more than max_volume_texels in all; ParseError for a slice that cannot be read.
  static ImageVolume from_png_slices(const std::vector<std::string>& paths);
};

struct Texture3D {
  enum class Kind { Checker, Grid, Wood, Marble, Volume };
  Kind kind = Kind::Checker;
  /// Repetitions of the pattern per unit of UVW (checker: cells per axis; grid: lines per
  /// axis; wood: rings per unit radius; marble: veins per unit). > 0.
  float scale = 8.0f;
  /// Checker/grid: the factor of the dark cells or lines; wood/marble: of the dark shade.
  float dark = 0.35f;
  /// Grid: line width as a fraction of one period.
  float line_width = 0.08f;
  /// Volume: the image (uvw in [0, 1]^3 spans it once per scale).
  std::shared_ptr<const ImageVolume> volume;

  /// What the texture does to a linear base color at `uvw`.
  glm::vec3 apply(glm::vec3 base, glm::vec3 uvw) const;
  /// The modulation factor in [dark, 1] of a procedural texture (1 for a volume).
  float factor(glm::vec3 uvw) const;
};

/// A texture from its command-line spelling: "checker[:SCALE]", "grid[:SCALE]", "wood[:SCALE]",
/// "marble[:SCALE]", or "volume:PATTERN[:SCALE]" where PATTERN is a directory (its *.png in
/// name order) or a slice pattern with one %d or %0Nd ("slices/z%03d.png", parse_slice_pattern;
/// numbered from 0 until the first missing file). \throw InputError naming the spec;
/// ParseError for a slice that cannot be read.
Texture3D parse_texture(const std::string& spec);

/// Which texture each face of a section gets: a cell's own, else its scene object's, else
/// `all` (null: untextured).
struct TextureAssignment {
  std::shared_ptr<const Texture3D> all;
  std::map<std::uint32_t, std::shared_ptr<const Texture3D>> per_object;
  std::map<std::uint32_t, std::shared_ptr<const Texture3D>> per_cell;  ///< cells of the model

  bool empty() const { return !all && per_object.empty() && per_cell.empty(); }
  const Texture3D* find(std::uint32_t object, std::uint32_t cell) const;
};

/// Adds one "--texture" value: "SPEC" (every face), "object=I:SPEC" or "cell=I:SPEC".
/// \throw InputError for a malformed value.
void add_texture(TextureAssignment& assignment, const std::string& value);

}  // namespace cw4d::render
