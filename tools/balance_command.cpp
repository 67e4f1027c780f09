// geovor balance SITES -o CELLS: the radii for which every power cell's WGS84 area is its site's
// capacity's share of the Earth (the library's balance(), relax/balance.hpp); writes the cells as
// `geovor cells --weight-field` does and, optionally, the sites with their radii.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "cell_output.hpp"
#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/output_target.hpp"
#include "geovor/relax/balance.hpp"
#include "numeric_options.hpp"
#include "geovor/core/output_file.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

// Not converged: nothing is written (the documented exit code of the command).
constexpr int kNotConverged = 4;
// The target area of each cell, a column of the cells.
constexpr const char* kTargetField = "target_m2";

struct BalanceArgs {
  SiteInputArgs sites;
  CellOutputArgs cells;
  std::string capacity_field;
  double tolerance = 1e-6;
  int max_iterations = 50;
  std::string sites_output;
};

// Refused before the solve, so that a long run is not lost to an existing file.
void check_writable(const std::string& path, bool overwrite) {
  if (path.empty() || path == "-" || overwrite) return;
  std::error_code ec;
  if (std::filesystem::exists(path, ec)) throw Error(ErrorCode::Io, output_exists(path));
}

// The capacity in `text`, or why it is none.
std::string parse_capacity(const std::string& text, bool decimal_comma, double& value) {
  std::string s = text;
  s.erase(0, s.find_first_not_of(" \t"));
  s.erase(s.find_last_not_of(" \t") + 1);
  if (s.empty()) return "empty: a site needs a positive capacity";
  if (decimal_comma && std::count(s.begin(), s.end(), ',') == 1 && s.find('.') == std::string::npos)
    std::replace(s.begin(), s.end(), ',', '.');
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data() + (s[0] == '+'), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) return "\"" + s + "\" is not a number";
  if (!(value > 0)) return "capacity " + s + " is not positive";
  return {};
}

// Each accepted row's capacity from column `field`; rows without a positive one move to
// table.rejected (listed on stderr as the readers list theirs).
std::vector<double> read_capacities(SiteTable& table, const std::string& field) {
  std::vector<double> capacities;
  if (field.empty()) {
    capacities.assign(table.sites.size(), 1.0);
    return capacities;
  }
  const int column = find_column(table.columns, field);
  if (column < 0) {
    std::string names;
    for (const std::string& c : table.columns) names += (names.empty() ? "" : ", ") + c;
    throw Error(ErrorCode::InvalidArgument, table.source + ": no capacity column '" + field + "' (columns: " + names + ")");
  }
  const auto c = static_cast<std::size_t>(column);
  std::vector<InputSite> kept;
  std::vector<RejectedRow> rejected;
  for (InputSite& s : table.sites) {
    double value = 0;
    const std::string reason = c < s.fields.size() ? parse_capacity(s.fields[c], table.delimiter != ',', value)
                                                   : std::string("empty: a site needs a positive capacity");
    if (reason.empty()) {
      kept.push_back(std::move(s));
      capacities.push_back(value);
    } else {
      rejected.push_back({s.row, s.line, table.columns[c] + ": " + reason});
      std::fprintf(stderr, "%s: row %llu (line %llu) rejected: %s\n", table.source.c_str(),
                   static_cast<unsigned long long>(s.row), static_cast<unsigned long long>(s.line),
                   rejected.back().reason.c_str());
    }
  }
  table.sites = std::move(kept);
  std::vector<RejectedRow> all;
  std::merge(table.rejected.begin(), table.rejected.end(), rejected.begin(), rejected.end(), std::back_inserter(all),
             [](const RejectedRow& a, const RejectedRow& b) { return a.row < b.row; });
  table.rejected = std::move(all);
  if (table.sites.empty()) throw Error(ErrorCode::BadData, table.source + ": no row has a positive capacity");
  return capacities;
}

// The sites as CSV, one row per site (the row it was built from: rows merged into it are not
// repeated, so that the file reads back as the sites balanced): site_id, lat_deg, lon_deg, weight_m (the radius),
// target_m2, every value with 17 digits so that `geovor cells FILE --weight-field weight_m` reads
// back the same doubles and builds the same cells.
void write_sites_csv(const std::string& path, bool overwrite, const SiteTable& table, const BuildReport& build,
                     const BalanceReport& report) {
  std::vector<char> merged(table.sites.size(), 0);
  for (const Merge& m : build.merges) merged[m.input] = 1;
  OutputFile out(path, overwrite);
  std::FILE* f = out.get();
  std::fprintf(f, "site_id,lat_deg,lon_deg,weight_m,target_m2\n");
  for (std::size_t i = 0; i < table.sites.size(); ++i) {
    if (merged[i]) continue;
    const InputSite& s = table.sites[i];
    std::string id = "\"";
    for (const char ch : s.id) id += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    std::fprintf(f, "%s\",%.17g,%.17g,%.17g,%.17g\n", id.c_str(), s.lat_deg, s.lon_deg, report.radii_m[i],
                 report.targets[i]);
  }
  out.commit();
}

