// The cells file of `geovor cells`, `relax` and `balance`: its options, which fill the library's
// CellFileOptions (geovor/layers/cell_file.hpp).
#pragma once

#include <string>

#include "geovor/layers/cell_file.hpp"
#include "output_model.hpp"

namespace geovor::tools {

/// The output options of the cells (the --output, --format, --densify-m, --precision, --overwrite,
/// --quiet and --threads options of `geovor cells`, and its --nln, --update, --lco, --dsco).
struct CellOutputArgs {
  std::string output;
  std::string format;
  OutputModelArgs model;
  double densify_m = 100;
  int precision = 7;
  bool overwrite = false;
  bool quiet = false;
  int threads = 0;  // 0: one per core
};

/// The writer options of the cells file (layer `cells` unless --nln).
WriterOptions cell_writer_options(const CellOutputArgs& args);

/// The library's options of the cells file: the writer's, the layer's, quiet, and the messages
/// naming --precision and --report.
CellFileOptions cell_file_options(const CellOutputArgs& args);

}  // namespace geovor::tools
