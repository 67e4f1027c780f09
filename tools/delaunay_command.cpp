// geovor delaunay INPUT -o TRIANGLES [--edges EDGES]: the Delaunay triangulation of the sites as
// GIS polygons (its triangles) and lines (its edges, with their great-circle length).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/core/output_target.hpp"
#include "geovor/layers/delaunay_layers.hpp"
#include "geovor/lonlat/cell_geometry.hpp"
#include "numeric_options.hpp"
#include "output_model.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct DelaunayArgs {
  SiteInputArgs sites;
  std::string triangles;
  std::string edges;
  std::string format;
  std::string edges_format;
  OutputModelArgs model;
  std::string edges_layer = "edges";
  double densify_m = 100;
  int precision = 7;
  bool no_ghosts = false;
  bool overwrite = false;
  bool quiet = false;
};

// The options of one output: its format and layer, the output model's data-source options.
WriterOptions writer_options(const DelaunayArgs& args, const std::string& format, const std::string& layer) {
  WriterOptions o;
  o.format = format;
  o.precision = args.precision;
  o.overwrite = args.overwrite;
  apply_output_model(args.model, o);
  o.layer = layer;
  return o;
}

int run(DelaunayArgs& args) {
  if (args.triangles.empty() && args.edges.empty())
    throw Error(ErrorCode::InvalidArgument, "nothing to write: give -o TRIANGLES and/or --edges EDGES");
  DelaunayOutput output;
  output.triangles_path = args.triangles;
  output.triangles = writer_options(args, args.format, args.model.layer.empty() ? "triangles" : args.model.layer);
  output.edges_path = args.edges;
  output.edges = writer_options(args, args.edges_format, args.edges_layer);
  // --update concerns the outputs whose format holds several layers, --lco/--dsco those GDAL
  // writes; an edges file of another format is created as it would be without them.
  if (!args.edges.empty() && !one_data_source(output)) {
    if (!output_needs_gdal(args.edges, args.edges_format)) output.edges.layer_options.clear(), output.edges.dataset_options.clear();
    if (!format_holds_layers(args.edges, output.edges.format)) output.edges.update = false;
  }
  // Two outputs that are one file (a path, an alias, a link; `-` twice) are refused before any
  // work, unless it is one data source that holds both layers (GPKG, ...).
  if (!(one_data_source(output) && format_holds_layers(args.triangles, output.triangles.format)))
    check_distinct_outputs({{"--output", args.triangles}, {"--edges", args.edges}});
  if (!args.triangles.empty()) check_writer_options(args.triangles, GeometryType::MultiPolygon, output.triangles);  // before any work
  if (!args.edges.empty()) check_writer_options(args.edges, GeometryType::MultiLineString, output.edges);
  const SiteTable table = read_site_input(args.sites);
  const std::vector<Vec3> points = site_points(table);
  BuildReport report;
  const SphericalDelaunay dt = build_sites(points, table.weighted ? site_lifts(table) : std::vector<double>(),
                                           args.sites, report);
  if (!args.quiet) list_merges(stderr, table, report);  // merged rows stay in the counts
  list_hidden(stderr, table, report);                   // a hidden site is no vertex of any triangle
  const SiteRows rows = rows_of_sites(report, dt.site_capacity());
  DelaunayGeometryOptions geometry_options;
  geometry_options.densify_m = args.densify_m;
  // Positions as the text outputs (GeoJSON) write them; the binary formats store doubles, and
  // a binary output beside a text one gets the rounded positions (as doubles) too.
  const bool text = (!args.triangles.empty() && !output_needs_gdal(args.triangles, args.format)) ||
                    (!args.edges.empty() && !output_needs_gdal(args.edges, args.edges_format));
  geometry_options.precision = text ? args.precision : kFullPrecision;
  const DelaunayGeometry geometry(dt, geometry_options);
  const std::size_t total = (args.triangles.empty() ? 0 : dt.num_triangles()) +
                            (args.edges.empty() ? 0 : dt.halfedges().size() / 2);
  Progress progress(total, Progress::on_terminal(stderr, args.quiet));
  DelaunayLayerOptions layer_options;
  layer_options.no_ghosts = args.no_ghosts;
  layer_options.progress = [&](std::size_t done) { progress.advance(done); };
  const DelaunayLayersReport written = write_delaunay_layers(output, table, rows, geometry, layer_options);
  const TriangleLayerReport& triangles = written.triangles;
  const EdgeLayerReport& edges = written.edges;
  progress.finish();
  const std::string where =
      geometry_options.precision >= 0 ? "--precision " + std::to_string(geometry_options.precision) : "full precision";
  const std::vector<UnwrittenTriangle>& unwritten = triangles.unwritten;
  if (!unwritten.empty()) {
    // Listed even with --quiet, as rejected rows are: a feature without geometry must not pass unseen.
    std::fprintf(stderr, "%zu triangle(s) written with an empty geometry: at %s they collapse or would not be valid polygons (raise --precision):\n",
                 unwritten.size(), where.c_str());
    for (std::size_t i = 0; i < unwritten.size() && i < 20; ++i) {
      const TriId t = unwritten[i].triangle;
      std::fprintf(stderr, "  triangle %u (sites %u, %u, %u): %s\n", t, dt.tri_site(t, 0), dt.tri_site(t, 1),
                   dt.tri_site(t, 2), to_string(unwritten[i].status));
    }
    if (unwritten.size() > 20) std::fprintf(stderr, "  ... (%zu more)\n", unwritten.size() - 20);
  }
  if (edges.collapsed > 0)
    std::fprintf(stderr, "%zu edge(s) written with an empty geometry: their ends are one position at %s\n", edges.collapsed,
                 where.c_str());
  if (!args.quiet) {
    std::fprintf(stderr, "%s: rows %llu, sites %zu, merged %zu, rejected %zu; triangles %zu (ghost %zu)",
                 table.source.c_str(), static_cast<unsigned long long>(table.rows_read), dt.num_sites(),
                 report.merges.size(), table.rejected.size(), dt.num_triangles(), dt.num_ghost_triangles());
    if (!args.triangles.empty()) std::fprintf(stderr, ", %zu written to %s", triangles.triangles_written, args.triangles.c_str());
    if (!args.edges.empty()) std::fprintf(stderr, "; edges %zu written to %s", edges.edges_written, args.edges.c_str());
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
  add_output_model_options(cmd, args->format, args->overwrite, args->model, "triangles");
  cmd->add_option("--edges-format", args->edges_format, "OGR driver of the edges file, overriding its extension");
  cmd->add_option("--edges-nln", args->edges_layer, "Layer name of the edges (default edges)");
  cmd->add_option("--densify-m", args->densify_m,
                  "Largest distance in metres between a written segment and the true great-circle arc (default 100)")
      ->check(finite_above(0, false));
  cmd->add_option("--precision", args->precision, "Decimals of coordinates in GeoJSON (default 7, about 1 cm; binary formats store doubles): positions are computed, checked valid and measured as written; what collapses or cannot be written valid gets an empty geometry and is reported")
      ->check(integer_in(1, 17));
  cmd->add_flag("--no-ghosts", args->no_ghosts,
                "Leave out the faces and edges with ghost = 1 (outside the sites' convex hull: only when all sites lie "
                "in one hemisphere); the other triangles tile the sites' convex hull");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress, no summary and no list of merged rows on stderr");
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
      "  geovor delaunay stations.gpkg -o tin.gpkg --edges edges.fgb --no-ghosts\n"
      "  geovor delaunay stations.csv -o tin.gpkg --edges tin.gpkg   (one GeoPackage, layers triangles and edges)");
  return {[args] { return run(*args); },
          [args] {
            return site_input_needs_gdal(args->sites) ||
                   (!args->triangles.empty() && output_needs_gdal(args->triangles, args->format)) ||
                   (!args->edges.empty() && output_needs_gdal(args->edges, args->edges_format));
          }};
}

}  // namespace geovor::tools
