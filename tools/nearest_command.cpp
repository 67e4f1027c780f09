// geovor nearest --sites SITES [--queries FILE|-]: the exact nearest site (or k nearest) of every
// query of a CSV stream or an OGR point layer, a spatial join. The arguments, the sites (an index
// file or a table) and the streams; the join itself is layers/nearest_join.hpp.
#include <sys/stat.h>

#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/output_target.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/io/ogr_site_reader.hpp"
#include "geovor/layers/nearest_join_files.hpp"
#include "geovor/locate/index_file.hpp"
#include "geovor/locate/knn.hpp"
#include "geovor/locate/locator.hpp"
#include "numeric_options.hpp"
#include "output_model.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct NearestArgs {
  SiteInputArgs sites;
  std::vector<CLI::Option*> site_options;  // the table-only options, refused with an index
  NearestJoinFiles files;  // --queries, --layer, -o, --format, --overwrite
  std::string locator = "keep-jump-climb";
  std::size_t k = 1;
  CLI::Option* k_option = nullptr;
  std::string metric;  // "": the index's default (power for weighted sites, else sphere)
  int threads = 0;  // 0: one per core
  bool strict = false;
  QueryColumns query_columns;
  std::vector<std::string> site_fields;
  double max_distance_m = std::numeric_limits<double>::infinity();
  OutputModelArgs model;                              // --nln, --update, --lco, --dsco
  std::vector<FieldTypeOverride> query_field_types;  // --query-field-type
};

int run(NearestArgs& args) {
  const std::string& sites_path = args.sites.input;
  NearestJoinFiles& files = args.files;
  if (files.queries == "-" && sites_path == "-")
    throw Error(ErrorCode::InvalidArgument, "--sites and --queries cannot both be standard input");
  if (args.k < 1) throw Error(ErrorCode::InvalidArgument, "--k must be at least 1");
  if (!(args.max_distance_m >= 0))
    throw Error(ErrorCode::InvalidArgument, "--max-distance-m must be a number of metres, at least 0");
  if (queries_are_ogr(files) && is_csv_site_path(files.queries))
    throw Error(ErrorCode::InvalidArgument, files.queries + ": --layer is for OGR query sources; a CSV stream has one table");
  const bool csv = writes_csv(files);
  if (!csv && files.output == "-" && output_needs_gdal(files.output, files.writer.format))
    throw Error(ErrorCode::InvalidArgument, "--format " + files.writer.format + " cannot be written to standard output; give -o FILE");
  if (csv && !args.query_field_types.empty())
    throw Error(ErrorCode::InvalidArgument, "--query-field-type types the query columns of point features (GeoPackage, "
                                            "FlatGeobuf, ...); geovor's CSV output has no types");
  if (csv && sets_gdal_options(args.model))
    throw Error(ErrorCode::InvalidArgument, "--nln, --update, --lco and --dsco apply to OGR point outputs (GeoPackage, "
                                            "FlatGeobuf, ...); geovor writes its CSV itself, one table");
  apply_output_model(args.model, files.writer);
  if (!csv)  // a format that cannot hold the points (GPX without extensions, ...): before any work
    check_writer_options(files.output, GeometryType::Point, files.writer);
  if (!args.metric.empty() && args.metric != "sphere" && args.metric != "geodesic" && args.metric != "power")
    throw Error(ErrorCode::InvalidArgument, "--metric must be sphere, geodesic or power, not '" + args.metric + "'");
  LocatorOptions locator_options;
  locator_options.strategy = parse_strategy(args.locator);
  struct stat st;
  if (files.output != "-" && !files.writer.overwrite && !args.model.update && stat(files.output.c_str(), &st) == 0 &&
      S_ISREG(st.st_mode))
    throw Error(ErrorCode::Io, output_exists(files.output, " (or --update to add a layer)"));

  // The sites: an index file, or a table built here.
  if (is_index_path(sites_path))
    for (const CLI::Option* o : args.site_options)
      if (o->count() > 0)
        throw Error(ErrorCode::InvalidArgument, o->get_name() + " applies to a site table; " + sites_path +
                                                    " is an index (its columns were chosen by geovor index)");
  args.sites.reader.threads = static_cast<unsigned>(args.threads);
  const SiteIndex index = load_site_index(args.sites, static_cast<unsigned>(args.threads));

  NearestJoinOptions options;
  options.k = args.k;
  options.rank_column = args.k_option->count() > 0;
  if (!args.metric.empty()) options.metric = parse_metric(args.metric);
  options.locator = locator_options;
  options.threads = static_cast<unsigned>(args.threads);
  options.strict = args.strict;
  options.columns = args.query_columns;
  options.site_fields = args.site_fields;
  options.max_distance_m = args.max_distance_m;
  options.query_field_types = args.query_field_types;  // an OGR layer's through its reader
  nearest_join_fields(index, {}, options);  // an unknown --site-fields column before any output

  const NearestJoinReport report = nearest_join_files(index, files, options);
  if (report.stopped)
    throw Error(ErrorCode::BadData, query_source(files) + ": stopped at the first malformed query (--strict); " +
                                        std::to_string(report.answered) + " queries answered before it");
  if (report.malformed > 0 || (report.unmatched > 0 && !args.sites.quiet))
    std::fprintf(stderr,
                 "geovor nearest: %llu queries answered (%llu without a site within --max-distance-m), %llu malformed "
                 "(written with an empty match)\n",
                 static_cast<unsigned long long>(report.answered), static_cast<unsigned long long>(report.unmatched),
                 static_cast<unsigned long long>(report.malformed));
  return kOk;
}

}  // namespace

