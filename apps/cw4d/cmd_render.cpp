// cw4d render: pictures (PNG) of sections, voxel clouds, 4D wireframes, stereographic views,
// stereo pairs and sweeps, drawn by the software rasterizer of render/.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <optional>
#include <tuple>

#include "cli.hpp"
#include "cw4d/complex/atomic_file.hpp"
#include "cw4d/complex/text.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/render/animation.hpp"
#include "cw4d/render/color.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/schlegel.hpp"
#include "cw4d/render/section_view.hpp"
#include "cw4d/render/stereographic.hpp"
#include "cw4d/render/voxel_cloud.hpp"
#include "cw4d/render/wireframe4d.hpp"
#include "cw4d/tetrahedralize/tet_mesh.hpp"
#include "cw4d/tetrahedralize/tet_slice.hpp"

namespace cw4d::cli {

namespace {

struct RenderSettings {
  Placement placement;
  std::string mode = "section";
  double offset = 0.0;
  std::string output;
  std::string size = "800x600";
  int samples = 3;
  int threads = 0;
  std::string projection = "perspective";
  std::string view_text;
  bool edges = false;
  bool cull = false;
  int layers = 0;  // 0: the mode's default
  float opacity = 0.97f;
  int columns = 0;
  std::string eye4_text = "0.3,0.2,0.1,-1";
  double fov4 = 60.0;
  bool no_occlusion = false;
  bool lines = false;
  double separation = 0.0;
  long long cell = -1;  // schlegel: the front cell, -1: default
  bool faces = false;   // schlegel: draw the faces too
  std::vector<std::string> textures;
  std::string light_mode = "3d";
  std::vector<std::string> lights4;
  std::string method = "cw";
  std::string stack = "auto";
  bool stereo = false;
  bool with_section = false;
  std::string eye4_at_text;
  std::string look4_text;
  std::string animate;
  int frames = 36;
  int frame_ms = 80;
};

// "X,Y,Z,W" (directional, towards the light) or "point:X,Y,Z,W[:REFERENCE]".
render::Light4 parse_light4(const std::string& text) {
  render::Light4 light;
  std::string rest = text;
  if (rest.rfind("point:", 0) == 0) {
    light.kind = render::Light4::Kind::Point;
    rest = rest.substr(6);
    const auto colon = rest.find(':');
    if (colon != std::string::npos) {
      const auto r = parse_vector(rest.substr(colon + 1), "--light4 reference");
      if (r.size() != 1 || !(r[0] > 0.0) || !std::isfinite(r[0]))
        throw InputError("--light4 " + quote_user_text(text) +
                         ": the reference distance must be > 0");
      light.reference = static_cast<float>(r[0]);
      rest = rest.substr(0, colon);
    }
  }
  const auto v = parse_vector(rest, "--light4");
  if (v.size() != 4)
    throw InputError("--light4 " + quote_user_text(text) + " needs 4 components X,Y,Z,W");
  light.vector = glm::vec4(static_cast<float>(v[0]), static_cast<float>(v[1]),
                           static_cast<float>(v[2]), static_cast<float>(v[3]));
  if (light.kind == render::Light4::Kind::Directional && light.vector == glm::vec4(0.0f))
    throw InputError("--light4 " + quote_user_text(text) +
                     ": a direction must not be the zero vector");
  return light;
}

glm::vec3 parse_vec3(const std::string& text, const std::string& option) {
  const auto v = parse_vector(text, option);
  if (v.size() != 3) throw InputError(option + " takes 3 components X,Y,Z");
  const glm::vec3 g(static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2]));
  if (g == glm::vec3(0.0f)) throw InputError(option + " must not be the zero vector");
  return g;
}

render::RasterOptions raster_options(const RenderSettings& s) {
  render::RasterOptions r;
  std::tie(r.width, r.height) = parse_image_size(s.size);
  r.samples_per_axis = s.samples;
  r.threads = s.threads;
  return r;
}

