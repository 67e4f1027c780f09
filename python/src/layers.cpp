// cells(), delaunay(), relax(): the library's layers (geovor/layers/) written to memory for
// geovor.cells / geovor.delaunay / geovor.relax, which make GeoDataFrames of them.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <geos_c.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bindings.hpp"
#include "geovor/core/coordinate_grid.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_weights.hpp"
#include "geovor/layers/cell_layer.hpp"
#include "geovor/layers/clipped_cell_layer.hpp"
#include "geovor/layers/region_clip.hpp"
#include "geovor/layers/delaunay_layers.hpp"
#include "geovor/lonlat/delaunay_geometry.hpp"
#include "geovor/relax/balance.hpp"
#include "geovor/relax/lloyd.hpp"
#include "geovor/relax/measure.hpp"
#include "memory_writer.hpp"
#include "site_arrays.hpp"

namespace py = pybind11;

namespace geovor::python {
namespace {

using Ids = std::optional<std::vector<std::string>>;

// The triangulation of a table's sites, with what became of each input.
struct Built {
  SiteTable table;
  BuildReport report;
  SphericalDelaunay dt;
};

using Radii = std::optional<Doubles>;

Built build(const Doubles& lat, const Doubles& lon, Ids ids, double merge_m, const Radii& radii_m = std::nullopt) {
  Built b{site_table_from_arrays(lat, lon, std::move(ids)), {}, {}};
  if (radii_m) set_radii(b.table, *radii_m);
  DelaunayOptions options;
  if (merge_m > 0) options.merge_distance = std::max(SphericalDelaunay::kMinSeparation, merge_m / SiteEncoder::kEarthRadiusM);
  std::vector<Vec3> points(b.table.sites.size());
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = b.table.sites[i].unit;
  const std::vector<double> lifts = b.table.weighted ? site_lifts(b.table) : std::vector<double>();
  py::gil_scoped_release unlocked;
  b.dt = lifts.empty() ? SphericalDelaunay::build(points, options, &b.report)
                       : SphericalDelaunay::build(points, lifts, options, &b.report);
  return b;
}

// (hidden site's input row, the input row of a site holding its position) of weighted sites.
py::list hidden_pairs(const Built& b, const SiteRows& rows) {
  py::list out;
  for (const Hidden& h : b.report.hidden) out.append(py::make_tuple(rows.first(h.site), rows.first(h.by)));
  return out;
}

// Input index -> the input index of the site it went into (itself when not merged).
py::array_t<std::int64_t> site_first_rows(const Built& b, const SiteRows& rows) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(b.dt.site_capacity()));
  for (std::size_t s = 0; s < b.dt.site_capacity(); ++s) {
    const auto r = rows.of(static_cast<SiteId>(s));
    out.mutable_data()[s] = r.empty() ? -1 : static_cast<std::int64_t>(rows.first(static_cast<SiteId>(s)));
  }
  return out;
}

py::list merged_pairs(const Built& b, const SiteRows& rows) {
  py::list out;
  for (const Merge& m : b.report.merges)
    out.append(py::make_tuple(m.input, m.site == kNoIndex ? -1 : static_cast<std::int64_t>(rows.first(m.site))));
  return out;
}

py::dict cell_layer(const Built& b, double densify_m, unsigned threads) {
  MemoryFeatureWriter writer(cell_layer_schema(b.table));
  CellLayerOptions options;
  options.densify_m = densify_m;
  options.threads = threads;
  CellLayerReport report;
  {
    py::gil_scoped_release unlocked;
    report = write_cell_layer(writer, b.table, b.report, b.dt, options);
  }
  py::dict out = writer.to_python();
  py::list unwritten;
  for (const UnwrittenCell& u : report.unwritten) unwritten.append(py::make_tuple(u.site, to_string(u.status)));
  out["unwritten"] = unwritten;
  return out;
}

py::dict cells(const Doubles& lat, const Doubles& lon, Ids ids, double densify_m, double merge_m, unsigned threads,
               const Radii& weights_m) {
  const Built b = build(lat, lon, std::move(ids), merge_m, weights_m);
  const SiteRows rows = rows_of_sites(b.report, b.dt.site_capacity());
  py::dict out = cell_layer(b, densify_m, threads);
  out["site_first_row"] = site_first_rows(b, rows);
  out["merged"] = merged_pairs(b, rows);
  out["hidden"] = hidden_pairs(b, rows);
  return out;
}

