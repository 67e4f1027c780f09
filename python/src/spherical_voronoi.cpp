// spherical_voronoi(points): the exact Voronoi diagram of unit vectors, in flat arrays by input
// point, for geovor.SphericalVoronoi (python/geovor/_spherical_voronoi.py).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "bindings.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace py = pybind11;

namespace geovor::python {
namespace {

py::dict spherical_voronoi(const py::array_t<double, py::array::c_style | py::array::forcecast>& points,
                           unsigned threads) {
  if (points.ndim() != 2 || points.shape(1) != 3)
    throw Error(ErrorCode::InvalidArgument, "points must be an array of shape (n, 3)");
  const std::size_t n = static_cast<std::size_t>(points.shape(0));
  const double* p = points.data();
  std::vector<Vec3> unit(n);
  for (std::size_t i = 0; i < n; ++i) unit[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};

  BuildReport report;
  SphericalDelaunay dt;
  VoronoiDiagram vd;
  {
    py::gil_scoped_release unlocked;
    dt = SphericalDelaunay::build(unit, {}, &report);
    vd.assign(dt, threads);
  }
  // The arrays are numpy's own, filled in place (no copies of the large ones).
  const std::size_t nv = vd.num_vertices();
  py::array_t<double> vertices({static_cast<py::ssize_t>(nv), py::ssize_t{3}});
  py::array_t<std::int64_t> site_of_input(static_cast<py::ssize_t>(n)), offsets(static_cast<py::ssize_t>(n + 1));
  py::array_t<double> areas(static_cast<py::ssize_t>(n));
  std::vector<std::int64_t> merged;  // pairs: input, the input whose site it went into
  std::vector<char> is_merged(n, 0);
  std::int64_t* region_offset = offsets.mutable_data();
  {
    py::gil_scoped_release unlocked;
    std::vector<std::int64_t> input_of_site(dt.site_capacity(), -1);
    std::int64_t* site = site_of_input.mutable_data();
    for (std::size_t i = 0; i < n; ++i) {
      const SiteId s = report.site_of_input[i];
      site[i] = s == kNoIndex ? -1 : static_cast<std::int64_t>(s);
      if (s != kNoIndex && input_of_site[s] < 0) input_of_site[s] = static_cast<std::int64_t>(i);
    }
    for (const Merge& mg : report.merges) {
      is_merged[mg.input] = 1;
      merged.push_back(mg.input);
      merged.push_back(mg.site == kNoIndex ? -1 : input_of_site[mg.site]);
    }
    double* v = vertices.mutable_data();
    parallel_for(nv, threads, [&](unsigned, std::size_t begin, std::size_t end) {
      for (std::size_t t = begin; t < end; ++t) {
        const Vec3& x = vd.vertex(static_cast<TriId>(t));
        v[3 * t] = x.x, v[3 * t + 1] = x.y, v[3 * t + 2] = x.z;
      }
    });
    region_offset[0] = 0;
    for (std::size_t i = 0; i < n; ++i)
      region_offset[i + 1] = region_offset[i] + (is_merged[i] || site[i] < 0 ? 0 : static_cast<std::int64_t>(
                                                     vd.cell_vertices(static_cast<SiteId>(site[i])).size()));
    double* area = areas.mutable_data();
    parallel_for(n, threads, [&](unsigned, std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        area[i] = is_merged[i] || site[i] < 0 ? 0.0 : vd.cell_area_sr(static_cast<SiteId>(site[i]));
    });
  }
  // regions as scipy has them: a list of lists of ints, made here (much faster than in Python).
  // Without the cyclic collector meanwhile (a million new lists would run it again and again),
  // and one int object per vertex, shared by the (three or more) regions that hold it.
  struct CollectorPause {
    int was_on = PyGC_Disable();
    ~CollectorPause() {
      if (was_on) PyGC_Enable();
    }
  } pause;
  std::vector<py::object> vertex_ints(nv);
  py::list regions(n);
  const std::int64_t* site = site_of_input.data();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t size = static_cast<std::size_t>(region_offset[i + 1] - region_offset[i]);
    PyObject* list = PyList_New(static_cast<Py_ssize_t>(size));
    if (list == nullptr) throw py::error_already_set();
    PyList_SET_ITEM(regions.ptr(), static_cast<Py_ssize_t>(i), list);
    if (size == 0) continue;
    const std::span<const TriId> cell = vd.cell_vertices(static_cast<SiteId>(site[i]));
    for (std::size_t k = 0; k < size; ++k) {
      py::object& value = vertex_ints[cell[k]];
      if (!value) value = py::int_(cell[k]);
      PyList_SET_ITEM(list, static_cast<Py_ssize_t>(k), value.inc_ref().ptr());
    }
  }
  py::array_t<std::int64_t> merged_array({static_cast<py::ssize_t>(merged.size() / 2), py::ssize_t{2}});
  std::copy(merged.begin(), merged.end(), merged_array.mutable_data());
  py::dict out;
  out["site_of_input"] = site_of_input;
  out["vertices"] = vertices;
  out["region_offsets"] = offsets;
  out["regions"] = regions;
  out["areas_sr"] = areas;
  out["merged"] = merged_array;
  return out;
}

}  // namespace

void bind_spherical_voronoi(py::module_& m) {
  m.def("spherical_voronoi", &spherical_voronoi, py::arg("points"), py::arg("threads") = 0,
        "The exact Voronoi diagram of unit vectors (n, 3): a dict of flat arrays by input point.");
}

}  // namespace geovor::python
