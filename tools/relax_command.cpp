// geovor relax INPUT -o OUTPUT --iterations N: Lloyd's iterations toward a spherical centroidal
// Voronoi tessellation; writes the final cells as `geovor cells` does and, optionally, the sites.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cell_output.hpp"
#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/core/output_target.hpp"
#include "geovor/layers/site_layer.hpp"
#include "geovor/relax/lloyd.hpp"
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

// The final sites as points (geovor/layers/site_layer.hpp).
void write_sites(const RelaxArgs& args, const SiteTable& table, const BuildReport& report, const SphericalDelaunay& dt,
                 const std::vector<Vec3>& start, bool into_cells_source) {
  WriterOptions options;
  options.format = into_cells_source ? args.cells.format : "";
  options.layer = "sites";
  options.precision = args.cells.precision;
  options.overwrite = args.cells.overwrite;
  options.update = into_cells_source || (args.cells.model.update && format_holds_layers(args.sites_output, ""));
  if (args.cells.ids_repeat) options.id_field = "site_index";  // feature ids stay unique
  const auto writer = open_site_layer_writer(args.sites_output, table, options);
  write_site_layer(*writer, table, rows_of_sites(report, dt.site_capacity()), dt, start);
  writer->finish();
}

int run(RelaxArgs& args) {
  LloydOptions options;
  options.iterations = args.iterations;
  options.tolerance_rad = args.tolerance_m / SiteEncoder::kEarthRadiusM;
  options.threads = static_cast<unsigned>(args.cells.threads);
  if (args.relocation == "filtered")
    options.relocation = Relocation::Filtered;
  else if (args.relocation == "naive")
    options.relocation = Relocation::Naive;
  else if (args.relocation == "rebuild")
    options.relocation = Relocation::Rebuild;
  else
    throw Error(ErrorCode::InvalidArgument, "--relocation: expected filtered, naive or rebuild, got '" + args.relocation + "'");
  // Two outputs that are one file (a path, an alias, a link; `-` twice): refused before any work.
  // The sites may be a second layer of the cells' data source (GPKG, ...), added once the cells are in place.
  const bool one_source = !args.sites_output.empty() && same_output_file(args.cells.output, args.sites_output) &&
                          format_holds_layers(args.cells.output, args.cells.format);
  if (!one_source) check_distinct_outputs({{"--output", args.cells.output}, {"--sites-output", args.sites_output}});
  check_writer_options(args.cells.output, GeometryType::MultiPolygon, cell_writer_options(args.cells));  // before the iterations
  if (!args.sites_output.empty()) {
    WriterOptions sites;
    sites.format = one_source ? args.cells.format : "";
    check_writer_options(args.sites_output, GeometryType::Point, sites);
  }
  // Refused before the iterations run, so that a long run is not lost to an existing file.
  refuse_existing_output(args.cells.output, args.cells.overwrite || args.cells.model.update);
  if (!one_source)
    refuse_existing_output(args.sites_output, args.cells.overwrite || (args.cells.model.update && !args.sites_output.empty() &&
                                                                       format_holds_layers(args.sites_output, "")));

  DuplicateIds duplicates;
  if (!args.sites.weight_field.empty())
    throw Error(ErrorCode::InvalidArgument, "--weight-field: Lloyd's iterations move unweighted sites only");
  const SiteTable table = read_site_input(args.sites, &duplicates);
  args.cells.ids_repeat = duplicates.rows > 0;
  const std::vector<Vec3> points = site_points(table);
  BuildReport report;
  SphericalDelaunay dt = SphericalDelaunay::build(points, delaunay_options(args.sites), &report);
  if (!args.cells.quiet) list_merges(stderr, table, report);  // merged rows stay in the cells' ids
  const std::vector<Vec3> start(dt.sites().begin(), dt.sites().end());

  // Site ids never change (no site is removed), so the build's row report still names the rows.
  if (!args.cells.quiet)
    std::fprintf(stderr, "%s: %zu sites, %d iterations (%s relocation)\n%9s %22s %14s %14s %9s %9s\n",
                 table.source.c_str(), dt.num_sites(), args.iterations, to_string(options.relocation), "iteration",
                 "energy", "max_move_m", "mean_move_m", "filtered", "seconds");
  const LloydReport lloyd_report = lloyd(dt, options, [&](const LloydIteration& it) {
    if (args.cells.quiet) return;
    std::fprintf(stderr, "%9d %22.15e %14.3f %14.3f %9zu %9.3f\n", it.iteration, it.energy, it.max_move_m,
                 it.mean_move_m, it.moves.filtered, it.seconds);
  });
  std::size_t refused = 0, undefined = 0;
  for (const LloydIteration& it : lloyd_report.iterations) {
    refused += it.moves.refused;
    undefined = std::max(undefined, it.undefined);
  }
  if (!args.cells.quiet) {
    std::fprintf(stderr, "final energy %.15e", lloyd_report.final_energy);
    if (refused) std::fprintf(stderr, "; %zu moves refused (centroid within the merge distance of a site)", refused);
    if (undefined) std::fprintf(stderr, "; %zu site(s) without a centroid kept in place", undefined);
    std::fprintf(stderr, "\n");
  }

  const std::size_t written = write_cells(args.cells, table, report, dt).cells_written;
  if (!args.sites_output.empty()) write_sites(args, table, report, dt, start, one_source);
  if (!args.cells.quiet)
    std::fprintf(stderr, "%s: rows %llu, sites %zu, merged %zu, rejected %zu; %zu cells written to %s%s%s\n",
                 table.source.c_str(), static_cast<unsigned long long>(table.rows_read), dt.num_sites(),
                 report.merges.size(), table.rejected.size(), written, args.cells.output.c_str(),
                 args.sites_output.empty() ? "" : ", sites to ", args.sites_output.c_str());
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
  cmd->add_option("--threads", args->cells.threads,
                  "Threads computing the centroids and the cells (default: one per core); the output is the same")
      ->check(integer_in(0, kMaxThreads));
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
