#include "cw4d/render/raster.hpp"

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <numeric>
#include <span>
#include <thread>

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>
#elif defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/fork_join.hpp"
#include "cw4d/complex/index.hpp"
#include "cw4d/render/color.hpp"

namespace cw4d::render {

namespace {

constexpr int kSubpixelBits = 8;
constexpr std::int64_t kSubpixel = 1 << kSubpixelBits;
constexpr int kTile = 64;
constexpr int kNarrow = 16;           // rows up to this many pixels are tested pixel by pixel
constexpr std::size_t kChunk = 2048;  // triangles per geometry work item
constexpr int kMaxSide = 16384;

static_assert(kTile <= 64, "a tile row's pixels are the bits of one std::uint64_t");
// The n lowest bits set, 0 <= n <= 64 (a tile row's pixel mask).
constexpr std::uint64_t low_bits(int n) {
  return n >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1;
}

// Interpolated per vertex: world position, normal, color, texture coordinates.
struct Attr {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f};
  glm::vec4 color{0.0f};
  glm::vec3 uvw{0.0f};
};

Attr lerp(const Attr& a, const Attr& b, float t) {
  return {a.position + t * (b.position - a.position), a.normal + t * (b.normal - a.normal),
          a.color + t * (b.color - a.color), a.uvw + t * (b.uvw - a.uvw)};
}

Attr scaled(const Attr& a, float s) {
  return {a.position * s, a.normal * s, a.color * s, a.uvw * s};
}

struct ClipVertex {
  glm::vec4 clip;
  Attr attr;
};

// A triangle ready for rasterization: fixed-point screen position (y down), depth, 1/w and
// attributes premultiplied by 1/w. Oriented so that its edge functions are positive inside.
struct ScreenTriangle {
  // What binning and coverage read first, together; the shading attributes after them.
  int x0, y0, x1, y1;  // pixel bounding box, inclusive, inside the image
  std::uint32_t draw;
  std::array<std::int64_t, 3> x, y;
  std::array<float, 3> z;
  std::array<float, 3> inv_w;
  std::array<Attr, 3> attr;            // attr / w
  glm::vec4 normal4{0.0f};             // flat, for 4D lighting
  const Texture3D* texture = nullptr;  // flat
};

struct DrawState {
  View view;
  Lighting lighting;
  DrawOptions options;
  float specular_cutoff = 0.0f;  // below this N.H the highlight is under 1e-3: not computed
  int integer_shininess = 0;     // the shininess when it is a whole number 1..1024, else 0
  // Per light of lighting.lights: a directional light's vector divided by its length, as the
  // shading computes it for every fragment (the same float operations), so the SIMD path
  // reads it instead of recomputing it; lit false when that length is not positive.
  struct Unit {
    glm::vec3 l{0.0f};
    bool lit = false;
  };
  std::vector<Unit> unit_lights;
};

DrawState make_state(const View& view, const Lighting& lighting, const DrawOptions& options) {
  DrawState d{view, lighting, options, 0.0f, 0, {}};
  for (const Light& light : lighting.lights) {
    DrawState::Unit u;
    if (light.kind == Light::Kind::Directional) {
      const glm::vec3 l = light.vector;
      const float len = std::sqrt(l.x * l.x + l.y * l.y + l.z * l.z);
      u.lit = len > 0.0f;
      u.l = glm::vec3(l.x / len, l.y / len, l.z / len);
    }
    d.unit_lights.push_back(u);
  }
  if (options.blend == Blend::Over) d.options.depth_write = false;
  if (lighting.shininess > 0.0f) d.specular_cutoff = std::exp(std::log(1e-3f) / lighting.shininess);
  if (lighting.shininess >= 1.0f && lighting.shininess <= 1024.0f &&
      lighting.shininess == std::floor(lighting.shininess))
    d.integer_shininess = static_cast<int>(lighting.shininess);
  return d;
}

// x^n by repeated squaring (n >= 1): within a few ulps of std::pow, and the same sequence of
// float products in the scalar and the SIMD path.
template <class T>
T integer_power(T x, int n) {
  T result = x;
  bool first = true;
  for (;;) {
    if (n & 1) {
      result = first ? x : result * x;
      first = false;
    }
    n >>= 1;
    if (!n) return result;
    x = x * x;
  }
}

float specular_power(const DrawState& d, float nh) {
  return d.integer_shininess ? integer_power(nh, d.integer_shininess)
                             : std::pow(nh, d.lighting.shininess);
}

// Inside when >= 0: the six frustum planes of OpenGL clip space.
float plane_value(const glm::vec4& c, int plane) {
  switch (plane) {
    case 0:
      return c.w + c.x;
    case 1:
      return c.w - c.x;
    case 2:
      return c.w + c.y;
    case 3:
      return c.w - c.y;
    case 4:
      return c.w + c.z;
    default:
      return c.w - c.z;
  }
}

// Sutherland-Hodgman against the planes in `mask` (bit i = plane i), in clip space where
// linear interpolation of every attribute is exact.
void clip_polygon(std::vector<ClipVertex>& poly, std::vector<ClipVertex>& scratch, unsigned mask) {
  for (int plane = 0; plane < 6 && !poly.empty(); ++plane) {
    if (!(mask & (1u << plane))) continue;
    scratch.clear();
    const std::size_t n = poly.size();
    for (std::size_t i = 0; i < n; ++i) {
      const ClipVertex& a = poly[i];
      const ClipVertex& b = poly[(i + 1) % n];
      const float da = plane_value(a.clip, plane), db = plane_value(b.clip, plane);
      if (da >= 0.0f) scratch.push_back(a);
      if ((da >= 0.0f) != (db >= 0.0f)) {
        // Computed from the inside end, so that the two triangles sharing this edge get the
        // very same point (no crack, no double coverage along a clipped shared edge).
        const ClipVertex& from = da >= 0.0f ? a : b;
        const ClipVertex& to = da >= 0.0f ? b : a;
        const float df = da >= 0.0f ? da : db, dt = da >= 0.0f ? db : da;
        const float t = df / (df - dt);
        scratch.push_back({from.clip + t * (to.clip - from.clip), lerp(from.attr, to.attr, t)});
      }
    }
    poly.swap(scratch);
  }
}

unsigned outcode(const glm::vec4& c) {
  unsigned code = 0;
  for (int p = 0; p < 6; ++p)
    if (plane_value(c, p) < 0.0f) code |= 1u << p;
  return code;
}

struct ScreenVertex {
  float x, y, z, inv_w;
  Attr attr;  // divided by w
};

ScreenVertex to_screen(const ClipVertex& v, int width, int height) {
  const float inv_w = 1.0f / v.clip.w;
  ScreenVertex s;
  s.x = (v.clip.x * inv_w * 0.5f + 0.5f) * static_cast<float>(width);
  s.y = (0.5f - v.clip.y * inv_w * 0.5f) * static_cast<float>(height);
  s.z = std::clamp(v.clip.z * inv_w * 0.5f + 0.5f, 0.0f, 1.0f);
  s.inv_w = inv_w;
  s.attr = scaled(v.attr, inv_w);
  return s;
}

// std::llround (halfway cases away from zero) without the library call: x minus its whole
// part is exact below 2^52.
std::int64_t round_half_away(double x) {
  if (!(std::abs(x) < 4503599627370496.0)) return std::llround(x);
  const auto whole = static_cast<std::int64_t>(x);
  const double frac = x - static_cast<double>(whole);
  return whole + (frac >= 0.5 ? 1 : 0) - (frac <= -0.5 ? 1 : 0);
}

// Builds the screen triangle (a, b, c); false when it has no area or is culled.
bool setup(const ScreenVertex& a, const ScreenVertex& b, const ScreenVertex& c, bool cull_back,
           int width, int height, std::uint32_t draw, ScreenTriangle& t) {
  const ScreenVertex* v[3] = {&a, &b, &c};
  for (int i = 0; i < 3; ++i) {
    t.x[i] = round_half_away(static_cast<double>(v[i]->x) * kSubpixel);
    t.y[i] = round_half_away(static_cast<double>(v[i]->y) * kSubpixel);
  }
  const std::int64_t cross =
      (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.y[1] - t.y[0]) * (t.x[2] - t.x[0]);
  if (cross == 0) return false;
  // y points down: counter-clockwise in normalized device coordinates (front) has cross < 0.
  const bool front = cross < 0;
  if (cull_back && !front) return false;
  if (front) {  // make the edge functions positive inside
    std::swap(v[1], v[2]);
    std::swap(t.x[1], t.x[2]);
    std::swap(t.y[1], t.y[2]);
  }
  for (int i = 0; i < 3; ++i) {
    t.z[i] = v[i]->z;
    t.inv_w[i] = v[i]->inv_w;
    t.attr[i] = v[i]->attr;
  }
  const std::int64_t min_x = std::min({t.x[0], t.x[1], t.x[2]});
  const std::int64_t max_x = std::max({t.x[0], t.x[1], t.x[2]});
  const std::int64_t min_y = std::min({t.y[0], t.y[1], t.y[2]});
  const std::int64_t max_y = std::max({t.y[0], t.y[1], t.y[2]});
  t.x0 = static_cast<int>(std::clamp<std::int64_t>(min_x >> kSubpixelBits, 0, width - 1));
  t.x1 = static_cast<int>(std::clamp<std::int64_t>(max_x >> kSubpixelBits, 0, width - 1));
  t.y0 = static_cast<int>(std::clamp<std::int64_t>(min_y >> kSubpixelBits, 0, height - 1));
  t.y1 = static_cast<int>(std::clamp<std::int64_t>(max_y >> kSubpixelBits, 0, height - 1));
  if (max_x < 0 || max_y < 0 || min_x >= static_cast<std::int64_t>(width) * kSubpixel ||
      min_y >= static_cast<std::int64_t>(height) * kSubpixel)
    return false;
  t.draw = draw;
  return true;
}

// One light's Blinn-Phong term, in 3D or in 4D (Vec: glm::vec3 or glm::vec4): n the unit normal,
// v the direction to the viewer, l the (unnormalised) direction to the light, intensity its
// fall-off. Zero for a light behind the surface.
template <class Vec>
glm::vec3 blinn_phong(const DrawState& d, const glm::vec4& base, const Vec& n, const Vec& v, Vec l,
                      float intensity, const glm::vec3& color) {
  const float len = glm::length(l);
  if (!(len > 0.0f)) return glm::vec3(0.0f);
  l /= len;
  const float diffuse = glm::dot(n, l);
  if (diffuse <= 0.0f) return glm::vec3(0.0f);
  const Vec h = glm::normalize(l + v);
  const float nh = glm::dot(n, h);
  const Lighting& lit = d.lighting;
  const float spec =
      nh > d.specular_cutoff ? lit.specular * specular_power(d, std::max(nh, 0.0f)) : 0.0f;
  return intensity * color * (glm::vec3(base) * diffuse + glm::vec3(spec));
}

// The same Blinn-Phong in 4D: position and viewer lifted into the hyperplane, N the 4D normal.
glm::vec4 shade4(const DrawState& d, const Attr& a, const glm::vec4& base, glm::vec4 normal4) {
  const Lighting& lit = d.lighting;
  const glm::vec3 v3 = d.view.to_viewer(a.position);
  if (!(glm::dot(normal4, normal4) > 0.0f)) normal4 = lit.basis4 * a.normal;
  glm::vec4 n = glm::normalize(normal4);
  if (glm::dot(a.normal, v3) < 0.0f) n = -n;  // two-sided, decided by the side the viewer sees
  const glm::vec4 p = lit.origin4 + lit.basis4 * a.position;
  const glm::vec4 v = lit.basis4 * v3;
  glm::vec3 c = lit.ambient * glm::vec3(base);
  for (const Light4& light : lit.lights4) {
    glm::vec4 l = light.vector;
    float intensity = 1.0f;
    if (light.kind == Light4::Kind::Point) {
      l = light.vector - p;
      const float r = std::max(glm::length(l), 1e-3f * light.reference);
      const float q = light.reference / r;
      intensity = q * q * q;
    }
    c += blinn_phong(d, base, n, v, l, intensity, light.color);
  }
  return glm::vec4(c, base.a);
}

glm::vec4 shade(const DrawState& d, const Attr& a, const ScreenTriangle& t) {
  glm::vec4 base = a.color;
  if (t.texture) base = glm::vec4(t.texture->apply(glm::vec3(base), a.uvw), base.a);
  if (d.options.shading == Shading::Unlit || glm::dot(a.normal, a.normal) <= 0.0f) return base;
  if (d.lighting.four_d) return shade4(d, a, base, t.normal4);
  glm::vec3 n = glm::normalize(a.normal);
  const glm::vec3 v = d.view.to_viewer(a.position);
  if (glm::dot(n, v) < 0.0f) n = -n;  // two-sided: light the side the viewer sees
  const Lighting& lit = d.lighting;
  glm::vec3 c = lit.ambient * glm::vec3(base);
  for (const Light& light : lit.lights) {
    glm::vec3 l = light.vector;
    float intensity = 1.0f;
    if (light.kind == Light::Kind::Point) {
      l = light.vector - a.position;
      const float d2 = glm::dot(l, l);
      intensity = 1.0f / (1.0f + light.attenuation * d2);
    }
    c += blinn_phong(d, base, n, v, l, intensity, light.color);
  }
  return glm::vec4(c, base.a);
}

// Edge k is opposite vertex k, from v[k+1] to v[k+2]: E_k = A x + B y + C > 0 inside, and
// E_k(v_k) = twice the area. bias is -1 for edges that are not top or left: a sample exactly
// on such an edge belongs to the neighbour.
struct Edges {
  std::int64_t A[3], B[3], C[3], bias[3];
  double inv_area;
};

Edges edges_of(const ScreenTriangle& t) {
  Edges e;
  for (int k = 0; k < 3; ++k) {
    const int i0 = (k + 1) % 3, i1 = (k + 2) % 3;
    const std::int64_t dx = t.x[i1] - t.x[i0], dy = t.y[i1] - t.y[i0];
    e.A[k] = -dy;
    e.B[k] = dx;
    e.C[k] = dy * t.x[i0] - dx * t.y[i0];
    const bool top_left = (dy == 0 && dx > 0) || dy < 0;
    e.bias[k] = top_left ? 0 : -1;
  }
  e.inv_area = 1.0 / static_cast<double>(e.A[0] * t.x[0] + e.B[0] * t.y[0] + e.C[0]);
  return e;
}

// Barycentric weights of the fixed-point sample (X, Y): the edge functions, exact in integers,
// scaled by 1 / (twice the area).
void barycentrics(const Edges& e, std::int64_t X, std::int64_t Y, float b[3]) {
  for (int k = 0; k < 3; ++k)
    b[k] = static_cast<float>(static_cast<double>(e.A[k] * X + e.B[k] * Y + e.C[k]) * e.inv_area);
}

// Perspective-correct attributes at the barycentric weights b, shaded.
glm::vec4 shade_bary(const DrawState& d, const ScreenTriangle& t, const float b[3]) {
  const float inv_w = b[0] * t.inv_w[0] + b[1] * t.inv_w[1] + b[2] * t.inv_w[2];
  const float wgt = inv_w != 0.0f ? 1.0f / inv_w : 0.0f;
  Attr a;
  a.position =
      (b[0] * t.attr[0].position + b[1] * t.attr[1].position + b[2] * t.attr[2].position) * wgt;
  a.normal = (b[0] * t.attr[0].normal + b[1] * t.attr[1].normal + b[2] * t.attr[2].normal) * wgt;
  a.color = (b[0] * t.attr[0].color + b[1] * t.attr[1].color + b[2] * t.attr[2].color) * wgt;
  if (t.texture) a.uvw = (b[0] * t.attr[0].uvw + b[1] * t.attr[1].uvw + b[2] * t.attr[2].uvw) * wgt;
  return shade(d, a, t);
}

// Perspective-correct attributes at the fixed-point sample (X, Y), shaded.
glm::vec4 shade_at(const DrawState& d, const ScreenTriangle& t, const Edges& e, std::int64_t X,
                   std::int64_t Y) {
  float b[3];
  barycentrics(e, X, Y, b);
  return shade_bary(d, t, b);
}

// Eight samples of one triangle shaded at once with AVX (x86-64, chosen at run time). It
// evaluates shade_bary's very operations in the same order, without fused multiply-adds (the
// function is compiled for AVX2 only, not FMA), and the same power for the specular lanes
// (integer_power, or std::pow lane by lane), so every lane is bit for bit the scalar result:
// the picture does not depend on the path. Covers untextured triangles lit in 3D or unlit; the rest
// goes through shade_bary.
#if defined(__GNUC__) && defined(__x86_64__)
#define CW4D_RASTER_SIMD 1
#define CW4D_AVX2 __attribute__((target("avx2")))
typedef float v8f __attribute__((vector_size(32)));
typedef int v8i __attribute__((vector_size(32)));
typedef double v4d __attribute__((vector_size(32)));

struct V3 {
  v8f x, y, z;
};

CW4D_AVX2 inline v8f splat(float f) {
  return v8f{f, f, f, f, f, f, f, f};
}
CW4D_AVX2 inline v8f vsqrt(v8f x) {
  return reinterpret_cast<v8f>(_mm256_sqrt_ps(reinterpret_cast<__m256>(x)));
}
CW4D_AVX2 inline v8f dot3(const V3& a, const V3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
// (b0 a0 + b1 a1 + b2 a2) w, as glm evaluates it for one component.
CW4D_AVX2 inline v8f interp3(const v8f* B, float a0, float a1, float a2, v8f wgt) {
  return (B[0] * a0 + B[1] * a1 + B[2] * a2) * wgt;
}
CW4D_AVX2 inline v8f pick(v8i mask, v8f a, v8f b) {
  return mask ? a : b;
}

// integer_power for eight lanes (the same products).
CW4D_AVX2 inline v8f integer_power8(v8f x, int n) {
  v8f result = x;
  bool first = true;
  for (;;) {
    if (n & 1) {
      result = first ? x : result * x;
      first = false;
    }
    n >>= 1;
    if (!n) return result;
    x = x * x;
  }
}

bool simd_available() {
  static const bool ok = __builtin_cpu_supports("avx2");
  return ok;
}

bool simd_shadable(const DrawState& d, const ScreenTriangle& t) {
  return !t.texture && (d.options.shading == Shading::Unlit || !d.lighting.four_d);
}

// Eight samples (X, Y) of one triangle (fixed point, exact in double: below 2^23 each, so the
// edge functions below 2^47) shaded into eight unpremultiplied colors.
CW4D_AVX2 void shade8(const DrawState& d, const ScreenTriangle& t, const Edges& e,
                      const double (&X)[8], const double (&Y)[8], glm::vec4* out) {
  // The barycentrics as barycentrics() computes them: the integer edge function (exact here
  // too), times 1 / area in double, rounded to float.
  float b[3][8];
  for (int h = 0; h < 8; h += 4) {
    v4d x, y;
    std::memcpy(&x, X + h, sizeof x);
    std::memcpy(&y, Y + h, sizeof y);
    for (int k = 0; k < 3; ++k) {
      const v4d edge = static_cast<double>(e.A[k]) * x + static_cast<double>(e.B[k]) * y +
                       static_cast<double>(e.C[k]);
      const __m128 f = _mm256_cvtpd_ps(reinterpret_cast<__m256d>(edge * e.inv_area));
      std::memcpy(&b[k][h], &f, sizeof f);
    }
  }
  v8f B[3];
  std::memcpy(&B[0], b[0], sizeof(v8f));
  std::memcpy(&B[1], b[1], sizeof(v8f));
  std::memcpy(&B[2], b[2], sizeof(v8f));
  const v8f zero = splat(0.0f);
  const v8f inv_w = B[0] * t.inv_w[0] + B[1] * t.inv_w[1] + B[2] * t.inv_w[2];
  const v8f wgt = pick(inv_w != zero, splat(1.0f) / inv_w, zero);
  const Attr &a0 = t.attr[0], &a1 = t.attr[1], &a2 = t.attr[2];
  const v8f base[4] = {interp3(B, a0.color.r, a1.color.r, a2.color.r, wgt),
                       interp3(B, a0.color.g, a1.color.g, a2.color.g, wgt),
                       interp3(B, a0.color.b, a1.color.b, a2.color.b, wgt),
                       interp3(B, a0.color.a, a1.color.a, a2.color.a, wgt)};
  v8f rgb[3] = {base[0], base[1], base[2]};
  if (d.options.shading != Shading::Unlit) {
    const V3 p{interp3(B, a0.position.x, a1.position.x, a2.position.x, wgt),
               interp3(B, a0.position.y, a1.position.y, a2.position.y, wgt),
               interp3(B, a0.position.z, a1.position.z, a2.position.z, wgt)};
    V3 n{interp3(B, a0.normal.x, a1.normal.x, a2.normal.x, wgt),
         interp3(B, a0.normal.y, a1.normal.y, a2.normal.y, wgt),
         interp3(B, a0.normal.z, a1.normal.z, a2.normal.z, wgt)};
    const v8f nn = dot3(n, n);
    const v8i lit = ~(nn <= zero);  // unlit lanes (zero normal) keep the base color
    const v8f inv_len = splat(1.0f) / vsqrt(nn);
    n = {n.x * inv_len, n.y * inv_len, n.z * inv_len};
    const View& view = d.view;
    V3 v{splat(-view.forward.x), splat(-view.forward.y), splat(-view.forward.z)};
    if (!view.orthographic) {
      const V3 to{splat(view.eye.x) - p.x, splat(view.eye.y) - p.y, splat(view.eye.z) - p.z};
      const v8f len = vsqrt(dot3(to, to));
      const v8i ok = len > zero;
      v = {pick(ok, to.x / len, v.x), pick(ok, to.y / len, v.y), pick(ok, to.z / len, v.z)};
    }
    const v8i flip = dot3(n, v) < zero;
    n = {pick(flip, -n.x, n.x), pick(flip, -n.y, n.y), pick(flip, -n.z, n.z)};
    const Lighting& lit_rig = d.lighting;
    v8f c[3] = {lit_rig.ambient.x * base[0], lit_rig.ambient.y * base[1],
                lit_rig.ambient.z * base[2]};
    for (std::size_t li = 0; li < lit_rig.lights.size(); ++li) {
      const Light& light = lit_rig.lights[li];
      V3 l;
      v8f intensity = splat(1.0f);
      v8i on;
      if (light.kind == Light::Kind::Point) {
        l = {light.vector.x - p.x, light.vector.y - p.y, light.vector.z - p.z};
        const v8f d2 = dot3(l, l);
        intensity = splat(1.0f) / (splat(1.0f) + light.attenuation * d2);
        const v8f len = vsqrt(d2);
        on = len > zero;
        l = {l.x / len, l.y / len, l.z / len};
      } else {  // the unit vector is the same in every lane: computed once per draw
        const DrawState::Unit& u = d.unit_lights[li];
        if (!u.lit) continue;
        l = {splat(u.l.x), splat(u.l.y), splat(u.l.z)};
        on = ~(zero != zero);
      }
      const v8f diffuse = dot3(n, l);
      on &= diffuse > zero;
      if (!_mm256_movemask_ps(reinterpret_cast<__m256>(on))) continue;
      V3 h{l.x + v.x, l.y + v.y, l.z + v.z};
      const v8f inv_h = splat(1.0f) / vsqrt(dot3(h, h));
      h = {h.x * inv_h, h.y * inv_h, h.z * inv_h};
      const v8f nh = dot3(n, h);
      const v8i highlight = on & (nh > d.specular_cutoff);
      v8f spec = zero;
      if (const int bits = _mm256_movemask_ps(reinterpret_cast<__m256>(highlight))) {
        if (d.integer_shininess) {
          const v8f x = pick(nh > zero, nh, zero);
          spec = pick(highlight, lit_rig.specular * integer_power8(x, d.integer_shininess), zero);
        } else {
          float nh_lane[8], spec_lane[8];
          std::memcpy(nh_lane, &nh, sizeof nh_lane);
          for (int i = 0; i < 8; ++i)
            spec_lane[i] = (bits >> i) & 1 ? lit_rig.specular * std::pow(std::max(nh_lane[i], 0.0f),
                                                                         lit_rig.shininess)
                                           : 0.0f;
          std::memcpy(&spec, spec_lane, sizeof spec);
        }
      }
      for (int k = 0; k < 3; ++k) {
        const v8f term = (intensity * light.color[k]) * (base[k] * diffuse + spec);
        c[k] = pick(on, c[k] + term, c[k]);
      }
    }
    for (int k = 0; k < 3; ++k) rgb[k] = pick(lit, c[k], base[k]);
  }
  // Premultiplied as the scalar path's store does: alpha = clamp(a, 0, 1).
  const v8f alpha = pick(base[3] < zero, zero, pick(splat(1.0f) < base[3], splat(1.0f), base[3]));
  float lanes[4][8];
  for (int k = 0; k < 3; ++k) {
    const v8f premul = rgb[k] * alpha;
    std::memcpy(lanes[k], &premul, sizeof lanes[k]);
  }
  std::memcpy(lanes[3], &alpha, sizeof lanes[3]);
  for (int i = 0; i < 8; ++i)
    out[i] = glm::vec4(lanes[0][i], lanes[1][i], lanes[2][i], lanes[3][i]);
}
#endif

}  // namespace

void TriangleMesh::append(const TriangleMesh& other) {
  const auto offset = static_cast<std::uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const auto& t : other.triangles)
    triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
}

