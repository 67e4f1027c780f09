// geovor._geovor: the C++ library's products for the geovor Python package (python/geovor/).
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "geovor/core/error.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_geovor, m) {
  m.doc() = "geovor's C++ core; use the geovor package, which wraps it.";
  // The command's messages, as Python's exceptions: bad data and arguments are ValueError, files
  // OSError, a failed invariant RuntimeError.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const geovor::Error& e) {
      switch (e.code()) {
        case geovor::ErrorCode::InvalidArgument:
        case geovor::ErrorCode::BadData:
          PyErr_SetString(PyExc_ValueError, e.what());
          return;
        case geovor::ErrorCode::Io:
          PyErr_SetString(PyExc_OSError, e.what());
          return;
        case geovor::ErrorCode::Internal:
          PyErr_SetString(PyExc_RuntimeError, e.what());
          return;
      }
      PyErr_SetString(PyExc_RuntimeError, e.what());
    }
  });
  geovor::python::bind_spherical_voronoi(m);
  geovor::python::bind_index(m);
  geovor::python::bind_layers(m);
}
