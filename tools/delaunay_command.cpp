// geovor delaunay INPUT -o TRIANGLES [--edges EDGES]: the Delaunay triangulation of the sites as
// GIS polygons (its triangles) and lines (its edges, with their great-circle length).
#include <memory>
#include <string>

#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/layers/delaunay_files.hpp"
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
  int threads = 0;  // 0: one per core
};

int run(DelaunayArgs& args) {
  if (args.triangles.empty() && args.edges.empty())
    throw Error(ErrorCode::InvalidArgument, "nothing to write: give -o TRIANGLES and/or --edges EDGES");
  WriterOptions options;  // of both outputs
  options.format = args.format;
  options.precision = args.precision;
  options.overwrite = args.overwrite;
  apply_output_model(args.model, options);
  options.layer = args.model.layer.empty() ? "triangles" : args.model.layer;
  const DelaunayOutput output = delaunay_output(args.triangles, args.edges, options, args.edges_format, args.edges_layer);
  check_delaunay_output(output, "--output", "--edges");  // before any work
  args.sites.quiet = args.quiet;  // merged rows stay in the counts
  args.sites.reader.threads = static_cast<unsigned>(args.threads);  // the conversion of the coordinates
  DelaunayFilesOptions files;
  files.densify_m = args.densify_m;
  files.no_ghosts = args.no_ghosts;
  files.quiet = args.quiet;
  files.precision_name = "--precision";
  delaunay_to_files(args.sites, output, files);
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
  add_threads_option(cmd, args->threads);
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
