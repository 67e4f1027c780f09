#include "geovor/layers/relaxed_cells.hpp"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "geovor/core/output_target.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "geovor/layers/row_accounting.hpp"
#include "geovor/layers/site_layer.hpp"

namespace geovor {
namespace {

// The header, one line per iteration and the totals on the log (nothing when quiet).
class LloydLog {
 public:
  LloydLog(std::FILE* log, bool quiet) : log_(quiet ? nullptr : log) {}
  void header(const SiteTable& table, const SphericalDelaunay& dt, const LloydOptions& options) const {
    if (log_ == nullptr) return;
    std::fprintf(log_, "%s: %zu sites, %d iterations (%s relocation)\n%9s %22s %14s %14s %9s %9s\n",
                 table.source.c_str(), dt.num_sites(), options.iterations, to_string(options.relocation), "iteration",
                 "energy", "max_move_m", "mean_move_m", "filtered", "seconds");
  }
  void iteration(const LloydIteration& it) const {
    if (log_ == nullptr) return;
    std::fprintf(log_, "%9d %22.15e %14.3f %14.3f %9zu %9.3f\n", it.iteration, it.energy, it.max_move_m,
                 it.mean_move_m, it.moves.filtered, it.seconds);
  }
  void totals(const LloydReport& report) const {
    if (log_ == nullptr) return;
    std::size_t refused = 0, undefined = 0;
    for (const LloydIteration& it : report.iterations) {
      refused += it.moves.refused;
      undefined = std::max(undefined, it.undefined);
    }
    std::fprintf(log_, "final energy %.15e", report.final_energy);
    if (refused) std::fprintf(log_, "; %zu moves refused (centroid within the merge distance of a site)", refused);
    if (undefined) std::fprintf(log_, "; %zu site(s) without a centroid kept in place", undefined);
    std::fprintf(log_, "\n");
  }

 private:
  std::FILE* log_;
};

// The sites file's options (the file comment).
WriterOptions sites_writer_options(const RelaxedCellsOptions& options, bool into_cells_source) {
  const WriterOptions& cells = options.cells.writer;
  WriterOptions sites;
  sites.format = into_cells_source ? cells.format : "";
  sites.layer = "sites";
  sites.precision = cells.precision;
  sites.overwrite = cells.overwrite;
  sites.update = into_cells_source || (cells.update && format_holds_layers(options.sites_path, ""));
  sites.id_field = cells.id_field;
  return sites;
}

// The final sites as points, with how far each moved from `start`.
void write_sites(const RelaxedCellsOptions& options, bool into_cells_source, const SiteTable& table,
                 const BuildReport& report, const SphericalDelaunay& dt, const std::vector<Vec3>& start) {
  const auto writer = open_site_layer_writer(options.sites_path, table, sites_writer_options(options, into_cells_source));
  write_site_layer(*writer, table, rows_of_sites(report, dt.site_capacity()), dt, start);
  writer->finish();
}

}  // namespace

bool sites_in_cells_source(const std::string& cells_path, const RelaxedCellsOptions& options) {
  return !options.sites_path.empty() && same_output_file(cells_path, options.sites_path) &&
         format_holds_layers(cells_path, options.cells.writer.format);
}

void check_relaxed_outputs(const std::string& cells_path, const RelaxedCellsOptions& options,
                           const std::string& cells_name, const std::string& sites_name) {
  const std::string& sites_path = options.sites_path;
  const WriterOptions& cells = options.cells.writer;
  const bool one_source = sites_in_cells_source(cells_path, options);
  if (!one_source) check_distinct_outputs({{cells_name, cells_path}, {sites_name, sites_path}});
  check_writer_options(cells_path, GeometryType::MultiPolygon, cells);
  if (!sites_path.empty()) {
    WriterOptions sites;
    sites.format = one_source ? cells.format : "";
    check_writer_options(sites_path, GeometryType::Point, sites);
  }
  refuse_existing_output(cells_path, cells.overwrite || cells.update);
  if (!one_source)
    refuse_existing_output(sites_path, cells.overwrite || (cells.update && !sites_path.empty() &&
                                                           format_holds_layers(sites_path, "")));
}

LloydReport relax_to_files(const SiteInput& input, const std::string& cells_path, const RelaxedCellsOptions& options) {
  const bool into_cells_source = sites_in_cells_source(cells_path, options);  // before the cells exist
  DuplicateIds duplicates;
  const SiteTable table = read_site_input(input, &duplicates);
  RelaxedCellsOptions o = options;
  if (duplicates.rows > 0) o.cells.writer.id_field = "site_index";  // feature ids stay unique
  BuildReport report;
  SphericalDelaunay dt = build_sites(site_points(table), {}, input, report);
  list_build(input, table, report);  // merged rows stay in the cells' ids
  const std::vector<Vec3> start(dt.sites().begin(), dt.sites().end());
  // Site ids never change (no site is removed), so the build's row report still names the rows.
  const LloydLog log(o.cells.log, o.cells.quiet);
  log.header(table, dt, o.lloyd);
  const LloydReport lloyd_report = lloyd(dt, o.lloyd, [&](const LloydIteration& it) { log.iteration(it); });
  log.totals(lloyd_report);
  const std::size_t written = write_cell_file(cells_path, table, report, dt, o.cells).cells_written;
  if (!o.sites_path.empty()) write_sites(o, into_cells_source, table, report, dt, start);
  if (!o.cells.quiet && o.cells.log != nullptr)
    std::fprintf(o.cells.log, "%s; %zu cells written to %s%s%s\n", row_counts(table, dt.num_sites(), report.merges.size()).c_str(),
                 written, cells_path.c_str(), o.sites_path.empty() ? "" : ", sites to ", o.sites_path.c_str());
  return lloyd_report;
}

}  // namespace geovor
