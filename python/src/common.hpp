#pragma once
// Helpers shared by the binding translation units: numpy views of C++ storage (zero-copy, kept
// alive by a Python owner), arrays that take over a computed std::vector, and argument checks.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/scene.hpp"
#include "cw4d/complex/transform.hpp"
#include "cw4d/section/hyperplane.hpp"

namespace cw4d::python {

namespace py = pybind11;

/// A read-only numpy view of `count` rows of `row_size` T's (or a flat array when row_size is
/// 0) at `data`, whose memory belongs to `owner`: numpy keeps `owner` alive through .base.
template <class T>
py::array_t<T> view(const T* data, py::ssize_t count, py::ssize_t row_size, py::handle owner,
                    py::ssize_t stride_bytes = 0) {
  static const T empty{};
  if (data == nullptr) data = &empty;  // numpy wants an address even for zero elements
  std::vector<py::ssize_t> shape, strides;
  const py::ssize_t step = stride_bytes ? stride_bytes : static_cast<py::ssize_t>(sizeof(T));
  if (row_size == 0) {
    shape = {count};
    strides = {step};
  } else {
    shape = {count, row_size};
    strides = {row_size * step, step};
  }
  py::array_t<T> a(shape, strides, data, owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

/// A numpy array that takes over a vector's storage (no copy): shape (count,) or (count, row).
template <class T>
py::array_t<T> adopt(std::vector<T>&& values, py::ssize_t row_size = 0) {
  auto* owned = new std::vector<T>(std::move(values));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  const auto n = static_cast<py::ssize_t>(owned->size());
  if (row_size == 0)
    return py::array_t<T>({n}, {static_cast<py::ssize_t>(sizeof(T))}, owned->data(),
                          free_when_done);
  return py::array_t<T>(
      {n / row_size, row_size},
      {row_size * static_cast<py::ssize_t>(sizeof(T)), static_cast<py::ssize_t>(sizeof(T))},
      owned->data(), free_when_done);
}

/// Any 1-D sequence of numbers as an Eigen vector. \throw InputError naming `what`.
Eigen::VectorXd to_vector(py::handle obj, const char* what);
/// (N, n) points (or one (n,) point) as an n x N Eigen matrix.
Eigen::MatrixXd to_points(py::handle obj, int n, const char* what);
/// The plane {x : (n/|n|) . x = d}. \throw InputError for a zero or non-finite normal.
Hyperplane to_plane(py::handle normal, double offset);
/// The transform or the identity of dimension dim.
AffineTransform or_identity(const std::optional<AffineTransform>& t, int dim);
/// The CLI's check of a placement (check_placement), for a model cut from Python: a transform
/// that is not finite, or that puts the model beyond 1e100 or makes it thinner than 1e-100,
/// raises InputError instead of giving an empty section.
void check_model_placement(const Complex& model, const AffineTransform& model_to_world);
/// check_placement of every object of a scene, named "object i (spec) of the scene".
void check_scene_placement(const Scene& scene);
/// A finite, nonzero direction of 3 components (view_from, light_from). \throw InputError
Eigen::Vector3d direction3(py::handle obj, const char* what);

void bind_complex(py::module_& m);
void bind_section(py::module_& m);
void bind_output(py::module_& m);

}  // namespace cw4d::python