// GEOS's reader of the regions' WKB, freed with its context.
class GeosWkbReader {
 public:
  GeosWkbReader() : h_(GEOS_init_r()), reader_(GEOSWKBReader_create_r(h_)) {}
  ~GeosWkbReader() {
    GEOSWKBReader_destroy_r(h_, reader_);
    GEOS_finish_r(h_);
  }
  GeosWkbReader(const GeosWkbReader&) = delete;
  GeosWkbReader& operator=(const GeosWkbReader&) = delete;

  // The polygons of one region's WKB (a Polygon or MultiPolygon), empty ones left out, Z or M dropped.
  MultiPolygon read(std::string_view wkb, std::size_t row) const {
    GEOSGeometry* g = GEOSWKBReader_read_r(h_, reader_, reinterpret_cast<const unsigned char*>(wkb.data()), wkb.size());
    if (!g) throw Error(ErrorCode::InvalidArgument, "clip row " + std::to_string(row) + ": unreadable WKB");
    MultiPolygon out;
    // Empty: no polygon (shapely 1.8 writes an empty Polygon as an empty GeometryCollection).
    const int type = GEOSisEmpty_r(h_, g) ? GEOS_POLYGON : GEOSGeomTypeId_r(h_, g);
    if (type == GEOS_POLYGON) add_polygon(g, out);
    else if (type == GEOS_MULTIPOLYGON)
      for (int i = 0; i < GEOSGetNumGeometries_r(h_, g); ++i) add_polygon(GEOSGetGeometryN_r(h_, g, i), out);
    GEOSGeom_destroy_r(h_, g);
    if (type != GEOS_POLYGON && type != GEOS_MULTIPOLYGON)
      throw Error(ErrorCode::InvalidArgument, "clip row " + std::to_string(row) + ": not a Polygon or MultiPolygon");
    return out;
  }

 private:
  void add_polygon(const GEOSGeometry* p, MultiPolygon& out) const {
    if (GEOSisEmpty_r(h_, p)) return;
    Polygon polygon{ring(GEOSGetExteriorRing_r(h_, p)), {}};
    for (int i = 0; i < GEOSGetNumInteriorRings_r(h_, p); ++i) polygon.holes.push_back(ring(GEOSGetInteriorRingN_r(h_, p, i)));
    out.push_back(std::move(polygon));
  }
  Ring ring(const GEOSGeometry* r) const {
    const GEOSCoordSequence* seq = GEOSGeom_getCoordSeq_r(h_, r);
    unsigned n = 0;
    GEOSCoordSeq_getSize_r(h_, seq, &n);
    Ring out(n);
    for (unsigned i = 0; i < n; ++i) GEOSCoordSeq_getXY_r(h_, seq, i, &out[i].lon_deg, &out[i].lat_deg);
    return out;
  }

  GEOSContextHandle_t h_;
  GEOSWKBReader* reader_;
};

// Regions from Python: the WKB of each (lon/lat), in order; GEOS reads it faster than Python
// hands over each ring's coordinates.
RegionTable regions_from_python(const py::list& regions) {
  RegionTable t;
  t.source = "clip";
  const GeosWkbReader reader;
  for (std::size_t r = 0; r < regions.size(); ++r) {
    Region region;
    region.row = r + 1;
    region.id = std::to_string(r + 1);  // the row number, as the command numbers regions without an id field
    region.geometry = reader.read(regions[r].cast<std::string_view>(), r);
    t.regions.push_back(std::move(region));
  }
  return t;
}

