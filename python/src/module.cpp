// The _cw4d extension module: the error classes and the helpers; the classes and functions are
// bound in bind_complex.cpp, bind_section.cpp and bind_output.cpp.
#include <cmath>
#include <exception>

#include "common.hpp"
#include "cw4d/complex/placement.hpp"

namespace cw4d::python {

Eigen::VectorXd to_vector(py::handle obj, const char* what) {
  // Lists and tuples of numbers need no numpy (cw4d imports without it; only arrays need it).
  if (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj)) {
    const auto seq = py::reinterpret_borrow<py::sequence>(obj);
    Eigen::VectorXd v(static_cast<Eigen::Index>(seq.size()));
    for (std::size_t i = 0; i < seq.size(); ++i) {
      py::handle item = seq[i];
      if (!PyNumber_Check(item.ptr()) || py::isinstance<py::str>(item))
        throw InputError(std::string(what) + " must be a 1-D sequence of numbers");
      v(static_cast<Eigen::Index>(i)) =
          py::cast<double>(py::float_(py::reinterpret_borrow<py::object>(item)));
    }
    return v;
  }
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  } catch (const py::error_already_set&) {
    a = {};
  }
  if (!a || a.ndim() != 1)
    throw InputError(std::string(what) + " must be a 1-D sequence of numbers");
  Eigen::VectorXd v(a.shape(0));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) v(i) = a.at(i);
  return v;
}

Eigen::MatrixXd to_points(py::handle obj, int n, const char* what) {
  auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!a) throw InputError(std::string(what) + " must be an array of numbers");
  if (a.ndim() == 1) a = a.reshape({py::ssize_t{1}, a.shape(0)});
  if (a.ndim() != 2 || a.shape(1) != n)
    throw InputError(std::string(what) + " must have shape (N, " + std::to_string(n) + ")");
  Eigen::MatrixXd m(n, a.shape(0));
  auto r = a.unchecked<2>();
  for (py::ssize_t j = 0; j < a.shape(0); ++j)
    for (int i = 0; i < n; ++i) m(i, j) = r(j, i);
  return m;
}

Hyperplane to_plane(py::handle normal, double offset) {
  return Hyperplane::from(to_vector(normal, "normal"), offset);
}

AffineTransform or_identity(const std::optional<AffineTransform>& t, int dim) {
  return t ? *t : AffineTransform(dim);
}

void check_model_placement(const Complex& model, const AffineTransform& model_to_world) {
  check_placement(model, model_to_world, "the model");
}

void check_scene_placement(const Scene& scene) {
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    check_placement(*o.complex, o.transform,
                    "object " + std::to_string(i) + " (" + o.model + ") of the scene");
  }
}

Eigen::Vector3d direction3(py::handle obj, const char* what) {
  const Eigen::VectorXd v = to_vector(obj, what);
  if (v.size() != 3) throw InputError(std::string(what) + " takes 3 components");
  if (!v.allFinite()) throw InputError(std::string(what) + " must be finite");
  const double big = v.cwiseAbs().maxCoeff();
  if (big == 0.0) throw InputError(std::string(what) + " must not be the zero vector");
  // Brought near unit length by a power of two (exact), as the CLI does, so that 1e300 or
  // 1e-300 components become neither infinite nor zero in float cameras and squared lengths.
  const int e = std::ilogb(big);
  return v.unaryExpr([e](double x) { return std::scalbn(x, -e); });
}

namespace {

PyObject* error_type = nullptr;
PyObject* input_error_type = nullptr;
PyObject* parse_error_type = nullptr;
PyObject* topology_error_type = nullptr;
PyObject* io_error_type = nullptr;

PyObject* new_error(py::module_& m, const char* name, py::tuple bases, const char* doc) {
  const std::string full = std::string("cw4d.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(full.c_str(), doc, bases.ptr(), nullptr);
  if (!type) throw py::error_already_set();
  m.add_object(name, py::handle(type));  // steals a reference; the module keeps the type
  Py_INCREF(type);
  return type;
}

// Raises `type` with the message and sets the given attributes on the instance.
void raise(PyObject* type, const char* message,
           std::initializer_list<std::pair<const char*, py::object>> attributes = {}) {
  py::object exc = py::reinterpret_borrow<py::object>(type)(message);
  for (const auto& [name, value] : attributes) exc.attr(name) = value;
  PyErr_SetObject(type, exc.ptr());
}

}  // namespace

}  // namespace cw4d::python

PYBIND11_MODULE(_cw4d, m) {
  using namespace cw4d::python;
  m.doc() =
      "cw4d: 4D polytopes as CW complexes and their hyperplane sections (the C++ extension; "
      "import cw4d, not this module).";

  const py::tuple base_only = py::make_tuple(py::handle(PyExc_RuntimeError));
  error_type = new_error(m, "Error", base_only, "Base of every error cw4d raises on purpose.");
  const py::handle error(error_type);
  input_error_type = new_error(m, "InputError", py::make_tuple(error, py::handle(PyExc_ValueError)),
                               "An argument that makes no sense (zero normal, unknown model spec, "
                               "wrong dimension, ...).");
  parse_error_type =
      new_error(m, "ParseError", py::make_tuple(error, py::handle(PyExc_ValueError)),
                "A file or text could not be parsed: str() is 'FILE:LINE: message'; the parts "
                "are .file, .line (1-based, 0 when the file could not be opened) and .message.");
  topology_error_type =
      new_error(m, "TopologyError", py::make_tuple(error, py::handle(PyExc_ValueError)),
                "The structure of a complex is broken: .rank and .ids name the elements.");
  io_error_type = new_error(m, "IoError", py::make_tuple(error, py::handle(PyExc_OSError)),
                            "Reading or writing a file failed at the operating-system level.");

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const cw4d::ParseError& e) {
      raise(parse_error_type, e.what(),
            {{"file", py::str(e.file())},
             {"line", py::int_(e.line())},
             {"message", py::str(e.message())}});
    } catch (const cw4d::TopologyError& e) {
      raise(topology_error_type, e.what(),
            {{"rank", py::int_(e.rank())}, {"ids", py::cast(e.ids())}});
    } catch (const cw4d::InputError& e) {
      raise(input_error_type, e.what());
    } catch (const cw4d::IoError& e) {
      raise(io_error_type, e.what());
    } catch (const cw4d::Error& e) {
      raise(error_type, e.what());
    }
  });

  bind_complex(m);
  bind_section(m);
  bind_output(m);
}
