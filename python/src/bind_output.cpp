// The writers (OBJ, glTF/GLB, PLY, STL, SVG, nOFF, PNG) and render().
#include <algorithm>
#include <cctype>
#include <filesystem>

#include "common.hpp"
#include "cw4d/complex/g4mf.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/export/g4mf.hpp"
#include "cw4d/export/gltf.hpp"
#include "cw4d/export/mesh.hpp"
#include "cw4d/export/mesh_files.hpp"
#include "cw4d/export/obj.hpp"
#include "cw4d/export/svg.hpp"
#include "cw4d/render/image.hpp"
#include "cw4d/render/section_view.hpp"
#include "cw4d/section/provenance.hpp"
#include "cw4d/section/uvw.hpp"

namespace cw4d::python {

namespace {

ObjOptions obj_options(bool triangulate, bool group_by_source, const std::string& comment) {
  ObjOptions o;
  o.triangulate = triangulate;
  o.group_by_source = group_by_source;
  o.comment = comment;
  return o;
}

// The models a section was cut from: None, one Complex, or the Scene of section_scene().
struct Models {
  std::vector<const Complex*> models;
  std::vector<std::string> names;  // the CLI's mesh names: object names for a scene
};

Models models_of(py::handle obj) {
  Models m;
  if (obj.is_none()) return m;
  if (py::isinstance<Scene>(obj)) {
    const Scene& scene = obj.cast<const Scene&>();
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
      const SceneObject& o = scene.objects[i];
      m.models.push_back(o.complex.get());
      m.names.push_back(!o.name.empty() ? o.name
                                        : "object " + std::to_string(i) + " (" + o.model + ")");
    }
    return m;
  }
  m.models.push_back(&obj.cast<const Complex&>());
  return m;
}

// Texture coordinates of the section (what the CLI writes unless --no-uvw), when its models
// are given and it has polygons.
// A model that is not the section's source is refused (InputError) before anything is
// written: section_uvw checks the provenance, and without polygons it is checked here.
bool corner_uvw(const Section& s, const Models& models, CornerUvw& out) {
  if (models.models.empty()) return false;
  if (s.complex.ambient_dim() != 3 || s.complex.top_rank() < 2) {
    check_provenance(s, models.models);
    return false;
  }
  out = section_uvw(s, models.models);
  return true;
}

std::vector<Section> sections_of(py::handle obj) {
  if (py::isinstance<Section>(obj)) return {obj.cast<Section>()};
  return obj.cast<std::vector<Section>>();
}

glm::vec3 vec3(py::handle obj, const char* what) {
  const Eigen::VectorXd v = to_vector(obj, what);
  if (v.size() != 3) throw InputError(std::string(what) + " takes 3 components");
  return {static_cast<float>(v(0)), static_cast<float>(v(1)), static_cast<float>(v(2))};
}

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

SvgOptions svg_options(int width, int height, py::object view_from, py::object light_from,
                       bool edges) {
  SvgOptions o;
  o.width = width;
  o.height = height;
  if (!view_from.is_none()) o.view_from = direction3(view_from, "view_from");
  if (!light_from.is_none()) o.light_from = direction3(light_from, "light_from");
  o.edges = edges;
  return o;
}

}  // namespace

