// Index: the nearest-site index (locate/index_file.hpp's SiteIndex) for geovor.Index: built from
// coordinate arrays, saved and loaded as `geovor index` files, queried by numpy arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/locate/index_file.hpp"
#include "geovor/locate/knn.hpp"
#include "geovor/locate/locator.hpp"
#include "site_arrays.hpp"

namespace py = pybind11;

namespace geovor::python {
namespace {

// (lat, lon) normalised, or ValueError naming the row.
void normalize(double& lat_deg, double& lon_deg, std::size_t row) {
  const std::string problem = normalize_lat_lon(lat_deg, lon_deg);
  if (!problem.empty()) throw Error(ErrorCode::BadData, "query " + std::to_string(row) + ": " + problem);
}

class Index {
 public:
  Index(const Doubles& lat, const Doubles& lon, std::optional<std::vector<std::string>> ids,
        const std::optional<Doubles>& weights_m) {
    SiteTable table = site_table_from_arrays(lat, lon, std::move(ids));
    if (weights_m) set_radii(table, *weights_m);
    py::gil_scoped_release unlocked;
    index_ = build_site_index(table);
    index_.hierarchy.walk_graph(0);  // the packed copy the queries walk, now, on every core
  }
  explicit Index(SiteIndex index) : index_(std::move(index)) {}

  static Index load(const std::string& path) {
    py::gil_scoped_release unlocked;
    Index index(load_index(path, 0));
    index.index_.hierarchy.walk_graph(0);  // as at construction
    return index;
  }
  void save(const std::string& path, bool overwrite) const {
    py::gil_scoped_release unlocked;
    save_index(path, index_.hierarchy, index_.attributes, overwrite);
  }

  std::size_t num_sites() const { return index_.attributes.num_sites(); }
  bool weighted() const { return index_.hierarchy.is_weighted(); }

  // Per site: its lift cos(r / R) (1 for unweighted sites) and whether it is hidden.
  py::tuple weights() const {
    const SphericalDelaunay& base = index_.hierarchy.base();
    const std::size_t n = base.site_capacity();
    py::array_t<double> lift(static_cast<py::ssize_t>(n));
    py::array_t<bool> hidden(static_cast<py::ssize_t>(n));
    for (SiteId s = 0; s < n; ++s) {
      lift.mutable_data()[s] = base.lift(s);
      hidden.mutable_data()[s] = base.is_hidden(s);
    }
    return py::make_tuple(lift, hidden);
  }

  // Per site: its id, its first row's position, and the rows merged into it (0-based input rows).
  py::dict sites() const {
    const SiteAttributes& a = index_.attributes;
    const std::size_t n = a.num_sites();
    py::array_t<double> lat(static_cast<py::ssize_t>(n)), lon(static_cast<py::ssize_t>(n));
    py::array_t<std::int64_t> first_row(static_cast<py::ssize_t>(n)), rows_begin(static_cast<py::ssize_t>(n + 1));
    py::array_t<std::int64_t> rows(static_cast<py::ssize_t>(a.num_rows()));
    py::list ids;
    for (std::size_t s = 0; s < n; ++s) {
      const bool live = a.site_rows[s] < a.site_rows[s + 1];
      const double nan = std::numeric_limits<double>::quiet_NaN();
      lat.mutable_data()[s] = live ? a.rows[a.site_rows[s]].lat_deg : nan;
      lon.mutable_data()[s] = live ? a.rows[a.site_rows[s]].lon_deg : nan;
      first_row.mutable_data()[s] = live ? static_cast<std::int64_t>(a.rows[a.site_rows[s]].row) - 1 : -1;
      rows_begin.mutable_data()[s] = static_cast<std::int64_t>(a.site_rows[s]);
      ids.append(py::str(std::string(a.site_id(static_cast<SiteId>(s)))));
    }
    rows_begin.mutable_data()[n] = static_cast<std::int64_t>(a.site_rows[n]);
    for (std::size_t r = 0; r < a.num_rows(); ++r) rows.mutable_data()[r] = static_cast<std::int64_t>(a.rows[r].row) - 1;
    py::dict out;
    out["id"] = ids;
    out["lat"] = lat;
    out["lon"] = lon;
    out["first_row"] = first_row;
    out["rows_begin"] = rows_begin;
    out["rows"] = rows;
    out["columns"] = a.columns;
    out["source"] = a.source;
    // Each column's field of each site's first row, as read (empty for a site without rows).
    py::dict fields;
    for (std::size_t c = 0; c < a.columns.size(); ++c) {
      py::list values;
      for (std::size_t s = 0; s < n; ++s)
        values.append(py::str(a.site_rows[s] < a.site_rows[s + 1] ? std::string(a.field(a.site_rows[s], c)) : std::string()));
      fields[py::str(a.columns[c])] = values;
    }
    out["fields"] = fields;
    return out;
  }

