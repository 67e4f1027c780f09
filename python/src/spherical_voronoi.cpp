// spherical_voronoi(points): the exact Voronoi diagram of the directions of points, in flat arrays by input
// point, for geovor.SphericalVoronoi (python/geovor/_spherical_voronoi.py).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <type_traits>
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
  // Divided by the length as numpy's points / np.linalg.norm(points, axis=1)[:, None] does.
  for (std::size_t i = 0; i < n; ++i) {
    const double x = p[3 * i], y = p[3 * i + 1], z = p[3 * i + 2];
    const double len = std::sqrt(x * x + y * y + z * z);
    unit[i] = {x / len, y / len, z / len};
  }

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
    region_offset[0] = 0;
    for (std::size_t i = 0; i < n; ++i)
      region_offset[i + 1] = region_offset[i] + (is_merged[i] || site[i] < 0 ? 0 : static_cast<std::int64_t>(
                                                     vd.cell_vertices(static_cast<SiteId>(site[i])).size()));
  }
  // The regions' vertices, flat; regions_lists makes scipy's lists of them when they are asked for.
  py::array_t<std::uint32_t> region_vertices(static_cast<py::ssize_t>(region_offset[n]));
  {
    py::gil_scoped_release unlocked;
    // The areas in the diagram's storage order, whose neighbouring cells share vertices (in cache),
    // not in input order (random points: a cache miss per vertex).
    const std::span<const SiteId> order = vd.storage_order();
    std::vector<double> area_of_site(dt.site_capacity(), 0.0);
    parallel_for(order.size(), threads, [&](unsigned, std::size_t begin, std::size_t end) {
      for (std::size_t j = begin; j < end; ++j) area_of_site[order[j]] = vd.cell_area_sr(order[j]);
    });
    const std::int64_t* site = site_of_input.data();
    std::uint32_t* flat = region_vertices.mutable_data();
    double* area = areas.mutable_data();
    parallel_for(n, threads, [&](unsigned, std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        if (is_merged[i] || site[i] < 0) {
          area[i] = 0.0;
          continue;
        }
        const SiteId s = static_cast<SiteId>(site[i]);
        std::copy_n(vd.cell_vertices(s).begin(), region_offset[i + 1] - region_offset[i], flat + region_offset[i]);
        area[i] = area_of_site[s];
      }
    });
  }
  py::array_t<std::int64_t> merged_array({static_cast<py::ssize_t>(merged.size() / 2), py::ssize_t{2}});
  std::copy(merged.begin(), merged.end(), merged_array.mutable_data());
  // The vertices are the diagram's own array, handed to numpy (no copy of 2n - 4 vertices).
  static_assert(sizeof(Vec3) == 3 * sizeof(double) && std::is_standard_layout_v<Vec3>);
  auto* owned = new std::vector<Vec3>(vd.release_vertices());
  py::capsule owner(owned, [](void* v) { delete static_cast<std::vector<Vec3>*>(v); });
  py::array_t<double> vertices({static_cast<py::ssize_t>(nv), py::ssize_t{3}},
                               {static_cast<py::ssize_t>(sizeof(Vec3)), static_cast<py::ssize_t>(sizeof(double))},
                               owned->empty() ? nullptr : &owned->front().x, owner);
  py::dict out;
  out["site_of_input"] = site_of_input;
  out["vertices"] = vertices;
  out["region_offsets"] = offsets;
  out["region_vertices"] = region_vertices;
  out["areas_sr"] = areas;
  out["merged"] = merged_array;
  return out;
}

// regions_lists(offsets, flat): [flat[offsets[i]:offsets[i + 1]] as a list of ints for each i],
// made here (much faster than in Python): without the cyclic collector meanwhile (a million new
// lists would run it again and again), and one int object per distinct vertex, shared by the
// (three or more) regions that hold it.
py::list regions_lists(const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& offsets,
                       const py::array_t<std::uint32_t, py::array::c_style | py::array::forcecast>& flat) {
  if (offsets.ndim() != 1 || offsets.shape(0) < 1 || flat.ndim() != 1)
    throw Error(ErrorCode::InvalidArgument, "regions_lists: offsets (n + 1,) and flat (m,) arrays expected");
  const std::size_t n = static_cast<std::size_t>(offsets.shape(0)) - 1;
  const std::int64_t* offset = offsets.data();
  const std::uint32_t* value = flat.data();
  const std::int64_t m = flat.shape(0);
  std::uint32_t largest = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (offset[i] < 0 || offset[i] > offset[i + 1] || offset[i + 1] > m)
      throw Error(ErrorCode::InvalidArgument, "regions_lists: offsets not increasing within flat");
  for (std::int64_t k = 0; k < m; ++k) largest = std::max(largest, value[k]);
  struct CollectorPause {
    int was_on = PyGC_Disable();
    ~CollectorPause() {
      if (was_on) PyGC_Enable();
    }
  } pause;
  std::vector<py::object> ints(m > 0 ? std::size_t{largest} + 1 : 0);
  py::list regions(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::int64_t size = offset[i + 1] - offset[i];
    PyObject* list = PyList_New(static_cast<Py_ssize_t>(size));
    if (list == nullptr) throw py::error_already_set();
    PyList_SET_ITEM(regions.ptr(), static_cast<Py_ssize_t>(i), list);
    for (std::int64_t k = 0; k < size; ++k) {
      py::object& shared = ints[value[offset[i] + k]];
      if (!shared) shared = py::int_(value[offset[i] + k]);
      PyList_SET_ITEM(list, static_cast<Py_ssize_t>(k), shared.inc_ref().ptr());
    }
  }
  return regions;
}

}  // namespace

void bind_spherical_voronoi(py::module_& m) {
  m.def("spherical_voronoi", &spherical_voronoi, py::arg("points"), py::arg("threads") = 0,
        "The exact Voronoi diagram of the directions of points (n, 3), normalized here: a dict of flat arrays by input point.");
  m.def("regions_lists", &regions_lists, py::arg("offsets"), py::arg("flat"),
        "[flat[offsets[i]:offsets[i + 1]] as a list of ints for each i].");
}

}  // namespace geovor::python
