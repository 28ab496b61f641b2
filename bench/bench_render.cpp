// Frame time of the software rasterizer (render/) at 1920x1080, next to Mesa's llvmpipe through
// OSMesa drawing the same triangles with legacy OpenGL (client arrays), in two ways:
//   llvmpipe/...       fixed-function lighting: the rig lit per vertex (Gouraud), the colors
//                      interpolated; cheaper per pixel than cw4d's model, and not the same picture;
//   llvmpipe-glsl/...  a GLSL fragment shader evaluating cw4d's Blinn-Phong per pixel: the same
//                      lights and terms (ambient, two-sided normal, the point light's
//                      1 / (1 + k d^2), the highlight cut below 1e-3), perspective-correct
//                      position, normal and color: the like-for-like reference.
//
// Scenes: the section of the 120-cell by a generic plane (~200 triangles: fill-bound) and the
// section of spherinder:1,320 (~1e5 triangles: setup-bound). Both renderers draw every triangle
// of the same mesh (no culling), with a depth buffer, two directional lights and a point light.
// Differences that favour llvmpipe: the fixed-function reference lights per vertex (Gouraud)
// where cw4d lights per pixel (Blinn-Phong), and both references write 8-bit pixels where cw4d
// resolves to linear float RGBA. Each reference reports how far its picture is from cw4d's
// (the counters dev = mean |difference| of the RGB bytes over the pixels both drew, in 8-bit
// steps of the linear value, and off = the fraction of those pixels with a channel off by more
// than 2 steps), so that "the same lighting model" is measured, not asserted.
// cw4d runs with 1 sample per pixel (as llvmpipe, which has no MSAA through OSMesa) and with
// 2x2 samples; threads = all cores unless the name says /threads:1. One Rasterizer and one
// Image serve every frame (as llvmpipe keeps its context and buffer), except in /fresh, which
// allocates both anew per frame. /srgb8 resolves straight to 8-bit sRGB RGBA (straight alpha)
// like the PNG writer's encoding, as llvmpipe writes 8-bit RGBA (it without the sRGB transfer
// function); the other rows write the linear float frame.
//
// In console mode the program ends with wall-time ratios cw4d / llvmpipe and cw4d /
// llvmpipe-glsl from the same run.
//
//   bench_render [--benchmark_filter=REGEX] [--benchmark_min_time=SECONDS] ...
#include <benchmark/benchmark.h>

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>  // with GL_GLEXT_PROTOTYPES: glext.h, the GL 2.0 shader calls
#include <GL/osmesa.h>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <unistd.h>

#include "bench_options.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/render/camera.hpp"
#include "cw4d/render/raster.hpp"
#include "cw4d/render/section_view.hpp"
#include "cw4d/section/section.hpp"

