// geovor index SITES -o FILE: read sites, build the Delaunay hierarchy, save both as an index
// file that `geovor nearest --sites FILE` loads instead of rebuilding.
#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/output_target.hpp"
#include "geovor/locate/index_file.hpp"
#include "numeric_options.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct IndexArgs {
  SiteInputArgs sites;
  std::string output;
  bool overwrite = false;
  int threads = 0;  // 0: one per core
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

int run(IndexArgs& args) {
  struct stat st;
  // Refuse an existing output before the work (save_index checks again, atomically).
  if (!args.overwrite && stat(args.output.c_str(), &st) == 0)
    throw Error(ErrorCode::Io, output_exists(args.output));
  args.sites.reader.threads = static_cast<unsigned>(args.threads);  // the conversion of the coordinates
  TableBuild summary;
  const SiteIndex index = build_index_from_table(args.sites, &summary);
  const auto t0 = std::chrono::steady_clock::now();
  save_index(args.output, index.hierarchy, index.attributes, args.overwrite);
  const double save_s = seconds_since(t0);
  if (stat(args.output.c_str(), &st) != 0) st.st_size = 0;
  std::printf("input: %s\n", summary.source.c_str());
  std::printf("output: %s\n", args.output.c_str());
  std::printf("rows: %llu\n", static_cast<unsigned long long>(summary.rows));
  std::printf("sites: %llu\n", static_cast<unsigned long long>(summary.sites));
  std::printf("merged: %llu\n", static_cast<unsigned long long>(summary.merged));
  std::printf("rejected: %llu\n", static_cast<unsigned long long>(summary.rejected));
  if (summary.hidden) std::printf("hidden: %llu\n", static_cast<unsigned long long>(*summary.hidden));
  std::printf("levels: %d\n", index.hierarchy.num_levels());
  std::printf("bytes: %lld\n", static_cast<long long>(st.st_size));
  std::printf("read_seconds: %.3f\n", summary.read_seconds);
  std::printf("build_seconds: %.3f\n", summary.build_seconds);
  std::printf("save_seconds: %.3f\n", save_s);
  return kOk;
}

}  // namespace

Command add_index_command(CLI::App& app) {
  auto args = std::make_shared<IndexArgs>();
  CLI::App* cmd = app.add_subcommand(
      "index", "Read sites, build the nearest-site index (Delaunay hierarchy) and save it to a file");
  add_site_input_options(cmd, args->sites);
  cmd->add_option("-o,--output", args->output, "The index file to write (by convention *.gvi)")->required();
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing output file");
  cmd->add_flag("-q,--quiet", args->sites.quiet, "No list of merged rows on stderr (rejected rows are still listed)");
  add_threads_option(cmd, args->threads);
  cmd->footer(
      "Reads the sites as `geovor info` does and saves the hierarchy and every row's attributes\n"
      "(id, fields, merged rows) in a checksummed binary file, written to a temporary file and\n"
      "renamed. Prints input, output, rows, sites, merged, rejected, hidden (with --weight-field),\n"
      "levels, bytes and timings; rejected rows, merged and hidden sites are listed on stderr with\n"
      "their row numbers. With --weight-field, geovor nearest answers the site whose power cell\n"
      "holds each query, as geovor cells --weight-field draws it (--metric power).\n"
      "Example: geovor index datasets/weather_stations.csv -o stations.gvi");
  return {[args] { return run(*args); },
          [args] { return site_input_needs_gdal(args->sites); }};
}

}  // namespace geovor::tools