Command add_nearest_command(CLI::App& app) {
  auto args = std::make_shared<NearestArgs>();
  CLI::App* cmd = app.add_subcommand(
      "nearest", "Spatial join: the exact nearest site (or k nearest) of every query of a CSV stream or OGR point layer");
  cmd->add_option("--sites", args->sites.input,
                  "An index file (geovor index), or sites: CSV with a header (- for stdin) or any OGR point layer")
      ->required();
  cmd->add_option("--queries", args->files.queries,
                  "Queries: CSV, lat,lon[,id] lines with or without a header (default -: stdin; a pipe or FIFO is read as CSV), or any OGR point layer");
  cmd->add_option("--query-lat-field", args->query_columns.lat_field, "Latitude column of the queries (default: found by name as for sites: lat, Latitude (deg), stop_lat, decimalLatitude, y...)");
  cmd->add_option("--query-lon-field", args->query_columns.lon_field,
                  "Longitude column of the queries (default: found by name as for sites: lon, lng, Longitude, stop_lon, x...)");
  cmd->add_option("--query-id-field", args->query_columns.id_field,
                  "Identifier column of the queries (default: query_id, id, icao, code or name; else the line number)");
  cmd->add_option("--layer", args->files.query_layer, "Layer of a multi-layer OGR query source (GeoPackage, ...); not for CSV");
  add_field_type_option(cmd, "--query-field-type", args->query_field_types,
                        "Declare a query column's type in a point output: NAME=TYPE (String, Integer, Integer64, Real, "
                        "Date, DateTime; case-insensitive), repeatable or NAME=TYPE,NAME2=TYPE2; a value not of that type "
                        "is bad data (exit 3); not with CSV output (text)");
  cmd->add_option("--site-fields", args->site_fields, "Site columns to join to each match, e.g. name,elev (from the index or table)")
      ->delimiter(',');
  cmd->add_option("--max-distance-m", args->max_distance_m,
                  "No site farther than this many metres: a query without one gets a row with an empty match");
  cmd->add_option("-o,--output", args->files.output,
                  "Output: CSV (-: stdout, .csv, .txt or no extension), or points with attributes in any OGR format (.gpkg, .geojson, .fgb, .shp, ...)");
  add_output_model_options(cmd, args->files.writer.format, args->files.writer.overwrite, args->model, "nearest");
  cmd->add_option("--locator", args->locator,
                  "Strategy: walk, jump-walk, keep-jump-walk, hierarchy, climb or keep-jump-climb (default)");
  args->k_option = cmd->add_option("--k", args->k, "The k nearest sites, one row each with a rank column")
                      ->check(integer_in(1, 2147483647));
  cmd->add_option("--metric", args->metric,
                  "sphere (great circle on the mean-radius sphere; the default), geodesic (WGS84), or power: the "
                  "site whose power cell holds the query (weighted sites: the default and their only metric)");
  add_threads_option(cmd, args->threads);
  cmd->add_flag("--strict", args->strict, "Stop at the first malformed query line (exit 3)");
  cmd->add_flag("-q,--quiet", args->sites.quiet, "Do not list the merged sites of a site table nor count the queries without a match (malformed queries are still listed)");
  args->site_options = add_site_table_options(cmd, args->sites);  // of a site table, not an index
  args->site_options.push_back(cmd->add_option("--merge-m", args->sites.merge_m, "Merge sites closer than this many metres")
                                                   ->check(finite_above(0, true)));
  args->site_options.push_back(cmd->add_option("--weight-field", args->sites.weight_field,
                                               "Weighted sites: the column of each site's radius in metres (as geovor "
                                               "cells --weight-field); each query gets the site whose power cell holds it"));
  cmd->footer(
      "Writes query_id,site_index,site_id,distance_m (with --k: query_id,rank,site_index,site_id,\n"
      "distance_m, one row per neighbour, nearest first), then every column of the queries (src_NAME\n"
      "on a clash), then the --site-fields (site_NAME on a clash); as CSV, or as points at the queries\n"
      "in an OGR format. query_id is the query's id column (query_id, id, icao, code or name) or its\n"
      "line (feature) number. Every query gets at least one row: without a site within\n"
      "--max-distance-m, or malformed (reported on stderr with its line number and reason; --strict:\n"
      "exit 3), a row with an empty match (a null point for a malformed one). On weighted sites (an\n"
      "index built with --weight-field, or --weight-field here) the answer is the site whose power\n"
      "cell holds the query, the cell geovor cells --weight-field writes; --k ranks by power, and\n"
      "distance_m stays the distance to the site.\n"
      "Examples: geovor nearest --sites stations.gvi --queries points.csv -o nearest.csv\n"
      "  geovor nearest --sites stations.gvi --queries trips.csv --query-lat-field pickup_latitude \\\n"
      "    --query-lon-field pickup_longitude --site-fields name --max-distance-m 5000 -o trips.gpkg");
  return {[args] { return run(*args); },
          [args] {
            return (!is_index_path(args->sites.input) && site_input_needs_gdal(args->sites)) ||
                   queries_are_ogr(args->files) ||
                   (!writes_csv(args->files) && output_needs_gdal(args->files.output, args->files.writer.format));
          }};
}

}  // namespace geovor::tools
