// geovor delaunay INPUT -o TRIANGLES [--edges EDGES]: the Delaunay triangulation of the sites as
// GIS polygons (its triangles) and lines (its edges, with their great-circle length).
#include <GeographicLib/Geodesic.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/io/output_target.hpp"
#include "geovor/lonlat/cell_geometry.hpp"
#include "geovor/lonlat/delaunay_geometry.hpp"
#include "geovor/lonlat/ellipsoid_area.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct DelaunayArgs {
  SiteInputArgs sites;
  std::string triangles;
  std::string edges;
  std::string format;
  std::string edges_format;
  double densify_m = 100;
  int precision = 7;
  bool no_ghosts = false;
  bool overwrite = false;
  bool quiet = false;
};

WriterOptions writer_options(const DelaunayArgs& args, const std::string& format, const char* layer) {
  WriterOptions o;
  o.format = format;
  o.layer = layer;
  o.precision = args.precision;
  o.overwrite = args.overwrite;
  return o;
}

int run(DelaunayArgs& args) {
  if (args.triangles.empty() && args.edges.empty())
    throw Error(ErrorCode::InvalidArgument, "nothing to write: give -o TRIANGLES and/or --edges EDGES");
  // Two outputs that are one file (a path, an alias, a link; `-` twice): refused before any work.
  check_distinct_outputs({{"--output", args.triangles}, {"--edges", args.edges}});
  const SiteTable table = read_site_input(args.sites);
  const std::vector<Vec3> points = site_points(table);
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(points, delaunay_options(args.sites), &report);
  report_merges(table, report);
  const auto rows = rows_of_sites(report, dt.site_capacity());
  auto site_id = [&](SiteId s) -> const std::string& { return table.sites[rows[s].front()].id; };
  DelaunayGeometryOptions geometry_options;
  geometry_options.densify_m = args.densify_m;
  // Positions as the text outputs (GeoJSON) write them; the binary formats store doubles, and
  // a binary output beside a text one gets the rounded positions (as doubles) too.
  const bool text = (!args.triangles.empty() && !output_needs_gdal(args.triangles, args.format)) ||
                    (!args.edges.empty() && !output_needs_gdal(args.edges, args.edges_format));
  geometry_options.precision = text ? args.precision : kFullPrecision;
  std::vector<std::pair<TriId, WrittenStatus>> unwritten;
  std::size_t collapsed_edges = 0;
  const DelaunayGeometry geometry(dt, geometry_options);
  std::size_t triangles_written = 0, edges_written = 0;
  const std::size_t total = (args.triangles.empty() ? 0 : dt.num_triangles()) +
                            (args.edges.empty() ? 0 : dt.halfedges().size() / 2);
  Progress progress(total, args.quiet);

  if (!args.triangles.empty()) {
    const std::vector<Field> schema = {
        {"tri_index", FieldType::Integer}, {"kind", FieldType::String},      {"ghost", FieldType::Integer},
        {"site_a", FieldType::Integer},    {"site_b", FieldType::Integer},   {"site_c", FieldType::Integer},
        {"id_a", FieldType::String},       {"id_b", FieldType::String},      {"id_c", FieldType::String},
        {"area_m2", FieldType::Real},      {"area_sr", FieldType::Real},     {"circumradius_m", FieldType::Real}};
    const auto writer =
        open_feature_writer(args.triangles, GeometryType::MultiPolygon, schema, writer_options(args, args.format, "triangles"));
    MultiPolygon polygon;
    std::vector<FieldValue> values(schema.size());
    for (TriId t = 0; t < dt.num_triangles(); ++t) {
      const FaceKind kind = geometry.kind(t);
      const bool outer = geometry.is_outer(t);
      if (outer && args.no_ghosts) continue;
      const WrittenStatus status = geometry.triangle_polygon(t, polygon);
      if (status != WrittenStatus::Written) unwritten.push_back({t, status});
      const SiteId a = dt.tri_site(t, 0), b = dt.tri_site(t, 1), c = dt.tri_site(t, 2);
      values[0] = static_cast<std::int64_t>(t);
      values[1] = std::string(to_string(kind));
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
      writer->write(polygon, values);
      ++triangles_written;
      if (t % 4096 == 0) progress.advance(t);
    }
    writer->finish();
  }

  if (!args.edges.empty()) {
    const std::vector<Field> schema = {
        {"edge_index", FieldType::Integer}, {"site_a", FieldType::Integer},  {"site_b", FieldType::Integer},
        {"id_a", FieldType::String},        {"id_b", FieldType::String},     {"length_m", FieldType::Real},
        {"geodesic_m", FieldType::Real},    {"hull", FieldType::Integer},  {"ghost", FieldType::Integer}};
    const auto writer =
        open_feature_writer(args.edges, GeometryType::MultiLineString, schema, writer_options(args, args.edges_format, "edges"));
    const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
    MultiLineString line;
    std::vector<FieldValue> values(schema.size());
    std::int64_t index = 0;
    const auto halfedges = dt.halfedges();
    for (HalfedgeId e = 0; e < halfedges.size(); ++e) {
      if (halfedges[e] < e) continue;  // each edge once, from its first half-edge
      const SiteId a = dt.tri_site(e / 3, static_cast<int>(e % 3));
      const SiteId b = dt.tri_site(e / 3, static_cast<int>((e + 1) % 3));
      const bool outer = geometry.is_outer_edge(e);
      if (outer && args.no_ghosts) continue;
      geometry.edge_line(e, line);
      collapsed_edges += line.empty();
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
      writer->write(line, values);
      ++edges_written;
      if (edges_written % 4096 == 0) progress.advance(triangles_written + edges_written);
    }
    writer->finish();
  }
  progress.finish();
  const std::string where =
      geometry_options.precision >= 0 ? "--precision " + std::to_string(geometry_options.precision) : "full precision";
  if (!unwritten.empty()) {
    // Listed even with --quiet, as rejected rows are: a feature without geometry must not pass unseen.
    std::fprintf(stderr, "%zu triangle(s) written with an empty geometry: at %s they collapse or would not be valid polygons (raise --precision):\n",
                 unwritten.size(), where.c_str());
    for (std::size_t i = 0; i < unwritten.size() && i < 20; ++i)
      std::fprintf(stderr, "  triangle %u (sites %u, %u, %u): %s\n", unwritten[i].first, dt.tri_site(unwritten[i].first, 0),
                   dt.tri_site(unwritten[i].first, 1), dt.tri_site(unwritten[i].first, 2), to_string(unwritten[i].second));
    if (unwritten.size() > 20) std::fprintf(stderr, "  ... (%zu more)\n", unwritten.size() - 20);
  }
  if (collapsed_edges > 0)
    std::fprintf(stderr, "%zu edge(s) written with an empty geometry: their ends are one position at %s\n", collapsed_edges,
                 where.c_str());
  if (!args.quiet) {
    std::fprintf(stderr, "%s: rows %llu, sites %zu, merged %zu, rejected %zu; triangles %zu (ghost %zu)",
                 table.source.c_str(), static_cast<unsigned long long>(table.rows_read), dt.num_sites(),
                 report.merges.size(), table.rejected.size(), dt.num_triangles(), dt.num_ghost_triangles());
    if (!args.triangles.empty()) std::fprintf(stderr, ", %zu written to %s", triangles_written, args.triangles.c_str());
    if (!args.edges.empty()) std::fprintf(stderr, "; edges %zu written to %s", edges_written, args.edges.c_str());
    std::fprintf(stderr, "\n");
  }
  return kOk;
}

}  // namespace