Lighting Lighting::studio(const Camera& camera) {
  const glm::vec3 f = camera.forward();
  const glm::vec3 r = camera.right();
  const glm::vec3 u = glm::cross(r, f);
  Lighting l;
  l.ambient = glm::vec3(0.2f);
  l.lights.push_back(
      {Light::Kind::Directional, glm::normalize(-f - 0.6f * r + 0.8f * u), glm::vec3(0.75f), 0.0f});
  l.lights.push_back(
      {Light::Kind::Directional, glm::normalize(-f + 0.9f * r - 0.2f * u), glm::vec3(0.25f), 0.0f});
  const float dist = glm::length(camera.eye - camera.target);
  l.lights.push_back({Light::Kind::Point, camera.eye, glm::vec3(0.15f),
                      dist > 0.0f ? 1.0f / (dist * dist) : 0.0f});
  return l;
}

// Orders the streaming stores below before whatever the thread does next.
void store_fence() {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

// Writes n pixels to dst. The frame is written once and not read again here, so on x86-64 the
// stores bypass the cache (non-temporal: no read of the lines they replace); the caller
// fences.
void write_pixels(glm::vec4* dst, const glm::vec4* src, int n) {
#if defined(__SSE2__)
  if ((reinterpret_cast<std::uintptr_t>(dst) & 15) == 0) {
    for (int i = 0; i < n; ++i)
      _mm_stream_ps(reinterpret_cast<float*>(dst + i), _mm_loadu_ps(&src[i].x));
    return;
  }
#endif
  std::copy(src, src + n, dst);
}

void fill_pixels(glm::vec4* dst, const glm::vec4& value, int n) {
#if defined(__SSE2__)
  if ((reinterpret_cast<std::uintptr_t>(dst) & 15) == 0) {
    const __m128 v = _mm_loadu_ps(&value.x);
    for (int i = 0; i < n; ++i) _mm_stream_ps(reinterpret_cast<float*>(dst + i), v);
    return;
  }
#endif
  std::fill(dst, dst + n, value);
}

struct Rasterizer::Impl {
  std::vector<DrawState> draws;
  // The queued triangles in submission order, blocks[0 .. used) one after the other (a block
  // per geometry work item, so its output is never copied); clear() keeps their storage, so
  // that a rasterizer drawing frame after frame reuses it.
  std::vector<std::vector<ScreenTriangle>> blocks;
  std::size_t used = 0;
  std::size_t count = 0;             // triangles in blocks[0 .. used)
  std::vector<ScreenVertex> screen;  // per mesh vertex, when inside the frustum
  std::vector<unsigned> codes;       // per mesh vertex: outcode
};

Rasterizer::Rasterizer(const RasterOptions& options)
    : options_(options), impl_(std::make_unique<Impl>()) {
  if (options.width < 1 || options.height < 1 || options.width > kMaxSide ||
      options.height > kMaxSide)
    throw InputError("image size " + std::to_string(options.width) + "x" +
                     std::to_string(options.height) + " outside 1..16384");
  if (options.samples_per_axis < 1 || options.samples_per_axis > 4)
    throw InputError("samples per axis must be 1..4, not " +
                     std::to_string(options.samples_per_axis));
  if (options.threads < 0) throw InputError("the thread count cannot be negative");
}

Rasterizer::~Rasterizer() = default;
Rasterizer::Rasterizer(Rasterizer&&) noexcept = default;
Rasterizer& Rasterizer::operator=(Rasterizer&&) noexcept = default;

std::size_t Rasterizer::queued_triangles() const {
  return impl_->count;
}

void Rasterizer::clear() {
  impl_->draws.clear();
  impl_->used = 0;
  impl_->count = 0;
}

namespace {

int worker_count(int requested) {
  if (requested > 0) return requested;
  return std::max(1u, std::thread::hardware_concurrency());
}

// f(i) for i in [0, n) on up to `threads` workers (each index exactly once; fork_join.hpp).
template <class F>
void run_parallel(std::size_t n, int threads, F&& f) {
  cw4d::parallel_for(n, static_cast<unsigned>(std::max(1, threads)), std::forward<F>(f));
}

// Geometry stage over chunks: each chunk's output is a block of its own, appended in order
// after the queued ones, so the result is independent of the number of workers. With sort
// (blended draws) the draw's blocks are joined into one and sorted back to front, stably.
// per_item: the triangles one input item usually gives (the block's first reservation).
template <class Produce>
void run_chunks(std::size_t count, std::size_t per_item, int threads, bool sort,
                std::vector<std::vector<ScreenTriangle>>& blocks, std::size_t& used,
                std::size_t& queued, Produce&& produce) {
  const std::size_t chunks = (count + kChunk - 1) / kChunk;
  if (blocks.size() < used + chunks) blocks.resize(used + chunks);
  run_parallel(chunks, threads, [&](std::size_t c) {
    std::vector<ScreenTriangle>& block = blocks[used + c];
    block.clear();
    block.reserve(per_item * (std::min(count, (c + 1) * kChunk) - c * kChunk));
    produce(c * kChunk, std::min(count, (c + 1) * kChunk), block);
  });
  for (std::size_t c = 0; c < chunks; ++c) queued += blocks[used + c].size();
  if (sort && chunks > 0) {
    std::vector<ScreenTriangle>& all = blocks[used];
    for (std::size_t c = 1; c < chunks; ++c)
      all.insert(all.end(), blocks[used + c].begin(), blocks[used + c].end());
    std::stable_sort(all.begin(), all.end(), [](const ScreenTriangle& a, const ScreenTriangle& b) {
      return a.z[0] + a.z[1] + a.z[2] > b.z[0] + b.z[1] + b.z[2];
    });
    used += 1;
  } else {
    used += chunks;
  }
}

}  // namespace

void Rasterizer::draw(const TriangleMesh& mesh, const View& view, const Lighting& lighting,
                      const DrawOptions& options) {
  const std::size_t nv = mesh.vertices.size();
  for (const auto& t : mesh.triangles)
    if (t[0] >= nv || t[1] >= nv || t[2] >= nv)
      throw InputError("triangle mesh: vertex index out of range");
  const auto draw_id = static_cast<std::uint32_t>(impl_->draws.size());
  impl_->draws.push_back(make_state(view, lighting, options));
  const int w = options_.width, h = options_.height;
  const int threads = worker_count(options_.threads);
  // Every vertex to clip space and, where it is inside the frustum, to the screen, once.
  auto& screen_of = impl_->screen;
  auto& codes = impl_->codes;
  screen_of.resize(nv);
  codes.resize(nv);
  run_parallel((nv + kChunk - 1) / kChunk, threads, [&](std::size_t c) {
    for (std::size_t i = c * kChunk; i < std::min(nv, (c + 1) * kChunk); ++i) {
      const Vertex& v = mesh.vertices[i];
      const ClipVertex cv{view.clip_from_world * glm::vec4(v.position, 1.0f),
                          {v.position, v.normal, v.color, v.uvw}};
      codes[i] = outcode(cv.clip);
      if (!codes[i]) screen_of[i] = to_screen(cv, w, h);
    }
  });
  run_chunks(mesh.triangles.size(), 1, threads, options.blend == Blend::Over, impl_->blocks,
             impl_->used, impl_->count,
             [&](std::size_t begin, std::size_t end, std::vector<ScreenTriangle>& out) {
               std::vector<ClipVertex> poly, scratch;
               std::vector<ScreenVertex> screen;
               for (std::size_t i = begin; i < end; ++i) {
                 const auto& tri = mesh.triangles[i];
                 const Vertex& flat = mesh.vertices[tri[0]];
                 if (!(codes[tri[0]] | codes[tri[1]] | codes[tri[2]])) {  // nothing to clip
                   ScreenTriangle st;
                   if (setup(screen_of[tri[0]], screen_of[tri[1]], screen_of[tri[2]],
                             options.cull_back_faces, w, h, draw_id, st)) {
                     st.normal4 = flat.normal4;
                     st.texture = flat.texture;
                     out.push_back(st);
                   }
                   continue;
                 }
                 poly.clear();
                 unsigned all = ~0u, any = 0;
                 for (auto id : tri) {
                   const Vertex& v = mesh.vertices[id];
                   ClipVertex cv{view.clip_from_world * glm::vec4(v.position, 1.0f),
                                 {v.position, v.normal, v.color, v.uvw}};
                   const unsigned code = outcode(cv.clip);
                   all &= code;
                   any |= code;
                   poly.push_back(cv);
                 }
                 if (all) continue;  // entirely outside one plane
                 if (any) clip_polygon(poly, scratch, any);
                 if (poly.size() < 3) continue;
                 screen.clear();
                 for (const auto& cv : poly) screen.push_back(to_screen(cv, w, h));
                 for (std::size_t k = 1; k + 1 < screen.size(); ++k) {
                   ScreenTriangle st;
                   if (setup(screen[0], screen[k], screen[k + 1], options.cull_back_faces, w, h,
                             draw_id, st)) {
                     st.normal4 = flat.normal4;
                     st.texture = flat.texture;
                     out.push_back(st);
                   }
                 }
               }
             });
}

void Rasterizer::draw_lines(const std::vector<LineSegment>& lines, const View& view,
                            const DrawOptions& options) {
  const auto draw_id = static_cast<std::uint32_t>(impl_->draws.size());
  impl_->draws.push_back(make_state(view, Lighting{}, options));
  impl_->draws.back().options.shading = Shading::Unlit;
  const int w = options_.width, h = options_.height;
  const float half = 0.5f * std::max(options.line_width, 0.0f);
  run_chunks(
      lines.size(), 2, worker_count(options_.threads), options.blend == Blend::Over, impl_->blocks,
      impl_->used, impl_->count,
      [&](std::size_t begin, std::size_t end, std::vector<ScreenTriangle>& out) {
        for (std::size_t i = begin; i < end; ++i) {
          const LineSegment& s = lines[i];
          glm::vec3 a = s.a, b = s.b;
          if (options.pull_toward_viewer != 0.0f) {
            a += options.pull_toward_viewer * view.to_viewer(a);
            b += options.pull_toward_viewer * view.to_viewer(b);
          }
          ClipVertex ca{view.clip_from_world * glm::vec4(a, 1.0f), {a, {}, s.color_a, {}}};
          ClipVertex cb{view.clip_from_world * glm::vec4(b, 1.0f), {b, {}, s.color_b, {}}};
          // Liang-Barsky in homogeneous coordinates.
          float t0 = 0.0f, t1 = 1.0f;
          bool visible = true;
          for (int p = 0; p < 6 && visible; ++p) {
            const float da = plane_value(ca.clip, p), db = plane_value(cb.clip, p);
            if (da < 0.0f && db < 0.0f)
              visible = false;
            else if (da < 0.0f)
              t0 = std::max(t0, da / (da - db));
            else if (db < 0.0f)
              t1 = std::min(t1, da / (da - db));
          }
          if (!visible || t0 >= t1) continue;
          const ClipVertex pa{ca.clip + t0 * (cb.clip - ca.clip), lerp(ca.attr, cb.attr, t0)};
          const ClipVertex pb{ca.clip + t1 * (cb.clip - ca.clip), lerp(ca.attr, cb.attr, t1)};
          const ScreenVertex sa = to_screen(pa, w, h), sb = to_screen(pb, w, h);
          glm::vec2 d(sb.x - sa.x, sb.y - sa.y);
          const float len = glm::length(d);
          d = len > 1e-6f ? d / len : glm::vec2(1.0f, 0.0f);
          const glm::vec2 n(-d.y * half, d.x * half);
          const glm::vec2 e = d * half;
          auto corner = [](const ScreenVertex& v, glm::vec2 off) {
            ScreenVertex c = v;
            c.x += off.x;
            c.y += off.y;
            return c;
          };
          const ScreenVertex q0 = corner(sa, -e + n), q1 = corner(sa, -e - n);
          const ScreenVertex q2 = corner(sb, e - n), q3 = corner(sb, e + n);
          ScreenTriangle st;
          if (setup(q0, q1, q2, false, w, h, draw_id, st)) out.push_back(st);
          if (setup(q0, q2, q3, false, w, h, draw_id, st)) out.push_back(st);
        }
      });
}

Image Rasterizer::render() const {
  Image out;
  render(out);
  return out;
}

namespace {

// Rasterizes every queued triangle tile by tile and hands each tile's resolved rows to the
// sink: sink.fill(x, y, n) for n background pixels, sink.write(x, y, src, n) for n resolved
// pixels (linear, premultiplied), sink.fence() when a worker is done with a tile.
template <class Sink>
void render_tiles(const RasterOptions& options,
                  const std::vector<std::vector<ScreenTriangle>>& blocks, std::size_t used,
                  const std::vector<DrawState>& draws, Sink& sink) {
  const int width = options.width, height = options.height;
  const int s = options.samples_per_axis, spp = s * s;
  const int tiles_x = (width + kTile - 1) / kTile, tiles_y = (height + kTile - 1) / kTile;

  // Binning in submission order, counted first: bin b is items[start[b] .. start[b + 1]).
  const std::size_t tile_count = static_cast<std::size_t>(tiles_x) * tiles_y;
  // The triangles' tile ranges are noted in the counting pass, so that the triangle array
  // is read once.
  struct Span {
    const ScreenTriangle* t;
    std::uint16_t tx0, tx1, ty0, ty1;
  };
  std::vector<Span> spans;
  std::size_t total = 0;
  for (std::size_t b = 0; b < used; ++b) total += blocks[b].size();
  spans.reserve(total);
  std::vector<std::size_t> start(tile_count + 1, 0);
  for (std::size_t b = 0; b < used; ++b)
    for (const ScreenTriangle& t : blocks[b]) {
      const Span sp{
          &t, static_cast<std::uint16_t>(t.x0 / kTile), static_cast<std::uint16_t>(t.x1 / kTile),
          static_cast<std::uint16_t>(t.y0 / kTile), static_cast<std::uint16_t>(t.y1 / kTile)};
      spans.push_back(sp);
      for (int ty = sp.ty0; ty <= sp.ty1; ++ty)
        for (int tx = sp.tx0; tx <= sp.tx1; ++tx)
          ++start[static_cast<std::size_t>(ty) * tiles_x + tx + 1];
    }
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<const ScreenTriangle*> items(start.back());
  std::vector<std::size_t> fill(start.begin(), start.end() - 1);
  for (const Span& sp : spans)
    for (int ty = sp.ty0; ty <= sp.ty1; ++ty)
      for (int tx = sp.tx0; tx <= sp.tx1; ++tx)
        items[fill[static_cast<std::size_t>(ty) * tiles_x + tx]++] = sp.t;

  // Sample offsets inside a pixel (fixed point), an s x s ordered grid.
  std::vector<std::int64_t> off_x(spp), off_y(spp);
  for (int j = 0; j < s; ++j)
    for (int i = 0; i < s; ++i) {
      off_x[j * s + i] = ((2 * i + 1) * kSubpixel) / (2 * s);
      off_y[j * s + i] = ((2 * j + 1) * kSubpixel) / (2 * s);
    }
#ifdef CW4D_RASTER_SIMD
  const bool simd = simd_available();
#endif

  const glm::vec4 background = options.background;
  run_parallel(tile_count, worker_count(options.threads), [&](std::size_t tile) {
    const int tx0 = static_cast<int>(tile % tiles_x) * kTile;
    const int ty0 = static_cast<int>(tile / tiles_x) * kTile;
    const int tw = std::min(kTile, width - tx0), th = std::min(kTile, height - ty0);
    const std::span<const ScreenTriangle* const> bin(items.data() + start[tile],
                                                     start[tile + 1] - start[tile]);
    if (bin.empty()) {
      for (int y = 0; y < th; ++y) sink.fill(tx0, ty0 + y, tw);
      sink.fence();
      return;
    }
    struct Entry {
      std::uint16_t pixel;  // y * kTile + x in the tile
      std::uint16_t q;      // the first sample showing the triangle
      std::uint32_t mask;   // every sample of the pixel showing it
    };
    constexpr std::uint32_t kBatch = 8;
    thread_local std::vector<glm::vec4> color;
    thread_local std::vector<float> depth;
    // Opaque triangle per sample, not shaded yet, as its position in this tile's bin.
    thread_local std::vector<std::uint32_t> visible;
    thread_local std::vector<Edges> edges;  // per bin position
    // Per bin position: up to kBatch samples waiting to be shaded, and how many.
    thread_local std::vector<Entry> waiting;
    thread_local std::vector<std::uint8_t> waiting_count;
    const std::size_t samples = static_cast<std::size_t>(kTile) * kTile * spp;
    // One sample per pixel: a pixel's color is written only once it shows a triangle (rows of
    // bits, `covered`); the others get the background when the tile is written. With more
    // samples every sample starts as the background.
    std::uint64_t covered[kTile] = {};
    if (spp == 1)
      color.resize(samples);
    else
      color.assign(samples, background);
    depth.assign(samples, 1.0f);
    visible.assign(samples, no_index);
    edges.resize(bin.size());
    waiting.resize(bin.size() * kBatch);
    waiting_count.assign(bin.size(), 0);
    bool pending = false;

    auto sample_xy = [&](const Entry& en, std::int64_t& X, std::int64_t& Y) {
      X = static_cast<std::int64_t>(tx0 + en.pixel % kTile) * kSubpixel + off_x[en.q];
      Y = static_cast<std::int64_t>(ty0 + en.pixel / kTile) * kSubpixel + off_y[en.q];
    };
    auto store_premul = [&](const Entry& en, const glm::vec4& premul) {
      const std::size_t base = static_cast<std::size_t>(en.pixel) * spp;
      for (std::uint32_t m = en.mask; m; m &= m - 1)
        color[base + static_cast<unsigned>(__builtin_ctz(m))] = premul;
    };
    // Shades n waiting samples of the triangle at bin position id.
    auto shade_batch = [&](std::uint32_t id, const Entry* batch, std::uint32_t n) {
      const ScreenTriangle& t = *bin[id];
      const DrawState& d = draws[t.draw];
      const Edges& e = edges[id];
#ifdef CW4D_RASTER_SIMD
      if (simd && simd_shadable(d, t)) {
        double X[kBatch], Y[kBatch];
        for (std::uint32_t i = 0; i < kBatch; ++i) {
          std::int64_t x, y;
          sample_xy(batch[std::min(i, n - 1)], x, y);
          X[i] = static_cast<double>(x);
          Y[i] = static_cast<double>(y);
        }
        glm::vec4 c[kBatch];
        shade8(d, t, e, X, Y, c);
        for (std::uint32_t i = 0; i < n; ++i) store_premul(batch[i], c[i]);
        return;
      }
#endif
      for (std::uint32_t i = 0; i < n; ++i) {
        std::int64_t X, Y;
        sample_xy(batch[i], X, Y);
        const glm::vec4 c = shade_at(d, t, e, X, Y);
        const float alpha = std::clamp(c.a, 0.0f, 1.0f);
        store_premul(batch[i], glm::vec4(glm::vec3(c) * alpha, alpha));
      }
    };
    // Queues samples of triangle id; every full batch is shaded at once.
    auto enqueue = [&](std::uint32_t id, Entry en, std::uint32_t run) {
#ifdef CW4D_RASTER_SIMD
      // One sample per pixel: a run's groups of eight neighbours are shaded at once, straight
      // into the row (the same lanes as a batch of eight, without the queue).
      if (spp == 1 && simd && run >= kBatch) {
        const ScreenTriangle& t = *bin[id];
        const DrawState& d = draws[t.draw];
        if (simd_shadable(d, t)) {
          double X[kBatch], Y[kBatch];
          const std::int64_t y =
              static_cast<std::int64_t>(ty0 + en.pixel / kTile) * kSubpixel + off_y[0];
          std::fill(Y, Y + kBatch, static_cast<double>(y));
          for (; run >= kBatch; run -= kBatch, en.pixel += kBatch) {
            for (std::uint32_t i = 0; i < kBatch; ++i)
              X[i] = static_cast<double>(
                  static_cast<std::int64_t>(tx0 + en.pixel % kTile + i) * kSubpixel + off_x[0]);
            shade8(d, t, edges[id], X, Y, &color[en.pixel]);
          }
        }
      }
#endif
      Entry* batch = &waiting[static_cast<std::size_t>(id) * kBatch];
      std::uint32_t n = waiting_count[id];
      for (std::uint32_t r = 0; r < run; ++r, ++en.pixel) {
        batch[n++] = en;
        if (n == kBatch) {
          shade_batch(id, batch, n);
          n = 0;
        }
      }
      waiting_count[id] = static_cast<std::uint8_t>(n);
    };

    // Deferred shading of the opaque samples: each pixel shades each distinct triangle left
    // visible in it once (at its first sample), so hidden fragments cost no lighting. Samples
    // wait per triangle until eight can be shaded at once (where the SIMD path applies).
    auto flush = [&] {
      if (!pending) return;
      pending = false;
      for (int y = 0; y < th; ++y) {
        const std::size_t row = static_cast<std::size_t>(y) * kTile;
        if (spp == 1) {  // runs of one triangle along the row
          for (int x = 0; x < tw;) {
            const std::uint32_t id = visible[row + x];
            if (id == no_index) {
              ++x;
              continue;
            }
            int end = x + 1;
            while (end < tw && visible[row + end] == id) ++end;
            std::fill(visible.begin() + static_cast<std::ptrdiff_t>(row + x),
                      visible.begin() + static_cast<std::ptrdiff_t>(row + end), no_index);
            covered[y] |= low_bits(end - x) << x;
            enqueue(id, {static_cast<std::uint16_t>(row + x), 0, 1u},
                    static_cast<std::uint32_t>(end - x));
            x = end;
          }
          continue;
        }
        for (int x = 0; x < tw; ++x) {
          const std::size_t base = (row + x) * spp;
          for (int q = 0; q < spp; ++q) {
            const std::uint32_t id = visible[base + q];
            if (id == no_index) continue;
            std::uint32_t mask = 0;
            for (int q2 = q; q2 < spp; ++q2)
              if (visible[base + q2] == id) {
                mask |= 1u << q2;
                visible[base + q2] = no_index;
              }
            enqueue(id, {static_cast<std::uint16_t>(row + x), static_cast<std::uint16_t>(q), mask},
                    1);
          }
        }
      }
      for (std::uint32_t id = 0; id < bin.size(); ++id)
        if (waiting_count[id]) {
          shade_batch(id, &waiting[static_cast<std::size_t>(id) * kBatch], waiting_count[id]);
          waiting_count[id] = 0;
        }
    };

    std::vector<std::int64_t> edge_sample(static_cast<std::size_t>(3) * spp);
    std::vector<double> z_sample(spp);
    constexpr std::uint32_t kAhead = 4;  // triangles whose coverage data is fetched ahead
    for (std::uint32_t j = 0; j < bin.size(); ++j) {
      if (j + kAhead < bin.size()) {
        // The bin jumps through the triangle array: load what coverage reads (the fields
        // before inv_w, over two or three cache lines) before it is needed.
        constexpr std::size_t kCoverageBytes = offsetof(ScreenTriangle, inv_w);
        const char* ahead = reinterpret_cast<const char*>(bin[j + kAhead]);
        __builtin_prefetch(ahead);
        __builtin_prefetch(ahead + kCoverageBytes / 2);
        __builtin_prefetch(ahead + kCoverageBytes - 1);
      }
      const ScreenTriangle& t = *bin[j];
      const DrawState& d = draws[t.draw];
      const bool test = d.options.depth_test, write = d.options.depth_write;
      const bool over = d.options.blend == Blend::Over;
      const int px0 = std::max(t.x0, tx0), px1 = std::min(t.x1, tx0 + tw - 1);
      const int py0 = std::max(t.y0, ty0), py1 = std::min(t.y1, ty0 + th - 1);
      if (px0 > px1 || py0 > py1) continue;
      if (over) flush();  // blending needs the colors underneath
      const Edges& e = edges[j] = edges_of(t);
      for (int k = 0; k < 3; ++k)
        for (int q = 0; q < spp; ++q)
          edge_sample[k * spp + q] = e.A[k] * off_x[q] + e.B[k] * off_y[q];
      std::int64_t max_offset[3];
      for (int k = 0; k < 3; ++k)
        max_offset[k] =
            *std::max_element(edge_sample.begin() + k * spp, edge_sample.begin() + (k + 1) * spp);
      const bool wide = spp > 1 || px1 - px0 >= kNarrow;
      const std::int64_t step0 = e.A[0] * kSubpixel, step1 = e.A[1] * kSubpixel,
                         step2 = e.A[2] * kSubpixel;
      // Depth along a row, stepped in double from its exact value at the span's first pixel.
      const double z_step =
          (static_cast<double>(step0) * t.z[0] + static_cast<double>(step1) * t.z[1] +
           static_cast<double>(step2) * t.z[2]) *
          e.inv_area;
      for (int py = py0; py <= py1; ++py) {
        const std::int64_t Y = static_cast<std::int64_t>(py) * kSubpixel;
        const std::int64_t X0 = static_cast<std::int64_t>(px0) * kSubpixel;
        // Edge functions at the pixel's corner, stepped along the row (+ bias: top-left rule).
        std::int64_t e0 = e.A[0] * X0 + e.B[0] * Y + e.C[0] + e.bias[0];
        std::int64_t e1 = e.A[1] * X0 + e.B[1] * Y + e.C[1] + e.bias[1];
        std::int64_t e2 = e.A[2] * X0 + e.B[2] * Y + e.C[2] + e.bias[2];
        // The span of the row where some sample can be inside (conservative by a pixel): each
        // edge function is linear along the row. Narrow boxes test every pixel instead.
        int lo = px0, hi = px1;
        const std::int64_t row_e[3] = {e0, e1, e2}, steps[3] = {step0, step1, step2};
        for (int k = 0; k < 3 && wide; ++k) {
          const std::int64_t best = row_e[k] + max_offset[k];
          if (steps[k] == 0) {
            if (best < 0) hi = lo - 1;
            continue;
          }
          const double x =
              std::clamp(-static_cast<double>(best) / static_cast<double>(steps[k]), -1e9, 1e9);
          if (steps[k] > 0)
            lo = std::max(lo, px0 + static_cast<int>(std::floor(x)));
          else
            hi = std::min(hi, px0 + static_cast<int>(std::ceil(x)));
        }
        if (lo > hi) continue;
        e0 += step0 * (lo - px0);
        e1 += step1 * (lo - px0);
        e2 += step2 * (lo - px0);
        for (int q = 0; q < spp; ++q) {
          const double l0 = static_cast<double>(e0 + edge_sample[q] - e.bias[0]) * e.inv_area;
          const double l1 = static_cast<double>(e1 + edge_sample[spp + q] - e.bias[1]) * e.inv_area;
          const double l2 =
              static_cast<double>(e2 + edge_sample[2 * spp + q] - e.bias[2]) * e.inv_area;
          z_sample[q] = l0 * t.z[0] + l1 * t.z[1] + l2 * t.z[2];
        }
        if (spp == 1 && !over) {  // the common case, without the loop over samples
          const std::size_t row = static_cast<std::size_t>(py - ty0) * kTile - tx0;
          const std::int64_t w[3] = {e0 + edge_sample[0], e1 + edge_sample[1], e2 + edge_sample[2]};
          if (hi - lo < kNarrow) {  // testing each pixel is cheaper than three divisions
            bool any = false;
            std::int64_t w0 = w[0], w1 = w[1], w2 = w[2];
            for (int px = lo; px <= hi; ++px, w0 += step0, w1 += step1, w2 += step2) {
              if ((w0 | w1 | w2) < 0) continue;
              const std::size_t at = row + px;
              const float z = static_cast<float>(z_sample[0] + z_step * (px - lo));
              if (test && !(z < depth[at])) continue;
              if (write) depth[at] = z;
              visible[at] = j;
              any = true;
            }
            pending |= any;
            continue;
          }
          // The exact run of pixel centres inside all three edges: w + step * i >= 0.
          std::int64_t first_i = 0, last_i = hi - lo;
          for (int k = 0; k < 3; ++k) {
            if (steps[k] > 0) {
              if (w[k] < 0) first_i = std::max(first_i, (-w[k] + steps[k] - 1) / steps[k]);
            } else if (w[k] < 0) {
              last_i = -1;
            } else if (steps[k] < 0) {
              last_i = std::min(last_i, w[k] / -steps[k]);
            }
          }
          bool any = false;
          for (int px = lo + static_cast<int>(first_i); px <= lo + last_i; ++px) {
            const std::size_t at = row + px;
            const float z = static_cast<float>(z_sample[0] + z_step * (px - lo));
            if (test && !(z < depth[at])) continue;
            if (write) depth[at] = z;
            visible[at] = j;
            any = true;
          }
          pending |= any;
          continue;
        }
        for (int px = lo; px <= hi; ++px, e0 += step0, e1 += step1, e2 += step2) {
          const std::size_t base = (static_cast<std::size_t>(py - ty0) * kTile + (px - tx0)) * spp;
          const double dz = z_step * (px - lo);
          unsigned mask = 0;
          int first_q = -1;
          for (int q = 0; q < spp; ++q) {
            const std::int64_t w0 = e0 + edge_sample[q], w1 = e1 + edge_sample[spp + q],
                               w2 = e2 + edge_sample[2 * spp + q];
            if ((w0 | w1 | w2) < 0) continue;
            const float z = static_cast<float>(z_sample[q] + dz);
            if (test && !(z < depth[base + q])) continue;
            mask |= 1u << q;
            if (write) depth[base + q] = z;
            if (first_q < 0) first_q = q;
          }
          if (!mask) continue;
          if (!over) {
            for (int q = 0; q < spp; ++q)
              if (mask & (1u << q)) visible[base + q] = j;
            pending = true;
            continue;
          }
          const std::int64_t X = static_cast<std::int64_t>(px) * kSubpixel + off_x[first_q];
          const std::int64_t Ys = Y + off_y[first_q];
          const glm::vec4 c = shade_at(d, t, e, X, Ys);
          const float alpha = std::clamp(c.a, 0.0f, 1.0f);
          const glm::vec4 premul(glm::vec3(c) * alpha, alpha);
          if (spp == 1) {
            std::uint64_t& bits = covered[py - ty0];
            const std::uint64_t bit = std::uint64_t{1} << (px - tx0);
            if (!(bits & bit)) color[base] = background;
            bits |= bit;
          }
          for (int q = 0; q < spp; ++q)
            if (mask & (1u << q)) color[base + q] = premul + (1.0f - alpha) * color[base + q];
        }
      }
    }
    flush();
    if (spp == 1) {
      for (int y = 0; y < th; ++y) {
        glm::vec4* row = &color[static_cast<std::size_t>(y) * kTile];
        if (!covered[y]) {
          sink.fill(tx0, ty0 + y, tw);
          continue;
        }
        for (std::uint64_t gaps = ~covered[y] & low_bits(tw); gaps; gaps &= gaps - 1)
          row[__builtin_ctzll(gaps)] = background;
        sink.write(tx0, ty0 + y, row, tw);
      }
      sink.fence();
      return;
    }
    const float inv_spp = 1.0f / static_cast<float>(spp);
    glm::vec4 resolved[kTile];
    for (int y = 0; y < th; ++y) {
      for (int x = 0; x < tw; ++x) {
        const std::size_t base = (static_cast<std::size_t>(y) * kTile + x) * spp;
        glm::vec4 sum(0.0f);
        for (int q = 0; q < spp; ++q) sum += color[base + q];
        resolved[x] = sum * inv_spp;
      }
      sink.write(tx0, ty0 + y, resolved, tw);
    }
    sink.fence();
  });
}

struct FloatSink {
  Image& out;
  glm::vec4 background;
  void fill(int x, int y, int n) { fill_pixels(&out.at(x, y), background, n); }
  void write(int x, int y, const glm::vec4* src, int n) { write_pixels(&out.at(x, y), src, n); }
  void fence() { store_fence(); }
};

// One pixel as to_srgb8 encodes it (the same operations), `encode` standing for
// linear_to_srgb8.
void encode_pixel(const Srgb8Encoder& encode, const glm::vec4& p, const glm::vec3& background,
                  bool alpha, std::uint8_t* dst) {
  if (alpha) {
    const float a = std::clamp(p.a, 0.0f, 1.0f);
    const glm::vec3 c = a > 0.0f ? glm::vec3(p) / a : glm::vec3(0.0f);
    for (int i = 0; i < 3; ++i) dst[i] = encode(c[i]);
    dst[3] = static_cast<std::uint8_t>(std::lround(a * 255.0f));
  } else {
    const glm::vec3 c = glm::vec3(p) + (1.0f - std::clamp(p.a, 0.0f, 1.0f)) * background;
    for (int i = 0; i < 3; ++i) dst[i] = encode(c[i]);
  }
}

#ifdef CW4D_RASTER_SIMD
// The byte of each lane as Srgb8Encoder gives it (c not NaN): the bucket's first byte by a
// gather, then up to max_steps comparisons with the next threshold.
CW4D_AVX2 inline __m256i encode8(const Srgb8Encoder& e, v8f c) {
  const v8f zero = splat(0.0f), one = splat(1.0f);
  const v8f clamped = pick(c > zero, pick(c < one, c, one), zero);
  const __m256i bits = _mm256_castps_si256(reinterpret_cast<__m256>(clamped));
  const __m256i bucket = _mm256_srli_epi32(bits, Srgb8Encoder::kShift);
  __m256i k =
      _mm256_and_si256(_mm256_i32gather_epi32(reinterpret_cast<const int*>(e.start), bucket, 1),
                       _mm256_set1_epi32(0xFF));
  const __m256i ones = _mm256_set1_epi32(1);
  for (int step = 0; step < e.max_steps; ++step) {
    const __m256i next = _mm256_i32gather_epi32(reinterpret_cast<const int*>(e.threshold),
                                                _mm256_add_epi32(k, ones), 4);
    // k += 1 where bits >= next (both below 2^31: a signed comparison).
    k = _mm256_add_epi32(k, _mm256_andnot_si256(_mm256_cmpgt_epi32(next, bits), ones));
  }
  return k;
}

// Eight pixels as encode_pixel encodes them; false (nothing written) when a lane is NaN, which
// the scalar code then handles.
// bg_bits: the bits of the raster background's channels; fill8: eight pixels of it, encoded.
CW4D_AVX2 bool encode_pixels8(const Srgb8Encoder& e, const glm::vec4* src,
                              const glm::vec3& background, bool alpha, const v8i (&bg_bits)[4],
                              const std::uint8_t* fill8, std::uint8_t* dst) {
  // Transposed to one register per channel, the lanes in the pixel order 0 2 4 6 1 3 5 7
  // (undone on the packed bytes below).
  const float* f = &src[0].x;
  const __m256 q0 = _mm256_loadu_ps(f), q1 = _mm256_loadu_ps(f + 8);
  const __m256 q2 = _mm256_loadu_ps(f + 16), q3 = _mm256_loadu_ps(f + 24);
  const __m256 lo01 = _mm256_unpacklo_ps(q0, q1), hi01 = _mm256_unpackhi_ps(q0, q1);
  const __m256 lo23 = _mm256_unpacklo_ps(q2, q3), hi23 = _mm256_unpackhi_ps(q2, q3);
  const v8f p[4] = {reinterpret_cast<v8f>(_mm256_shuffle_ps(lo01, lo23, 0x44)),
                    reinterpret_cast<v8f>(_mm256_shuffle_ps(lo01, lo23, 0xEE)),
                    reinterpret_cast<v8f>(_mm256_shuffle_ps(hi01, hi23, 0x44)),
                    reinterpret_cast<v8f>(_mm256_shuffle_ps(hi01, hi23, 0xEE))};
  const v8f zero = splat(0.0f), one = splat(1.0f);
  // Eight untouched pixels (the raster background exactly): its bytes.
  const v8i same =
      (reinterpret_cast<v8i>(p[0]) == bg_bits[0]) & (reinterpret_cast<v8i>(p[1]) == bg_bits[1]) &
      (reinterpret_cast<v8i>(p[2]) == bg_bits[2]) & (reinterpret_cast<v8i>(p[3]) == bg_bits[3]);
  if (_mm256_movemask_ps(reinterpret_cast<__m256>(same)) == 0xFF) {
    std::memcpy(dst, fill8, alpha ? 32 : 24);
    return true;
  }
  const v8f a = pick(p[3] < zero, zero, pick(one < p[3], one, p[3]));  // std::clamp
  v8f c[3];
  if (alpha) {
    const v8i positive = a > zero;
    for (int k = 0; k < 3; ++k) c[k] = pick(positive, p[k] / a, zero);
  } else {
    for (int k = 0; k < 3; ++k) c[k] = p[k] + (one - a) * background[k];
  }
  const v8i nan = (a != a) | (c[0] != c[0]) | (c[1] != c[1]) | (c[2] != c[2]);
  if (_mm256_movemask_ps(reinterpret_cast<__m256>(nan))) return false;
  __m256i packed =
      _mm256_or_si256(encode8(e, c[0]), _mm256_or_si256(_mm256_slli_epi32(encode8(e, c[1]), 8),
                                                        _mm256_slli_epi32(encode8(e, c[2]), 16)));
  const __m256i order = _mm256_setr_epi32(0, 4, 1, 5, 2, 6, 3, 7);
  if (alpha) {
    // std::lround(a * 255) for a in [0, 1]: the whole part plus one from a fraction of 1/2 on.
    const __m256 x = reinterpret_cast<__m256>(a * 255.0f);
    const __m256 whole = _mm256_round_ps(x, _MM_FROUND_TO_ZERO | _MM_FROUND_NO_EXC);
    const __m256 up = _mm256_cmp_ps(_mm256_sub_ps(x, whole), _mm256_set1_ps(0.5f), _CMP_GE_OQ);
    const __m256i bytes =
        _mm256_cvtps_epi32(_mm256_add_ps(whole, _mm256_and_ps(up, _mm256_set1_ps(1.0f))));
    packed = _mm256_or_si256(packed, _mm256_slli_epi32(bytes, 24));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(dst),
                        _mm256_permutevar8x32_epi32(packed, order));
    return true;
  }
  packed = _mm256_permutevar8x32_epi32(packed, order);
  // RGB: the three low bytes of each pixel, 12 bytes per 128-bit half.
  const __m256i rgb = _mm256_shuffle_epi8(
      packed, _mm256_setr_epi8(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1, 0, 1, 2, 4,
                               5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1));
  std::uint8_t bytes[32];
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(bytes), rgb);
  std::memcpy(dst, bytes, 12);
  std::memcpy(dst + 12, bytes + 16, 12);
  return true;
}
#endif

