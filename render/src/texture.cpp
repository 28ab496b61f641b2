#include "cw4d/render/texture.hpp"

#include <glm/common.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <span>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/input_file.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/render/color.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/tolerances.hpp"

// Ken Perlin's improved noise as Debian's libstb-dev ships it (stb_perlin.h, public domain),
// compiled here with static linkage.
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wpedantic"
#endif
#define STB_PERLIN_IMPLEMENTATION
#define STB_PERLIN_STATIC
#include <stb_perlin.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace cw4d::render {

namespace {

float fract(float x) {
  return x - std::floor(x);
}

// The lattice cell of x with the tie-break of texture.hpp: within tol::texture_lattice_tie of
// a period below a whole number counts as that number's side.
float lattice_floor(float x) {
  return std::floor(x + tol::texture_lattice_tie);
}

float smooth(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

// Fractal turbulence (sum of |noise| over octaves) in about [0, 1].
float turbulence(glm::vec3 p) {
  return 0.5f * stb_perlin_turbulence_noise3(p.x, p.y, p.z, 2.0f, 0.5f, 4);
}

}  // namespace

glm::vec3 ImageVolume::sample(glm::vec3 uvw) const {
  const float fx = std::clamp(uvw.x * width - 0.5f, 0.0f, static_cast<float>(width - 1));
  const float fy = std::clamp(uvw.y * height - 0.5f, 0.0f, static_cast<float>(height - 1));
  const float fz = std::clamp(uvw.z * depth - 0.5f, 0.0f, static_cast<float>(depth - 1));
  const int i0 = static_cast<int>(fx), j0 = static_cast<int>(fy), k0 = static_cast<int>(fz);
  const int i1 = std::min(i0 + 1, width - 1), j1 = std::min(j0 + 1, height - 1),
            k1 = std::min(k0 + 1, depth - 1);
  const float tx = fx - i0, ty = fy - j0, tz = fz - k0;
  auto row = [&](int j, int k) { return glm::mix(at(i0, j, k), at(i1, j, k), tx); };
  auto plane = [&](int k) { return glm::mix(row(j0, k), row(j1, k), ty); };
  return glm::mix(plane(k0), plane(k1), tz);
}

ImageVolume ImageVolume::from_png_slices(const std::vector<std::string>& paths) {
  if (paths.empty()) throw InputError("an image volume needs at least one PNG slice");
  if (paths.size() > static_cast<std::size_t>(max_volume_slices))
    throw InputError("an image volume has at most " + std::to_string(max_volume_slices) +
                     " slices, not " + std::to_string(paths.size()));
  ImageVolume v;
  v.depth = static_cast<int>(paths.size());
  std::uint64_t total = 0;
  for (std::size_t k = 0; k < paths.size(); ++k) {
    const std::string data = read_input_file(paths[k], max_png_file_bytes);
    const std::span bytes(reinterpret_cast<const unsigned char*>(data.data()), data.size());
    // The slice's header against what the volume has left, before it is decoded: a stack of
    // small files declaring large pictures is refused before its texels are allocated.
    if (const auto header = png_header(bytes)) {
      const std::uint64_t texels = std::uint64_t(header->width) * std::uint64_t(header->height);
      if (texels <= max_png_texels && total + texels > max_volume_texels)
        throw InputError("image volume slice " + quote_user_text(paths[k]) + " (" +
                         std::to_string(header->width) + "x" + std::to_string(header->height) +
                         ") brings the volume beyond the " + std::to_string(max_volume_texels) +
                         " texels cw4d holds (" + std::to_string(paths.size()) + " slices)");
      total += texels;
    }
    const Image8 img = decode_png(bytes, paths[k]);
    if (k == 0) {
      v.width = img.width;
      v.height = img.height;
      v.texels.reserve(static_cast<std::size_t>(v.width) * v.height * v.depth);
    } else if (img.width != v.width || img.height != v.height) {
      throw InputError("image volume slice " + quote_user_text(paths[k]) + " is " +
                       std::to_string(img.width) + "x" + std::to_string(img.height) +
                       ", the first slice " + std::to_string(v.width) + "x" +
                       std::to_string(v.height));
    }
    const int n = img.channels;
    for (int j = 0; j < img.height; ++j) {
      const int row = img.height - 1 - j;  // v = 0 at the bottom
      for (int i = 0; i < img.width; ++i) {
        const std::uint8_t* p = &img.bytes[(static_cast<std::size_t>(row) * img.width + i) * n];
        const bool gray = n < 3;
        const glm::vec3 srgb(p[0] / 255.0f, (gray ? p[0] : p[1]) / 255.0f,
                             (gray ? p[0] : p[2]) / 255.0f);
        v.texels.push_back(to_linear(srgb));
      }
    }
  }
  return v;
}

float Texture3D::factor(glm::vec3 uvw) const {
  const glm::vec3 p = uvw * scale;
  switch (kind) {
    case Kind::Checker: {
      const long s = static_cast<long>(lattice_floor(p.x)) + static_cast<long>(lattice_floor(p.y)) +
                     static_cast<long>(lattice_floor(p.z));
      return (s & 1) ? dark : 1.0f;
    }
    case Kind::Grid: {
      // A line where any two coordinates are within half a line width of a whole number:
      // the edges of the lattice's cubes, so every section shows a grid. Near k means
      // [k - h, k + h) with both edges tie-broken like the checker's walls: a whole number
      // lies between p - h and p + h when their lattice cells differ (width < 1 period).
      const float h = 0.5f * line_width;
      int near = 0;
      for (int i = 0; i < 3; ++i)
        if (lattice_floor(p[i] + h) != lattice_floor(p[i] - h)) ++near;
      return near >= 2 ? dark : 1.0f;
    }
    case Kind::Wood: {
      // Rings about the w axis through the box centre, warped by noise.
      const glm::vec3 q = uvw - glm::vec3(0.5f);
      const float r = std::sqrt(q.x * q.x + q.y * q.y) * scale;
      const float warp = 0.35f * stb_perlin_noise3(2.0f * p.x, 2.0f * p.y, 0.6f * p.z, 0, 0, 0);
      const float ring = fract(r + warp);
      return dark + (1.0f - dark) * (1.0f - smooth(0.55f, 0.95f, ring));
    }
    case Kind::Marble: {
      const float t = std::sin(2.0f * std::numbers::pi_v<float> *
                               (p.x + 0.5f * p.y + 3.0f * turbulence(2.0f * p)));
      return dark + (1.0f - dark) * std::pow(0.5f + 0.5f * t, 0.4f);
    }
    case Kind::Volume:
      return 1.0f;
  }
  return 1.0f;
}

glm::vec3 Texture3D::apply(glm::vec3 base, glm::vec3 uvw) const {
  if (kind == Kind::Volume && volume) {
    const glm::vec3 p = uvw * scale;
    // Repeats `scale` times; a repeat's wall is tie-broken like the checker's (p in
    // [-tie, 1 - tie): sample() clamps the sliver below 0 to the first texels).
    const glm::vec3 cell(lattice_floor(p.x), lattice_floor(p.y), lattice_floor(p.z));
    return volume->sample(p - cell);
  }
  return base * factor(uvw);
}

std::string SlicePattern::path(int i) const {
  std::string digits = std::to_string(i);
  if (digits.size() < static_cast<std::size_t>(width))
    digits.insert(digits.begin(), static_cast<std::size_t>(width) - digits.size(), '0');
  return prefix + digits + suffix;
}

SlicePattern parse_slice_pattern(std::string_view pattern) {
  auto refuse = [&](const std::string& why) -> SlicePattern {
    throw InputError("texture volume pattern " + quote_user_text(pattern) + " " + why +
                     " (write one %d or %0Nd with N = 1..9, and %% for a percent sign)");
  };
  if (pattern.size() > 4096) return refuse("is longer than 4096 characters");
  SlicePattern p;
  bool number = false;
  std::string* text = &p.prefix;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      text->push_back(pattern[i]);
      continue;
    }
    const std::size_t at = i;
    if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
      text->push_back('%');
      ++i;
      continue;
    }
    int width = 0;
    if (i + 1 < pattern.size() && pattern[i + 1] == '0') {
      if (i + 3 < pattern.size() && pattern[i + 2] >= '1' && pattern[i + 2] <= '9' &&
          pattern[i + 3] == 'd') {
        width = pattern[i + 2] - '0';
        i += 3;
      } else {
        return refuse("has '" + std::string(pattern.substr(at, 4)) + "' at character " +
                      std::to_string(at + 1) + ", not %0Nd with one digit N = 1..9");
      }
    } else if (i + 1 < pattern.size() && pattern[i + 1] == 'd') {
      i += 1;
    } else {
      return refuse("has '" + std::string(pattern.substr(at, 2)) + "' at character " +
                    std::to_string(at + 1) + ", which is not %d, %0Nd or %%");
    }
    if (number) return refuse("has more than one number (%d)");
    number = true;
    p.width = width;
    text = &p.suffix;
  }
  if (!number) return refuse("is neither a directory nor a pattern with a number (%d)");
  return p;
}

