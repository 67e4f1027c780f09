// geovor info INPUT: read sites, build the triangulation, validate it, and say what happened.
#include <algorithm>
#include <chrono>
#include <memory>
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/kernel/predicates.hpp"

namespace geovor::tools {
namespace {

struct InfoArgs {
  std::string input;
  SiteReaderOptions reader;
  std::string ecef_fields;
  double merge_m = 0;
  bool global_check = false;
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// What kind of input this was, in the terms of docs/: the degenerate cases are named.
std::string degenerate_case(const SphericalDelaunay& dt) {
  if (dt.num_sites() == 0) return "no sites";
  if (dt.num_sites() == 1) return "one site";
  if (dt.num_sites() == 2) return "two sites";
  bool all_flat = true;
  for (TriId t = 0; t < dt.num_triangles() && all_flat; ++t)
    all_flat = kernel::orient(dt.site(dt.tri_site(t, 0)), dt.site(dt.tri_site(t, 1)),
                              dt.site(dt.tri_site(t, 2))) == Sign::Zero;
  if (all_flat) return "all sites on one great circle";
  if (dt.num_ghost_triangles() > 0) return "all sites in one open hemisphere";
  return "none";
}

int run(const InfoArgs& args_in) {
  InfoArgs args = args_in;
  if (!args.ecef_fields.empty()) {
    std::string field;
    for (char c : args.ecef_fields + ",") {
      if (c == ',') {
        args.reader.ecef_fields.push_back(field);
        field.clear();
      } else {
        field += c;
      }
    }
  }
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  const SiteTable table = read_sites_csv_file(args.input, args.reader);
  const double read_s = seconds_since(t0);
  for (const RejectedRow& r : table.rejected)
    std::fprintf(stderr, "%s: row %llu (line %llu) rejected: %s\n", table.source.c_str(),
                 static_cast<unsigned long long>(r.row), static_cast<unsigned long long>(r.line),
                 r.reason.c_str());

  std::vector<Vec3> points;
  points.reserve(table.sites.size());
  for (const InputSite& s : table.sites) points.push_back(s.unit);
  DelaunayOptions options;
  if (args.merge_m > 0) {
    options.merge_distance = std::max(SphericalDelaunay::kMinSeparation, args.merge_m / SiteEncoder::kEarthRadiusM);
  }
  t0 = Clock::now();
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(points, options, &report);
  const double build_s = seconds_since(t0);
  // Name each merged row and the row that holds its site (the site's first input).
  std::vector<std::uint32_t> first_input(dt.site_capacity(), kNoIndex);
  for (std::uint32_t i = 0; i < report.site_of_input.size(); ++i)
    if (first_input[report.site_of_input[i]] == kNoIndex) first_input[report.site_of_input[i]] = i;
  for (const Merge& m : report.merges) {
    const InputSite& row = table.sites[m.input];
    const InputSite& kept = table.sites[first_input[m.site]];
    char why[96];
    if (m.chord == 0)
      std::snprintf(why, sizeof why, "same position");
    else
      std::snprintf(why, sizeof why, "%.3g m apart, closer than the merge distance%s",
                    m.chord * SiteEncoder::kEarthRadiusM, m.hidden ? " (hidden)" : "");
    std::fprintf(stderr, "%s: row %llu (id %s) merged into the site of row %llu (id %s): %s\n",
                 table.source.c_str(), static_cast<unsigned long long>(row.row), row.id.c_str(),
                 static_cast<unsigned long long>(kept.row), kept.id.c_str(), why);
  }
  t0 = Clock::now();
  const Validation valid = dt.validate(&report, args.global_check);
  const double validate_s = seconds_since(t0);
  for (const std::string& e : valid.errors) std::fprintf(stderr, "validate: %s\n", e.c_str());

  std::printf("input: %s\n", table.source.c_str());
  std::printf("rows: %llu\n", static_cast<unsigned long long>(table.rows_read));
  std::printf("sites: %zu\n", dt.num_sites());
  std::printf("merged: %zu\n", report.merges.size());
  std::printf("rejected: %zu\n", table.rejected.size());
  std::printf("triangles: %zu\n", dt.num_triangles());
  std::printf("ghost_triangles: %zu\n", dt.num_ghost_triangles());
  std::printf("degenerate: %s\n", degenerate_case(dt).c_str());
  std::printf("valid: %s\n", valid.ok() ? "yes" : "no");
  std::printf("read_seconds: %.3f\n", read_s);
  std::printf("build_seconds: %.3f\n", build_s);
  std::printf("validate_seconds: %.3f\n", validate_s);
  return valid.ok() ? kOk : kInternal;
}

}  // namespace

std::function<int()> add_info_command(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = app.add_subcommand(
      "info", "Read sites, build the Delaunay triangulation, validate it and print a summary");
  cmd->add_option("INPUT", args->input, "CSV file with a header, or - for stdin")->required();
  cmd->add_option("--lat-field", args->reader.lat_field, "Latitude column (default: lat, latitude, lat_deg or y)");
  cmd->add_option("--lon-field", args->reader.lon_field, "Longitude column (default: lon, lng, long, longitude, lon_deg or x)");
  cmd->add_option("--id-field", args->reader.id_field, "Identifier column (default: id, icao, code or name; else the row number)");
  cmd->add_option("--ecef-fields", args->ecef_fields, "X,Y,Z columns of ECEF metres instead of latitude/longitude");
  cmd->add_option("--merge-m", args->merge_m, "Merge sites closer than this many metres (default and minimum: 2^-24 R = 0.38 m)");
  cmd->add_flag("--global-check", args->global_check, "Also check every triangle against every site (O(n^2))");
  cmd->footer(
      "Prints one 'key: value' line each: input, rows, sites, merged, rejected, triangles,\n"
      "ghost_triangles, degenerate, valid, read_seconds, build_seconds, validate_seconds.\n"
      "Rejected rows and merged sites are listed on stderr with their row numbers.\n"
      "Example: geovor info datasets/weather_stations.csv");
  return [args] { return run(*args); };
}

}  // namespace geovor::tools