render::SectionViewOptions section_options(const RenderSettings& s) {
  render::SectionViewOptions o;
  o.raster = raster_options(s);
  o.projection = s.projection == "orthographic" ? render::Projection::Orthographic
                                                : render::Projection::Perspective;
  if (!s.view_text.empty()) o.view_from = parse_vec3(s.view_text, "--view");
  o.edges = s.edges;
  o.cull_back_faces = s.cull;
  for (const auto& t : s.textures) render::add_texture(o.textures, t);
  o.light_4d = s.light_mode == "4d" || !s.lights4.empty();
  for (const auto& l : s.lights4) o.lights4.push_back(parse_light4(l));
  // With several lights the intensities share one unit, like the studio's key and fill.
  for (auto& l : o.lights4) l.color /= static_cast<float>(o.lights4.size());
  return o;
}

// "dir/name.png" -> "dir/name_0007.png"
std::string frame_path(const std::string& output, int i) {
  const std::filesystem::path p(output);
  char num[16];
  std::snprintf(num, sizeof num, "_%04d", i);
  return (p.parent_path() / (p.stem().string() + num + p.extension().string())).string();
}

const Complex* single_model(const Input& input) {
  return input.is_scene ? nullptr : input.models().front();
}

// The axis pair of "rotate:xw" (axes x, y, z, w).
std::pair<int, int> rotation_plane(const std::string& spec) {
  const std::string plane = spec.size() > 7 ? spec.substr(7) : std::string();
  const std::string axes = "xyzw";
  if (plane.size() != 2 || axes.find(plane[0]) == std::string::npos ||
      axes.find(plane[1]) == std::string::npos || plane[0] == plane[1])
    throw InputError("--animate rotate:PLANE takes two different axes of x, y, z, w (xw), not '" +
                     spec + "'");
  return {static_cast<int>(axes.find(plane[0])), static_cast<int>(axes.find(plane[1]))};
}

// An animated WebP of the section: a sweep of the plane across the input, a full turn of every
// object in one plane about the origin, or the 3D camera orbiting the section's up axis.
std::string run_animation(const RenderSettings& s, const Input& input, Placement& p) {
  const bool sweep = s.animate == "sweep", orbit = s.animate == "orbit";
  std::pair<int, int> plane{0, 3};
  if (!sweep && !orbit) {
    if (s.animate.rfind("rotate:", 0) != 0)
      throw InputError("--animate takes sweep, rotate:PLANE or orbit, not " +
                       quote_user_text(s.animate));
    plane = rotation_plane(s.animate);
  }
  const Hyperplane plane0 = p.plane(0.0);
  const HyperplaneFrame frame0(plane0);
  auto o = section_options(s);
  std::vector<double> offsets(static_cast<std::size_t>(s.frames), s.offset);
  if (sweep) {
    const auto [lo, hi] = render::scene_extent(input.scene, plane0.normal);
    offsets = render::layer_offsets(lo, hi, s.frames);
    o.frame = render::scene_frame(input.scene, frame0);
  } else if (!orbit) {
    // Every turned position lies in the ball about the origin through the farthest vertex.
    double radius = 0.0;
    for (const auto& obj : input.scene.objects) {
      const Eigen::MatrixXd w = (obj.transform.linear() * obj.complex->positions()).colwise() +
                                obj.transform.translation();
      if (w.cols() > 0) radius = std::max(radius, w.colwise().norm().maxCoeff());
    }
    const Eigen::VectorXd c = frame0.to_plane(Eigen::VectorXd::Zero(4));
    o.frame.centre =
        glm::vec3(static_cast<float>(c(0)), static_cast<float>(c(1)), static_cast<float>(c(2)));
    o.frame.radius = static_cast<float>(std::max(radius, 1e-9));
  } else {
    o.frame = render::scene_frame(input.scene, HyperplaneFrame(p.plane(s.offset)));
  }
  const glm::vec3 view0 = o.view_from;
  // Each frame is encoded as soon as it is drawn: memory holds one frame, not all of them.
  render::AnimationOptions ao;
  ao.frame_ms = s.frame_ms;
  render::AnimationEncoder encoder(lower_extension(s.output) == ".gif"
                                       ? render::AnimationEncoder::Format::Gif
                                       : render::AnimationEncoder::Format::WebP,
                                   o.raster.width, o.raster.height, ao);
  ProgressBar progress("render", "frames", static_cast<std::size_t>(s.frames), true);
  int empty = 0;
  for (int i = 0; i < s.frames; ++i) {
    const double turn = 2.0 * std::numbers::pi * i / s.frames;
    Input in = input;
    if (!sweep && !orbit)
      for (auto& obj : in.scene.objects)
        obj.transform =
            AffineTransform::rotation(4, plane.first, plane.second, turn) * obj.transform;
    if (orbit) {
      const float c = static_cast<float>(std::cos(turn)), sn = static_cast<float>(std::sin(turn));
      o.view_from = glm::vec3(c * view0.x - sn * view0.y, sn * view0.x + c * view0.y, view0.z);
    }
    o.source = &in.scene;
    const Cut c = cut(in, p.plane(offsets[static_cast<std::size_t>(i)]));
    if (c.section.empty()) ++empty;
    encoder.add(
        render::to_srgb8(render::render_section(c.section, o, single_model(in)), glm::vec3(1.0f)));
    progress.step(i + 1);
  }
  if (empty == s.frames)
    throw EmptySection("the plane misses " + p.input_label() + " in every frame (it meets " +
                       offset_range(input, p.plane(s.offset)) + "); nothing written to '" +
                       s.output + "'");
  write_file_atomically(s.output, encoder.finish());
  return "animation (" + std::to_string(s.frames) + " frames, " + s.animate + ")";
}