  // (site_index, distance_m): shape (n,) for k == 1, (n, k) otherwise; -1 and inf where fewer
  // than k sites lie within max_distance_m.
  py::tuple nearest(const Doubles& lat, const Doubles& lon, std::size_t k, const std::string& metric,
                    std::optional<double> max_distance_m, unsigned threads) const {
    if (k == 0) throw Error(ErrorCode::InvalidArgument, "k must be at least 1");
    if (!metric.empty() && metric != "sphere" && metric != "geodesic" && metric != "power")
      throw Error(ErrorCode::InvalidArgument, "metric must be 'sphere', 'geodesic' or 'power', not '" + metric + "'");
    if (max_distance_m && !(*max_distance_m >= 0))
      throw Error(ErrorCode::InvalidArgument, "max_distance_m must be a number >= 0");
    const Metric m = metric.empty() ? default_metric(index_.hierarchy) : parse_metric(metric);
    check_metric(index_.hierarchy, m);
    std::size_t n = static_cast<std::size_t>(-1);
    const double* la = column_data(lat, "lat", n);
    const double* lo = column_data(lon, "lon", n);
    std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(n)};
    if (k > 1) shape.push_back(static_cast<py::ssize_t>(k));
    py::array_t<std::int64_t> site(shape);
    py::array_t<double> dist(shape);
    std::int64_t* site_out = site.mutable_data();
    double* dist_out = dist.mutable_data();
    const double limit = max_distance_m.value_or(std::numeric_limits<double>::infinity());
    {
      py::gil_scoped_release unlocked;
      // Bad queries are found before any work: the error names the first.
      std::vector<double> lat_deg(la, la + n), lon_deg(lo, lo + n);
      for (std::size_t i = 0; i < n; ++i) normalize(lat_deg[i], lon_deg[i], i);
      Locator prototype(index_.hierarchy);
      if (n >= 1024) prototype.prepare();
      parallel_for(n, threads, [&](unsigned, std::size_t begin, std::size_t end) {
        Locator locator = prototype;
        std::vector<NearestResult> found;
        for (std::size_t i = begin; i < end; ++i) {
          nearest_within(locator, lat_deg[i], lon_deg[i], k, m, limit, found);
          for (std::size_t j = 0; j < k; ++j) {
            const bool ok = j < found.size();
            site_out[i * k + j] = ok ? static_cast<std::int64_t>(found[j].site) : -1;
            dist_out[i * k + j] = ok ? found[j].dist_m : std::numeric_limits<double>::infinity();
          }
        }
      });
    }
    return py::make_tuple(site, dist);
  }

 private:
  SiteIndex index_;
};

}  // namespace

void bind_index(py::module_& m) {
  py::class_<Index>(m, "Index")
      .def(py::init<const Doubles&, const Doubles&, std::optional<std::vector<std::string>>, const std::optional<Doubles>&>(),
           py::arg("lat"), py::arg("lon"), py::arg("ids") = py::none(), py::arg("weights_m") = py::none())
      .def_static("load", &Index::load, py::arg("path"))
      .def("save", &Index::save, py::arg("path"), py::arg("overwrite") = false)
      .def_property_readonly("num_sites", &Index::num_sites)
      .def_property_readonly("weighted", &Index::weighted)
      .def("weights", &Index::weights)
      .def("sites", &Index::sites)
      .def("nearest", &Index::nearest, py::arg("lat"), py::arg("lon"), py::arg("k") = 1,
           py::arg("metric") = "", py::arg("max_distance_m") = py::none(), py::arg("threads") = 0);
}

}  // namespace geovor::python