namespace {

std::vector<std::string> slice_paths(const std::string& pattern) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  std::error_code ec;
  if (fs::is_directory(pattern, ec)) {
    // Every *.png entry, so that one that is not a regular file is refused by the reader
    // rather than silently left out of the volume.
    for (const auto& e : fs::directory_iterator(pattern, ec))
      if (e.path().extension() == ".png") out.push_back(e.path().string());
    std::sort(out.begin(), out.end());
    if (out.empty())
      throw InputError("no .png slices in the directory " + quote_user_text(pattern));
    return out;
  }
  const SlicePattern p = parse_slice_pattern(pattern);
  for (int i = 0; i < max_volume_slices; ++i) {
    std::string path = p.path(i);
    // Whatever exists (a dangling link too) is taken, so that a slice that is not a regular
    // file (a FIFO, a device) is reported by the reader instead of silently ending the volume.
    if (!fs::exists(fs::symlink_status(path, ec))) break;
    out.push_back(std::move(path));
  }
  if (out.empty())
    throw InputError("texture volume pattern " + quote_user_text(pattern) +
                     " names no file (from number 0)");
  return out;
}

float parse_scale(const std::string& text, const std::string& spec) {
  std::size_t used = 0;
  float v = 0.0f;
  try {
    v = std::stof(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !(v > 0.0f) || !std::isfinite(v) || v > 1e6f)
    throw InputError("texture " + quote_user_text(spec) +
                     ": the scale must be a number in (0, 1e6], not " + quote_user_text(text));
  return v;
}

}  // namespace

