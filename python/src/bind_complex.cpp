// Complex, AffineTransform, validation, the model builders and the operators.
#include <cmath>
#include <sstream>

#include "common.hpp"
#include "cw4d/complex/builder.hpp"
#include "cw4d/complex/builtins.hpp"
#include "cw4d/complex/complex.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/mass.hpp"
#include "cw4d/complex/off_io.hpp"
#include "cw4d/complex/operators.hpp"
#include "cw4d/complex/toratopes.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/complex/validate.hpp"
#include "cw4d/complex/wythoff.hpp"
#include "cw4d/tetrahedralize/catalogue.hpp"

namespace cw4d::python {

namespace {

void check_rank(const Complex& c, int rank) {
  if (rank < 1 || rank > c.top_rank())
    throw py::index_error("rank " + std::to_string(rank) + " has no boundary table (ranks 1.." +
                          std::to_string(c.top_rank()) + ")");
}

std::string fvector_text(const std::vector<std::size_t>& f) {
  std::string s = "(";
  for (std::size_t i = 0; i < f.size(); ++i) s += (i ? ", " : "") + std::to_string(f[i]);
  return s + ")";
}

Eigen::MatrixXd to_matrix(py::handle obj, const char* what) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 2) throw InputError(std::string(what) + " must be a 2-D array");
  Eigen::MatrixXd m(a.shape(0), a.shape(1));
  auto r = a.unchecked<2>();
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    for (py::ssize_t j = 0; j < a.shape(1); ++j) m(i, j) = r(i, j);
  return m;
}

py::array_t<double> matrix_copy(const Eigen::MatrixXd& m) {
  py::array_t<double> a({m.rows(), m.cols()});
  auto w = a.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.rows(); ++i)
    for (Eigen::Index j = 0; j < m.cols(); ++j) w(i, j) = m(i, j);
  return a;
}

// A transform built from Python numbers: NaN or infinite entries are refused here, where the
// user typed them, rather than when a cut finds nothing.
AffineTransform finite_transform(AffineTransform t, const char* what) {
  if (!t.linear().allFinite() || !t.translation().allFinite())
    throw InputError(std::string(what) + " must be finite (NaN or infinite entry)");
  return t;
}

std::vector<std::uint32_t> to_ids(py::handle obj, const char* what) {
  auto a = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a || a.ndim() != 1) throw InputError(std::string(what) + " must be a 1-D list of ids");
  std::vector<std::uint32_t> ids;
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    if (a.at(i) < 0 || a.at(i) > 0xfffffffeLL)
      throw InputError(std::string(what) + " holds the id " + std::to_string(a.at(i)) +
                       ", outside 0..2^32-2");
    ids.push_back(static_cast<std::uint32_t>(a.at(i)));
  }
  return ids;
}

}  // namespace

