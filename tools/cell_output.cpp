#include "cell_output.hpp"

#include <cstdio>
#include <string>

#include "commands.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "site_input.hpp"

namespace geovor::tools {

bool writes_geojson(const CellOutputArgs& args) { return !output_needs_gdal(args.output, args.format); }

WriterOptions cell_writer_options(const CellOutputArgs& args) {
  WriterOptions writer_options;
  writer_options.format = args.format;
  writer_options.layer = "cells";
  writer_options.precision = args.precision;
  writer_options.overwrite = args.overwrite;
  if (args.ids_repeat) writer_options.id_field = "site_index";  // feature ids stay unique
  apply_output_model(args.model, writer_options);
  return writer_options;
}

CellLayerReport write_cells(const CellOutputArgs& args, const SiteTable& table, const BuildReport& report,
                            const SphericalDelaunay& dt, const std::function<void(const CellLayerReport&)>& before_finish,
                            const CellIdTexts* id_texts, const VoronoiDiagram* diagram) {
  const auto writer = open_cell_layer_writer(args.output, table, cell_writer_options(args));
  Progress progress(dt.num_sites(), Progress::on_terminal(stderr, args.quiet));
  CellLayerOptions options;
  options.densify_m = args.densify_m;
  options.precision = args.precision;
  options.threads = static_cast<unsigned>(args.threads);
  options.id_texts = id_texts;
  options.diagram = diagram;
  options.progress = [&](std::size_t written) { progress.advance(written); };
  const CellLayerReport cells = write_cell_layer(*writer, table, report, dt, options);
  // Listed even with --quiet, as rejected rows are: a cell without geometry must not pass unseen.
  if (!cells.unwritten.empty()) {
    const std::string where =
        writer->encoder() ? "--precision " + std::to_string(args.precision) : std::string("full precision");
    std::fprintf(stderr, "%zu cell(s) written with an empty geometry: at %s they %s:\n", cells.unwritten.size(),
                 where.c_str(), "collapse or would not be valid polygons (raise --precision)");
    const SiteRows rows = rows_of_sites(report, dt.site_capacity());
    for (std::size_t i = 0; i < cells.unwritten.size(); ++i) {
      if (i == 20) {
        std::fprintf(stderr, "  ... (%zu more; --report lists them all)\n", cells.unwritten.size() - 20);
        break;
      }
      const UnwrittenCell& c = cells.unwritten[i];
      std::fprintf(stderr, "  site %u (id %s): %s\n", c.site, table.sites[rows.first(c.site)].id.c_str(),
                   to_string(c.status));
    }
  }
  if (before_finish) before_finish(cells);
  writer->finish();
  progress.finish();
  return cells;
}

}  // namespace geovor::tools