// The pixels a render holds at once are bounded by kMaxHeldPixels: a contact sheet keeps every
// layer and the sheet, a stereo pair both views and the pair. An animation's frames are drawn
// one at a time, bounded in all by this.
constexpr double kMaxAnimationPixels = 8e8;

void check_pixel_budget(const RenderSettings& s) {
  const render::RasterOptions r = raster_options(s);
  const int layers = s.layers > 0 ? s.layers : (s.mode == "sheet" ? 16 : 24);
  double images = s.mode == "sheet" ? 2.0 * layers : (s.mode == "stereo" || s.stereo) ? 4.0 : 1.0;
  // An animation holds one frame and the encoder's canvases (8-bit ARGB) at a time.
  if (!s.animate.empty()) images = 2.0;
  // An animation's work: frames x pixels, bounded as the frames held once bounded it (about
  // a minute and a half on one core at the limit; a progress bar shows on a terminal).
  const double drawn = static_cast<double>(r.width) * r.height * s.frames;
  if (!s.animate.empty() && drawn > kMaxAnimationPixels)
    throw InputError("--animate with --size " + s.size + " and " + std::to_string(s.frames) +
                     " frames would draw " + std::to_string(static_cast<long long>(drawn)) +
                     " pixels; render animates at most " +
                     std::to_string(static_cast<long long>(kMaxAnimationPixels)) +
                     ": give a smaller --size or fewer --frames");
  check_held_pixels(s.size, r.width, r.height, images,
                    s.mode == "sheet"    ? " or fewer --layers"
                    : !s.animate.empty() ? " or fewer --frames"
                                         : "");
}