// Resolves tiles straight into 8-bit sRGB, as to_srgb8 would encode the float frame.
struct Srgb8Sink {
  Image8& out;
  glm::vec3 background;  // under the picture when !alpha
  bool alpha;
  const Srgb8Encoder& encoder;
  std::uint8_t fill_row[kTile * 4];  // kTile pixels of the raster background, encoded
  bool simd;
#ifdef CW4D_RASTER_SIMD
  v8i bg_bits[4];  // the bits of the raster background's channels, in every lane
#endif

  void fill(int x, int y, int n) {
    const int ch = out.channels;
    std::memcpy(&out.bytes[(static_cast<std::size_t>(y) * out.width + x) * ch], fill_row,
                static_cast<std::size_t>(n) * ch);
  }
  void write(int x, int y, const glm::vec4* src, int n) {
    const int ch = out.channels;
    std::uint8_t* dst = &out.bytes[(static_cast<std::size_t>(y) * out.width + x) * ch];
    int i = 0;
#ifdef CW4D_RASTER_SIMD
    if (simd)
      for (; i + 8 <= n; i += 8)
        if (!encode_pixels8(encoder, src + i, background, alpha, bg_bits, fill_row, dst + i * ch))
          for (int j = i; j < i + 8; ++j)
            encode_pixel(encoder, src[j], background, alpha, dst + j * ch);
#endif
    for (; i < n; ++i) encode_pixel(encoder, src[i], background, alpha, dst + i * ch);
  }
  void fence() {}
};

}  // namespace

