#pragma once
// NumPy <-> icrkit arrays: strict checks with messages that say what was
// expected, and views (no copies) onto the data of a C++ object that a
// Python object keeps alive.

#include <icrkit/core/point_cloud.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace icrkit::python {

namespace py = pybind11;

inline std::string describe(const py::array& a) {
  std::string shape = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
  shape += a.ndim() == 1 ? ",)" : ")";
  return std::string(py::str(a.dtype())) + " array of shape " + shape;
}

/// An (N, 3) C-contiguous float64 array as 3-vectors (copied: icrkit's types
/// own their data). ValueError naming `what` otherwise.
inline std::vector<Eigen::Vector3d> toVectors(const py::handle& object, const char* what) {
  if (!py::isinstance<py::array>(object))
    throw py::value_error(std::string(what) + ": expected a numpy float64 array of shape (N, 3)");
  const py::array a = py::reinterpret_borrow<py::array>(object);
  if (!a.dtype().is(py::dtype::of<double>()) || a.ndim() != 2 || a.shape(1) != 3)
    throw py::value_error(std::string(what) + ": expected a float64 array of shape (N, 3), got a " + describe(a) +
                          " (convert with numpy.asarray(x, dtype=numpy.float64).reshape(-1, 3))");
  if (!(a.flags() & py::array::c_style))
    throw py::value_error(std::string(what) + ": the array is not C-contiguous (use numpy.ascontiguousarray)");
  const auto* data = static_cast<const double*>(a.data());
  std::vector<Eigen::Vector3d> out(static_cast<std::size_t>(a.shape(0)));
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = Eigen::Vector3d(data[3 * i], data[3 * i + 1], data[3 * i + 2]);
  return out;
}

/// A read-write (N, 3) float64 view onto `vectors`, kept alive by `owner`.
inline py::array_t<double> viewOf(std::vector<Eigen::Vector3d>& vectors, py::handle owner) {
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "Vector3d must be three packed doubles");
  return py::array_t<double>({static_cast<py::ssize_t>(vectors.size()), py::ssize_t{3}},
                             {static_cast<py::ssize_t>(sizeof(Eigen::Vector3d)), static_cast<py::ssize_t>(sizeof(double))},
                             vectors.empty() ? nullptr : vectors.front().data(), owner);
}

/// A copy of `vectors` as a new (N, 3) float64 array.
inline py::array_t<double> copyOf(const std::vector<Eigen::Vector3d>& vectors) {
  py::array_t<double> out({static_cast<py::ssize_t>(vectors.size()), py::ssize_t{3}});
  auto* data = out.mutable_data();
  for (std::size_t i = 0; i < vectors.size(); ++i)
    for (int k = 0; k < 3; ++k) data[3 * i + static_cast<std::size_t>(k)] = vectors[i][k];
  return out;
}

/// Poses as a new (K, 4, 4) float64 array.
inline py::array_t<double> posesArray(const std::vector<Eigen::Isometry3d>& poses) {
  py::array_t<double> out({static_cast<py::ssize_t>(poses.size()), py::ssize_t{4}, py::ssize_t{4}});
  auto view = out.mutable_unchecked<3>();
  for (std::size_t k = 0; k < poses.size(); ++k)
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) view(static_cast<py::ssize_t>(k), i, j) = poses[k].matrix()(i, j);
  return out;
}

/// A PointCloud from (N, 3) arrays of points and, unless None, normals
/// (geometry_bindings.cpp).
PointCloud cloudFromPython(const py::handle& points, const py::handle& normals);

}  // namespace icrkit::python
