#include "geovor/layers/cell_file.hpp"

#include "geovor/core/progress.hpp"
#include "geovor/delaunay/site_rows.hpp"

namespace geovor {
namespace {

// Listed even when quiet, as rejected rows are: a cell without geometry must not pass unseen.
void list_unwritten(const CellLayerReport& cells, bool has_encoder, const SiteTable& table, const BuildReport& report,
                    const SphericalDelaunay& dt, const CellFileOptions& options) {
  if (cells.unwritten.empty() || options.log == nullptr) return;
  const std::string where = has_encoder ? options.precision_name + " " + std::to_string(options.writer.precision)
                                        : std::string("full precision");
  std::fprintf(options.log, "%zu cell(s) written with an empty geometry: at %s they collapse or would not be valid polygons (raise %s):\n",
               cells.unwritten.size(), where.c_str(), options.precision_name.c_str());
  const SiteRows rows = rows_of_sites(report, dt.site_capacity());
  for (std::size_t i = 0; i < cells.unwritten.size(); ++i) {
    if (i == 20) {
      std::fprintf(options.log, "  ... (%zu more; %s lists them all)\n", cells.unwritten.size() - 20,
                   options.report_name.c_str());
      break;
    }
    const UnwrittenCell& c = cells.unwritten[i];
    std::fprintf(options.log, "  site %u (id %s): %s\n", c.site, table.sites[rows.first(c.site)].id.c_str(),
                 to_string(c.status));
  }
}

}  // namespace

CellLayerReport write_cell_file(const std::string& path, const SiteTable& table, const BuildReport& report,
                                const SphericalDelaunay& dt, const CellFileOptions& options,
                                const std::function<void(const CellLayerReport&)>& before_finish) {
  const auto writer = open_cell_layer_writer(path, table, options.writer);
  Progress progress(dt.num_sites(), Progress::on_terminal(options.log, options.quiet));
  CellLayerOptions layer = options.layer;
  layer.precision = options.writer.precision;
  layer.progress = [&](std::size_t written) { progress.advance(written); };
  const CellLayerReport cells = write_cell_layer(*writer, table, report, dt, layer);
  list_unwritten(cells, writer->encoder() != nullptr, table, report, dt, options);
  if (before_finish) before_finish(cells);
  writer->finish();
  progress.finish();
  return cells;
}

}  // namespace geovor