Texture3D parse_texture(const std::string& spec) {
  Texture3D t;
  const auto colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  std::string rest = colon == std::string::npos ? std::string() : spec.substr(colon + 1);
  if (name == "checker" || name == "grid" || name == "wood" || name == "marble") {
    t.kind = name == "checker" ? Texture3D::Kind::Checker
             : name == "grid"  ? Texture3D::Kind::Grid
             : name == "wood"  ? Texture3D::Kind::Wood
                               : Texture3D::Kind::Marble;
    t.scale = name == "checker" ? 8.0f : name == "grid" ? 4.0f : name == "wood" ? 6.0f : 2.0f;
    if (colon != std::string::npos) t.scale = parse_scale(rest, spec);
    return t;
  }
  if (name == "volume") {
    t.kind = Texture3D::Kind::Volume;
    t.scale = 1.0f;
    // An optional trailing ":SCALE" (a path may itself hold colons: only a numeric tail counts).
    const auto last = rest.rfind(':');
    if (last != std::string::npos) {
      const std::string tail = rest.substr(last + 1);
      if (!tail.empty() && tail.find_first_not_of("0123456789.eE+-") == std::string::npos) {
        t.scale = parse_scale(tail, spec);
        rest = rest.substr(0, last);
      }
    }
    if (rest.empty())
      throw InputError("texture " + quote_user_text(spec) + ": give volume:DIRECTORY or PATTERN");
    t.volume = std::make_shared<const ImageVolume>(ImageVolume::from_png_slices(slice_paths(rest)));
    return t;
  }
  throw InputError("unknown texture " + quote_user_text(spec) +
                   " (checker[:S], grid[:S], wood[:S], marble[:S], volume:PNGS[:S])");
}

const Texture3D* TextureAssignment::find(std::uint32_t object, std::uint32_t cell) const {
  if (auto it = per_cell.find(cell); it != per_cell.end()) return it->second.get();
  if (auto it = per_object.find(object); it != per_object.end()) return it->second.get();
  return all.get();
}

void add_texture(TextureAssignment& a, const std::string& value) {
  for (const char* key : {"object=", "cell="}) {
    const std::string k(key);
    if (value.rfind(k, 0) != 0) continue;
    const auto colon = value.find(':', k.size());
    const std::string id =
        value.substr(k.size(), colon == std::string::npos ? std::string::npos : colon - k.size());
    if (colon == std::string::npos || id.empty() ||
        id.find_first_not_of("0123456789") != std::string::npos || id.size() > 9)
      throw InputError("--texture " + quote_user_text(value) + ": write " + k + "INDEX:SPEC");
    auto tex = std::make_shared<const Texture3D>(parse_texture(value.substr(colon + 1)));
    const auto index = static_cast<std::uint32_t>(std::stoul(id));
    (k == "cell=" ? a.per_cell : a.per_object)[index] = std::move(tex);
    return;
  }
  a.all = std::make_shared<const Texture3D>(parse_texture(value));
}

}  // namespace cw4d::render