py::dict cells_clipped(const Doubles& lat, const Doubles& lon, Ids ids, double densify_m, double merge_m, unsigned threads,
                       const Radii& weights_m, const py::list& clip) {
  const Built b = build(lat, lon, std::move(ids), merge_m, weights_m);
  const SiteRows rows = rows_of_sites(b.report, b.dt.site_capacity());
  const RegionTable regions = regions_from_python(clip);
  MemoryFeatureWriter writer(clipped_cell_layer_schema(b.table, regions));
  RegionClipReport report;
  {
    py::gil_scoped_release unlocked;
    const VoronoiDiagram diagram(b.dt, threads == 0 ? 0 : threads);
    CellGeometryOptions geometry;
    geometry.densify_m = densify_m;
    geometry.threads = threads;
    const CellGeometry cells(diagram, geometry);
    const std::vector<ClipPiece> pieces = clip_cells_to_regions(diagram, cells, regions, {.threads = threads}, report);
    write_clipped_cells(writer, b.table, rows, regions, pieces);
  }
  py::dict out = writer.to_python();
  out["site_first_row"] = site_first_rows(b, rows);
  out["outside"] = report.sites_outside;
  py::list problems;
  for (const RegionProblem& p : report.problems) problems.append(py::make_tuple(p.region, p.reason));
  out["problems"] = problems;
  out["hidden"] = hidden_pairs(b, rows);
  return out;
}

py::tuple delaunay(const Doubles& lat, const Doubles& lon, Ids ids, double densify_m, bool no_ghosts, double merge_m,
                   const Radii& weights_m) {
  const Built b = build(lat, lon, std::move(ids), merge_m, weights_m);
  const SiteRows rows = rows_of_sites(b.report, b.dt.site_capacity());
  MemoryFeatureWriter triangles(triangle_layer_schema()), edges(edge_layer_schema());
  TriangleLayerReport triangle_report;
  {
    py::gil_scoped_release unlocked;
    DelaunayGeometryOptions geometry_options;
    geometry_options.densify_m = densify_m;
    geometry_options.precision = kFullPrecision;
    const DelaunayGeometry geometry(b.dt, geometry_options);
    DelaunayLayerOptions options;
    options.no_ghosts = no_ghosts;
    triangle_report = write_triangle_layer(triangles, b.table, rows, geometry, options);
    write_edge_layer(edges, b.table, rows, geometry, options);
  }
  py::dict t = triangles.to_python(), e = edges.to_python();
  py::list unwritten;
  for (const UnwrittenTriangle& u : triangle_report.unwritten) unwritten.append(py::make_tuple(u.triangle, to_string(u.status)));
  t["unwritten"] = unwritten;
  t["merged"] = merged_pairs(b, rows);
  t["hidden"] = hidden_pairs(b, rows);
  return py::make_tuple(t, e);
}

// geovor balance: the radii of equal (or given) shares of the WGS84 ellipsoid's area, then the
// balanced cells through the cells' layer.
py::dict balance(const Doubles& lat, const Doubles& lon, Ids ids, const Radii& shares, double tolerance,
                 int max_iterations, double densify_m, double merge_m, unsigned threads) {
  Built b{site_table_from_arrays(lat, lon, std::move(ids)), {}, {}};
  DelaunayOptions delaunay;
  if (merge_m > 0) delaunay.merge_distance = std::max(SphericalDelaunay::kMinSeparation, merge_m / SiteEncoder::kEarthRadiusM);
  std::vector<Vec3> points(b.table.sites.size());
  for (std::size_t i = 0; i < points.size(); ++i) points[i] = b.table.sites[i].unit;
  std::vector<double> share(points.size(), 1.0);
  if (shares) {
    std::size_t n = points.size();
    const double* s = column_data(*shares, "capacity", n);
    share.assign(s, s + n);
  }
  BalanceOptions options;
  options.tolerance = tolerance;
  options.max_iterations = max_iterations;
  options.threads = threads;
  BalanceReport result;
  {
    py::gil_scoped_release unlocked;
    result = geovor::balance(points, share, EllipsoidAreaMeasure(), options, delaunay);
    if (result.converged) b.dt = balanced_triangulation(points, result, delaunay, b.report);
  }
  if (!result.converged) {
    const double last = result.iterations.empty() ? result.initial_relative_error : result.iterations.back().max_relative_error;
    throw Error(ErrorCode::BadData, "balance: not converged after " + std::to_string(result.iterations.size()) +
                                        " iterations: largest relative area error " + std::to_string(last) +
                                        " above the tolerance (docs/user-guide.md, geovor balance: when there is no solution)");
  }
  for (std::size_t i = 0; i < points.size(); ++i) b.table.sites[i].weight_m = result.radii_m[i];
  b.table.weighted = true;
  const SiteRows rows = rows_of_sites(b.report, b.dt.site_capacity());
  py::dict out = cell_layer(b, densify_m, threads);
  out["site_first_row"] = site_first_rows(b, rows);
  out["merged"] = merged_pairs(b, rows);
  py::array_t<double> radii(static_cast<py::ssize_t>(points.size())), targets(static_cast<py::ssize_t>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    radii.mutable_data()[i] = result.radii_m[i];
    targets.mutable_data()[i] = result.targets[i];
  }
  out["radii_m"] = radii;
  out["target_m2"] = targets;
  py::list iterations;
  for (const BalanceIteration& it : result.iterations) iterations.append(py::make_tuple(it.max_relative_error, it.step));
  out["iterations"] = iterations;
  return out;
}