// Each site's target area as one more input column, target_m2 (Real), which the cell layer writes
// after the input's own (unless the input has a column of that name already: then it is kept).
void add_target_column(SiteTable& table, const BalanceReport& result) {
  if (find_column(table.columns, kTargetField) >= 0) {
    std::fprintf(stderr, "%s: has a column '%s' already: the targets are not written\n", table.source.c_str(), kTargetField);
    return;
  }
  if (table.column_types.empty()) table.column_types.assign(table.columns.size(), FieldType::String);
  table.columns.push_back(kTargetField);
  table.column_types.push_back(FieldType::Real);
  char text[32];
  for (std::size_t i = 0; i < table.sites.size(); ++i) {
    std::vector<std::string>& fields = table.sites[i].fields;
    fields.resize(table.columns.size() - 1);  // a short row's missing values are empty
    std::snprintf(text, sizeof text, "%.17g", result.targets[i]);
    fields.push_back(text);
  }
}

int run(BalanceArgs& args) {
  if (!args.sites.weight_field.empty())
    throw Error(ErrorCode::InvalidArgument, "--weight-field: balance computes the radii (use --capacity-field)");
  check_distinct_outputs({{"--output", args.cells.output}, {"--sites-output", args.sites_output}});
  check_writer_options(args.cells.output, GeometryType::MultiPolygon, cell_writer_options(args.cells));
  check_writable(args.cells.output, args.cells.overwrite || args.cells.model.update);
  check_writable(args.sites_output, args.cells.overwrite);

  DuplicateIds duplicates;
  SiteTable table = read_site_input(args.sites, &duplicates);
  const std::vector<double> capacities = read_capacities(table, args.capacity_field);
  args.cells.ids_repeat = duplicates.rows > 0;
  const std::vector<Vec3> points = site_points(table);

  BalanceOptions options;
  options.tolerance = args.tolerance;
  options.max_iterations = args.max_iterations;
  options.threads = static_cast<unsigned>(args.cells.threads);
  const EllipsoidAreaMeasure area;
  int k = 0;
  if (!args.cells.quiet)
    std::fprintf(stderr, "%s: %zu sites, tolerance %g\n%9s %22s %12s %9s\n", table.source.c_str(), points.size(),
                 args.tolerance, "iteration", "max_relative_error", "step", "seconds");
  const BalanceReport result =
      balance(points, capacities, area, options, delaunay_options(args.sites), [&](const BalanceIteration& it) {
        if (!args.cells.quiet)
          std::fprintf(stderr, "%9d %22.3e %12g %9.3f\n", ++k, it.max_relative_error, it.step, it.seconds);
      });
  if (!result.converged) {
    const double error = result.iterations.empty() ? result.initial_relative_error
                                                   : result.iterations.back().max_relative_error;
    std::fprintf(stderr,
                 "geovor balance: not converged after %zu iterations (largest relative area error %.3e > %g); "
                 "nothing written\n",
                 result.iterations.size(), error, args.tolerance);
    return finish_command(kNotConverged);
  }

  // The cells of the exact lifts balance() ended with, through the path of `geovor cells`.
  for (std::size_t i = 0; i < table.sites.size(); ++i) table.sites[i].weight_m = result.radii_m[i];
  add_target_column(table, result);
  table.weighted = true;
  BuildReport report;
  const SphericalDelaunay dt = balanced_triangulation(points, result, delaunay_options(args.sites), report);
  if (!args.cells.quiet) list_merges(stderr, table, report);
  list_hidden(stderr, table, report);
  const std::size_t written = write_cells(args.cells, table, report, dt).cells_written;
  if (!args.sites_output.empty()) write_sites_csv(args.sites_output, args.cells.overwrite, table, report, result);
  if (!args.cells.quiet)
    std::fprintf(stderr, "%s: rows %llu, sites %zu, merged %zu, rejected %zu; %zu cells written to %s%s%s\n",
                 table.source.c_str(), static_cast<unsigned long long>(table.rows_read), dt.num_sites(),
                 report.merges.size(), table.rejected.size(), written, args.cells.output.c_str(),
                 args.sites_output.empty() ? "" : ", sites to ", args.sites_output.c_str());
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
  cmd->add_option("--threads", args->cells.threads,
                  "Threads computing the areas, the Hessian and the cells (default: one per core); the output is the same")
      ->check(integer_in(0, kMaxThreads));
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
