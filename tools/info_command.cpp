// geovor info INPUT: read sites, build the triangulation, validate it, and say what happened.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "geovor/core/ascii.hpp"
#include "geovor/delaunay/degenerate_case.hpp"
#include "geovor/geo/site_weights.hpp"
#include "numeric_options.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct InfoArgs {
  SiteInputArgs sites;
  bool global_check = false;
  int threads = 0;  // 0: one per core
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int run(InfoArgs& args) {
  using Clock = std::chrono::steady_clock;
  const unsigned threads = static_cast<unsigned>(args.threads);
  args.sites.reader.threads = threads;  // the conversion of the coordinates; the build is serial
  auto t0 = Clock::now();
  const SiteTable table = read_site_input(args.sites);
  const double read_s = seconds_since(t0);
  const std::vector<Vec3> points = site_points(table);
  t0 = Clock::now();
  BuildReport report;
  const SphericalDelaunay dt = build_sites(points, table.weighted ? site_lifts(table) : std::vector<double>(),
                                           args.sites, report);
  const double build_s = seconds_since(t0);
  list_build(args.sites, table, report);  // merged rows counted in `merged` either way; hidden ones listed even with --quiet
  t0 = Clock::now();
  const Validation valid = dt.validate(&report, args.global_check, threads);
  const double validate_s = seconds_since(t0);
  for (const std::string& e : valid.errors) std::fprintf(stderr, "validate: %s\n", e.c_str());

  std::printf("input: %s\n", printable(table.source).c_str());
  std::printf("rows: %llu\n", static_cast<unsigned long long>(table.rows_read));
  std::printf("sites: %zu\n", dt.num_sites());
  std::printf("merged: %zu\n", report.merges.size());
  if (table.weighted) std::printf("hidden: %zu\n", report.hidden.size());
  std::printf("rejected: %zu\n", table.rejected.size());
  std::printf("triangles: %zu\n", dt.num_triangles());
  std::printf("ghost_triangles: %zu\n", dt.num_ghost_triangles());
  std::printf("degenerate: %s\n", degenerate_case(dt));
  std::printf("valid: %s\n", valid.ok() ? "yes" : "no");
  std::printf("read_seconds: %.3f\n", read_s);
  std::printf("build_seconds: %.3f\n", build_s);
  std::printf("validate_seconds: %.3f\n", validate_s);
  return valid.ok() ? kOk : kInternal;
}

}  // namespace

Command add_info_command(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "info", "Read sites, build the Delaunay triangulation, validate it and print a summary");
  add_site_input_options(cmd, args->sites);
  cmd->add_flag("--global-check", args->global_check, "Also check every triangle against every site (O(n^2))");
  cmd->add_flag("-q,--quiet", args->sites.quiet, "No list of merged rows on stderr (rejected rows are still listed)");
  add_threads_option(cmd, args->threads);
  cmd->footer(
      "Prints one 'key: value' line each: input, rows, sites, merged, hidden (with --weight-field: weighted\n"
      "sites whose power cell is empty), rejected, triangles, ghost_triangles, degenerate, valid,\n"
      "read_seconds, build_seconds, validate_seconds. 'sites' counts the vertices of the triangulation.\n"
      "Rejected rows, merged and hidden sites are listed on stderr with their row numbers.\n"
      "Example: geovor info datasets/weather_stations.csv");
  return {[args] { return run(*args); },
          [args] { return site_input_needs_gdal(args->sites); }};
}

}  // namespace geovor::tools