py::dict relax(const Doubles& lat, const Doubles& lon, Ids ids, int iterations, double tolerance_rad,
               const std::string& relocation, double densify_m, double merge_m, unsigned threads) {
  Built b = build(lat, lon, std::move(ids), merge_m);
  LloydOptions options;
  options.iterations = iterations;
  options.tolerance_rad = tolerance_rad;
  options.threads = threads;
  if (relocation == "filtered") options.relocation = Relocation::Filtered;
  else if (relocation == "naive") options.relocation = Relocation::Naive;
  else if (relocation == "rebuild") options.relocation = Relocation::Rebuild;
  else throw Error(ErrorCode::InvalidArgument, "relocation must be 'filtered', 'naive' or 'rebuild', not '" + relocation + "'");
  LloydReport report;
  {
    py::gil_scoped_release unlocked;
    report = lloyd(b.dt, options);
  }
  const SiteRows rows = rows_of_sites(b.report, b.dt.site_capacity());
  py::dict out = cell_layer(b, densify_m, threads);
  // The sites' final positions, by site id.
  const std::size_t n = b.dt.site_capacity();
  py::array_t<double> site_lat(static_cast<py::ssize_t>(n)), site_lon(static_cast<py::ssize_t>(n));
  for (std::size_t s = 0; s < n; ++s) {
    const LatLon p = SiteEncoder::to_lat_lon(b.dt.site(static_cast<SiteId>(s)));
    site_lat.mutable_data()[s] = p.lat_deg;
    site_lon.mutable_data()[s] = p.lon_deg;
  }
  out["site_lat"] = site_lat;
  out["site_lon"] = site_lon;
  out["site_first_row"] = site_first_rows(b, rows);
  out["merged"] = merged_pairs(b, rows);
  py::list energy, max_move_m;
  for (const LloydIteration& it : report.iterations) {
    energy.append(it.energy);
    max_move_m.append(it.max_move_m);
  }
  out["energy"] = energy;
  out["max_move_m"] = max_move_m;
  out["final_energy"] = report.final_energy;
  return out;
}

}  // namespace

void bind_layers(py::module_& m) {
  m.def("cells", &cells, py::arg("lat"), py::arg("lon"), py::arg("ids"), py::arg("densify_m"), py::arg("merge_m"),
        py::arg("threads"), py::arg("weights_m") = py::none());
  m.def("cells_clipped", &cells_clipped, py::arg("lat"), py::arg("lon"), py::arg("ids"), py::arg("densify_m"),
        py::arg("merge_m"), py::arg("threads"), py::arg("weights_m"), py::arg("clip"));
  m.def("delaunay", &delaunay, py::arg("lat"), py::arg("lon"), py::arg("ids"), py::arg("densify_m"),
        py::arg("no_ghosts"), py::arg("merge_m"), py::arg("weights_m") = py::none());
  m.def("balance", &balance, py::arg("lat"), py::arg("lon"), py::arg("ids"), py::arg("shares"), py::arg("tolerance"),
        py::arg("max_iterations"), py::arg("densify_m"), py::arg("merge_m"), py::arg("threads"));
  m.def("relax", &relax, py::arg("lat"), py::arg("lon"), py::arg("ids"), py::arg("iterations"),
        py::arg("tolerance_rad"), py::arg("relocation"), py::arg("densify_m"), py::arg("merge_m"), py::arg("threads"));
}

}  // namespace geovor::python
