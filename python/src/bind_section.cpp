// section(), Section, the fast SliceModel / Slicer (GIL released while they cut), and scenes.
#include <chrono>
#include <cstddef>
#include <mutex>
#include <sstream>

#include "common.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/section/atlas.hpp"
#include "cw4d/section/scene_section.hpp"
#include "cw4d/section/section.hpp"
#include "cw4d/section/slicer.hpp"
#include "cw4d/section/triangulate.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"

namespace cw4d::python {

namespace {

// The boundary measure of a section: the sum of its facets' (n-2)-volumes (the surface area of
// a 3D section, the perimeter of a 2D one).
double facet_measure(const Complex& c) {
  const int r = c.facet_rank();
  if (r < 1 || r > c.top_rank()) return 0.0;
  double sum = 0.0;
  for (std::uint32_t i = 0; i < c.count(r); ++i) sum += element_volume(c, r, i);
  return sum;
}

// Thread safety of the bound objects whose methods release the GIL. Complex, Section,
// SliceModel, Scene and AffineTransform are immutable from Python (read-only properties, no
// mutating method) and the C++ they call only reads them (the per-thread caches of section()
// are thread_local), so any number of threads may share them. Slicer and SceneSlicer own
// scratch space that every call rewrites: they refuse a second thread with ValueError instead
// of racing (each holds a mutex taken with try_lock, for the call and for the properties that
// read the scratch state).

// One Slicer with its buffers, used by one thread at a time.
struct PySlicer {
  Slicer slicer;
  SliceBuffers buffers;
  std::vector<SliceBuffers> layers;
  std::mutex busy;
};

// A SceneSlicer (its placements, touched list and per-object buffers change on every slice),
// used by one thread at a time.
struct PySceneSlicer {
  SceneSlicer slicer;
  std::mutex busy;
  PySceneSlicer(const Scene& scene, const SliceModelOptions& o) : slicer(scene, o) {}
};

// Holds `m` for the scope, or raises ValueError naming the class when another thread holds it.
class Busy {
 public:
  Busy(std::mutex& m, const char* type) : lock_(m, std::try_to_lock) {
    if (!lock_.owns_lock())
      throw py::value_error(std::string("this ") + type +
                            " is cutting on another thread: give every thread its own " + type);
  }

