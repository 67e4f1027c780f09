// geovor nearest --sites SITES [--queries FILE|-]: the exact nearest site (or k nearest) of every
// query of a CSV stream. The arguments, the sites (an index file or a table) and the streams;
// the join itself is layers/nearest_join.hpp.
#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/layers/nearest_join.hpp"
#include "geovor/locate/index_file.hpp"
#include "geovor/locate/knn.hpp"
#include "geovor/locate/locator.hpp"
#include "output_file.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct NearestArgs {
  SiteInputArgs sites;
  std::vector<CLI::Option*> site_options;  // the table-only options, refused with an index
  std::string queries = "-";
  std::string output = "-";
  bool overwrite = false;
  std::string locator = "keep-jump-climb";
  std::size_t k = 1;
  CLI::Option* k_option = nullptr;
  std::string metric = "sphere";
  int threads = 1;
  bool strict = false;
};

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f != stdin && f != stdout) std::fclose(f);
  }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// Whether --sites names an index file (by its header, or a .gvi name) rather than a site table.
bool is_index_path(const std::string& path) {
  return path != "-" && (is_index_file(path) || (path.size() > 4 && path.ends_with(".gvi")));
}

int run(NearestArgs& args) {
  const std::string& sites_path = args.sites.input;
  if (args.queries == "-" && sites_path == "-")
    throw Error(ErrorCode::InvalidArgument, "--sites and --queries cannot both be standard input");
  if (args.k < 1) throw Error(ErrorCode::InvalidArgument, "--k must be at least 1");
  if (args.threads < 1) throw Error(ErrorCode::InvalidArgument, "--threads must be at least 1");
  if (args.metric != "sphere" && args.metric != "geodesic")
    throw Error(ErrorCode::InvalidArgument, "--metric must be sphere or geodesic, not '" + args.metric + "'");
  LocatorOptions locator_options;
  locator_options.strategy = parse_strategy(args.locator);
  struct stat st;
  if (args.output != "-" && !args.overwrite && stat(args.output.c_str(), &st) == 0 && S_ISREG(st.st_mode))
    throw Error(ErrorCode::Io, args.output + ": exists; use --overwrite to replace it");

  // The sites: an index file, or a table built here.
  const bool is_index = is_index_path(sites_path);
  SiteIndex index;
  if (is_index) {
    for (const CLI::Option* o : args.site_options)
      if (o->count() > 0)
        throw Error(ErrorCode::InvalidArgument, o->get_name() + " applies to a site table; " + sites_path +
                                                    " is an index (its columns were chosen by geovor index)");
    index = load_index(sites_path, static_cast<unsigned>(args.threads));
  } else {
    index = build_index_from_table(args.sites, nullptr);
  }

  // The streams.
  File in(args.queries == "-" ? stdin : std::fopen(args.queries.c_str(), "rb"));
  const std::string qname = args.queries == "-" ? "<stdin>" : args.queries;
  if (!in) throw Error(ErrorCode::Io, args.queries + ": cannot open: " + std::strerror(errno));
  OutputFile out(args.output, args.overwrite);  // a temporary file renamed by commit(): never half-written

  NearestJoinOptions options;
  options.k = args.k;
  options.rank_column = args.k_option->count() > 0;
  options.metric = parse_metric(args.metric);
  options.locator = locator_options;
  options.threads = static_cast<unsigned>(args.threads);
  options.strict = args.strict;
  const NearestJoinReport report = nearest_join(
      index, in.get(), qname, options, [&](std::string_view s) { out.write(s.data(), s.size()); },
      [&](const MalformedQuery& m) {
        std::fprintf(stderr, "%s: line %llu: %s\n", qname.c_str(), static_cast<unsigned long long>(m.line), m.reason.c_str());
      });
  out.commit();  // with --strict, the answers before the malformed line are kept
  if (report.stopped)
    throw Error(ErrorCode::BadData, qname + ": stopped at the first malformed query (--strict); " +
                                        std::to_string(report.answered) + " queries answered before it");
  if (report.malformed > 0)
    std::fprintf(stderr, "geovor nearest: %llu queries answered, %llu malformed lines skipped\n",
                 static_cast<unsigned long long>(report.answered), static_cast<unsigned long long>(report.malformed));
  return kOk;
}

}  // namespace

Command add_nearest_command(CLI::App& app) {
  auto args = std::make_shared<NearestArgs>();
  CLI::App* cmd = app.add_subcommand("nearest", "The exact nearest site (or k nearest) of every query of a CSV stream");
  cmd->add_option("--sites", args->sites.input,
                  "An index file (geovor index), or sites: CSV with a header (- for stdin) or any OGR point layer")
      ->required();
  cmd->add_option("--queries", args->queries, "Query CSV: lat,lon[,id] lines, with or without a header (default -: stdin)");
  cmd->add_option("-o,--output", args->output, "Output CSV (default -: stdout)");
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing output file");
  cmd->add_option("--locator", args->locator,
                  "Strategy: walk, jump-walk, keep-jump-walk, hierarchy, climb or keep-jump-climb (default)");
  args->k_option = cmd->add_option("--k", args->k, "The k nearest sites, one row each with a rank column");
  cmd->add_option("--metric", args->metric, "sphere (great circle on the mean-radius sphere, default) or geodesic (WGS84)");
  cmd->add_option("--threads", args->threads, "Threads (default 1); the output order is the input order");
  cmd->add_flag("--strict", args->strict, "Stop at the first malformed query line (exit 3)");
  args->site_options = add_site_table_options(cmd, args->sites);  // of a site table, not an index
  args->site_options.push_back(cmd->add_option("--merge-m", args->sites.merge_m, "Merge sites closer than this many metres"));
  cmd->footer(
      "Writes CSV: query_id,site_index,site_id,distance_m (with --k: query_id,rank,site_index,site_id,\n"
      "distance_m, one row per neighbour, nearest first). query_id is the query's id column (query_id,\n"
      "id, icao, code or name) or its line number. Malformed query lines are reported on stderr with\n"
      "their line number and skipped (--strict: exit 3).\n"
      "Example: geovor nearest --sites stations.gvi --queries points.csv -o nearest.csv");
  return {[args] { return run(*args); },
          [args] { return !is_index_path(args->sites.input) && site_input_needs_gdal(args->sites); }};
}

}  // namespace geovor::tools
