#include "cell_output.hpp"

namespace geovor::tools {

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

CellFileOptions cell_file_options(const CellOutputArgs& args) {
  CellFileOptions options;
  options.writer = cell_writer_options(args);
  options.layer.densify_m = args.densify_m;
  options.layer.threads = static_cast<unsigned>(args.threads);
  options.quiet = args.quiet;
  options.precision_name = "--precision";
  options.report_name = "--report";
  return options;
}

CellLayerReport write_cells(const CellOutputArgs& args, const SiteTable& table, const BuildReport& report,
                            const SphericalDelaunay& dt, const std::function<void(const CellLayerReport&)>& before_finish,
                            const CellIdTexts* id_texts, const VoronoiDiagram* diagram) {
  CellFileOptions options = cell_file_options(args);
  options.layer.id_texts = id_texts;
  options.layer.diagram = diagram;
  return write_cell_file(args.output, table, report, dt, options, before_finish);
}

}  // namespace geovor::tools
