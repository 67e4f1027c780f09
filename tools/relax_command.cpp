// geovor relax INPUT -o OUTPUT --iterations N: Lloyd's iterations toward a spherical centroidal
// Voronoi tessellation; writes the final cells as `geovor cells` does and, optionally, the sites.
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "cell_output.hpp"
#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/layers/relaxed_cells.hpp"
#include "numeric_options.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct RelaxArgs {
  SiteInputArgs sites;
  CellOutputArgs cells;
  int iterations = 10;
  std::string relocation = "filtered";
  double tolerance_m = 0;
  std::string sites_output;
};

int run(RelaxArgs& args) {
  RelaxedCellsOptions options;
  options.lloyd.iterations = args.iterations;
  options.lloyd.tolerance_rad = args.tolerance_m / SiteEncoder::kEarthRadiusM;
  options.lloyd.threads = static_cast<unsigned>(args.cells.threads);
  args.sites.reader.threads = static_cast<unsigned>(args.cells.threads);
  const auto relocations = {Relocation::Filtered, Relocation::Naive, Relocation::Rebuild};
  const auto r = std::find_if(relocations.begin(), relocations.end(),
                              [&](Relocation x) { return args.relocation == to_string(x); });
  if (r == relocations.end())
    throw Error(ErrorCode::InvalidArgument, "--relocation: expected filtered, naive or rebuild, got '" + args.relocation + "'");
  options.lloyd.relocation = *r;
  options.cells = cell_file_options(args.cells);
  options.sites_path = args.sites_output;
  // Two outputs that are one file (a path, an alias, a link; `-` twice) or existing outputs: refused
  // before any work. The sites may be a second layer of the cells' data source (GPKG, ...).
  check_relaxed_outputs(args.cells.output, options, "--output", "--sites-output");
  if (!args.sites.weight_field.empty())
    throw Error(ErrorCode::InvalidArgument, "--weight-field: Lloyd's iterations move unweighted sites only");
  args.sites.quiet = args.cells.quiet;  // merged rows stay in the cells' ids
  relax_to_files(args.sites, args.cells.output, options);
  return kOk;
}

}  // namespace

Command add_relax_command(CLI::App& app) {
  auto args = std::make_shared<RelaxArgs>();
  CLI::App* cmd = app.add_subcommand(
      "relax", "Move every site to the centroid of its cell, N times (Lloyd), and write the final cells");
  add_site_input_options(cmd, args->sites);
  cmd->add_option("-o,--output", args->cells.output,
                  "Output cells (- for GeoJSON on stdout), as `geovor cells` writes them; the format follows the "
                  "extension: .geojson, .geojsons/.geojsonl, .gpkg, .fgb, .shp, .csv")
      ->required();
  cmd->add_option("-n,--iterations", args->iterations, "Number of Lloyd iterations (default 10)")
      ->check(integer_in(0, 1000000000));
  cmd->add_option("--relocation", args->relocation,
                  "How the triangulation follows the sites: filtered (default: tolerance filter, then flips), "
                  "naive (remove + insert) or rebuild (from scratch); the result is the same");
  cmd->add_option("--tolerance-m", args->tolerance_m,
                  "Stop early once no site moves more than this many metres in an iteration (default 0: never)")
      ->check(finite_above(0, true));
  cmd->add_option("--sites-output", args->sites_output,
                  "Also write the final sites as points (site_index, site_id, lat_deg, lon_deg, moved_m, then the "
                  "input columns but the positions), in any format --output takes; layer sites, which may be a "
                  "second layer of --output's GeoPackage (or other multi-layer data source)");
  add_output_model_options(cmd, args->cells.format, args->cells.overwrite, args->cells.model, "cells");
  cmd->add_option("--densify-m", args->cells.densify_m,
                  "Largest distance in metres between a written edge and the true great-circle arc (default 100)")
      ->check(finite_above(0, false));
  cmd->add_option("--precision", args->cells.precision, "Decimals of coordinates in GeoJSON (default 7, about 1 cm; binary formats store doubles): positions are computed, checked valid and measured as written; what collapses or cannot be written valid gets an empty geometry and is reported")
      ->check(integer_in(1, 17));
  cmd->add_flag("-q,--quiet", args->cells.quiet, "No per-iteration lines, progress, summary or list of merged rows on stderr");
  add_threads_option(cmd, args->cells.threads);
  cmd->footer(
      "Each iteration moves every site to the centroid of its spherical Voronoi cell (the mass centre\n"
      "projected to the sphere), toward a centroidal Voronoi tessellation. It prints on stderr the energy\n"
      "(sum over cells of the integral of |x - site|^2 on the unit sphere, which decreases), the largest\n"
      "and mean displacement in metres, the moves the tolerance filter certified, and the time.\n"
      "A site whose centroid falls within the merge distance of another site stays where it was.\n"
      "The cells carry the fields of `geovor cells` (the attributes of the input rows).\n"
      "Exit codes: 0 ok, 2 usage error, 3 bad input data, 4 I/O error.\n"
      "Examples:\n"
      "  geovor relax datasets/weather_stations.csv -o relaxed.geojson --iterations 50\n"
      "  geovor relax sites.csv -o cells.gpkg -n 100 --sites-output sites.fgb --relocation rebuild");
  return {[args] { return run(*args); },
          [args] {
            return site_input_needs_gdal(args->sites) ||
                   output_needs_gdal(args->cells.output, args->cells.format) ||
                   (!args->sites_output.empty() && output_needs_gdal(args->sites_output, ""));
          }};
}

}  // namespace geovor::tools