namespace {

constexpr int kWidth = 1920, kHeight = 1080;

struct Case {
  std::string name;
  cw4d::render::TriangleMesh mesh;
  cw4d::render::Camera camera;
};

Case make_case(const std::string& name, const std::string& spec, const Eigen::VectorXd& normal,
               double offset) {
  const cw4d::Complex model = cw4d::load_model(spec);
  const cw4d::Section s = cw4d::section(model, cw4d::Hyperplane::from(normal, offset));
  Case c;
  c.name = name;
  c.mesh = cw4d::render::section_mesh(s, &model);
  for (auto& v : c.mesh.vertices) v.normal = glm::normalize(v.normal);  // GL wants unit normals
  cw4d::render::SectionViewOptions o;
  o.raster.width = kWidth;
  o.raster.height = kHeight;
  c.camera = cw4d::render::section_camera(s, o);
  return c;
}

const std::vector<Case>& cases() {
  static const std::vector<Case> all = [] {
    Eigen::VectorXd n(4);
    n << 1.0, 0.7, 0.4, 0.2;
    Eigen::VectorXd m(4);
    m << 0.3, 0.0, 0.0, 1.0;
    std::vector<Case> v;
    v.push_back(make_case("120-cell", "120-cell", n, 0.3));
    v.push_back(make_case("spherinder:1,320", "spherinder:1,320", m, 0.1));
    return v;
  }();
  return all;
}

// fresh: a new Rasterizer and a new Image every frame (the storage allocated and faulted in
// anew each time) instead of one of each reused through clear() and render(Image&).
// srgb8: render(Image8&) (8-bit sRGB RGBA) instead of the float frame.
void bm_cw4d(benchmark::State& state, const Case* c, int samples, int threads, bool fresh,
             bool srgb8) {
  using namespace cw4d::render;
  RasterOptions ro;
  ro.width = kWidth;
  ro.height = kHeight;
  ro.samples_per_axis = samples;
  ro.threads = threads;
  const Lighting lighting = Lighting::studio(c->camera);
  // One rasterizer and one frame reused from frame to frame (clear() keeps the storage), as
  // llvmpipe keeps its context and the OSMesa buffer.
  Rasterizer r(ro);
  Image img;
  Image8 img8;
  for (auto _ : state) {
    if (srgb8) {
      r.clear();
      r.draw(c->mesh, c->camera.view(r.aspect()), lighting);
      r.render(img8, glm::vec3(0.0f), true);
      benchmark::DoNotOptimize(img8.bytes.data());
    } else if (fresh) {
      Rasterizer f(ro);
      f.draw(c->mesh, c->camera.view(f.aspect()), lighting);
      img = f.render();
    } else {
      r.clear();
      r.draw(c->mesh, c->camera.view(r.aspect()), lighting);
      r.render(img);
    }
    benchmark::DoNotOptimize(img.pixels.data());
  }
  // Counted after the timed loop, as llvmpipe's `drawn` is.
  if (srgb8) {
    std::size_t drawn = 0;
    for (std::size_t i = 3; i < img8.bytes.size(); i += 4) drawn += img8.bytes[i] != 0;
    state.counters["drawn"] = static_cast<double>(drawn) / (kWidth * kHeight);
  } else {
    state.counters["drawn"] = img.coverage() / (kWidth * kHeight);
  }
  state.counters["triangles"] = static_cast<double>(c->mesh.triangles.size());
}

// One OSMesa context per case, created on first use.
struct GlState {
  OSMesaContext ctx = nullptr;
  std::vector<unsigned char> buffer;
  std::vector<float> positions, normals, colors;
  std::vector<unsigned> indices;
  std::string renderer;
  GLuint program = 0;  // the per-fragment Blinn-Phong shader, or 0 (fixed function)
};

// cw4d's Blinn-Phong (raster.cpp, shade) per fragment, in world coordinates: the mesh positions
// are world positions and the modelview matrix is the camera's view matrix.
constexpr const char* kVertexShader = R"(#version 120
varying vec3 p;
varying vec3 n;
varying vec4 col;
void main() {
  p = gl_Vertex.xyz;
  n = gl_Normal;
  col = gl_Color;
  gl_Position = gl_ModelViewProjectionMatrix * gl_Vertex;
}
)";

// Written for a SIMD shader compiler: the light loop has a constant bound (LIGHTS, defined
// before this text) and no branches, every term selected instead; a light behind the surface
// or at the fragment adds nothing, as in cw4d. A directional light has w = 0 and attenuation 0,
// so L is its vector and the intensity 1 exactly.
constexpr const char* kFragmentShader = R"(
uniform vec3 ambient;
uniform vec3 eye;
uniform vec3 forward;
uniform float specular;
uniform float shininess;
uniform float cutoff;
uniform vec4 light_vector[LIGHTS];  // w = 1: a point light at xyz; w = 0: towards the light
uniform vec3 light_color[LIGHTS];
uniform float light_attenuation[LIGHTS];
varying vec3 p;
varying vec3 n;
varying vec4 col;
void main() {
  vec3 base = col.rgb;
  float nn = dot(n, n);
  vec3 N = n / sqrt(nn);
  vec3 to = eye - p;
  float d = length(to);
  vec3 V = d > 0.0 ? to / d : -forward;
  N = dot(N, V) < 0.0 ? -N : N;
  vec3 c = ambient * base;
  for (int i = 0; i < LIGHTS; ++i) {
    vec3 L = light_vector[i].xyz - light_vector[i].w * p;
    float intensity = 1.0 / (1.0 + light_attenuation[i] * dot(L, L));
    float len = length(L);
    L = L / len;
    float diffuse = dot(N, L);
    vec3 H = normalize(L + V);
    float nh = dot(N, H);
    float s = nh > cutoff ? specular * pow(max(nh, 0.0), shininess) : 0.0;
    c += len > 0.0 && diffuse > 0.0 ? intensity * light_color[i] * (base * diffuse + vec3(s))
                                    : vec3(0.0);
  }
  c = nn > 0.0 ? c : base;
  float a = clamp(col.a, 0.0, 1.0);
  gl_FragColor = vec4(c * a, a);
}
)";