void Rasterizer::render(Image& out) const {
  out.width = options_.width;
  out.height = options_.height;
  out.pixels.resize(static_cast<std::size_t>(out.width) * out.height);
  FloatSink sink{out, options_.background};
  render_tiles(options_, impl_->blocks, impl_->used, impl_->draws, sink);
}

void Rasterizer::render(Image8& out, glm::vec3 background, bool alpha) const {
  out.width = options_.width;
  out.height = options_.height;
  out.channels = alpha ? 4 : 3;
  out.bytes.resize(static_cast<std::size_t>(out.width) * out.height * out.channels);
  const Srgb8Encoder& encoder = Srgb8Encoder::instance();
  bool simd = false;
#ifdef CW4D_RASTER_SIMD
  simd = simd_available() && encoder.exact;
#endif
#ifdef CW4D_RASTER_SIMD
  Srgb8Sink sink{out, background, alpha, encoder, {}, simd, {}};
#else
  Srgb8Sink sink{out, background, alpha, encoder, {}, simd};
#endif
  for (int i = 0; i < kTile; ++i)
    encode_pixel(encoder, options_.background, background, alpha, sink.fill_row + i * out.channels);
#ifdef CW4D_RASTER_SIMD
  for (int k = 0; k < 4; ++k) {
    const int bits = std::bit_cast<int>(options_.background[k]);
    sink.bg_bits[k] = v8i{bits, bits, bits, bits, bits, bits, bits, bits};
  }
#endif
  render_tiles(options_, impl_->blocks, impl_->used, impl_->draws, sink);
}

}  // namespace cw4d::render
