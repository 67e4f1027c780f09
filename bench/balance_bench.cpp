// geovor_bench_balance FILE [--gz] [--capacity-field NAME | --synthetic-capacity] [--solver cholesky|cg]
//   [--tolerance T] [--threads N] [--lloyd N,N,...] [--no-lloyd]
// The balance solver (issue 33) on the sites of a CSV (read as `geovor balance` reads them,
// read_sites_csv): each iteration's largest relative area error, step and time, then the total;
// then Lloyd's iterations (geovor relax) on the same sites, the other way to even out areas, with
// the largest relative area error they reach after each count of --lloyd (default 10,50,200;
// --no-lloyd: none); last a line "summary: ..." with the figures of both.
//
// Shares: equal by default; --capacity-field NAME reads each row's capacity from column NAME
// (typed Real by the library's apply_field_types; an empty or non-positive one is an error);
// --synthetic-capacity gives row r (1-based data row) the capacity 1 + (r mod 5). The bundled
// weather stations have no column that could be a capacity (icao, name, lat_deg, lon_deg: no
// elevation, no traffic), so bench/balance_bench.sh balances them with the synthetic one: shares
// from 1 to 5 interleaved along the ICAO order, neighbours of very different sizes.
// Lloyd cannot weight: with capacities its error is given against them and against equal shares.
// Exit: 0 converged, 1 not converged, 2 usage, 3 an error reading the sites.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/column_types.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/relax/balance.hpp"
#include "geovor/relax/lloyd.hpp"
#include "geovor/relax/measure.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Args {
  std::string path;
  bool gz = false;
  std::string capacity_field;
  bool synthetic_capacity = false;
  geovor::BalanceOptions balance;
  std::vector<int> lloyd_counts{10, 50, 200};
};

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// --lloyd: increasing positive counts, or none for "none" (as --no-lloyd).
bool parse_lloyd_counts(const std::string& value, std::vector<int>& counts) {
  counts.clear();
  if (value == "none") return true;
  std::vector<std::size_t> sizes;
  std::string bad;
  if (!geovor::bench::parse_sizes(value, 1, sizes, bad)) return false;
  for (const std::size_t n : sizes) {
    if (!counts.empty() && static_cast<int>(n) <= counts.back()) return false;
    counts.push_back(static_cast<int>(n));
  }
  return true;
}

// The options after FILE; false on an unknown or malformed one.
bool parse_args(int argc, char** argv, Args& args) {
  if (argc < 2) return false;
  args.path = argv[1];
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--gz") args.gz = true;
    else if (a == "--synthetic-capacity") args.synthetic_capacity = true;
    else if (a == "--no-lloyd") args.lloyd_counts.clear();
    else if (a == "--capacity-field" && has_value) args.capacity_field = argv[++i];
    else if (a == "--solver" && has_value)
      args.balance.solver = std::string(argv[++i]) == "cg" ? geovor::BalanceSolver::ConjugateGradient
                                                           : geovor::BalanceSolver::Cholesky;
    else if (a == "--tolerance" && has_value) args.balance.tolerance = std::stod(argv[++i]);
    else if (a == "--threads" && has_value) args.balance.threads = static_cast<unsigned>(std::stoul(argv[++i]));
    else if (a == "--lloyd" && has_value) {
      if (!parse_lloyd_counts(argv[++i], args.lloyd_counts)) return false;
    } else return false;
  }
  return !(args.synthetic_capacity && !args.capacity_field.empty());
}

// The whole output of `gzip -dc path` (the library's reader refuses gzip data).
std::string gunzip(const std::string& path) {
  std::string quoted = "'";
  for (const char ch : path) quoted += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  std::FILE* f = ::popen(("gzip -dc " + quoted + "'").c_str(), "r");
  if (f == nullptr) throw geovor::Error(geovor::ErrorCode::Io, "cannot run gzip -dc on " + path);
  std::string text;
  char buffer[1 << 16];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, f)) > 0;) text.append(buffer, n);
  if (::pclose(f) != 0) throw geovor::Error(geovor::ErrorCode::Io, "gzip -dc failed on " + path);
  return text;
}

// The sites as `geovor balance` reads them (the library's CSV reader, column detection included).
geovor::SiteTable load_sites(const Args& args) {
  geovor::SiteTable table;
  if (args.gz) {
    std::istringstream in(gunzip(args.path));
    table = geovor::read_sites_csv(in, args.path);
  } else {
    table = geovor::read_sites_csv_file(args.path);
  }
  geovor::require_sites(table);
  return table;
}