GLuint compile(GLenum kind, const std::string& text) {
  const GLuint sh = glCreateShader(kind);
  const char* source = text.c_str();
  glShaderSource(sh, 1, &source, nullptr);
  glCompileShader(sh);
  GLint ok = 0;
  glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(sh, sizeof log, nullptr, log);
    std::fprintf(stderr, "bench_render: shader compilation failed: %s\n", log);
    glDeleteShader(sh);
    return 0;
  }
  return sh;
}

// The shader program with the uniforms of `lit` and the camera; 0 when GLSL is unavailable.
GLuint make_program(const cw4d::render::Lighting& lit, const cw4d::render::Camera& camera) {
  const int count = static_cast<int>(std::min<std::size_t>(lit.lights.size(), 8));
  if (count == 0) return 0;
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, "#version 120\n#define LIGHTS " +
                                                    std::to_string(count) + "\n" + kFragmentShader);
  if (!vs || !fs) return 0;
  const GLuint prog = glCreateProgram();
  glAttachShader(prog, vs);
  glAttachShader(prog, fs);
  glLinkProgram(prog);
  GLint ok = 0;
  glGetProgramiv(prog, GL_LINK_STATUS, &ok);
  if (!ok) return 0;
  glUseProgram(prog);
  auto loc = [&](const char* name) { return glGetUniformLocation(prog, name); };
  glUniform3f(loc("ambient"), lit.ambient.r, lit.ambient.g, lit.ambient.b);
  glUniform3f(loc("eye"), camera.eye.x, camera.eye.y, camera.eye.z);
  const glm::vec3 f = camera.forward();
  glUniform3f(loc("forward"), f.x, f.y, f.z);
  glUniform1f(loc("specular"), lit.specular);
  glUniform1f(loc("shininess"), lit.shininess);
  // As make_state in raster.cpp: below this N.H the highlight is under 1e-3.
  glUniform1f(loc("cutoff"),
              lit.shininess > 0.0f ? std::exp(std::log(1e-3f) / lit.shininess) : 0.0f);
  std::vector<float> vec, color, att;
  for (int i = 0; i < count; ++i) {
    const auto& l = lit.lights[static_cast<std::size_t>(i)];
    const bool point = l.kind == cw4d::render::Light::Kind::Point;
    vec.insert(vec.end(), {l.vector.x, l.vector.y, l.vector.z, point ? 1.0f : 0.0f});
    color.insert(color.end(), {l.color.r, l.color.g, l.color.b});
    att.push_back(point ? l.attenuation : 0.0f);
  }
  glUniform4fv(loc("light_vector"), count, vec.data());
  glUniform3fv(loc("light_color"), count, color.data());
  glUniform1fv(loc("light_attenuation"), count, att.data());
  return prog;
}

// How far the GL picture (8-bit linear RGBA, bottom row first) is from cw4d's float frame of
// the same case: mean |difference| of the RGB bytes over the pixels both drew, and the
// fraction of those pixels with a channel more than 2 steps off.
void deviation(const std::vector<unsigned char>& gl, const Case& c, benchmark::State& state) {
  cw4d::render::RasterOptions ro;
  ro.width = kWidth;
  ro.height = kHeight;
  ro.samples_per_axis = 1;
  cw4d::render::Rasterizer r(ro);
  r.draw(c.mesh, c.camera.view(r.aspect()), cw4d::render::Lighting::studio(c.camera));
  const cw4d::render::Image img = r.render();
  double sum = 0.0;
  std::size_t both = 0, off = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const unsigned char* g =
          &gl[(static_cast<std::size_t>(kHeight - 1 - y) * kWidth + static_cast<std::size_t>(x)) *
              4];
      const glm::vec4& p = img.at(x, y);
      if (g[3] == 0 || !(p.a > 0.0f)) continue;
      ++both;
      int worst = 0;
      for (int k = 0; k < 3; ++k) {
        const int ours = static_cast<int>(std::lround(std::clamp(p[k], 0.0f, 1.0f) * 255.0f));
        const int d = std::abs(ours - static_cast<int>(g[k]));
        sum += d;
        worst = std::max(worst, d);
      }
      off += worst > 2;
    }
  state.counters["dev"] = both ? sum / (3.0 * static_cast<double>(both)) : 0.0;
  state.counters["off"] = both ? static_cast<double>(off) / static_cast<double>(both) : 0.0;
}