 private:
  std::unique_lock<std::mutex> lock_;
};

std::vector<double> to_offsets(py::handle obj) {
  Eigen::VectorXd v = to_vector(obj, "offsets");
  return {v.data(), v.data() + v.size()};
}

std::vector<Section> sweep_sections(PySlicer& s, const SliceModel& model, const Eigen::VectorXd& n,
                                    const std::vector<double>& offsets, const AffineTransform& xf,
                                    unsigned threads) {
  s.slicer.sweep(model, n, offsets, xf, s.layers, threads);
  std::vector<Section> out;
  out.reserve(s.layers.size());
  for (const SliceBuffers& b : s.layers) out.push_back(to_section(b));
  return out;
}

}  // namespace

void bind_section(py::module_& m) {
  py::class_<Section>(
      m, "Section",
      "The cut of a model by a hyperplane: a closed complex in the plane's own coordinates "
      "(R^(n-1), basis in .basis), with where every element came from.")
      .def_property_readonly(
          "dim", [](const Section& s) { return s.complex.ambient_dim(); },
          "Dimension of the section (the model's minus one).")
      .def_property_readonly("empty", &Section::empty, "True when the plane misses the model.")
      .def_readonly("complex", &Section::complex,
                    "The section as a Complex (a view: it lives as long as the Section).")
      .def_property_readonly(
          "fvector", [](const Section& s) { return py::tuple(py::cast(s.complex.fvector())); })
      .def_property_readonly(
          "vertices",
          [](py::object self) {
            const Section& s = self.cast<const Section&>();
            return view(s.complex.positions().data(), static_cast<py::ssize_t>(s.complex.count(0)),
                        s.complex.ambient_dim(), self);
          },
          "Vertex coordinates in the plane's basis, a read-only (V, n-1) float64 view (no copy).")
      .def(
          "world_vertices",
          [](const Section& s) {
            const Eigen::MatrixXd w =
                (s.frame.basis * s.complex.positions()).colwise() + s.frame.origin();
            return adopt(std::vector<double>(w.data(), w.data() + w.size()), s.frame.plane.dim());
          },
          "Vertex positions in the model's world space, a new (V, n) array.")
      .def_property_readonly(
          "polygons",
          [](const Section& s) {
            std::vector<std::uint32_t> offsets{0}, ids;
            if (s.complex.top_rank() >= 2)
              for (std::uint32_t f = 0; f < s.complex.count(2); ++f) {
                const auto cycle = s.complex.face_cycle(f);
                ids.insert(ids.end(), cycle.begin(), cycle.end());
                offsets.push_back(static_cast<std::uint32_t>(ids.size()));
              }
            return py::make_tuple(adopt(std::move(offsets)), adopt(std::move(ids)));
          },
          "The polygons (rank-2 faces) as (offsets, ids): polygon i is the vertex cycle "
          "ids[offsets[i]:offsets[i+1]], outward oriented. New arrays (the complex stores "
          "signed edges, the cycles are computed).")
      .def(
          "triangles",
          [](const Section& s, bool with_faces) {
            std::vector<Triangle> tris;
            if (!s.empty() && s.complex.top_rank() >= 2 && s.complex.ambient_dim() <= 3) {
              py::gil_scoped_release nogil;
              tris = triangulate_section(s);
            }
            std::vector<std::uint32_t> v, faces;
            v.reserve(3 * tris.size());
            for (const Triangle& t : tris) {
              v.insert(v.end(), t.v.begin(), t.v.end());
              faces.push_back(t.face);
            }
            py::object out = adopt(std::move(v), 3);
            if (with_faces) return py::object(py::make_tuple(out, adopt(std::move(faces))));
            return out;
          },
          py::arg("with_faces") = false,
          "Ear-clipped triangles of the polygons (holes bridged), a new (T, 3) uint32 array of "
          "vertex ids in the polygons' orientation; with_faces=True also returns the polygon "
          "of each triangle.")
      .def_property_readonly(
          "normals",
          [](py::object self) {
            const Section& s = self.cast<const Section&>();
            const auto& n = s.complex.facet_normals();
            return view(n.data(), n.cols(), s.complex.ambient_dim(), self);
          },
          "Outward unit normal of every facet (the polygons of a 3D section), a read-only "
          "(F, n-1) view (no copy).")
      .def_property_readonly(
          "source_cells",
          [](py::object self) {
            const Section& s = self.cast<const Section&>();
            const int r = s.complex.facet_rank();
            static const std::vector<std::uint32_t> none;
            const auto& src =
                r >= 0 && static_cast<std::size_t>(r) < s.source.size() ? s.source[r] : none;
            return view(src.data(), static_cast<py::ssize_t>(src.size()), 0, self);
          },
          "The model facet (a 3-cell of a 4D model) that every section facet was cut from, a "
          "read-only uint32 view (no copy).")
      .def(
          "source",
          [](py::object self, int rank) {
            const Section& s = self.cast<const Section&>();
            if (rank < 1 || static_cast<std::size_t>(rank) >= s.source.size())
              throw py::index_error("no provenance for rank " + std::to_string(rank));
            const auto& src = s.source[rank];
            return view(src.data(), static_cast<py::ssize_t>(src.size()), 0, self);
          },
          py::arg("rank"),
          "The model element of rank+1 whose cut is each section element of `rank` (view).")
      .def_property_readonly(
          "vertex_source",
          [](py::object self) {
            const Section& s = self.cast<const Section&>();
            const auto* base = s.vertex_source.data();
            const auto n = static_cast<py::ssize_t>(s.vertex_source.size());
            constexpr auto stride = static_cast<py::ssize_t>(sizeof(VertexSource));
            const auto* bytes = reinterpret_cast<const unsigned char*>(base);
            return py::make_tuple(
                view(reinterpret_cast<const std::uint32_t*>(
                         bytes ? bytes + offsetof(VertexSource, element) : nullptr),
                     n, 0, self, stride),
                view(reinterpret_cast<const std::uint8_t*>(
                         bytes ? bytes + offsetof(VertexSource, rank) : nullptr),
                     n, 0, self, stride),
                view(reinterpret_cast<const double*>(bytes ? bytes + offsetof(VertexSource, t)
                                                           : nullptr),
                     n, 0, self, stride));
          },
          "Where each vertex comes from, as (element, rank, t): rank 1 -> the model edge "
          "`element` crossed at (1-t)*tail + t*head; rank 0 -> the model vertex `element` on "
          "the plane. Strided read-only views (no copy).")
      .def_property_readonly(
          "volume", [](const Section& s) { return s.empty() ? 0.0 : signed_volume(s.complex); },
          "The (n-1)-volume the section encloses (signed; winding numbers count for a "
          "self-intersecting cut).")
      .def_property_readonly(
          "area", [](const Section& s) { return s.empty() ? 0.0 : facet_measure(s.complex); },
          "The (n-2)-volume of its boundary: surface area of a 3D section, perimeter of a 2D "
          "one.")
      .def_property_readonly(
          "normal",
          [](const Section& s) {
            const auto& v = s.frame.plane.normal;
            return adopt(std::vector<double>(v.data(), v.data() + v.size()));
          },
          "The unit normal of the world-space plane (a new array).")
      .def_property_readonly(
          "offset", [](const Section& s) { return s.frame.plane.offset; },
          "The plane's signed distance from the origin along the unit normal.")
      .def_property_readonly(
          "basis",
          [](const Section& s) {
            std::vector<double> out;
            for (Eigen::Index i = 0; i < s.frame.basis.rows(); ++i)
              for (Eigen::Index j = 0; j < s.frame.basis.cols(); ++j)
                out.push_back(s.frame.basis(i, j));
            return adopt(std::move(out), s.frame.basis.cols());
          },
          "The plane's orthonormal basis, a new (n, n-1) array: world = offset * normal + "
          "basis @ y.")
      .def_readonly("self_intersecting", &Section::self_intersecting,
                    "True for the polygon soup of a star polychoron's cut.")
      .def("validate",
           [](const Section& s) {
             py::gil_scoped_release nogil;
             return validate(s.complex);
           })
      .def("__repr__", [](const Section& s) {
        std::string f;
        for (auto c : s.complex.fvector()) f += (f.empty() ? "" : ", ") + std::to_string(c);
        std::ostringstream out;
        out.precision(10);
        out << "<cw4d.Section in R^" << s.complex.ambient_dim() << ", f-vector (" << f
            << "), volume " << (s.empty() ? 0.0 : signed_volume(s.complex)) << ">";
        return out.str();
      });

  // section() and section_general() take the same arguments and release the GIL alike.
  const auto def_cut =
      [&m](const char* name,
           Section (*cut)(const Complex&, const Hyperplane&, const AffineTransform&),
           const char* doc) {
        m.def(
            name,
            [cut](const Complex& model, py::object normal, double offset,
                  const std::optional<AffineTransform>& transform) {
              const Hyperplane plane = to_plane(normal, offset);
              const AffineTransform xf = or_identity(transform, model.ambient_dim());
              check_model_placement(model, xf);
              py::gil_scoped_release nogil;
              return cut(model, plane, xf);
            },
            py::arg("model"), py::arg("normal"), py::arg("offset"),
            py::arg("transform") = py::none(), doc);
      };
  def_cut("section", &section,
          "Cuts `model`, placed in the world by `transform` (None: as it is), with the "
          "world-space hyperplane {x : (n/|n|) . x = offset}; the GIL is released while it cuts.");
  def_cut("section_general", &section_general,
          "The general layered cut alone (no fast path): same result as section(), the second "
          "algorithm of the tests.");

  m.def(
      "atlas",
      [](const Complex& model, py::object normal, const std::optional<AffineTransform>& transform,
         bool sections) {
        const Eigen::VectorXd n = to_vector(normal, "normal");
        (void)Hyperplane::from(n, 0.0);  // refuses a zero or non-finite normal
        const AffineTransform xf = or_identity(transform, model.ambient_dim());
        check_model_placement(model, xf);
        AtlasOptions options;
        options.keep_sections = sections;
        Atlas a;
        {
          py::gil_scoped_release nogil;
          a = section_atlas(model, n, xf, options);
        }
        const auto fv = [](const std::vector<std::size_t>& f) {
          py::list l;
          for (auto c : f) l.append(c);
          return l;
        };
        py::dict d;
        d["normal"] =
            adopt(std::vector<double>(a.normal.data(), a.normal.data() + a.normal.size()));
        d["tolerance"] = a.tolerance;
        py::list offsets, critical, intervals;
        for (double c : a.critical_offsets) offsets.append(c);
        for (const auto& c : a.critical) {
          py::dict x;
          x["offset"] = c.offset;
          x["f_vector"] = fv(c.fvector);
          x["degenerate"] = true;
          if (!c.contact.empty()) x["contact_f_vector"] = fv(c.contact);
          critical.append(x);
        }
        for (std::size_t i = 0; i < a.intervals.size(); ++i) {
          py::dict x;
          x["from"] = a.intervals[i].from;
          x["to"] = a.intervals[i].to;
          x["offset"] = a.intervals[i].section.offset;
          x["f_vector"] = fv(a.intervals[i].section.fvector);
          if (sections) x["section"] = std::move(a.sections[i]);
          intervals.append(x);
        }
        d["critical_offsets"] = offsets;
        d["critical_sections"] = critical;
        d["intervals"] = intervals;
        return d;
      },
      py::arg("model"), py::arg("normal"), py::arg("transform") = py::none(),
      py::arg("sections") = false,
      "The section atlas along `normal` (any length; offsets along the unit normal): a dict "
      "with 'critical_offsets' (the vertex heights, sorted, heights within 1e-9 of the model's "
      "radius merged), 'critical_sections' (offset, f_vector, degenerate=True at each, and "
      "contact_f_vector, the f-vector of what lies in the plane, where the section is empty), "
      "'intervals' (from, to, offset = the midpoint, f_vector; with sections=True also "
      "'section', the Section cut there), 'normal' and 'tolerance'. The GIL is released while "
      "it cuts.");

  m.def(
      "_seconds_per_section",
      [](const Complex& model, py::object normal, double offset, std::size_t calls) {
        const Hyperplane plane = to_plane(normal, offset);
        const AffineTransform xf(model.ambient_dim());
        check_model_placement(model, xf);
        py::gil_scoped_release nogil;
        std::size_t sink = 0;
        const auto t0 = std::chrono::steady_clock::now();
        for (std::size_t i = 0; i < calls; ++i) sink += section(model, plane, xf).complex.count(0);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        static volatile std::size_t keep = 0;
        keep = keep + sink;
        return seconds / static_cast<double>(calls ? calls : 1);
      },
      py::arg("model"), py::arg("normal"), py::arg("offset"), py::arg("calls"),
      "Seconds per call of the C++ section() in a C++ loop (for bench/bench_python.py: the "
      "baseline of the per-call overhead of cw4d.section).");

  py::class_<SliceModel>(
      m, "SliceModel",
      "A Complex compiled once for fast repeated slicing (flat arrays, cell clusters for "
      "culling). Keeps its Complex alive; immutable and shareable between threads.")
      .def(py::init([](const Complex& model, bool clustered) {
             py::gil_scoped_release nogil;
             return std::make_unique<SliceModel>(
                 model, clustered ? SliceModelOptions{} : SliceModelOptions::unclustered());
           }),
           py::arg("model"), py::arg("clustered") = true, py::keep_alive<1, 2>())
      .def_property_readonly("dim", &SliceModel::dim)
      .def_property_readonly("fast", &SliceModel::fast,
                             "Whether the fast path can cut this model at all.")
      .def_property_readonly("cluster_count", &SliceModel::cluster_count)
      .def_property_readonly("radius", &SliceModel::radius, "Radius of the bounding sphere.")
      .def_property_readonly("bytes", &SliceModel::bytes, "Size of the compiled arrays.")
      .def_property_readonly(
          "complex", [](const SliceModel& s) -> const Complex& { return s.complex(); },
          py::return_value_policy::reference_internal);

  py::class_<PySlicer>(
      m, "Slicer",
      "Scratch space for fast slicing, reused from call to call (one per thread; a Slicer "
      "used by two threads at once raises ValueError). Every call releases the GIL while it "
      "cuts, so several threads with their own Slicer cut in parallel.")
      .def(py::init<>())
      .def(
          "slice",
          [](PySlicer& s, const SliceModel& model, py::object normal, double offset,
             const std::optional<AffineTransform>& transform, bool reuse_topology, bool cull) {
            const Hyperplane plane = to_plane(normal, offset);
            const AffineTransform xf = or_identity(transform, model.dim());
            check_model_placement(model.complex(), xf);
            Busy busy(s.busy, "Slicer");
            py::gil_scoped_release nogil;
            SliceOptions o;
            o.cull = cull;
            o.reuse_topology = reuse_topology;
            s.slicer.slice(model, plane, xf, s.buffers, o);
            return to_section(s.buffers);
          },
          py::arg("model"), py::arg("normal"), py::arg("offset"), py::arg("transform") = py::none(),
          py::arg("reuse_topology") = false, py::arg("cull") = true,
          "The Section of one plane (exactly what section() gives). reuse_topology=True keeps "
          "the previous slice's connectivity when no vertex changed side (animation frames).")
      .def(
          "sweep",
          [](PySlicer& s, const SliceModel& model, py::object normal, py::object offsets,
             const std::optional<AffineTransform>& transform, unsigned threads) {
            const Eigen::VectorXd n = to_vector(normal, "normal");
            const std::vector<double> d = to_offsets(offsets);
            const AffineTransform xf = or_identity(transform, model.dim());
            check_model_placement(model.complex(), xf);
            Busy busy(s.busy, "Slicer");
            std::vector<Section> out;
            {
              py::gil_scoped_release nogil;
              out = sweep_sections(s, model, n, d, xf, threads);
            }
            py::list result;
            for (Section& sec : out) result.append(py::cast(std::move(sec)));
            return result;
          },
          py::arg("model"), py::arg("normal"), py::arg("offsets"),
          py::arg("transform") = py::none(), py::arg("threads") = 1,
          "The Sections of the parallel planes normal . x = offsets[i] in one pass over the "
          "model (each exactly what slice() gives); threads > 1 (0: all cores) splits the "
          "layers between C++ threads.")
      .def(
          "sweep_volumes",
          [](PySlicer& s, const SliceModel& model, py::object normal, py::object offsets,
             const std::optional<AffineTransform>& transform, unsigned threads) {
            const Eigen::VectorXd n = to_vector(normal, "normal");
            const std::vector<double> d = to_offsets(offsets);
            const AffineTransform xf = or_identity(transform, model.dim());
            check_model_placement(model.complex(), xf);
            Busy busy(s.busy, "Slicer");
            std::vector<double> volumes;
            {
              py::gil_scoped_release nogil;
              s.slicer.sweep(model, n, d, xf, s.layers, threads);
              volumes.reserve(s.layers.size());
              for (const SliceBuffers& b : s.layers)
                volumes.push_back(b.empty() ? 0.0 : signed_volume(to_section(b).complex));
            }
            return adopt(std::move(volumes));
          },
          py::arg("model"), py::arg("normal"), py::arg("offsets"),
          py::arg("transform") = py::none(), py::arg("threads") = 1,
          "The section volume of every layer of a sweep, a new float64 array; all of it runs "
          "without the GIL.")
      .def_property_readonly(
          "reused_topology",
          [](PySlicer& s) {
            Busy busy(s.busy, "Slicer");
            return s.buffers.reused_topology;
          },
          "Whether the topology cache answered the last slice().")
      .def_property_readonly(
          "fast_slices",
          [](PySlicer& s) {
            Busy busy(s.busy, "Slicer");
            return s.slicer.fast_slices();
          },
          "Fast-path slices since construction.")
      .def_property_readonly(
          "cached_slices",
          [](PySlicer& s) {
            Busy busy(s.busy, "Slicer");
            return s.slicer.cached_slices();
          },
          "How many of them the topology cache answered.");

  py::class_<SceneObject>(m, "SceneObject", "One placed, colored model of a Scene.")
      .def_readonly("model", &SceneObject::model, "The model spec as written in the scene.")
      .def_readonly("name", &SceneObject::name)
      .def_readonly("transform", &SceneObject::transform, "model -> world")
      .def_property_readonly(
          "complex",
          [](const SceneObject& o) { return std::const_pointer_cast<Complex>(o.complex); },
          "The loaded model (shared by the objects with the same spec).")
      .def_property_readonly(
          "color",
          [](const SceneObject& o) {
            return py::make_tuple(o.color.r, o.color.g, o.color.b, o.color.a);
          },
          "(r, g, b, opacity), sRGB components in 0..1.");

  py::class_<Scene>(m, "Scene", "Placed, colored models read from JSON (see read_scene).")
      .def_readonly("objects", &Scene::objects)
      .def_property_readonly("dim", &Scene::dim)
      .def("__len__", [](const Scene& s) { return s.objects.size(); })
      .def("__repr__", [](const Scene& s) {
        return "<cw4d.Scene of " + std::to_string(s.objects.size()) + " objects in R^" +
               std::to_string(s.dim()) + ">";
      });
  py::class_<PySceneSlicer>(
      m, "SceneSlicer",
      "A Scene compiled for repeated slicing (one SliceModel per distinct model, each "
      "object's placement copied, bounding-sphere culling). Keeps the Scene alive. One per "
      "thread: a SceneSlicer used by two threads at once raises ValueError.")
      .def(py::init([](const Scene& scene, bool clustered) {
             check_scene_placement(scene);
             py::gil_scoped_release nogil;
             return std::make_unique<PySceneSlicer>(
                 scene, clustered ? SliceModelOptions{} : SliceModelOptions::unclustered());
           }),
           py::arg("scene"), py::arg("clustered") = true, py::keep_alive<1, 2>())
      .def("__len__", [](const PySceneSlicer& s) { return s.slicer.size(); })
      .def(
          "slice",
          [](PySceneSlicer& s, py::object normal, double offset, unsigned threads, bool cull) {
            const Hyperplane plane = to_plane(normal, offset);
            Busy busy(s.busy, "SceneSlicer");
            std::vector<Section> out;
            {
              py::gil_scoped_release nogil;
              SceneSlice cut;
              SliceOptions o;
              o.cull = cull;
              s.slicer.slice(plane, cut, threads, o);
              out = to_sections(cut, s.slicer.size());
            }
            py::list result;
            for (Section& sec : out) result.append(py::cast(std::move(sec)));
            return result;
          },
          py::arg("normal"), py::arg("offset"), py::arg("threads") = 1, py::arg("cull") = true,
          "The Section of every object (empty when the plane misses it), as section_objects() "
          "gives them; threads > 1 (0: all cores) cuts objects in parallel.")
      .def_property_readonly(
          "touched",
          [](PySceneSlicer& s) {
            Busy busy(s.busy, "SceneSlicer");
            return s.slicer.touched();
          },
          "Objects the last slice() did not cull.");

  m.def(
      "read_scene",
      [](const std::string& path) {
        py::gil_scoped_release nogil;
        return read_scene_file(path, default_catalogue());
      },
      py::arg("path"),
      "Reads a JSON scene file (model paths relative to its directory); ParseError names "
      "file:line.");
  m.def(
      "parse_scene",
      [](const std::string& text, const std::string& name, const std::string& base_directory) {
        std::istringstream in(text);
        py::gil_scoped_release nogil;
        return read_scene(in, name, base_directory, default_catalogue());
      },
      py::arg("text"), py::arg("name") = "<string>", py::arg("base_directory") = "",
      "A scene from JSON text; `name` is the file name in error messages.");
  m.def(
      "section_scene",
      [](const Scene& scene, py::object normal, double offset) {
        const Hyperplane plane = to_plane(normal, offset);
        check_scene_placement(scene);
        py::gil_scoped_release nogil;
        return section_scene(scene, plane);
      },
      py::arg("scene"), py::arg("normal"), py::arg("offset"),
      "One Section of every object (merged, face colors from the scene).");
  m.def(
      "section_objects",
      [](const Scene& scene, py::object normal, double offset) {
        const Hyperplane plane = to_plane(normal, offset);
        check_scene_placement(scene);
        py::gil_scoped_release nogil;
        return section_objects(scene, plane);
      },
      py::arg("scene"), py::arg("normal"), py::arg("offset"),
      "The Section of each object (empty for objects the plane misses).");
}

}  // namespace cw4d::python
