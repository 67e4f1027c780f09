// The pieces of the geovor._geovor extension module, one per concept, registered by module.cpp.
#pragma once

#include <pybind11/pybind11.h>

namespace geovor::python {

void bind_spherical_voronoi(pybind11::module_& m);
void bind_index(pybind11::module_& m);
void bind_layers(pybind11::module_& m);

}  // namespace geovor::python
