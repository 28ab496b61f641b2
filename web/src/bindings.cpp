// The JavaScript interface of the WebAssembly core (embind): models from a spec, 4OFF text or
// the bytes of a G4MF file, the catalogue, a 4D placement, slices and sweeps as typed arrays, and
// the tetrahedra of the convex cells for the GPU path. Everything goes through the public API of
// complex/ and section/; errors come back as {error: "one line"} objects, never as aborts.
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/error.hpp"
#include "cw4d/complex/g4mf.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/complex/wythoff.hpp"
#include "cw4d/section/hyperplane.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"
#include "cw4d/section/triangulate.hpp"
#include "cw4d/section/uvw.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"

namespace cw4d::web {

using emscripten::val;

namespace {

// Typed-array copies of C++ vectors (the views into the wasm heap would die with the vectors).
template <class T>
val copy_array(const std::vector<T>& v) {
  return val(emscripten::typed_memory_view(v.size(), v.data())).call<val>("slice");
}

val error_object(const std::string& message) {
  val out = val::object();
  std::string line = message;
  std::replace(line.begin(), line.end(), '\n', ' ');
  out.set("error", line);
  return out;
}

val fvector_array(const Complex& c) {
  val out = val::array();
  for (std::size_t n : c.fvector()) out.call<void>("push", static_cast<double>(n));
  return out;
}

// A colour per cell when the model has none: hues spaced by the golden angle, so neighbouring
// ids differ (sRGB components in [0, 1]).
std::array<float, 3> palette(std::uint32_t cell) {
  const double h = std::fmod(static_cast<double>(cell) * 0.6180339887498949, 1.0) * 6.0;
  const double s = 0.55, v = 0.92;
  const int i = static_cast<int>(h);
  const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r = v, g = t, b = p;
  switch (i % 6) {
    case 0:
      r = v, g = t, b = p;
      break;
    case 1:
      r = q, g = v, b = p;
      break;
    case 2:
      r = p, g = v, b = t;
      break;
    case 3:
      r = p, g = q, b = v;
      break;
    case 4:
      r = t, g = p, b = v;
      break;
    default:
      r = v, g = p, b = q;
      break;
  }
  return {static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)};
}

// The families that need CGAL (the tetrahedralize/ library), which the WebAssembly build does
// not link: listed so that the catalogue shows them, marked as unavailable. The browser test
// checks this list against the native `cw4d list`.
// The families of `cw4d list` that are not in core_catalogue(), i.e. not in this build.
struct UnavailableFamily {
  const char* spec;
  const char* description;
  const char* reason;
};
constexpr const char* kNoOpenMesh =
    "reads OBJ/OFF/PLY/STL through OpenMesh, not in the WebAssembly build";
constexpr const char* kNoCgal = "needs CGAL (convex hulls), not in the WebAssembly build";
constexpr UnavailableFamily kUnavailable[] = {
    {"extrude:FILE", "4D prism over a closed polyhedron read from a mesh file", kNoOpenMesh},
    {"spin:FILE,STEPS", "4D solid of revolution of a closed polyhedron", kNoOpenMesh},
    {"hull:FILE", "convex hull of the points in FILE", kNoCgal},
    {"snub cube", "snub cube s4s3s", kNoCgal},
    {"snub dodecahedron", "snub dodecahedron s5s3s", kNoCgal},
    {"snub 24-cell", "snub 24-cell s3s4o3o", kNoCgal},
    {"grand antiprism", "grand antiprism", kNoCgal},
    {"glome:R,N", "convex polytope inscribed in the 3-sphere", kNoCgal},
};

// The bytes of a Uint8Array or an ArrayBuffer, copied into the wasm heap as they are; nullopt
// for any other value.
std::optional<std::string> to_bytes(const val& data) {
  const val u8 = val::global("Uint8Array");
  const bool view = data.instanceof (u8);
  if (!view && !data.instanceof (val::global("ArrayBuffer"))) return std::nullopt;
  const val bytes = view ? data : u8.new_(data);
  std::string out(bytes["length"].as<std::size_t>(), '\0');
  // No allocation between the view's making and its use: the heap cannot move under it.
  val(emscripten::typed_memory_view(out.size(), reinterpret_cast<std::uint8_t*>(out.data())))
      .call<void>("set", bytes);
  return out;
}

std::vector<double> to_doubles(const val& array) {
  return emscripten::vecFromJSArray<double>(array);
}

// The equal-probability planes of `cw4d bench` (apps/cw4d/cmd_bench.cpp): std::mt19937 seeded
// 20240401, normals from a standard normal distribution, offsets uniform in (-0.9, 0.9) times
// the radius. std::mt19937 is fully specified by the standard, the distributions are not, so
// both are written out as GNU libstdc++ implements them (generate_canonical with two 32-bit
// draws; the Marsaglia polar method, its second value kept for the next call).
class BenchPlanes {
 public:
  explicit BenchPlanes(std::uint32_t seed) : rng_(seed) {}
  double canonical() {
    const double lo = static_cast<double>(rng_() - std::mt19937::min());
    const double hi = static_cast<double>(rng_() - std::mt19937::min());
    const double r = 4294967296.0;
    double x = (lo + hi * r) / (r * r);
    if (x >= 1.0) x = std::nextafter(1.0, 0.0);
    return x;
  }
  double normal() {
    if (saved_) {
      saved_ = false;
      return saved_value_;
    }
    double x, y, r2;
    do {
      x = 2.0 * canonical() - 1.0;
      y = 2.0 * canonical() - 1.0;
      r2 = x * x + y * y;
    } while (r2 > 1.0 || r2 == 0.0);
    const double mult = std::sqrt(-2.0 * std::log(r2) / r2);
    saved_value_ = x * mult;
    saved_ = true;
    return y * mult;
  }
  double uniform(double a, double b) { return (b - a) * canonical() + a; }