Command add_delaunay_command(CLI::App& app) {
  auto args = std::make_shared<DelaunayArgs>();
  CLI::App* cmd = app.add_subcommand("delaunay", "Write the Delaunay triangles (polygons) and edges (lines) of the sites");
  add_site_input_options(cmd, args->sites);
  cmd->add_option("-o,--output", args->triangles,
                  "Triangles file (- for GeoJSON on stdout); the format follows the extension: .geojson, "
                  ".geojsons/.geojsonl, .gpkg, .fgb, .shp, .csv");
  cmd->add_option("--edges", args->edges, "Edges file (lines), same formats");
  cmd->add_option("--format", args->format, "OGR driver of the triangles file, overriding its extension");
  cmd->add_option("--edges-format", args->edges_format, "OGR driver of the edges file, overriding its extension");
  cmd->add_option("--densify-m", args->densify_m,
                  "Largest distance in metres between a written segment and the true great-circle arc (default 100)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--precision", args->precision, "Decimals of coordinates in GeoJSON (default 7, about 1 cm; binary formats store doubles): positions are computed, checked valid and measured as written; what collapses or cannot be written valid gets an empty geometry and is reported")
      ->check(CLI::Range(1, 17));
  cmd->add_flag("--no-ghosts", args->no_ghosts,
                "Leave out the faces and edges with ghost = 1 (outside the sites' convex hull: only when all sites lie "
                "in one hemisphere); the other triangles tile the sites' convex hull");
  cmd->add_flag("--overwrite", args->overwrite, "Replace existing output files");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress and no summary on stderr");
  cmd->footer(
      "At least one of -o and --edges. Triangles carry: tri_index, kind (proper, ghost or great_circle),\n"
      "ghost (1 for a face outside the triangulation of the sites' convex hull: a ghost face, whose\n"
      "circumcircle is larger than a hemisphere, written as the small triangle of its sites, or a\n"
      "great_circle face when other sites are off that circle), site_a/b/c (site indices, counter-clockwise),\n"
      "id_a/b/c, area_m2 (WGS84 ellipsoid, of the written polygon), area_sr (sphere), circumradius_m.\n"
      "Edges carry: edge_index, site_a, site_b, id_a, id_b, length_m (great circle on the sphere of radius\n"
      "6371008.8 m), geodesic_m (WGS84 geodesic between the two sites), hull (1 for an edge of the boundary\n"
      "of the sites' convex hull: between a face with ghost = 0 and one with ghost = 1), ghost (1 for an\n"
      "edge between two faces with ghost = 1: not an edge of the hull's triangulation).\n"
      "Examples:\n"
      "  geovor delaunay datasets/weather_stations.csv -o triangles.geojson --edges edges.geojson\n"
      "  geovor delaunay stations.gpkg -o tin.gpkg --edges edges.fgb --no-ghosts");
  return {[args] { return run(*args); },
          [args] {
            return site_input_needs_gdal(args->sites) ||
                   (!args->triangles.empty() && output_needs_gdal(args->triangles, args->format)) ||
                   (!args->edges.empty() && output_needs_gdal(args->edges, args->edges_format));
          }};
}

}  // namespace geovor::tools