void bind_output(py::module_& m) {
  m.def(
      "obj_text",
      [](const Section& s, bool triangulate, bool group_by_source, const std::string& comment,
         py::object model) {
        ObjOptions o = obj_options(triangulate, group_by_source, comment);
        const Models models = models_of(model);
        o.object_names = models.names;  // the `o` lines of a scene's objects
        CornerUvw uvw;
        if (corner_uvw(s, models, uvw)) o.uvw = &uvw;
        py::gil_scoped_release nogil;
        return obj_text(s, o);
      },
      py::arg("section"), py::arg("triangulate") = false, py::arg("group_by_source") = true,
      py::arg("comment") = "", py::arg("model") = py::none(),
      "Wavefront OBJ text of a section (a `g` group per source cell); with `model` (the "
      "Complex it was cut from, or the Scene of section_scene) also `vt u v w` texture "
      "coordinates.");
  m.def(
      "write_obj",
      [](const std::string& path, const Section& s, bool triangulate, bool group_by_source,
         const std::string& comment, py::object model) {
        ObjOptions o = obj_options(triangulate, group_by_source, comment);
        const Models models = models_of(model);
        o.object_names = models.names;  // the `o` lines of a scene's objects
        CornerUvw uvw;
        if (corner_uvw(s, models, uvw)) o.uvw = &uvw;
        py::gil_scoped_release nogil;
        write_obj_file(path, s, o);
      },
      py::arg("path"), py::arg("section"), py::arg("triangulate") = false,
      py::arg("group_by_source") = true, py::arg("comment") = "", py::arg("model") = py::none(),
      "Writes obj_text() to `path` (and the face colors to a .mtl beside it), atomically.");
  m.def(
      "write_gltf",
      [](const std::string& path, py::object sections, std::optional<bool> binary,
         double seconds_per_node, const std::string& description,
         std::optional<std::vector<std::string>> names, py::object model) {
        const std::vector<Section> secs = sections_of(sections);
        const Models models = models_of(model);
        if (names && names->size() != secs.size())
          throw InputError("names must have one entry per section");
        GltfOptions o;
        o.binary = binary ? *binary : lower_extension(path) == ".glb";
        o.seconds_per_node = seconds_per_node;
        o.description = description;
        py::gil_scoped_release nogil;
        std::vector<GltfNode> nodes;
        for (std::size_t i = 0; i < secs.size(); ++i) {
          const std::string name = names ? (*names)[i] : "section_" + std::to_string(i);
          CornerUvw uvw;
          const bool has_uvw = corner_uvw(secs[i], models, uvw);
          // A scene's section: one node per object mesh, named after the objects (as the CLI).
          const std::vector<std::string> mesh_names =
              models.names.empty() ? std::vector<std::string>{name} : models.names;
          for (auto& mesh : triangle_meshes(secs[i], mesh_names, has_uvw ? &uvw : nullptr)) {
            GltfNode node;
            node.name = models.names.empty() ? name : mesh.name;
            node.meshes.push_back(std::move(mesh));
            nodes.push_back(std::move(node));
          }
        }
        write_gltf_file(path, nodes, o);
      },
      py::arg("path"), py::arg("sections"), py::arg("binary") = py::none(),
      py::arg("seconds_per_node") = 0.0, py::arg("description") = "", py::arg("names") = py::none(),
      py::arg("model") = py::none(),
      "Writes a Section or a list of Sections (one node each; seconds_per_node > 0 animates "
      "them in turn) as glTF 2.0: .glb binary when the path ends in .glb (or binary=True), "
      "else .gltf JSON plus a .bin. With `model` (a Complex, or the Scene of section_scene: "
      "then one node per object, named as the CLI names them) the meshes get UVW.");
  m.def(
      "write_ply",
      [](const std::string& path, const Section& s) {
        py::gil_scoped_release nogil;
        write_ply_file(path, triangle_meshes(s));
      },
      py::arg("path"), py::arg("section"), "Binary PLY of the triangulated section.");
  m.def(
      "write_stl",
      [](const std::string& path, const Section& s) {
        py::gil_scoped_release nogil;
        write_stl_file(path, triangle_meshes(s));
      },
      py::arg("path"), py::arg("section"), "Binary STL of the triangulated section.");
  m.def(
      "svg_text",
      [](const Section& s, int width, int height, py::object view_from, py::object light_from,
         bool edges) {
        const SvgOptions o = svg_options(width, height, view_from, light_from, edges);
        py::gil_scoped_release nogil;
        return svg_text(s, o);
      },
      py::arg("section"), py::arg("width") = 640, py::arg("height") = 480,
      py::arg("view_from") = py::none(), py::arg("light_from") = py::none(),
      py::arg("edges") = true,
      "A flat-shaded SVG picture of a 3D section (orthographic, back faces culled).");
  m.def(
      "write_svg",
      [](const std::string& path, const Section& s, int width, int height, py::object view_from,
         py::object light_from, bool edges) {
        const SvgOptions o = svg_options(width, height, view_from, light_from, edges);
        py::gil_scoped_release nogil;
        write_svg_file(path, s, o);
      },
      py::arg("path"), py::arg("section"), py::arg("width") = 640, py::arg("height") = 480,
      py::arg("view_from") = py::none(), py::arg("light_from") = py::none(),
      py::arg("edges") = true, "Writes svg_text() to `path`.");
  m.def(
      "write_off",
      [](const std::string& path, py::object obj) {
        const Complex& c = py::isinstance<Section>(obj) ? obj.cast<const Section&>().complex
                                                        : obj.cast<const Complex&>();
        py::gil_scoped_release nogil;
        write_off_file(path, c);
      },
      py::arg("path"), py::arg("complex"),
      "Writes a Complex (or a Section's complex) as nOFF with full double precision.");

  m.def(
      "read_g4mf",
      [](const std::string& path) {
        py::gil_scoped_release nogil;
        return read_g4mf_file(path);
      },
      py::arg("path"),
      "Reads a G4MF file (.g4tf, .g4b: godot-4d's Good 4D Model Format; see docs/formats.md). "
      "Raises ParseError naming the part of the file.");
  m.def(
      "write_g4mf",
      [](const std::string& path, py::object obj, bool separate_buffer, bool uvw,
         const std::string& name, const std::string& description, py::object model) {
        const std::string ext = lower_extension(path);
        if (ext != ".g4tf" && ext != ".g4b")
          throw InputError("write_g4mf writes .g4tf or .g4b files, not '" + path + "'");
        if (separate_buffer && ext == ".g4b")
          throw InputError("separate_buffer applies to .g4tf files (a .g4b holds its buffer)");
        G4mfWriteOptions o;
        o.container = ext == ".g4b"     ? G4mfContainer::binary
                      : separate_buffer ? G4mfContainer::text_external
                                        : G4mfContainer::text_embedded;
        o.name = name.empty() ? std::filesystem::path(path).stem().string() : name;
        o.description = description;
        if (py::isinstance<Section>(obj)) {
          const Section& s = obj.cast<const Section&>();
          const Models models = models_of(model);
          CornerUvw corners;
          const bool has_uvw = uvw && corner_uvw(s, models, corners);
          py::gil_scoped_release nogil;
          return write_g4mf_section_file(path, s, o, has_uvw ? &corners : nullptr);
        }
        const Complex& c = obj.cast<const Complex&>();
        py::gil_scoped_release nogil;
        return write_g4mf_model_file(path, c, o, uvw);
      },
      py::arg("path"), py::arg("complex"), py::arg("separate_buffer") = false,
      py::arg("uvw") = true, py::arg("name") = "", py::arg("description") = "",
      py::arg("model") = py::none(),
      "Writes a Complex (a model, with each facet's box-mapped UVW when `uvw`) or a Section (its "
      "complex; with `model`, the Complex or Scene it was cut from, also its corner UVW) as G4MF: "
      ".g4tf with the buffer embedded (separate_buffer: in a .bin beside it) or binary .g4b. "
      "Returns the files written.");
  m.def(
      "render",
      [](const Section& s, int width, int height, int samples, const std::string& projection,
         py::object view_from, bool edges, bool cull_back_faces, py::object background,
         const Complex* model, int threads) {
        if (s.complex.ambient_dim() != 3)
          throw InputError("render draws 3D sections (of 4D models); this one lives in R^" +
                           std::to_string(s.complex.ambient_dim()));
        render::SectionViewOptions o;
        o.raster.width = width;
        o.raster.height = height;
        o.raster.samples_per_axis = samples;
        o.raster.threads = threads;
        if (projection == "orthographic")
          o.projection = render::Projection::Orthographic;
        else if (projection != "perspective")
          throw InputError("projection must be 'perspective' or 'orthographic', not '" +
                           projection + "'");
        if (!view_from.is_none()) {
          const Eigen::Vector3d d = direction3(view_from, "view_from");
          o.view_from = {static_cast<float>(d(0)), static_cast<float>(d(1)),
                         static_cast<float>(d(2))};
        }
        o.edges = edges;
        o.cull_back_faces = cull_back_faces;
        const glm::vec3 bg = vec3(background, "background");
        o.background = bg;
        render::Image8 img;
        {
          py::gil_scoped_release nogil;
          img = render::to_srgb8(render::render_section(s, o, model), bg, true);
        }
        return adopt(std::move(img.bytes), 0)
            .reshape({static_cast<py::ssize_t>(img.height), static_cast<py::ssize_t>(img.width),
                      py::ssize_t{4}});
      },
      py::arg("section"), py::arg("width") = 800, py::arg("height") = 600, py::arg("samples") = 3,
      py::arg("projection") = "perspective", py::arg("view_from") = py::none(),
      py::arg("edges") = false, py::arg("cull_back_faces") = false,
      py::arg("background") = py::make_tuple(1.0, 1.0, 1.0), py::arg("model") = nullptr,
      py::arg("threads") = 0,
      "A shaded picture of a 3D section (the CLI's `cw4d render`), an (H, W, 4) uint8 RGBA "
      "array (sRGB, opaque). `model` (the Complex it was cut from) supplies cell colors; "
      "background is linear RGB in 0..1.");
  m.def(
      "write_png",
      [](const std::string& path, py::array_t<std::uint8_t, py::array::c_style> image) {
        if (image.ndim() != 3 || (image.shape(2) != 3 && image.shape(2) != 4))
          throw InputError("a PNG image is an (H, W, 3) or (H, W, 4) uint8 array");
        render::Image8 img;
        img.height = static_cast<int>(image.shape(0));
        img.width = static_cast<int>(image.shape(1));
        img.channels = static_cast<int>(image.shape(2));
        img.bytes.assign(image.data(), image.data() + image.size());
        py::gil_scoped_release nogil;
        render::write_png(path, img);
      },
      py::arg("path"), py::arg("image"), "Writes an (H, W, 3|4) uint8 array as PNG.");
  m.def(
      "read_png",
      [](const std::string& path) {
        render::Image8 img = render::read_png(path);
        const int c = img.channels;
        return adopt(std::move(img.bytes), 0)
            .reshape({static_cast<py::ssize_t>(img.height), static_cast<py::ssize_t>(img.width),
                      static_cast<py::ssize_t>(c)});
      },
      py::arg("path"), "Reads a PNG written by write_png/render as an (H, W, C) uint8 array.");
}

}  // namespace cw4d::python