// Column `field` typed Real by the library (a bad value is its Error naming the row), then parsed.
std::vector<double> capacities_from_column(geovor::SiteTable& table, const std::string& field) {
  const int column = geovor::find_column(table.columns, field);
  if (column < 0)
    throw geovor::Error(geovor::ErrorCode::InvalidArgument, table.source + ": no capacity column '" + field + "'");
  const std::vector<geovor::FieldTypeOverride> real{{field, geovor::FieldType::Real}};
  geovor::apply_field_types(table, real);
  const auto c = static_cast<std::size_t>(column);
  std::vector<double> shares;
  for (const geovor::InputSite& s : table.sites) {
    const double value = c < s.fields.size() && !s.fields[c].empty() ? std::stod(s.fields[c]) : 0.0;
    if (!(value > 0))
      throw geovor::Error(geovor::ErrorCode::BadData,
                          table.source + ": row " + std::to_string(s.row) + ": capacity must be positive");
    shares.push_back(value);
  }
  return shares;
}

// Each site's share: equal, the column's capacity, or the synthetic 1 + (row mod 5).
std::vector<double> site_shares(geovor::SiteTable& table, const Args& args) {
  if (!args.capacity_field.empty()) return capacities_from_column(table, args.capacity_field);
  std::vector<double> shares(table.sites.size(), 1.0);
  if (args.synthetic_capacity)
    for (std::size_t i = 0; i < shares.size(); ++i) shares[i] = 1.0 + static_cast<double>(table.sites[i].row % 5);
  return shares;
}

std::string shares_name(const Args& args) {
  if (!args.capacity_field.empty()) return "capacity column " + args.capacity_field;
  return args.synthetic_capacity ? "capacity 1+(row mod 5)" : "equal shares";
}

struct BalanceRun {
  geovor::BalanceReport report;
  double seconds = 0;
  double final_error() const {
    return report.iterations.empty() ? report.initial_relative_error : report.iterations.back().max_relative_error;
  }
};

BalanceRun run_balance(const std::vector<geovor::Vec3>& points, const std::vector<double>& shares,
                       const geovor::BalanceOptions& options) {
  const auto t0 = Clock::now();
  int k = 0;
  const auto print_iteration = [&k](const geovor::BalanceIteration& it) {
    std::printf("iteration %d: max relative error %.3e, step %g, hidden in rejected trials %zu, %.2f s\n", ++k,
                it.max_relative_error, it.step, it.hidden, it.seconds);
    std::fflush(stdout);
  };
  BalanceRun run;
  run.report = geovor::balance(points, shares, geovor::EllipsoidAreaMeasure(), options, {}, print_iteration);
  run.seconds = seconds_since(t0);
  double largest = 0;
  for (const double x : run.report.radii_m) largest = std::max(largest, x);
  std::printf("%zu points: initial error %.3e, %s after %zu iterations, %.2f s in all; largest radius %.0f m\n",
              points.size(), run.report.initial_relative_error, run.report.converged ? "converged" : "NOT converged",
              run.report.iterations.size(), run.seconds, largest);
  return run;
}

// Each site's target mass under `shares` (merged points' shares summed into their site's, as balance() does).
std::vector<double> site_targets(const geovor::BuildReport& build, std::size_t num_ids,
                                 const std::vector<double>& shares, double total) {
  std::vector<double> targets(num_ids, 0.0);
  double sum = 0;
  for (std::size_t i = 0; i < shares.size(); ++i) {
    if (build.site_of_input[i] == geovor::kNoIndex) continue;
    targets[build.site_of_input[i]] += shares[i];
    sum += shares[i];
  }
  for (double& t : targets) t *= total / sum;
  return targets;
}

// Largest |mass / target - 1| over the cells of `dt`.
double max_relative_error(const geovor::SphericalDelaunay& dt, const geovor::SphereMeasure& measure,
                          const std::vector<double>& targets) {
  const geovor::VoronoiDiagram vd(dt);
  double worst = 0;
  for (geovor::SiteId s = 0; s < dt.site_capacity(); ++s)
    if (vd.has_cell(s)) worst = std::max(worst, std::abs(measure.cell_mass(vd, s) / targets[s] - 1));
  return worst;
}

