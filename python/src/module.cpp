// The _icrkit extension: geometry and file I/O, then the algorithms. icrkit's
// InputError (bad input: a file, an element, a parameter) becomes ValueError
// with the same message; any other C++ exception becomes RuntimeError.

#include <icrkit/core/error.hpp>

#include <pybind11/pybind11.h>

namespace py = pybind11;

namespace icrkit::python {
void bindGeometry(py::module_& m);
void bindAlgorithms(py::module_& m);
void bindEvaluation(py::module_& m);
void bindReconstructor(py::module_& m);
}  // namespace icrkit::python

PYBIND11_MODULE(_icrkit, m) {
  m.doc() = "icrkit: Independent Contact Regions on objects reconstructed from noisy range data (C++ core)";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const icrkit::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  icrkit::python::bindGeometry(m);
  icrkit::python::bindAlgorithms(m);
  icrkit::python::bindEvaluation(m);
  icrkit::python::bindReconstructor(m);
}