void run_render(RenderSettings& s) {
  Placement& p = s.placement;
  check_pixel_budget(s);
  const bool needs_plane =
      s.mode != "wireframe" && s.mode != "stereographic" && s.mode != "schlegel";
  const bool default_normal = p.normal_text.empty();
  if (default_normal) {
    if (needs_plane) throw InputError("render --mode " + s.mode + " needs --normal");
    p.normal_text = "0,0,0,1";
  }
  p.parse("render");
  if (!s.animate.empty()) {
    if (s.mode != "section")
      throw InputError("--animate draws --mode section (sweep, rotate:PLANE or orbit)");
    if (lower_extension(s.output) != ".webp" && lower_extension(s.output) != ".gif")
      throw InputError(
          "--animate writes an animated WebP or GIF: give -o NAME.webp or NAME.gif, "
          "not '" +
          s.output + "'");
  } else if (lower_extension(s.output) != ".png") {
    throw InputError("render writes PNG files: give -o NAME.png, not " + quote_user_text(s.output));
  }
  // A normal nobody gave is checked against the model only once the model is known to be 4D:
  // a 3D model is refused for its dimension, not for a --normal that was never typed.
  if (default_normal) p.normal.clear();
  const Input input = load_input(p);
  if (input.dim() != 4)
    throw InputError("render --mode " + s.mode + " draws 4D models; " + p.input_label() +
                     " lives in R^" + std::to_string(input.dim()));
  if (default_normal) p.normal = {0.0, 0.0, 0.0, 1.0};
  prepare_output_directory(s.output);
  const glm::vec3 background(1.0f);
  std::string what;

  const bool sections =
      s.mode == "section" || s.mode == "stereo" || s.mode == "sheet" || s.mode == "frames";
  if (!sections && (!s.textures.empty() || s.light_mode == "4d" || !s.lights4.empty()))
    throw InputError(
        "--texture, --light-mode 4d and --light4 draw sections (--mode section, "
        "stereo, sheet, frames), not --mode " +
        s.mode);
  if (s.stereo && s.mode != "cloud" && s.mode != "wireframe")
    throw InputError("--stereo is for --mode cloud and wireframe (sections: --mode stereo)");
  if (s.with_section && s.mode != "wireframe")
    throw InputError("--section draws the section inside a --mode wireframe picture");
  if ((!s.eye4_at_text.empty() || !s.look4_text.empty()) && s.mode != "wireframe")
    throw InputError("--eye4-at and --look4 place the camera of --mode wireframe");
  if (s.method == "tet" && s.mode != "section")
    throw InputError("--method tet draws --mode section only");
  if (!s.animate.empty()) {
    if (s.method == "tet") throw InputError("--animate cuts with --method cw");
    what = run_animation(s, input, p);
  } else if (s.method == "tet") {
    // The tetrahedral path: the model's tetrahedra cut one by one, each triangle carrying the
    // UVW and normals interpolated at its corners.
    if (input.is_scene) throw InputError("--method tet cuts a single model, not a --scene");
    if (s.edges) throw InputError("--edges draws the polygon outlines of --method cw only");
    const SceneObject& obj = input.scene.objects.front();
    const TetSection ts =
        slice_tets(tetrahedralize(*obj.complex), p.plane(s.offset), obj.transform);
    if (ts.empty())
      throw EmptySection("the plane misses " + p.input_label() + " (it meets " +
                         offset_range(input, p.plane(s.offset)) + "); nothing written to '" +
                         s.output + "'");
    auto o = section_options(s);
    const render::TriangleMesh mesh =
        render::soup_mesh(ts.positions, ts.normals, ts.uvw, ts.cell, obj, &o.textures);
    render::FrameSphere f = render::bounding_frame(mesh);
    const float aspect = static_cast<float>(o.raster.width) / static_cast<float>(o.raster.height);
    const render::Camera camera = render::Camera::framing(
        f.centre, std::max(f.radius, 1e-6f), o.view_from, aspect, o.projection, o.fov_y_degrees);
    render::write_png(s.output, render::render_mesh(mesh, {}, ts.frame, o, camera), background);
    what = "section (tetrahedral path, " + std::to_string(ts.triangle_count()) + " triangles)";
  } else if (s.mode == "section" || s.mode == "stereo") {
    const Cut c = cut(input, p.plane(s.offset));
    if (c.section.empty())
      throw EmptySection("the plane misses " + p.input_label() + " (it meets " +
                         offset_range(input, p.plane(s.offset)) + "); nothing written to '" +
                         s.output + "'");
    auto o = section_options(s);
    o.source = &input.scene;
    const render::Image img =
        s.mode == "section"
            ? render::render_section(c.section, o, single_model(input))
            : render::render_stereo_pair(c.section, o, static_cast<float>(s.separation),
                                         single_model(input));
    render::write_png(s.output, img, background);
    what = s.mode == "section" ? "section" : "stereo pair (left eye left)";
  } else if (s.mode == "sheet" || s.mode == "frames") {
    const int layers = s.layers > 0 ? s.layers : (s.mode == "sheet" ? 16 : 24);
    const Hyperplane plane0 = p.plane(0.0);
    const auto [lo, hi] = render::scene_extent(input.scene, plane0.normal);
    auto o = section_options(s);
    o.source = &input.scene;
    o.frame = render::scene_frame(input.scene, HyperplaneFrame(plane0));
    std::vector<render::Image> cells;
    const auto offsets = render::layer_offsets(lo, hi, layers);
    // Frames go into a hidden staging folder and move into place together once all are drawn:
    // a failed or interrupted run leaves no frame of its own and no half set over an old one.
    std::optional<StagedFiles> staged;
    std::vector<std::string> frame_names;
    if (s.mode == "frames") {
      prepare_output_directory(s.output);
      const std::filesystem::path out(s.output);
      staged.emplace(out.parent_path().string(), out.stem().string());
    }
    for (std::size_t i = 0; i < offsets.size(); ++i) {
      const Cut c = cut(input, p.plane(offsets[i]));
      render::Image img = render::render_section(c.section, o, single_model(input));
      if (staged) {
        frame_names.push_back(
            std::filesystem::path(frame_path(s.output, static_cast<int>(i))).filename().string());
        render::write_png(staged->staged(frame_names.back()), img, background);
      } else {
        cells.push_back(std::move(img));
      }
    }
    if (staged) staged->commit(frame_names);
    if (s.mode == "sheet") {
      render::write_png(s.output, render::contact_sheet(cells, s.columns), background);
      what = "contact sheet of " + std::to_string(layers) + " layers, offsets " +
             brief(offsets.front()) + " .. " + brief(offsets.back());
    } else {
      std::cout << "wrote " << layers << " frames " << frame_path(s.output, 0) << " .. "
                << frame_path(s.output, layers - 1) << " (offsets " << brief(offsets.front())
                << " .. " << brief(offsets.back()) << ")\n";
      return;
    }
  } else if (s.mode == "cloud") {
    render::CloudOptions o;
    o.raster = raster_options(s);
    o.layers = s.layers > 0 ? s.layers : 64;
    o.opacity = s.opacity;
    o.cell_palette = !input.is_scene;
    if (!s.view_text.empty()) o.view_from = parse_vec3(s.view_text, "--view");
    o.stack_axis = s.stack == "u" ? 0 : s.stack == "v" ? 1 : s.stack == "s" ? 2 : -1;
    Eigen::VectorXd n(4);
    for (int i = 0; i < 4; ++i) n(i) = p.normal[i];
    render::write_png(s.output,
                      s.stereo ? render::render_cloud_stereo_pair(input.scene, n, o)
                               : render::render_voxel_cloud(input.scene, n, o),
                      background);
    const int axis = render::cloud_stack_axis(o.view_from, o.stack_axis);
    what = std::string(s.stereo ? "stereo pair (left eye left) of a " : "") + "voxel cloud of " +
           std::to_string(o.layers) + " layers stacked along " + "uvs"[axis];
  } else if (s.mode == "wireframe") {
    render::WireframeOptions o;
    o.raster = raster_options(s);
    o.occlusion = !s.no_occlusion;
    if (!s.view_text.empty()) o.view_from = parse_vec3(s.view_text, "--view");
    const auto eye = parse_vector(s.eye4_text, "--eye4");
    if (eye.size() != 4) throw InputError("--eye4 takes 4 components X,Y,Z,W");
    // A direction: brought near unit length by a power of two (exact), so that 1e-300 or 1e300
    // components are not taken for zero or infinity.
    Eigen::Vector4d from = Eigen::Map<const Eigen::Vector4d>(eye.data());
    if (from.cwiseAbs().maxCoeff() == 0.0) throw InputError("--eye4 must not be the zero vector");
    const int e = std::ilogb(from.cwiseAbs().maxCoeff());
    from = from.unaryExpr([e](double x) { return std::scalbn(x, -e); }).eval();
    render::Camera4 cam = render::frame_scene(input.scene, from, s.fov4);
    if (!s.eye4_at_text.empty() || !s.look4_text.empty()) {
      // A camera placed at a point (inside a polytope, say) looking at --look4 (default: the
      // centre the framed camera looks at).
      auto point4 = [](const std::string& text, const std::string& option) {
        const auto v = parse_vector(text, option);
        if (v.size() != 4) throw InputError(option + " takes 4 components X,Y,Z,W");
        return Eigen::VectorXd(Eigen::Map<const Eigen::Vector4d>(v.data()));
      };
      Eigen::VectorXd look(4);
      if (s.look4_text.empty()) {  // the centre of the scene's bounding box
        for (int i = 0; i < 4; ++i) {
          const auto [lo, hi] = render::scene_extent(input.scene, Eigen::Vector4d::Unit(i));
          look(i) = 0.5 * (lo + hi);
        }
      } else {
        look = point4(s.look4_text, "--look4");
      }
      const Eigen::VectorXd eye =
          s.eye4_at_text.empty() ? cam.eye : point4(s.eye4_at_text, "--eye4-at");
      if ((look - eye).norm() == 0.0)
        throw InputError("--eye4-at must differ from the point the camera looks at (--look4)");
      cam = render::Camera4::look_at(eye, look, s.fov4);
    }
    Section sec;
    if (s.with_section) {
      sec = cut(input, p.plane(s.offset)).section;
      o.section = &sec;
    }
    render::write_png(s.output,
                      s.stereo ? render::render_wireframe_stereo_pair(input.scene, cam, o)
                               : render::render_wireframe(input.scene, cam, o),
                      background);
    what = std::string(s.stereo ? "stereo pair (left eye left) of a " : "") + "4D wireframe" +
           (o.occlusion ? " with occlusion" : "") + (s.with_section ? " and its section" : "");
  } else if (s.mode == "schlegel") {
    if (input.is_scene) throw InputError("--mode schlegel draws one MODEL, not a --scene");
    render::SchlegelOptions o;
    o.raster = raster_options(s);
    o.faces = s.faces;
    if (!s.view_text.empty()) o.view_from = parse_vec3(s.view_text, "--view");
    if (s.projection == "orthographic") o.projection = render::Projection::Orthographic;
    const SceneObject& obj = input.scene.objects.front();
    const Complex placed = transformed(*obj.complex, obj.transform);
    const render::SchlegelProjection sp = render::schlegel_projection(placed, s.cell);
    render::write_png(s.output, render::render_schlegel(placed, sp, o), background);
    what = "Schlegel diagram (" + std::to_string(placed.count(1)) + " edges" +
           (s.faces ? " and " + std::to_string(placed.count(2)) + " faces" : std::string()) +
           ", seen from outside cell " + std::to_string(sp.cell) + ")";
  } else {  // stereographic
    if (input.is_scene) throw InputError("--mode stereographic draws one MODEL, not a --scene");
    render::StereographicOptions o;
    o.raster = raster_options(s);
    o.tubes = !s.lines;
    o.facet_at_south_pole = p.rotate_text.empty();  // --rotate chooses the pole instead
    if (!s.view_text.empty()) o.view_from = parse_vec3(s.view_text, "--view");
    const SceneObject& obj = input.scene.objects.front();
    render::write_png(s.output,
                      render::render_stereographic(transformed(*obj.complex, obj.transform), o),
                      background);
    what = std::string("stereographic projection (") + (o.tubes ? "tubes" : "lines") + ")";
  }
  std::cout << "wrote " << s.output << ": " << what << " of " << p.input_label() << '\n';
}

}  // namespace

