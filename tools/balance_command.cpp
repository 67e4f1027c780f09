// geovor balance SITES -o CELLS: the radii for which every power cell's WGS84 area is its site's
// capacity's share of the Earth (the library's balance(), relax/balance.hpp); writes the cells as
// `geovor cells --weight-field` does and, optionally, the sites with their radii.
#include <cstdio>
#include <memory>
#include <string>

#include "cell_output.hpp"
#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/output_target.hpp"
#include "geovor/layers/balanced_cells.hpp"
#include "numeric_options.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

// Not converged: nothing is written (the documented exit code of the command).
constexpr int kNotConverged = 4;

struct BalanceArgs {
  SiteInputArgs sites;
  CellOutputArgs cells;
  std::string capacity_field;
  double tolerance = 1e-6;
  int max_iterations = 50;
  std::string sites_output;
};

int run(BalanceArgs& args) {
  if (!args.sites.weight_field.empty())
    throw Error(ErrorCode::InvalidArgument, "--weight-field: balance computes the radii (use --capacity-field)");
  check_distinct_outputs({{"--output", args.cells.output}, {"--sites-output", args.sites_output}});
  check_writer_options(args.cells.output, GeometryType::MultiPolygon, cell_writer_options(args.cells));
  refuse_existing_output(args.cells.output, args.cells.overwrite || args.cells.model.update);  // before the solve
  refuse_existing_output(args.sites_output, args.cells.overwrite);
  BalancedCellsOptions options;
  options.balance.tolerance = args.tolerance;
  options.balance.max_iterations = args.max_iterations;
  options.balance.threads = static_cast<unsigned>(args.cells.threads);
  args.sites.reader.threads = static_cast<unsigned>(args.cells.threads);
  options.capacity_field = args.capacity_field;
  options.cells = cell_file_options(args.cells);
  options.sites_path = args.sites_output;
  args.sites.quiet = args.cells.quiet;
  const BalanceReport result = balance_to_files(args.sites, args.cells.output, options);
  if (!result.converged) {
    const double error = result.iterations.empty() ? result.initial_relative_error
                                                   : result.iterations.back().max_relative_error;
    std::fprintf(stderr,
                 "geovor balance: not converged after %zu iterations (largest relative area error %.3e > %g); "
                 "nothing written\n",
                 result.iterations.size(), error, args.tolerance);
    return finish_command(kNotConverged);
  }
  return finish_command(kOk);
}

}  // namespace

Command add_balance_command(CLI::App& app) {
  auto args = std::make_shared<BalanceArgs>();
  CLI::App* cmd = app.add_subcommand(
      "balance", "Find the site radii that give every power cell its capacity's share of the Earth's area, and write the cells");
  add_site_input_options(cmd, args->sites);
  cmd->add_option("-o,--output", args->cells.output,
                  "Output cells (- for GeoJSON on stdout), as `geovor cells --weight-field` writes them; the format "
                  "follows the extension: .geojson, .geojsons/.geojsonl, .gpkg, .fgb, .shp, .csv")
      ->required();
  cmd->add_option("--capacity-field", args->capacity_field,
                  "Column of each site's capacity (positive; its cell gets capacity / sum of capacities of the "
                  "Earth's area); a row whose value is empty, not a number, zero or negative is rejected. Default: "
                  "equal shares");
  cmd->add_option("--tolerance", args->tolerance,
                  "Stop when every cell's relative area error |area - target| / target is at most this (default 1e-6)")
      ->check(finite_above(0, false));
  cmd->add_option("--max-iterations", args->max_iterations, "Newton iterations at most (default 50)")
      ->check(integer_in(0, 1000000));
  cmd->add_option("--sites-output", args->sites_output,
                  "Also write the sites as CSV, one row per site (site_id, lat_deg, lon_deg, weight_m: the radius in metres, target_m2) "
                  "so that `geovor cells FILE --weight-field weight_m` gives the same cells");
  add_output_model_options(cmd, args->cells.format, args->cells.overwrite, args->cells.model, "cells");
  cmd->add_option("--densify-m", args->cells.densify_m,
                  "Largest distance in metres between a written edge and the true great-circle arc (default 100)")
      ->check(finite_above(0, false));
  cmd->add_option("--precision", args->cells.precision, "Decimals of coordinates in GeoJSON (default 7)")
      ->check(integer_in(1, 17));
  cmd->add_flag("-q,--quiet", args->cells.quiet, "No per-iteration lines, progress, summary or list of merged rows on stderr");
  add_threads_option(cmd, args->cells.threads);
  cmd->footer(
      "The semi-discrete optimal transport problem of docs/weighted.md, solved by damped Newton (Kitagawa,\n"
      "Merigot and Thibert): each iteration prints on stderr the largest relative area error of a cell and\n"
      "the damping step taken. Areas are those of the exact power cells on the WGS84 ellipsoid (the\n"
      "area_m2 written is that of the densified ring, within the densification of it). The smallest radius\n"
      "is 0. Points merged into one site pool their capacities. The cells carry the fields of `geovor cells\n"
      "--weight-field` (weight_m: the radius), then target_m2, the target area.\n"
      "Exit codes: 0 ok, 2 usage error, 3 bad input data, 4 not converged (nothing written) or I/O error.\n"
      "Examples:\n"
      "  geovor balance datasets/weather_stations.csv -o balanced.geojson\n"
      "  geovor balance depots.csv -o territories.gpkg --capacity-field trucks --sites-output radii.csv");
  return {[args] { return run(*args); },
          [args] {
            return site_input_needs_gdal(args->sites) || output_needs_gdal(args->cells.output, args->cells.format);
          }};
}

}  // namespace geovor::tools