 private:
  std::mt19937 rng_;
  bool saved_ = false;
  double saved_value_ = 0.0;
};

}  // namespace

/// A loaded model with its placement and the compiled slicer state.
class WebModel {
 public:
  WebModel() = default;

  /// Loads a catalogue spec; returns "" or the error line.
  std::string load_spec(const std::string& spec) {
    try {
      return adopt(load_model(spec, core_catalogue()), spec);
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  /// Loads nOFF text (a dropped .4off file); `name` names it in messages.
  std::string load_off(const std::string& text, const std::string& name) {
    try {
      std::istringstream in(text);
      return adopt(read_off(in, name), name);
    } catch (const std::exception& e) {
      return e.what();
    }
  }

  /// Loads the bytes of a G4MF file (a dropped .g4tf or .g4b, as a Uint8Array or ArrayBuffer:
  /// .g4b is binary); `name` names it in messages. A buffer in an external file is refused
  /// (the page has the one file only).
  std::string load_g4mf(const val& data, const std::string& name) {
    try {
      const std::optional<std::string> bytes = to_bytes(data);
      if (!bytes)
        return name + ": the G4MF file's bytes must come as a Uint8Array or an ArrayBuffer";
      G4mfReadOptions options;
      options.allow_external = false;
      return adopt(read_g4mf(*bytes, name, options), name);
    } catch (const std::exception& e) {
      return e.what();
    }
  }

  val info() const {
    val out = val::object();
    if (!model_) return error_object("no model loaded");
    out.set("name", name_);
    out.set("dim", model_->ambient_dim());
    out.set("fvector", fvector_array(*model_));
    out.set("radius", compiled_->radius());
    out.set("fast", compiled_->fast());
    return out;
  }

  /// rotations: [[plane, degrees], ...] applied in order (plane "xw" etc.); translation: n
  /// numbers or []. x_world = R_k ... R_1 x_model + t, as the CLI's --rotate/--translate.
  std::string set_placement(const val& rotations, const val& translation) {
    try {
      if (!model_) return "no model loaded";
      const int n = model_->ambient_dim();
      AffineTransform m = AffineTransform::identity(n);
      const int count = rotations["length"].as<int>();
      for (int i = 0; i < count; ++i) {
        const val r = rotations[i];
        const auto [a, b] = parse_rotation_plane(r[0].as<std::string>());
        if (a >= n || b >= n)
          return "rotation plane " + r[0].as<std::string>() + " needs a 4D model";
        const double deg = r[1].as<double>();
        if (!std::isfinite(deg)) return "rotation angle is not finite";
        m = AffineTransform::rotation(n, a, b, deg * std::numbers::pi / 180.0) * m;
      }
      const std::vector<double> t = to_doubles(translation);
      if (!t.empty()) {
        if (static_cast<int>(t.size()) != n)
          return "translation needs " + std::to_string(n) + " components";
        m = AffineTransform::translation(Eigen::Map<const Eigen::VectorXd>(t.data(), n)) * m;
      }
      placement_ = m;
      inverse_ = m.inverse();
      return "";
    } catch (const std::exception& e) {
      return e.what();
    }
  }

  /// The placement as a matrix: `linear` holds n*n numbers row by row (x_world = L x_model +
  /// t), `translation` n numbers or []. The viewer composes its 4D rotations itself (rotations
  /// relative to the screen) and hands the product here. Returns "" or the error line.
  std::string set_matrix(const val& linear, const val& translation) {
    try {
      if (!model_) return "no model loaded";
      const int n = model_->ambient_dim();
      const std::vector<double> l = to_doubles(linear);
      if (static_cast<int>(l.size()) != n * n)
        return "the placement needs " + std::to_string(n * n) + " numbers, got " +
               std::to_string(l.size());
      Eigen::MatrixXd m(n, n);
      for (int r = 0; r < n; ++r)
        for (int c = 0; c < n; ++c) {
          const double x = l[static_cast<std::size_t>(r * n + c)];
          if (!std::isfinite(x)) return "the placement has a number that is not finite";
          m(r, c) = x;
        }
      if (!(std::abs(m.determinant()) > 1e-9)) return "the placement is singular";
      Eigen::VectorXd t = Eigen::VectorXd::Zero(n);
      const std::vector<double> tv = to_doubles(translation);
      if (!tv.empty()) {
        if (static_cast<int>(tv.size()) != n)
          return "translation needs " + std::to_string(n) + " components";
        for (int r = 0; r < n; ++r) {
          if (!std::isfinite(tv[static_cast<std::size_t>(r)]))
            return "the translation has a number that is not finite";
          t[r] = tv[static_cast<std::size_t>(r)];
        }
      }
      placement_ = AffineTransform(m, t);
      inverse_ = placement_.inverse();
      return "";
    } catch (const std::exception& e) {
      return e.what();
    }
  }

  /// The model's wireframe in model space, for the whole-polytope view drawn around the
  /// section: vertex positions padded to 4 numbers each (a 3D model gets w = 0) and the edges
  /// as pairs of vertex ids.
  val wireframe() const {
    try {
      if (!model_) return error_object("no model loaded");
      const Complex& m = *model_;
      const int n = m.ambient_dim();
      std::vector<float> pos(static_cast<std::size_t>(m.count(0)) * 4, 0.0f);
      for (std::uint32_t v = 0; v < m.count(0); ++v) {
        const auto p = m.position(v);
        for (int j = 0; j < n && j < 4; ++j)
          pos[4 * v + static_cast<std::size_t>(j)] = static_cast<float>(p[j]);
      }
      std::vector<std::uint32_t> edges;
      edges.reserve(static_cast<std::size_t>(m.count(1)) * 2);
      for (std::uint32_t e = 0; e < m.count(1); ++e) {
        const auto ids = m.edge(e);
        edges.push_back(ids[0]);
        edges.push_back(ids[1]);
      }
      val out = val::object();
      out.set("positions", copy_array(pos));
      out.set("edges", copy_array(edges));
      return out;
    } catch (const std::exception& e) {
      return error_object(e.what());
    }
  }

  /// The placement for the GPU: linear part column-major (n*n) then the translation (n).
  val placement() const {
    std::vector<float> out;
    for (int c = 0; c < placement_.dim(); ++c)
      for (int r = 0; r < placement_.dim(); ++r)
        out.push_back(static_cast<float>(placement_.linear()(r, c)));
    for (int r = 0; r < placement_.dim(); ++r)
      out.push_back(static_cast<float>(placement_.translation()[r]));
    return copy_array(out);
  }

  /// The section by the world-space plane normal . x = offset (normal normalised).
  val slice(const val& normal_js, double offset) {
    try {
      if (!model_) return error_object("no model loaded");
      const Hyperplane plane = make_plane(normal_js, offset);
      const auto t0 = std::chrono::steady_clock::now();
      slicer_.slice(*compiled_, plane, placement_, buffers_);
      const auto t1 = std::chrono::steady_clock::now();
      const Section sec = to_section(buffers_);
      val out = describe(sec);
      out.set("sliceMs", std::chrono::duration<double, std::milli>(t1 - t0).count());
      out.set("general", buffers_.general);
      if (sec.empty()) return out;
      add_mesh(sec, out);
      return out;
    } catch (const std::exception& e) {
      return error_object(e.what());
    }
  }

  /// Counts and volume of each of the planes normal . x = offsets[i], in one sweep.
  val sweep(const val& normal_js, const val& offsets_js) {
    try {
      if (!model_) return error_object("no model loaded");
      const std::vector<double> nv = to_doubles(normal_js);
      const std::vector<double> offsets = to_doubles(offsets_js);
      check_dim(nv.size());
      std::vector<SliceBuffers> layers;
      slicer_.sweep(*compiled_, Eigen::Map<const Eigen::VectorXd>(nv.data(), nv.size()), offsets,
                    placement_, layers, 1);
      val out = val::array();
      for (const SliceBuffers& b : layers) out.call<void>("push", describe(to_section(b)));
      return out;
    } catch (const std::exception& e) {
      return error_object(e.what());
    }
  }

  /// Microseconds per Slicer::slice over the 256 planes of `cw4d bench` (unplaced model, one
  /// thread, reused buffers, median of five rounds), to set beside the native figure.
  val bench_hot_path(double seconds) {
    try {
      if (!model_) return error_object("no model loaded");
      if (model_->ambient_dim() != 4) return error_object("bench needs a 4D model");
      const SliceModel compiled(*model_, SliceModelOptions::unclustered());
      BenchPlanes gen(20240401u);
      std::vector<Hyperplane> planes;
      for (int i = 0; i < 256; ++i) {
        Eigen::VectorXd n(4);
        for (int j = 0; j < 4; ++j) n[j] = gen.normal();
        planes.push_back(Hyperplane::from(n, gen.uniform(-0.9, 0.9) * compiled.radius()));
      }
      Slicer slicer;
      SliceBuffers out;
      double triangles = 0;
      for (const auto& p : planes) {
        slicer.slice(compiled, p, out);
        triangles += static_cast<double>(out.fan_triangles());
      }
      std::size_t next = 0;
      std::vector<double> rounds;
      for (int r = 0; r < 5; ++r) {
        slicer.slice(compiled, planes[next++ % planes.size()], out);  // warm
        std::size_t calls = 0;
        const auto t0 = std::chrono::steady_clock::now();
        double elapsed = 0;
        do {
          slicer.slice(compiled, planes[next++ % planes.size()], out);
          ++calls;
          elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        } while (elapsed < seconds / 5);
        rounds.push_back(elapsed / static_cast<double>(calls));
      }
      std::sort(rounds.begin(), rounds.end());
      val res = val::object();
      res.set("us", rounds[2] * 1e6);
      res.set("triangles", triangles / static_cast<double>(planes.size()));
      return res;
    } catch (const std::exception& e) {
      return error_object(e.what());
    }
  }

  /// Tetrahedra of the convex cells (tetrahedralize_cells of cw4d_tetra: the mesh `cw4d
  /// tetrahedralize` writes, without TetGen), in model space, for the GPU path: per tetrahedron
  /// four corners (4 x 4 floats), their UVW (4 x 3, the cell's texture map of section/uvw.hpp),
  /// the cell's outward unit normal (4), the cell id and its colour. Non-convex cells are
  /// counted in skippedCells.
  val tets() const {
    try {
      if (!model_) return error_object("no model loaded");
      if (model_->ambient_dim() != 4 || model_->top_rank() < 3)
        return error_object("the GPU path needs a 4D model with cells");
      const Complex& m = *model_;
      TetStats stats;
      const TetMesh mesh = tetrahedralize_cells(m, TetOptions{}, NonConvexCellMesher{}, &stats);
      const std::size_t T = mesh.size();
      std::vector<float> corners(16 * T), uvw(12 * T), cell_normal(4 * T), cell_id(T),
          colour(3 * T);
      const auto& colours = m.colors(3);
      for (std::size_t t = 0; t < T; ++t) {
        const std::uint32_t c = mesh.tet_cell[t];
        for (std::size_t k = 0; k < 4; ++k) {
          const auto v = static_cast<Eigen::Index>(mesh.tets[t][k]);
          for (Eigen::Index j = 0; j < 4; ++j)
            corners[16 * t + 4 * k + static_cast<std::size_t>(j)] =
                static_cast<float>(mesh.positions(j, v));
          for (Eigen::Index j = 0; j < 3; ++j)
            uvw[12 * t + 3 * k + static_cast<std::size_t>(j)] =
                static_cast<float>(mesh.corner_uvw(j, static_cast<Eigen::Index>(4 * t + k)));
        }
        for (Eigen::Index j = 0; j < 4; ++j)
          cell_normal[4 * t + static_cast<std::size_t>(j)] =
              static_cast<float>(mesh.cell_normals(j, c));
        cell_id[t] = static_cast<float>(c);
        const std::array<float, 3> rgb =
            colours.empty() ? palette(c)
                            : std::array<float, 3>{colours[c].r, colours[c].g, colours[c].b};
        for (std::size_t j = 0; j < 3; ++j) colour[3 * t + j] = rgb[j];
      }
      val out = val::object();
      out.set("count", static_cast<double>(T));
      out.set("corners", copy_array(corners));
      out.set("uvw", copy_array(uvw));
      out.set("normals", copy_array(cell_normal));
      out.set("cells", copy_array(cell_id));
      out.set("colours", copy_array(colour));
      out.set("skippedCells", static_cast<double>(stats.skipped_cells));
      return out;
    } catch (const std::exception& e) {
      return error_object(e.what());
    }
  }

  /// The orthonormal basis (n x (n-1), column-major) of the plane with this normal, in which
  /// section coordinates are written (hyperplane_basis).
  val plane_basis(const val& normal_js) const {
    try {
      const Hyperplane plane = make_plane(normal_js, 0.0);
      const Eigen::MatrixXd b = hyperplane_basis(plane.normal);
      std::vector<float> out(b.data(), b.data() + b.size());
      return copy_array(out);
    } catch (const std::exception& e) {
      return error_object(e.what());
    }
  }

 private:
  std::string adopt(Complex model, const std::string& name) {
    const ValidationReport report = validate(model);
    if (!report.ok()) return name + ": not a valid complex: " + report.summary(1);
    if (model.ambient_dim() < 3 || model.ambient_dim() > 4)
      return name + " lives in R^" + std::to_string(model.ambient_dim()) +
             "; the viewer shows 3D sections of 4D models (and 2D ones of 3D models)";
    compiled_.reset();
    model_ = std::make_unique<Complex>(std::move(model));
    compiled_ = std::make_unique<SliceModel>(*model_);
    maps_ =
        model_->has_facet_normals() ? facet_texture_maps(*model_) : std::vector<FacetTextureMap>{};
    placement_ = AffineTransform::identity(model_->ambient_dim());
    inverse_ = placement_;
    buffers_ = SliceBuffers{};
    name_ = name;
    return "";
  }

  void check_dim(std::size_t n) const {
    if (static_cast<int>(n) != model_->ambient_dim())
      throw InputError("the normal needs " + std::to_string(model_->ambient_dim()) +
                       " components, got " + std::to_string(n));
  }

  Hyperplane make_plane(const val& normal_js, double offset) const {
    const std::vector<double> nv = to_doubles(normal_js);
    if (model_) check_dim(nv.size());
    return Hyperplane::from(Eigen::Map<const Eigen::VectorXd>(nv.data(), nv.size()), offset);
  }

  static val describe(const Section& sec) {
    val out = val::object();
    out.set("fvector", fvector_array(sec.complex));
    out.set("volume", sec.empty() ? 0.0 : signed_volume(sec.complex));
    out.set("selfIntersecting", sec.self_intersecting);
    return out;
  }

  // Triangles of the polygons (ear clipping with holes, as the exporters), one corner per
  // polygon and vertex so that normals, colours and UVW stay per polygon; the outline is every
  // section edge once.
  void add_mesh(const Section& sec, val& out) const {
    const Complex& c = sec.complex;
    const int n = c.ambient_dim();  // 3 for a 4D model (2 for a 3D one: padded with z = 0)
    const std::vector<Triangle> tris = triangulate_section(sec);
    const auto& model_colours = model_->colors(model_->ambient_dim() - 1);
    std::vector<float> pos, nor, col, uvw;
    std::vector<std::uint32_t> cell, index;
    std::unordered_map<std::uint32_t, std::uint32_t> corner;  // vertex -> corner, per face
    std::uint32_t face = no_index;
    const bool has_normals = c.has_facet_normals() && n == 3;
    for (const Triangle& t : tris) {
      if (t.face != face) corner.clear(), face = t.face;
      const std::uint32_t src = sec.source.size() > 2 && !sec.source[2].empty()
                                    ? sec.source[2][t.face]
                                    : (sec.source.size() > 1 ? sec.source[1][t.face] : 0);
      for (std::uint32_t v : t.v) {
        auto [it, fresh] = corner.try_emplace(v, static_cast<std::uint32_t>(cell.size()));
        if (fresh) {
          for (int j = 0; j < 3; ++j)
            pos.push_back(j < n ? static_cast<float>(c.position(v)[j]) : 0.0f);
          for (int j = 0; j < 3; ++j)
            nor.push_back(has_normals ? static_cast<float>(c.facet_normals()(j, t.face))
                                      : (j == 2 ? 1.0f : 0.0f));
          const std::array<float, 3> rgb =
              model_colours.empty()
                  ? palette(src)
                  : std::array<float, 3>{model_colours[src].r, model_colours[src].g,
                                         model_colours[src].b};
          col.insert(col.end(), rgb.begin(), rgb.end());
          if (!maps_.empty() && src < maps_.size()) {
            const Eigen::VectorXd x = inverse_.apply(sec.world_position(v));
            const Eigen::VectorXd w = maps_[src](x);
            for (int j = 0; j < 3; ++j) uvw.push_back(j < w.size() ? static_cast<float>(w[j]) : 0);
          } else {
            uvw.insert(uvw.end(), {0.0f, 0.0f, 0.0f});
          }
          cell.push_back(src);
        }
        index.push_back(it->second);
      }
    }
    std::vector<float> outline;
    for (std::uint32_t e = 0; e < c.count(1); ++e) {
      const auto ids = c.edge(e);
      for (auto v : {ids[0], ids[1]})
        for (int j = 0; j < 3; ++j)
          outline.push_back(j < n ? static_cast<float>(c.position(v)[j]) : 0.0f);
    }
    out.set("positions", copy_array(pos));
    out.set("normals", copy_array(nor));
    out.set("colours", copy_array(col));
    out.set("uvw", copy_array(uvw));
    out.set("cells", copy_array(cell));
    out.set("indices", copy_array(index));
    out.set("outline", copy_array(outline));
  }

  std::unique_ptr<Complex> model_;
  std::unique_ptr<SliceModel> compiled_;
  std::vector<FacetTextureMap> maps_;
  AffineTransform placement_{4}, inverse_{4};
  Slicer slicer_;
  SliceBuffers buffers_;
  std::string name_;
};

/// The catalogue: [{spec, description, available, reason}], the families of core_catalogue()
/// (what load_model accepts here) first, then those of `cw4d list` this build does not include.
val catalogue() {
  val out = val::array();
  for (const BuiltinInfo& b : builtin_list(core_catalogue())) {
    val e = val::object();
    e.set("spec", b.spec);
    e.set("description", b.description);
    e.set("available", true);
    out.call<void>("push", e);
  }
  for (const UnavailableFamily& b : kUnavailable) {
    val e = val::object();
    e.set("spec", std::string(b.spec));
    e.set("description", std::string(b.description));
    e.set("available", false);
    e.set("reason", std::string(b.reason));
    out.call<void>("push", e);
  }
  return out;
}

/// The viewer's library: [{group, name, spec, diagram}] — the regular polychora, the convex
/// uniform ones by name with their Coxeter diagrams, the regular star and named non-convex
/// uniform ones (star_polychoron_names), each spec one that load_model accepts.
val library() {
  val out = val::array();
  const auto add = [&](const std::string& group, const std::string& name, const std::string& spec,
                       const std::string& diagram) {
    val e = val::object();
    e.set("group", group);
    e.set("name", name);
    e.set("spec", spec);
    e.set("diagram", diagram);
    out.call<void>("push", e);
  };
  const char* bases[] = {"5-cell", "tesseract", "16-cell", "24-cell", "120-cell", "600-cell"};
  for (const char* b : bases) add("regular", b, b, uniform_polychoron_diagram(b).value_or(""));
  const char* operations[] = {"truncated",  "rectified",      "bitruncated",    "cantellated",
                              "runcinated", "cantitruncated", "runcitruncated", "omnitruncated"};
  for (const char* b : bases)
    for (const char* op : operations) {
      const std::string name = std::string(op) + " " + b;
      if (const auto d = uniform_polychoron_diagram(name)) add("convex uniform", name, name, *d);
    }
  // star_polychoron_names() lists the ten regular star polychora first.
  const auto& stars = star_polychoron_names();
  for (std::size_t i = 0; i < stars.size(); ++i)
    add(i < 10 ? "regular star" : "non-convex uniform", stars[i].name, stars[i].name,
        stars[i].diagram);
  return out;
}

/// The viewer's colours of cells 0 .. count-1 (r, g, b each), for buffers made elsewhere.
val cell_palette(double count) {
  std::vector<float> out;
  for (std::uint32_t c = 0; c < static_cast<std::uint32_t>(std::max(0.0, count)); ++c) {
    const auto rgb = palette(c);
    out.insert(out.end(), rgb.begin(), rgb.end());
  }
  return copy_array(out);
}

}  // namespace cw4d::web

EMSCRIPTEN_BINDINGS(cw4d) {
  using cw4d::web::WebModel;
  emscripten::class_<WebModel>("Model")
      .constructor<>()
      .function("loadSpec", &WebModel::load_spec)
      .function("loadOff", &WebModel::load_off)
      .function("loadG4mf", &WebModel::load_g4mf)
      .function("info", &WebModel::info)
      .function("setPlacement", &WebModel::set_placement)
      .function("setMatrix", &WebModel::set_matrix)
      .function("wireframe", &WebModel::wireframe)
      .function("placement", &WebModel::placement)
      .function("slice", &WebModel::slice)
      .function("sweep", &WebModel::sweep)
      .function("benchHotPath", &WebModel::bench_hot_path)
      .function("tets", &WebModel::tets)
      .function("planeBasis", &WebModel::plane_basis);
  emscripten::function("catalogue", &cw4d::web::catalogue);
  emscripten::function("library", &cw4d::web::library);
  emscripten::function("cellPalette", &cw4d::web::cell_palette);
}