void bind_complex(py::module_& m) {
  py::class_<ValidationIssue>(m, "ValidationIssue", "One problem found by validate().")
      .def_readonly("rank", &ValidationIssue::rank, "Rank of the offending element.")
      .def_readonly("id", &ValidationIssue::id, "Its id.")
      .def_readonly("what", &ValidationIssue::what, "One-line description.")
      .def("__repr__", [](const ValidationIssue& i) {
        return "ValidationIssue(rank=" + std::to_string(i.rank) + ", id=" + std::to_string(i.id) +
               ", what=" + py::repr(py::str(i.what)).cast<std::string>() + ")";
      });

  py::class_<ValidationReport>(m, "ValidationReport",
                               "What validate() found; true when the complex is valid.")
      .def_readonly("issues", &ValidationReport::issues)
      .def_property_readonly("ok", &ValidationReport::ok)
      .def("__bool__", &ValidationReport::ok)
      .def("summary", &ValidationReport::summary, py::arg("max_issues") = 5,
           "'valid', or the first few issues joined by '; ' with a count of the rest.")
      .def("__repr__",
           [](const ValidationReport& r) { return "<ValidationReport " + r.summary() + ">"; });

  py::class_<Complex, std::shared_ptr<Complex>>(
      m, "Complex",
      "A ranked CW complex: vertex positions (rank 0) and signed boundary tables of ranks "
      "1..top_rank in compressed rows. Closed complexes in R^n store the outward-oriented "
      "boundary of a solid. Immutable from Python.")
      .def_property_readonly("dim", &Complex::ambient_dim, "Dimension n of the ambient space R^n.")
      .def_property_readonly("top_rank", &Complex::top_rank, "Highest rank with a boundary table.")
      .def_property_readonly(
          "fvector", [](const Complex& c) { return py::tuple(py::cast(c.fvector())); },
          "Element counts of ranks 0..top_rank, as a tuple.")
      .def("count", &Complex::count, py::arg("rank"), "Number of elements of a rank.")
      .def_property_readonly(
          "positions",
          [](py::object self) {
            const Complex& c = self.cast<const Complex&>();
            return view(c.positions().data(), static_cast<py::ssize_t>(c.count(0)), c.ambient_dim(),
                        self);
          },
          "Vertex coordinates, a read-only (V, n) float64 view of the complex's own storage "
          "(no copy).")
      .def_property_readonly(
          "facet_normals",
          [](py::object self) {
            const Complex& c = self.cast<const Complex&>();
            return view(c.facet_normals().data(), c.facet_normals().cols(), c.ambient_dim(), self);
          },
          "Outward unit normals of the facets (rank n-1), a read-only (F, n) view (no copy); "
          "F = 0 when not computed.")
      .def(
          "boundary",
          [](py::object self, int rank) {
            const Complex& c = self.cast<const Complex&>();
            check_rank(c, rank);
            const Incidence& b = c.boundary(rank);
            return py::make_tuple(
                view(b.offsets().data(), static_cast<py::ssize_t>(b.offsets().size()), 0, self),
                view(b.all_ids().data(), static_cast<py::ssize_t>(b.all_ids().size()), 0, self),
                view(b.all_signs().data(), static_cast<py::ssize_t>(b.all_signs().size()), 0,
                     self));
          },
          py::arg("rank"),
          "The boundary table of a rank as (offsets, ids, signs): row i is "
          "ids[offsets[i]:offsets[i+1]] (elements of rank-1) with signs +1/-1. Read-only "
          "uint32/uint32/int8 views of the complex's storage (no copy).")
      .def(
          "face_cycle",
          [](const Complex& c, std::uint32_t f) {
            check_rank(c, 2);
            if (f >= c.count(2))
              throw py::index_error("face " + std::to_string(f) + " out of range");
            return adopt(c.face_cycle(f));
          },
          py::arg("face"), "Vertex ids of a face in cycle order (a new array).")
      .def(
          "vertices_of",
          [](const Complex& c, int rank, std::uint32_t i) {
            check_rank(c, rank);
            if (i >= c.count(rank)) throw py::index_error("element out of range");
            return adopt(c.vertices_of(rank, i));
          },
          py::arg("rank"), py::arg("id"), "Sorted vertex ids of an element (a new array).")
      .def(
          "validate",
          [](const Complex& c, bool require_closed, bool require_planar_facets) {
            ValidateOptions o;
            o.require_closed = require_closed;
            o.require_planar_facets = require_planar_facets;
            py::gil_scoped_release nogil;
            return validate(c, o);
          },
          py::arg("require_closed") = true, py::arg("require_planar_facets") = true,
          "Checks the structure (and, by default, that it is a closed, outward, planar "
          "boundary); returns a ValidationReport naming every offending element.")
      .def_property_readonly(
          "volume", [](const Complex& c) { return signed_volume(c); },
          "Signed n-volume enclosed by the facets (positive when outward).")
      .def(
          "mass_properties",
          [](const Complex& c) {
            MassProperties m;
            {
              py::gil_scoped_release nogil;
              m = mass_properties(c);
            }
            const auto n = static_cast<py::ssize_t>(m.dim);
            std::vector<double> centroid(m.centroid.data(), m.centroid.data() + n);
            std::vector<double> second(static_cast<std::size_t>(n * n));
            for (py::ssize_t i = 0; i < n; ++i)
              for (py::ssize_t j = 0; j < n; ++j)
                second[static_cast<std::size_t>(i * n + j)] = m.second_moment(i, j);
            py::dict d;
            d["hypervolume"] = m.hypervolume;
            d["boundary_volume"] = m.boundary_volume;
            d["centroid"] = adopt(std::move(centroid));
            d["second_moment"] = adopt(std::move(second), n);
            d["winding_weighted"] = m.winding_weighted;
            return d;
          },
          "Mass properties of the solid of density 1 the closed model bounds, exact to rounding: "
          "a dict with 'hypervolume', 'boundary_volume' (the facets' (n-1)-volume), 'centroid' "
          "(n,), 'second_moment' (n, n) = int x x^T dV about the origin, and "
          "'winding_weighted' (True for a star model: the values are weighted by the winding "
          "number). Raises TopologyError for a model that is not closed.")
      .def(
          "element_volume",
          [](const Complex& c, int rank, std::uint32_t i) {
            check_rank(c, rank);
            if (i >= c.count(rank)) throw py::index_error("element out of range");
            return element_volume(c, rank, i);
          },
          py::arg("rank"), py::arg("id"), "k-volume of element id of rank k.")
      .def(
          "bounds",
          [](const Complex& c) {
            const Bounds b = bounds(c);
            std::vector<double> lo(b.min.data(), b.min.data() + b.min.size());
            std::vector<double> hi(b.max.data(), b.max.data() + b.max.size());
            return py::make_tuple(adopt(std::move(lo)), adopt(std::move(hi)));
          },
          "Axis-aligned bounds (min, max), two new arrays of n entries.")
      .def_property_readonly("has_solid", &Complex::has_solid,
                             "Whether the rank-n element (the solid) is stored.")
      .def(
          "is_convex", [](const Complex& c) { return is_convex(c); },
          "Whether every vertex lies inside every facet hyperplane (needs facet normals).")
      .def(
          "transformed",
          [](const Complex& c, const AffineTransform& t) {
            py::gil_scoped_release nogil;
            return transformed(c, t);
          },
          py::arg("transform"),
          "A copy placed by the transform (normals and orientation kept outward).")
      .def("__repr__", [](const Complex& c) {
        return "<cw4d.Complex in R^" + std::to_string(c.ambient_dim()) + ", f-vector " +
               fvector_text(c.fvector()) + ">";
      });

  py::class_<AffineTransform>(
      m, "AffineTransform",
      "x -> A x + t on R^n. Compose with @ (a @ b applies b first); apply to (n,) or (N, n) "
      "points with apply() or __call__.")
      .def(py::init([](py::object linear, py::object translation, int dim) {
             if (linear.is_none() && translation.is_none()) return AffineTransform(dim);
             if (!linear.is_none()) {
               Eigen::MatrixXd a = to_matrix(linear, "linear");
               if (a.rows() != a.cols()) throw InputError("linear must be a square matrix");
               Eigen::VectorXd t = translation.is_none() ? Eigen::VectorXd::Zero(a.rows())
                                                         : to_vector(translation, "translation");
               if (t.size() != a.rows())
                 throw InputError("translation must have as many entries as linear has rows");
               return finite_transform(AffineTransform(std::move(a), std::move(t)),
                                       "an AffineTransform");
             }
             Eigen::VectorXd t = to_vector(translation, "translation");
             return finite_transform(AffineTransform::translation(t), "translation");
           }),
           py::arg("linear") = py::none(), py::arg("translation") = py::none(), py::arg("dim") = 4,
           "From an (n, n) matrix and an optional translation (numpy or sequences); with "
           "neither, the identity of R^dim.")
      .def_static(
          "from_matrix",
          [](py::object matrix) {
            Eigen::MatrixXd h = to_matrix(matrix, "matrix");
            const Eigen::Index n = h.rows() - 1;
            if (h.rows() != h.cols() || n < 1)
              throw InputError("matrix must be square, (n+1) x (n+1)");
            if (!h.row(n).head(n).isZero(0.0) || h(n, n) != 1.0)
              throw InputError("the last row of a homogeneous matrix must be (0, ..., 0, 1)");
            return finite_transform(AffineTransform(h.topLeftCorner(n, n), h.col(n).head(n)),
                                    "matrix");
          },
          py::arg("matrix"), "From an (n+1, n+1) homogeneous matrix.")
      .def_static("identity", &AffineTransform::identity, py::arg("dim") = 4)
      .def_static(
          "rotation",
          [](py::object plane, double angle, int dim, bool degrees) {
            int i = 0, j = 0;
            if (py::isinstance<py::str>(plane)) {
              std::tie(i, j) = parse_rotation_plane(plane.cast<std::string>());
            } else {
              auto ij = plane.cast<std::pair<int, int>>();
              i = ij.first;
              j = ij.second;
            }
            if (i < 0 || j < 0 || i >= dim || j >= dim || i == j)
              throw InputError("rotation axes must be two distinct axes of R^" +
                               std::to_string(dim));
            if (!std::isfinite(angle)) throw InputError("the rotation angle must be finite");
            return AffineTransform::rotation(
                dim, i, j, degrees ? angle * 3.14159265358979323846 / 180.0 : angle);
          },
          py::arg("plane"), py::arg("angle"), py::arg("dim") = 4, py::arg("degrees") = false,
          "Rotation in the plane of two axes, given as 'xw', 'yz', ... or (i, j): e_i turns "
          "towards e_j by angle (radians unless degrees=True).")
      .def_static(
          "translation",
          [](py::object t) {
            return finite_transform(AffineTransform::translation(to_vector(t, "translation")),
                                    "translation");
          },
          py::arg("t"))
      .def_static(
          "scale",
          [](py::object s, int dim) {
            if (py::isinstance<py::float_>(s) || py::isinstance<py::int_>(s))
              return finite_transform(AffineTransform::scale(dim, s.cast<double>()), "scale");
            return finite_transform(AffineTransform::scale(to_vector(s, "scale")), "scale");
          },
          py::arg("s"), py::arg("dim") = 4, "Uniform (a number) or per-axis (a sequence) scale.")
      .def_property_readonly("dim", &AffineTransform::dim)
      .def_property_readonly(
          "linear", [](const AffineTransform& t) { return matrix_copy(t.linear()); },
          "The (n, n) matrix A (a new array).")
      .def_property_readonly(
          "translation_vector",
          [](const AffineTransform& t) {
            const auto& v = t.translation();
            return adopt(std::vector<double>(v.data(), v.data() + v.size()));
          },
          "The translation t (a new array).")
      .def_property_readonly(
          "matrix",
          [](const AffineTransform& t) {
            const int n = t.dim();
            Eigen::MatrixXd h = Eigen::MatrixXd::Identity(n + 1, n + 1);
            h.topLeftCorner(n, n) = t.linear();
            h.col(n).head(n) = t.translation();
            return matrix_copy(h);
          },
          "The (n+1, n+1) homogeneous matrix (a new array).")
      .def("inverse", &AffineTransform::inverse)
      .def("is_identity", &AffineTransform::is_identity)
      .def("__matmul__",
           [](const AffineTransform& a, const AffineTransform& b) {
             return finite_transform(a * b, "the product of the transforms");
           })
      .def(
          "apply",
          [](const AffineTransform& t, py::object points) {
            auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(points);
            const bool single = a && a.ndim() == 1;
            Eigen::MatrixXd p = to_points(points, t.dim(), "points");
            Eigen::MatrixXd q = (t.linear() * p).colwise() + t.translation();
            std::vector<double> out(q.data(), q.data() + q.size());  // column-major = (N, n)
            return single ? py::object(adopt(std::move(out)))
                          : py::object(adopt(std::move(out), t.dim()));
          },
          py::arg("points"), "A x + t for an (n,) point or (N, n) points (a new array).")
      .def("__call__",
           [](py::object self, py::object points) { return self.attr("apply")(points); })
      .def("__repr__", [](const AffineTransform& t) {
        std::ostringstream s;
        s << "<cw4d.AffineTransform of R^" << t.dim() << (t.is_identity() ? ", identity>" : ">");
        return s.str();
      });

  m.def(
      "load_model",
      [](const std::string& spec) {
        py::gil_scoped_release nogil;
        return load_model(spec, default_catalogue());
      },
      py::arg("spec"),
      "The model of a spec as the CLI takes it: a built-in ('tesseract', '120-cell', "
      "'duoprism:5,7', 'wythoff:x3o4o3o', ...; see builtin_list()) or a .4off/.off file.");
  m.def(
      "builtin_list",
      [] {
        std::vector<std::pair<std::string, std::string>> out;
        for (const auto& b : builtin_list(default_catalogue()))
          out.emplace_back(b.spec, b.description);
        return out;
      },
      "Every built-in model spec with its description, as (spec, description) pairs.");
  m.def(
      "read_off",
      [](const std::string& path) {
        py::gil_scoped_release nogil;
        return read_off_file(path);
      },
      py::arg("path"),
      "Reads a 4OFF / OFF / nOFF file (oriented, with facet normals, not validated). Raises "
      "ParseError with .file and .line.");
  m.def(
      "parse_off",
      [](const std::string& text, const std::string& name) {
        std::istringstream in(text);
        return read_off(in, name);
      },
      py::arg("text"), py::arg("name") = "<string>",
      "Reads nOFF text; `name` is the file name in error messages.");
  m.def(
      "off_text",
      [](const Complex& c) {
        std::ostringstream out;
        write_off(out, c);
        return out.str();
      },
      py::arg("complex"), "The complex as nOFF text.");
  m.def(
      "wythoff",
      [](const std::string& diagram) {
        py::gil_scoped_release nogil;
        return make_wythoff(diagram);
      },
      py::arg("diagram"),
      "The uniform polytope of a linear Coxeter-Dynkin diagram, e.g. 'x3o4o3o' (24-cell); "
      "centred, every edge of length 2.");
  m.def("uniform_polychoron_diagram", &uniform_polychoron_diagram, py::arg("name"),
        "The diagram of a convex uniform polychoron named in English ('truncated tesseract' "
        "-> 'x4x3o3o'), or None.");
  m.def(
      "build_complex",
      [](py::object positions, py::object faces, py::object cells, py::object edges) {
        ComplexSoup soup;
        auto pos =
            py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(positions);
        if (!pos || pos.ndim() != 2 || pos.shape(1) < 1)
          throw InputError("positions must be a (V, n) array");
        soup.ambient_dim = static_cast<int>(pos.shape(1));
        soup.positions = to_points(positions, soup.ambient_dim, "positions");
        for (py::handle f : faces) soup.faces.push_back(to_ids(f, "a face"));
        if (!cells.is_none()) {
          for (py::handle level : cells) {
            soup.higher.emplace_back();
            for (py::handle c : level) soup.higher.back().push_back(to_ids(c, "a cell"));
          }
        }
        if (!edges.is_none())
          for (py::handle e : edges) {
            auto ids = to_ids(e, "an edge");
            if (ids.size() != 2) throw InputError("an edge has two vertex ids");
            soup.edges.push_back({ids[0], ids[1]});
          }
        py::gil_scoped_release nogil;
        return build_complex(soup);
      },
      py::arg("positions"), py::arg("faces"), py::arg("cells") = py::none(),
      py::arg("edges") = py::none(),
      "A complex from numpy: positions (V, n), faces as vertex cycles, and cells as "
      "[[face ids of each 3-cell], [cell ids of each 4-cell], ...] (rank 3 first). Edges come "
      "from the face cycles; signs, outward orientation and facet normals are solved.");

  m.def("simplex", &make_simplex, py::arg("n"), "Regular n-simplex, circumradius 1.");
  m.def("cube", &make_cube, py::arg("n"), "The n-cube [-1, 1]^n.");
  m.def("orthoplex", &make_orthoplex, py::arg("n"), "The n-orthoplex, vertices +-e_i.");
  m.def("polygon", &make_polygon, py::arg("p"), "Regular p-gon, circumradius 1.");
  m.def("duoprism", &make_duoprism, py::arg("p"), py::arg("q"), "The p,q-duoprism.");
  m.def("product", &make_product, py::arg("p"), py::arg("q"),
        "Cartesian product of two closed complexes.");
  m.def("pyramid", &make_pyramid, py::arg("base"), py::arg("height"),
        "Pyramid over a closed complex in R^n, a closed complex in R^(n+1).");
  m.def("prism", &make_prism, py::arg("base"), py::arg("height") = 2.0,
        "base x [-height/2, height/2].");
  m.def(
      "dual",
      [](const Complex& c, std::optional<double> radius) {
        return radius ? make_dual(c, *radius) : make_dual_same_size(c);
      },
      py::arg("convex"), py::arg("radius") = py::none(),
      "Polar dual of a convex polytope about its vertex centroid (same circumradius when "
      "radius is None).");
  m.def("antiprism", &make_antiprism, py::arg("n"), "Uniform n-gonal antiprism in R^3.");
  m.def("uv_sphere", &make_uv_sphere, py::arg("r"), py::arg("n"), "Polyhedral sphere in R^3.");
  m.def("spin", &make_spin, py::arg("polyhedron"), py::arg("steps"),
        "Solid of revolution in R^4 of a polyhedron in x >= 0 (turned in the xw plane).");
  m.def("torus", &make_torus, py::arg("major"), py::arg("minor"), py::arg("n"),
        "Polyhedral torus of revolution about z in R^3.");
  m.def(
      "transformed", [](const Complex& c, const AffineTransform& t) { return transformed(c, t); },
      py::arg("complex"), py::arg("transform"), "complex.transformed(transform).");
  m.def(
      "validate",
      [](const Complex& c, bool require_closed, bool require_planar_facets) {
        ValidateOptions o;
        o.require_closed = require_closed;
        o.require_planar_facets = require_planar_facets;
        py::gil_scoped_release nogil;
        return validate(c, o);
      },
      py::arg("complex"), py::arg("require_closed") = true, py::arg("require_planar_facets") = true,
      "complex.validate(...).");
}

}  // namespace cw4d::python
