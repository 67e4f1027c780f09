#include "geovor/layers/balanced_cells.hpp"

#include <cstdio>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/layers/row_accounting.hpp"
#include "geovor/relax/balanced_sites.hpp"
#include "geovor/relax/capacities.hpp"

namespace geovor {
namespace {

// The capacities of table's sites; the rows without one listed on the log.
std::vector<double> capacities_of(SiteTable& table, const std::string& field, std::FILE* log) {
  const CapacityReport capacities = read_capacities(table, field);
  if (log != nullptr)
    for (const RejectedRow& r : capacities.rejected)
      std::fprintf(log, "%s: row %llu (line %llu) rejected: %s\n", table.source.c_str(),
                   static_cast<unsigned long long>(r.row), static_cast<unsigned long long>(r.line), r.reason.c_str());
  if (table.sites.empty()) throw Error(ErrorCode::BadData, table.source + ": no row has a positive capacity");
  return capacities.capacities;
}

// balance() with a header and a line per iteration on the log (none when null).
BalanceReport solve(const std::vector<Vec3>& points, const std::vector<double>& capacities, const SiteTable& table,
                    const SiteInput& input, const BalanceOptions& options, std::FILE* log) {
  if (log != nullptr)
    std::fprintf(log, "%s: %zu sites, tolerance %g\n%9s %22s %12s %9s\n", table.source.c_str(), points.size(),
                 options.tolerance, "iteration", "max_relative_error", "step", "seconds");
  int k = 0;
  const EllipsoidAreaMeasure area;
  return balance(points, capacities, area, options, delaunay_options(input), [&](const BalanceIteration& it) {
    if (log != nullptr) std::fprintf(log, "%9d %22.3e %12g %9.3f\n", ++k, it.max_relative_error, it.step, it.seconds);
  });
}

}  // namespace

BalanceReport balance_to_files(const SiteInput& input, const std::string& cells_path, const BalancedCellsOptions& options) {
  DuplicateIds duplicates;
  SiteTable table = read_site_input(input, &duplicates);
  const std::vector<double> capacities = capacities_of(table, options.capacity_field, options.cells.log);
  CellFileOptions cells = options.cells;
  if (duplicates.rows > 0) cells.writer.id_field = "site_index";  // feature ids stay unique
  std::FILE* log = cells.quiet ? nullptr : cells.log;
  const std::vector<Vec3> points = site_points(table);
  const BalanceReport result = solve(points, capacities, table, input, options.balance, log);
  if (!result.converged) return result;
  // The cells of the exact lifts balance() ended with, through the path of the cell layer.
  if (!apply_balance(table, result) && cells.log != nullptr)
    std::fprintf(cells.log, "%s: has a column '%s' already: the targets are not written\n", table.source.c_str(), kTargetField);
  BuildReport report;
  const SphericalDelaunay dt = balanced_triangulation(points, result, delaunay_options(input), report);
  list_build(input, table, report);
  const std::size_t written = write_cell_file(cells_path, table, report, dt, cells).cells_written;
  if (!options.sites_path.empty()) write_balanced_sites(options.sites_path, cells.writer.overwrite, table, report, result);
  if (log != nullptr)
    std::fprintf(log, "%s; %zu cells written to %s%s%s\n", row_counts(table, dt.num_sites(), report.merges.size()).c_str(),
                 written, cells_path.c_str(), options.sites_path.empty() ? "" : ", sites to ", options.sites_path.c_str());
  return result;
}

}  // namespace geovor