bool gl_setup(GlState& g, const Case& c, bool glsl) {
  g.ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
  if (!g.ctx) return false;
  g.buffer.assign(static_cast<std::size_t>(kWidth) * kHeight * 4, 0);
  if (!OSMesaMakeCurrent(g.ctx, g.buffer.data(), GL_UNSIGNED_BYTE, kWidth, kHeight)) return false;
  const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  g.renderer = r ? r : "?";
  for (const auto& v : c.mesh.vertices) {
    g.positions.insert(g.positions.end(), {v.position.x, v.position.y, v.position.z});
    g.normals.insert(g.normals.end(), {v.normal.x, v.normal.y, v.normal.z});
    g.colors.insert(g.colors.end(), {v.color.r, v.color.g, v.color.b, v.color.a});
  }
  for (const auto& t : c.mesh.triangles) g.indices.insert(g.indices.end(), {t[0], t[1], t[2]});
  const float aspect = static_cast<float>(kWidth) / kHeight;
  glViewport(0, 0, kWidth, kHeight);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glMatrixMode(GL_PROJECTION);
  glLoadMatrixf(glm::value_ptr(c.camera.projection_matrix(aspect)));
  glMatrixMode(GL_MODELVIEW);
  glLoadMatrixf(glm::value_ptr(c.camera.view_matrix()));
  // The same rig as Lighting::studio, given in world coordinates (modelview = view here).
  const cw4d::render::Lighting lit = cw4d::render::Lighting::studio(c.camera);
  glEnable(GL_LIGHTING);
  glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_TRUE);
  const float ambient[4] = {lit.ambient.r, lit.ambient.g, lit.ambient.b, 1.0f};
  glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
  for (std::size_t i = 0; i < lit.lights.size() && i < 8; ++i) {
    const auto& l = lit.lights[i];
    const GLenum id = GL_LIGHT0 + static_cast<GLenum>(i);
    const bool point = l.kind == cw4d::render::Light::Kind::Point;
    const float pos[4] = {l.vector.x, l.vector.y, l.vector.z, point ? 1.0f : 0.0f};
    const float col[4] = {l.color.r, l.color.g, l.color.b, 1.0f};
    const float spec[4] = {lit.specular, lit.specular, lit.specular, 1.0f};
    glEnable(id);
    glLightfv(id, GL_POSITION, pos);
    glLightfv(id, GL_DIFFUSE, col);
    glLightfv(id, GL_SPECULAR, spec);
    if (point) glLightf(id, GL_QUADRATIC_ATTENUATION, l.attenuation);
  }
  glEnable(GL_COLOR_MATERIAL);
  glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
  const float white[4] = {1, 1, 1, 1};
  glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, white);
  glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, std::min(lit.shininess, 128.0f));
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_NORMAL_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);
  glVertexPointer(3, GL_FLOAT, 0, g.positions.data());
  glNormalPointer(GL_FLOAT, 0, g.normals.data());
  glColorPointer(4, GL_FLOAT, 0, g.colors.data());
  glClearColor(0, 0, 0, 0);
  if (glsl) {
    g.program = make_program(lit, c.camera);
    if (!g.program) return false;
  }
  return true;
}

// glsl: cw4d's per-pixel Blinn-Phong as a fragment shader instead of fixed-function lighting.
void bm_llvmpipe(benchmark::State& state, const Case* c, bool glsl) {
  GlState g;
  if (!gl_setup(g, *c, glsl)) {
    state.SkipWithError(glsl ? "OSMesa context or GLSL program creation failed"
                             : "OSMesa context creation failed");
    return;
  }
  for (auto _ : state) {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(g.indices.size()), GL_UNSIGNED_INT,
                   g.indices.data());
    glFinish();
    benchmark::DoNotOptimize(g.buffer.data());
  }
  // Fraction of pixels drawn (alpha != 0), to compare with cw4d's coverage counter.
  std::size_t drawn = 0;
  for (std::size_t i = 3; i < g.buffer.size(); i += 4) drawn += g.buffer[i] != 0;
  state.counters["drawn"] = static_cast<double>(drawn) / (kWidth * kHeight);
  state.SetLabel(g.renderer);
  state.counters["triangles"] = static_cast<double>(c->mesh.triangles.size());
  deviation(g.buffer, *c, state);
  if (g.program) glDeleteProgram(g.program);
  OSMesaDestroyContext(g.ctx);
}

