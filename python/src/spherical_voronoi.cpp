// spherical_voronoi(points): the exact Voronoi diagram of unit vectors, in flat arrays by input
// point, for geovor.SphericalVoronoi (python/geovor/_spherical_voronoi.py).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "bindings.hpp"
#include "geovor/core/error.hpp"
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
  std::vector<Vec3> unit(n);
  const double* p = points.data();
  for (std::size_t i = 0; i < n; ++i) unit[i] = {p[3 * i], p[3 * i + 1], p[3 * i + 2]};

  std::vector<std::int64_t> site_of_input(n, -1), offsets(n + 1, 0), region;
  std::vector<double> areas(n, 0.0), vertices;
  std::vector<std::int64_t> merged;  // pairs: input, the input whose site it went into
  {
    py::gil_scoped_release unlocked;
    BuildReport report;
    const SphericalDelaunay dt = SphericalDelaunay::build(unit, {}, &report);
    const VoronoiDiagram vd(dt, threads);
    std::vector<std::int64_t> input_of_site(dt.sites().size(), -1);
    for (std::size_t i = 0; i < n; ++i) {
      const SiteId s = report.site_of_input[i];
      site_of_input[i] = s == kNoIndex ? -1 : static_cast<std::int64_t>(s);
      if (s != kNoIndex && input_of_site[s] < 0) input_of_site[s] = static_cast<std::int64_t>(i);
    }
    std::vector<char> is_merged(n, 0);
    for (const Merge& mg : report.merges) {
      is_merged[mg.input] = 1;
      merged.push_back(mg.input);
      merged.push_back(mg.site == kNoIndex ? -1 : input_of_site[mg.site]);
    }
    vertices.resize(3 * vd.num_vertices());
    for (std::size_t t = 0; t < vd.num_vertices(); ++t) {
      const Vec3& v = vd.vertex(static_cast<TriId>(t));
      vertices[3 * t] = v.x, vertices[3 * t + 1] = v.y, vertices[3 * t + 2] = v.z;
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (!is_merged[i] && site_of_input[i] >= 0) {
        const SiteId s = static_cast<SiteId>(site_of_input[i]);
        for (const TriId t : vd.cell_vertices(s)) region.push_back(t);
        areas[i] = vd.cell_area_sr(s);
      }
      offsets[i + 1] = static_cast<std::int64_t>(region.size());
    }
  }
  auto array = []<class T>(const std::vector<T>& v, std::vector<py::ssize_t> shape) {
    py::array_t<T> a(shape);
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
  };
  py::dict out;
  out["site_of_input"] = array(site_of_input, {static_cast<py::ssize_t>(n)});
  out["vertices"] = array(vertices, {static_cast<py::ssize_t>(vertices.size() / 3), 3});
  out["region_offsets"] = array(offsets, {static_cast<py::ssize_t>(n + 1)});
  out["region_vertices"] = array(region, {static_cast<py::ssize_t>(region.size())});
  out["areas_sr"] = array(areas, {static_cast<py::ssize_t>(n)});
  out["merged"] = array(merged, {static_cast<py::ssize_t>(merged.size() / 2), 2});
  return out;
}

}  // namespace

void bind_spherical_voronoi(py::module_& m) {
  m.def("spherical_voronoi", &spherical_voronoi, py::arg("points"), py::arg("threads") = 0,
        "The exact Voronoi diagram of unit vectors (n, 3): a dict of flat arrays by input point.");
}

}  // namespace geovor::python