struct LloydPoint {
  int iterations = 0;
  double seconds = 0;      // the build and the iterations so far, not the measuring
  double error_equal = 0;  // against equal shares, what Lloyd's iterations even out
  double error_shares = 0; // against the run's shares (error_equal with equal shares)
};

// The other way to even out areas: Lloyd's iterations move the sites to their cells' centroids.
std::vector<LloydPoint> run_lloyd(const std::vector<geovor::Vec3>& points, const std::vector<double>& shares,
                                  const std::vector<int>& counts, unsigned threads) {
  if (counts.empty()) return {};
  const geovor::EllipsoidAreaMeasure measure;
  const auto t0 = Clock::now();
  geovor::BuildReport build;
  geovor::SphericalDelaunay dt = geovor::SphericalDelaunay::build(points, {}, &build);
  double seconds = seconds_since(t0);
  const std::vector<double> equal(points.size(), 1.0);
  const std::vector<double> equal_targets = site_targets(build, dt.site_capacity(), equal, measure.total());
  const std::vector<double> share_targets = site_targets(build, dt.site_capacity(), shares, measure.total());
  std::vector<LloydPoint> out;
  int done = 0;
  for (const int until : counts) {
    geovor::LloydOptions options;
    options.iterations = until - done;
    options.threads = threads;  // as many as balance() uses, so that the times compare
    const auto t1 = Clock::now();
    geovor::lloyd(dt, options);
    seconds += seconds_since(t1);
    done = until;
    const LloydPoint p{done, seconds, max_relative_error(dt, measure, equal_targets),
                       max_relative_error(dt, measure, share_targets)};
    std::printf("lloyd: %d iterations: max relative error %.3e (equal shares), %.3e (the run's shares), %.2f s\n",
                p.iterations, p.error_equal, p.error_shares, p.seconds);
    std::fflush(stdout);
    out.push_back(p);
  }
  return out;
}

std::size_t distinct_sites(const std::vector<geovor::Vec3>& points) {
  return geovor::SphericalDelaunay::build(points).num_sites();
}

// One line with the figures of both methods, what bench/balance_bench.sh collects.
void print_summary(const Args& args, std::size_t sites, const BalanceRun& b, const std::vector<LloydPoint>& lloyd) {
  const bool equal = args.capacity_field.empty() && !args.synthetic_capacity;
  std::printf("summary: %s: %zu sites, %s: balance %s in %zu iterations, %.2f s, max relative error %.2e",
              args.path.c_str(), sites, shares_name(args).c_str(), b.report.converged ? "converged" : "NOT converged",
              b.report.iterations.size(), b.seconds, b.final_error());
  if (!lloyd.empty()) std::printf("; lloyd max relative error");
  for (const LloydPoint& p : lloyd) {
    std::printf(" %d: %.3g", p.iterations, equal ? p.error_equal : p.error_shares);
    if (!equal) std::printf(" (%.3g vs equal)", p.error_equal);
  }
  if (!lloyd.empty()) std::printf(", %.2f s for %d", lloyd.back().seconds, lloyd.back().iterations);
  // Only where both aim at equal areas do their times compare.
  if (!lloyd.empty() && equal) std::printf(" (%.2f x balance's time)", lloyd.back().seconds / b.seconds);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  Args args;
  if (!parse_args(argc, argv, args)) {
    std::fprintf(stderr,
                 "usage: geovor_bench_balance FILE [--gz] [--capacity-field NAME | --synthetic-capacity] "
                 "[--solver cholesky|cg] [--tolerance T] [--threads N] [--lloyd N,N,... | --no-lloyd]\n");
    return 2;
  }
  try {
    geovor::SiteTable table = load_sites(args);
    const std::vector<double> shares = site_shares(table, args);
    std::vector<geovor::Vec3> points;
    for (const geovor::InputSite& s : table.sites) points.push_back(s.unit);
    std::printf("%s: %llu rows, %zu points, %zu rejected; %s; %s\n", args.path.c_str(),
                static_cast<unsigned long long>(table.rows_read), points.size(), table.rejected.size(),
                shares_name(args).c_str(), geovor::bench::cpu_model().c_str());
    const BalanceRun b = run_balance(points, shares, args.balance);
    const std::vector<LloydPoint> lloyd = run_lloyd(points, shares, args.lloyd_counts, args.balance.threads);
    print_summary(args, distinct_sites(points), b, lloyd);
    return b.report.converged ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "geovor_bench_balance: %s\n", e.what());
    return 3;
  }
}
