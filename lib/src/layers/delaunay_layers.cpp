#include "geovor/layers/delaunay_layers.hpp"

#include <GeographicLib/Geodesic.hpp>

#include <cstdint>

#include "geovor/core/ascii.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/output_target.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/lonlat/cell_geometry.hpp"

namespace geovor {

std::vector<Field> triangle_layer_schema() {
  return {{"tri_index", FieldType::Integer64}, {"kind", FieldType::String},   {"ghost", FieldType::Integer64},
          {"site_a", FieldType::Integer64},    {"site_b", FieldType::Integer64}, {"site_c", FieldType::Integer64},
          {"id_a", FieldType::String},       {"id_b", FieldType::String},    {"id_c", FieldType::String},
          {"area_m2", FieldType::Real},      {"area_sr", FieldType::Real},   {"circumradius_m", FieldType::Real}};
}

std::vector<Field> edge_layer_schema() {
  return {{"edge_index", FieldType::Integer64}, {"site_a", FieldType::Integer64}, {"site_b", FieldType::Integer64},
          {"id_a", FieldType::String},        {"id_b", FieldType::String},    {"length_m", FieldType::Real},
          {"geodesic_m", FieldType::Real},    {"hull", FieldType::Integer64},   {"ghost", FieldType::Integer64}};
}

std::unique_ptr<FeatureWriter> open_triangle_layer_writer(const std::string& path, const WriterOptions& options) {
  return open_feature_writer(path, GeometryType::MultiPolygon, triangle_layer_schema(), options);
}

std::unique_ptr<FeatureWriter> open_edge_layer_writer(const std::string& path, const WriterOptions& options) {
  return open_feature_writer(path, GeometryType::MultiLineString, edge_layer_schema(), options);
}

TriangleLayerReport write_triangle_layer(FeatureWriter& writer, const SiteTable& table, const SiteRows& rows,
                                         const DelaunayGeometry& geometry, const DelaunayLayerOptions& options) {
  const SphericalDelaunay& dt = geometry.triangulation();
  auto site_id = [&](SiteId s) -> const std::string& { return table.sites[rows.first(s)].id; };
  TriangleLayerReport report;
  MultiPolygon polygon;
  std::vector<FieldValue> values(triangle_layer_schema().size());
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    const bool outer = geometry.is_outer(t);
    if (outer && options.no_ghosts) continue;
    const WrittenStatus status = geometry.triangle_polygon(t, polygon);
    if (status != WrittenStatus::Written) report.unwritten.push_back({t, status});
    const SiteId a = dt.tri_site(t, 0), b = dt.tri_site(t, 1), c = dt.tri_site(t, 2);
    values[0] = static_cast<std::int64_t>(t);
    values[1] = std::string(to_string(geometry.kind(t)));
    values[2] = static_cast<std::int64_t>(outer);
    values[3] = static_cast<std::int64_t>(a);
    values[4] = static_cast<std::int64_t>(b);
    values[5] = static_cast<std::int64_t>(c);
    values[6] = site_id(a);
    values[7] = site_id(b);
    values[8] = site_id(c);
    values[9] = ellipsoid_area_m2(polygon);
    values[10] = geometry.triangle_area_sr(t);
    values[11] = geometry.circumradius_m(t);
    writer.write(polygon, values);
    ++report.triangles_written;
    if (t % 4096 == 0 && options.progress) options.progress(t);
  }
  return report;
}

EdgeLayerReport write_edge_layer(FeatureWriter& writer, const SiteTable& table, const SiteRows& rows,
                                 const DelaunayGeometry& geometry, const DelaunayLayerOptions& options) {
  const SphericalDelaunay& dt = geometry.triangulation();
  auto site_id = [&](SiteId s) -> const std::string& { return table.sites[rows.first(s)].id; };
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  EdgeLayerReport report;
  MultiLineString line;
  std::vector<FieldValue> values(edge_layer_schema().size());
  std::int64_t index = 0;
  const auto halfedges = dt.halfedges();
  for (HalfedgeId e = 0; e < halfedges.size(); ++e) {
    if (halfedges[e] < e) continue;  // each edge once, from its first half-edge
    const SiteId a = dt.tri_site(e / 3, static_cast<int>(e % 3));
    const SiteId b = dt.tri_site(e / 3, static_cast<int>((e + 1) % 3));
    const bool outer = geometry.is_outer_edge(e);
    if (outer && options.no_ghosts) continue;
    geometry.edge_line(e, line);
    report.collapsed += line.empty();
    const LatLon la = SiteEncoder::to_lat_lon(dt.site(a)), lb = SiteEncoder::to_lat_lon(dt.site(b));
    double geodesic_m = 0;
    geod.Inverse(la.lat_deg, la.lon_deg, lb.lat_deg, lb.lon_deg, geodesic_m);
    values[0] = index++;
    values[1] = static_cast<std::int64_t>(a);
    values[2] = static_cast<std::int64_t>(b);
    values[3] = site_id(a);
    values[4] = site_id(b);
    values[5] = geometry.edge_length_m(e);
    values[6] = geodesic_m;
    values[7] = static_cast<std::int64_t>(geometry.is_hull_edge(e));
    values[8] = static_cast<std::int64_t>(outer);
    writer.write(line, values);
    ++report.edges_written;
    if (report.edges_written % 4096 == 0 && options.progress) options.progress(report.edges_written);
  }
  return report;
}

bool one_data_source(const DelaunayOutput& output) {
  return !output.triangles_path.empty() && !output.edges_path.empty() &&
         same_output_file(output.triangles_path, output.edges_path) &&
         (output.edges.format.empty() || ascii_iequals(output.edges.format, output.triangles.format));
}

DelaunayLayersReport write_delaunay_layers(const DelaunayOutput& output, const SiteTable& table, const SiteRows& rows,
                                           const DelaunayGeometry& geometry, const DelaunayLayerOptions& options) {
  const bool triangles = !output.triangles_path.empty(), edges = !output.edges_path.empty();
  if (!triangles && !edges) throw Error(ErrorCode::InvalidArgument, "nothing to write: no triangles path and no edges path");
  const bool one = one_data_source(output);
  if (one && !format_holds_layers(output.triangles_path, output.triangles.format))
    throw Error(ErrorCode::InvalidArgument, output.triangles_path +
                                                ": the triangles and the edges are two layers, and this format holds one: "
                                                "write them to two files, or to a format that holds several (GPKG, SQLite, ...)");
  DelaunayLayersReport report;
  DelaunayLayerOptions layer_options = options;
  // Both opened first, so that an existing output is refused before any feature is written.
  std::unique_ptr<FeatureWriter> triangle_writer, edge_writer;
  if (triangles) triangle_writer = open_triangle_layer_writer(output.triangles_path, output.triangles);
  if (edges && !one) edge_writer = open_edge_layer_writer(output.edges_path, output.edges);
  if (triangles) {
    layer_options.progress = options.progress;
    report.triangles = write_triangle_layer(*triangle_writer, table, rows, geometry, layer_options);
  }
  if (edges) {
    FeatureWriter* writer = edge_writer.get();
    if (one) {
      triangle_writer->next_layer(output.edges.layer, GeometryType::MultiLineString, edge_layer_schema());
      writer = triangle_writer.get();
    }
    const std::size_t done = report.triangles.triangles_written;
    if (options.progress) layer_options.progress = [&](std::size_t e) { options.progress(done + e); };
    report.edges = write_edge_layer(*writer, table, rows, geometry, layer_options);
  }
  if (triangle_writer) triangle_writer->finish();
  if (edge_writer) edge_writer->finish();
  return report;
}

}  // namespace geovor