void add_render_command(CLI::App& app, Commands& commands) {
  auto s = std::make_shared<RenderSettings>();
  auto* cmd = app.add_subcommand("render",
                                 "Draw a PNG picture: a shaded section, a voxel cloud, a "
                                 "4D wireframe, a stereographic view, a stereo pair or a sweep.");
  s->placement.add_options(*cmd);
  cmd->get_option("--normal")->required(false);
  cmd->add_option(
         "--mode", s->mode,
         "section (default), stereo, sheet, frames, cloud, wireframe, stereographic, schlegel")
      ->check(CLI::IsMember({"section", "stereo", "sheet", "frames", "cloud", "wireframe",
                             "stereographic", "schlegel"}));
  cmd->add_option("--offset", s->offset, "section/stereo: signed distance d of the plane n.x = d")
      ->type_name("D");
  cmd->add_option("-o,--output", s->output, "Output PNG (frames: NAME.png -> NAME_0000.png, ...)")
      ->required();
  cmd->add_option("--size", s->size, "Image size in pixels (default 800x600)")->type_name("WxH");
  cmd->add_option("--samples", s->samples,
                  "Anti-aliasing: S x S samples per pixel, S = 1..4 (default 3)")
      ->check(CLI::Range(1, 4));
  cmd->add_option("--threads", s->threads,
                  "Worker threads (default: all cores; the picture is the same)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--projection", s->projection, "perspective (default) or orthographic")
      ->check(CLI::IsMember({"perspective", "orthographic"}));
  cmd->add_option("--view", s->view_text,
                  "Direction the 3D camera looks from (section coordinates; cloud: (u,v,s) of the "
                  "volume; wireframe: the retina cube)")
      ->type_name("X,Y,Z");
  cmd->add_flag("--edges", s->edges,
                "section/stereo/sheet/frames: draw the section's edges on top");
  cmd->add_flag("--cull", s->cull, "Cull back faces (sections are closed surfaces)");
  cmd->add_option("--layers", s->layers,
                  "cloud (64), sheet (16), frames (24): number of parallel sections")
      ->check(CLI::Range(1, 4096));
  cmd->add_option(
         "--opacity", s->opacity,
         "cloud: opacity of the whole depth seen face-on, times each object's opacity (0.97)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--columns", s->columns, "sheet: images per row (default: about square)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--eye4", s->eye4_text,
                  "wireframe: direction the 4D camera looks from, towards the scene's centre "
                  "(default 0.3,0.2,0.1,-1)")
      ->type_name("X,Y,Z,W");
  cmd->add_option("--fov4", s->fov4, "wireframe: field of view of the 4D camera in degrees (60)")
      ->check(CLI::Range(1.0, 170.0));
  cmd->add_flag("--no-occlusion", s->no_occlusion, "wireframe: draw hidden edges too");
  cmd->add_flag("--lines", s->lines, "stereographic: lines instead of tubes");
  cmd->add_option("--texture", s->textures,
                  "section/stereo/sheet/frames: a 3D texture sampled through the cells' UVW: "
                  "checker[:S], grid[:S], wood[:S], marble[:S] (S repeats per cell box) or "
                  "volume:DIR|PATTERN[:S] (PNG slices); prefix object=I: or cell=I: for one "
                  "scene object or cell (repeatable)")
      ->type_name("SPEC");
  cmd->add_option("--light-mode", s->light_mode,
                  "section/stereo/sheet/frames: 3d (default: lights in the section's space) or "
                  "4d (lights in 4D, each face lit by its cell's 4D normal)")
      ->check(CLI::IsMember({"3d", "4d"}));
  cmd->add_option("--light4", s->lights4,
                  "A 4D light (implies --light-mode 4d; repeatable): X,Y,Z,W towards a "
                  "directional light, or point:X,Y,Z,W[:R] (intensity (R/r)^3, R = 1)")
      ->type_name("SPEC");
  cmd->add_option("--stack", s->stack,
                  "cloud: the volume axis the layers are stacked along: auto (default: the one "
                  "most aligned with --view, no stripes at grazing views), u, v or s")
      ->check(CLI::IsMember({"auto", "u", "v", "s"}));
  cmd->add_flag("--stereo", s->stereo,
                "cloud, wireframe: a side-by-side stereo pair (left eye left), the views turned "
                "by -/+3 degrees");
  cmd->add_flag("--section", s->with_section,
                "wireframe: also draw the section n.x = d (--normal, default 0,0,0,1; --offset) "
                "inside the wireframe, translucent");
  cmd->add_option("--eye4-at", s->eye4_at_text,
                  "wireframe: put the 4D camera at this point (it may be inside a polytope: "
                  "then only that polytope's inside is seen), looking at --look4")
      ->type_name("X,Y,Z,W");
  cmd->add_option("--look4", s->look4_text,
                  "wireframe: the point the 4D camera looks at (default: the scene's centre)")
      ->type_name("X,Y,Z,W");
  cmd->add_option("--animate", s->animate,
                  "section: write an animated WebP or GIF (-o NAME.webp, NAME.gif) of a sweep "
                  "across the input, "
                  "rotate:PLANE (every object turned once about the origin, e.g. rotate:xw) or "
                  "orbit (the 3D camera once around the section)")
      ->type_name("KIND");
  cmd->add_option("--frames", s->frames, "--animate: number of frames (36)")
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--frame-ms", s->frame_ms, "--animate: milliseconds per frame (80)")
      ->check(CLI::Range(1, 60000));
  cmd->add_option("--method", s->method,
                  "section: cw (default: the CW slicer) or tet (cut the model's tetrahedra)")
      ->check(CLI::IsMember({"cw", "tet"}));
  cmd->add_option("--separation", s->separation,
                  "stereo: eye distance in section units (default 6% of the section's diameter)");
  cmd->add_option("--cell", s->cell,
                  "schlegel: the cell the eye looks through (default: the one facing +w most)")
      ->type_name("N")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--faces", s->faces, "schlegel: draw the faces too, translucent");
  cmd->footer(
      "Modes:\n"
      "  section        the section n.x = d, shaded (Blinn-Phong), cell colors (scene colors,\n"
      "                 else a hue per cell); --edges overlays the polygon outlines\n"
      "  stereo         the same section twice, side by side (left eye left): the eyes are\n"
      "                 shifted inside the hyperplane\n"
      "  sheet          a contact sheet of --layers parallel sections n.x = d across the model\n"
      "  frames         the same sections as numbered PNGs for an animation\n"
      "  cloud          a voxel cloud: --layers parallel sections composited back to front with\n"
      "                 opacity corrected for layer spacing and view angle\n"
      "  wireframe      the 4D edges seen by a 4D perspective camera (--eye4, --fov4), clipped to\n"
      "                 its frustum, hidden parts removed (convex objects occlude), colored by 4D\n"
      "                 depth (near orange, far blue), inside the retina cube\n"
      "  stereographic  the edges projected from the 3-sphere, as tubes (or --lines)\n"
      "  schlegel       the Schlegel diagram: every edge in perspective from just outside one\n"
      "                 cell (--cell), projected into it; --faces adds translucent faces; no\n"
      "                 --normal needed\n"
      "Sections (section, stereo, sheet, frames) take --texture (3D textures through the cells'\n"
      "UVW) and --light-mode 4d / --light4 (lights in 4D, faces lit by their cells' 4D normals).\n"
      "--normal is required except for wireframe, stereographic and schlegel. Output is PNG\n"
      "(sRGB; --animate: an animated WebP), written through a temporary file. An empty section\n"
      "exits 5.\n"
      "Examples:\n"
      "  cw4d render 24-cell --normal 1,1,1,1 --offset 0.3 --edges -o section.png\n"
      "  cw4d render tesseract --mode cloud --normal 0,0,1,1 --rotate xw:20 -o cloud.png\n"
      "  cw4d render 120-cell --mode wireframe -o wire.png\n"
      "  cw4d render 24-cell --mode stereographic --rotate xw:10 -o stereo.png\n"
      "  cw4d render 24-cell --normal 1,1,1,1 --offset 0.3 --texture marble:2 -o marble.png\n"
      "  cw4d render tesseract --normal 0,0,0,1 --offset 0.3 --animate rotate:xw -o turn.webp\n"
      "Exit codes: see 'cw4d --help'.");
  commands.push_back({cmd, [s] { run_render(*s); }});
}

}  // namespace cw4d::cli