void register_cases() {
  for (const Case& c : cases()) {
    const Case* p = &c;
    const struct {
      const char* variant;
      int samples, threads;
      bool fresh, srgb8;
    } variants[] = {{"samples:1", 1, 0, false, false},
                    {"samples:1/threads:1", 1, 1, false, false},
                    {"samples:1/fresh", 1, 0, true, false},
                    {"samples:1/srgb8", 1, 0, false, true},
                    {"samples:1/srgb8/threads:1", 1, 1, false, true},
                    {"samples:2x2", 2, 0, false, false}};
    for (const auto& v : variants)
      benchmark::RegisterBenchmark(("cw4d/" + c.name + "/" + v.variant).c_str(), bm_cw4d, p,
                                   v.samples, v.threads, v.fresh, v.srgb8)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MinTime(1.0);
    for (const bool glsl : {false, true})
      benchmark::RegisterBenchmark(((glsl ? "llvmpipe-glsl/" : "llvmpipe/") + c.name).c_str(),
                                   bm_llvmpipe, p, glsl)
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MinTime(1.0);
  }
}

// The console reporter, plus wall-time ratios cw4d / llvmpipe of this run.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  explicit RatioReporter(bool color) : ConsoleReporter(color ? OO_ColorTabular : OO_Tabular) {}
  // With --benchmark_repetitions the ratios are of the medians, else of the single runs.
  void ReportRuns(const std::vector<Run>& reports) override {
    ConsoleReporter::ReportRuns(reports);
    for (const Run& run : reports) {
      if (run.error_occurred) continue;
      if (run.run_type == Run::RT_Iteration && !median_.count(run.run_name.str()))
        times_[run.run_name.str()] = run.GetAdjustedRealTime();
      if (run.run_type == Run::RT_Aggregate && run.aggregate_name == "median") {
        times_[run.run_name.str()] = run.GetAdjustedRealTime();
        median_.insert(run.run_name.str());
      }
    }
  }
  void Finalize() override {
    ConsoleReporter::Finalize();
    for (const char* ref : {"llvmpipe", "llvmpipe-glsl"}) {
      const std::string_view what = std::string_view(ref) == "llvmpipe"
                                        ? "fixed-function, per-vertex lighting"
                                        : "GLSL, cw4d's per-pixel Blinn-Phong";
      bool header = false;
      for (const Case& c : cases()) {
        const auto gl = times_.find(std::string(ref) + "/" + c.name + "/min_time:1.000/real_time");
        if (gl == times_.end()) continue;
        for (const char* variant :
             {"samples:1", "samples:1/threads:1", "samples:1/fresh", "samples:1/srgb8",
              "samples:1/srgb8/threads:1", "samples:2x2"}) {
          const auto ours =
              times_.find("cw4d/" + c.name + "/" + variant + "/min_time:1.000/real_time");
          if (ours == times_.end()) continue;
          if (!header)
            std::printf("\nWall time per frame, cw4d / %s (%.*s; same run%s):\n", ref,
                        static_cast<int>(what.size()), what.data(),
                        median_.empty() ? "" : ", medians");
          header = true;
          std::printf("  %-18s %-26s %6.2f\n", c.name.c_str(), variant, ours->second / gl->second);
        }
      }
    }
  }

 private:
  std::map<std::string, double> times_;
  std::set<std::string> median_;
};

}  // namespace

int main(int argc, char** argv) {
  const cw4d::bench::BenchOptions options = cw4d::bench::scan_options(argc, argv);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  register_cases();
  if (options.console) {
    RatioReporter reporter(options.color);
    benchmark::RunSpecifiedBenchmarks(&reporter);
  } else {
    benchmark::RunSpecifiedBenchmarks();
  }
  benchmark::Shutdown();
  return 0;
}
