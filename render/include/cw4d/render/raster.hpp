#pragma once
// The rasterizer core: triangles and lines in world space -> a linear RGBA image.
//
// Pipeline ([Tao 2024] "光栅化"; [wxyhly 2024] "视锥体裁剪/遮挡剔除"): vertices go to clip space; a
// triangle is clipped against the six frustum planes in homogeneous coordinates *before* the
// perspective divide (so points behind the eye never divide by w <= 0); screen positions snap
// to 1/256 pixel and coverage is decided by exact integer edge functions with the top-left fill
// rule (a sample on an edge shared by two triangles belongs to exactly one of them); depth is
// interpolated linearly in screen space (z/w is affine there), every other attribute
// perspective-correctly (attr/w and 1/w, divided back per fragment); a depth buffer per sample
// resolves visibility (MSAA: coverage and depth per sample, an s x s ordered grid of samples per
// pixel). Opaque draws are shaded deferred: each pixel evaluates Blinn-Phong once for each
// triangle still visible in it after all opaque triangles before the next blended one, so
// hidden fragments cost no lighting; blended triangles are shaded as they come.
//
// Work is split over 64 x 64 pixel tiles run on std::thread workers; every tile processes its
// triangles in submission order and owns its pixels, so the picture does not depend on the
// number of threads (bit for bit).
#include <glm/mat3x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "cw4d/render/camera.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/texture.hpp"

namespace cw4d::render {

/// A mesh vertex. color is linear RGB with straight alpha (opacity). uvw is interpolated
/// perspective-correctly like the color; normal4 and texture are flat: a triangle uses those of
/// its first vertex.
struct Vertex {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};  ///< need not be unit; zero = unlit
  glm::vec4 color{1.0f};
  glm::vec3 uvw{0.0f};      ///< 3D texture coordinates
  glm::vec4 normal4{0.0f};  ///< 4D normal for Lighting::four_d (zero: the 3D normal, lifted)
  /// Sampled at uvw (null: none); must outlive Rasterizer::render().
  const Texture3D* texture = nullptr;
};

/// Indexed triangles, counter-clockwise seen from their front side.
struct TriangleMesh {
  std::vector<Vertex> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  /// Appends another mesh (indices offset).
  void append(const TriangleMesh& other);
};

/// A world-space line segment with a linear color at each end (straight alpha).
struct LineSegment {
  glm::vec3 a{0.0f}, b{0.0f};
  glm::vec4 color_a{0.0f, 0.0f, 0.0f, 1.0f}, color_b{0.0f, 0.0f, 0.0f, 1.0f};
};

struct Light {
  enum class Kind { Directional, Point };
  Kind kind = Kind::Directional;
  glm::vec3 vector{0.0f, 0.0f, 1.0f};  ///< directional: towards the light; point: its position
  glm::vec3 color{1.0f};               ///< linear RGB intensity
  float attenuation = 0.0f;            ///< point lights: intensity / (1 + attenuation * d^2)
};

/// A light in 4D space, for sections lit as parts of 4D solids ([wxyhly 2024] "四维光照"):
/// directional (vector: towards the light) or a point (vector: its position) whose intensity
/// falls off as (reference / r)^3, the inverse cube law of light spreading over 3-spheres.
struct Light4 {
  enum class Kind { Directional, Point };
  Kind kind = Kind::Directional;
  glm::vec4 vector{0.0f, 0.0f, 0.0f, 1.0f};
  glm::vec3 color{1.0f};   ///< linear RGB; a point light's intensity at distance `reference`
  float reference = 1.0f;  ///< point lights: > 0 (distances below 1e-3 reference are clamped)
};

/// Blinn-Phong: base * ambient + sum over lights of color * (base * max(N.L, 0)
/// + specular * max(N.H, 0)^shininess), N facing the viewer (two-sided).
/// With four_d set, the 3D positions are points of the hyperplane x4 = origin4 + basis4 * p,
/// N is the 4D normal (Vertex::normal4), and the lights are lights4: the same formula in 4D
/// (the viewer's direction lifted into the hyperplane; N flipped with the 3D normal when that
/// faces away from the viewer).
struct Lighting {
  glm::vec3 ambient{0.22f};
  std::vector<Light> lights;
  float specular = 0.25f;
  float shininess = 48.0f;
  bool four_d = false;
  std::vector<Light4> lights4;
  glm::vec4 origin4{0.0f};
  glm::mat3x4 basis4{1.0f};  ///< columns: the hyperplane's orthonormal basis in 4D

  /// A key light over the viewer's left shoulder, a dim fill from the right and a weak point
  /// light at the eye: readable shading for any view.
  static Lighting studio(const Camera& camera);
};

enum class Shading { BlinnPhong, Unlit };
enum class Blend {
  Opaque,  ///< the fragment replaces the sample (premultiplied by its own alpha)
  Over,    ///< premultiplied "over" the sample; triangles sorted back to front per draw
};

struct DrawOptions {
  Shading shading = Shading::BlinnPhong;
  Blend blend = Blend::Opaque;
  bool cull_back_faces = false;
  bool depth_test = true;
  bool depth_write = true;  ///< ignored (false) for Blend::Over
  float line_width = 1.5f;  ///< lines: width in pixels
  /// Lines: moved towards the viewer by this many world units, so edges lying on a surface
  /// win the depth test against it.
  float pull_toward_viewer = 0.0f;
};

struct RasterOptions {
  int width = 800;
  int height = 600;
  int samples_per_axis = 2;    ///< 1..4: s x s samples per pixel
  int threads = 0;             ///< 0: std::thread::hardware_concurrency()
  glm::vec4 background{0.0f};  ///< linear, premultiplied; transparent by default
};

/// Collects draws, then rasterizes them all in render().
class Rasterizer {
 public:
  /// \throw InputError for a size outside 1..16384, samples outside 1..4 or negative threads.
  explicit Rasterizer(const RasterOptions& options);
  ~Rasterizer();
  Rasterizer(Rasterizer&&) noexcept;
  Rasterizer& operator=(Rasterizer&&) noexcept;

  const RasterOptions& options() const { return options_; }
  float aspect() const { return static_cast<float>(options_.width) / options_.height; }

  /// Queues a mesh seen through `view`. \throw InputError for an index out of range.
  void draw(const TriangleMesh& mesh, const View& view, const Lighting& lighting,
            const DrawOptions& options = {});
  /// Queues lines (unlit, drawn as screen-space quads of options.line_width pixels).
  void draw_lines(const std::vector<LineSegment>& lines, const View& view,
                  const DrawOptions& options = {});
  /// Screen triangles queued so far (after clipping and culling).
  std::size_t queued_triangles() const;
  /// Drops every queued draw (keeping the storage, for the next frame).
  void clear();

  /// Rasterizes everything queued: linear premultiplied RGBA, options().width x height.
  Image render() const;
  /// The same into `out`, reusing its storage when it has that size already (every pixel is
  /// written), as a frame loop would.
  void render(Image& out) const;
  /// The picture as 8-bit sRGB, byte for byte to_srgb8(render(), background, alpha), but
  /// encoded tile by tile as the tiles are resolved (no float frame is written).
  void render(Image8& out, glm::vec3 background = glm::vec3(1.0f), bool alpha = false) const;

 private:
  struct Impl;
  RasterOptions options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cw4d::render
