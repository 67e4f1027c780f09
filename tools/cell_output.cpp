#include "cell_output.hpp"

namespace geovor::tools {

WriterOptions cell_writer_options(const CellOutputArgs& args) {
  WriterOptions writer_options;
  writer_options.format = args.format;
  writer_options.layer = "cells";
  writer_options.precision = args.precision;
  writer_options.overwrite = args.overwrite;
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

}  // namespace geovor::tools
