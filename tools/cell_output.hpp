// The cells file of `geovor cells`, `relax` and `balance`: their output options, and the library's
// cell file (geovor/layers/cell_file.hpp) written with them.
#pragma once

#include <functional>
#include <string>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"
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
  bool ids_repeat = false;  // the input's ids are not unique: site_index is the feature id
};

/// The writer options of the cells file (layer `cells` unless --nln).
WriterOptions cell_writer_options(const CellOutputArgs& args);

/// The library's options of the cells file: the writer's, the layer's, quiet, and the messages
/// naming --precision and --report.
CellFileOptions cell_file_options(const CellOutputArgs& args);

/// write_cell_file() of `dt` to args.output with these options, its messages on stderr naming
/// --precision and --report. `id_texts`, if given, is make_cell_id_texts(table, ...);
/// `diagram`, if given, is VoronoiDiagram(dt) (CellLayerOptions).
/// @exception Error as write_cell_file().
CellLayerReport write_cells(const CellOutputArgs& args, const SiteTable& table, const BuildReport& report,
                            const SphericalDelaunay& dt,
                            const std::function<void(const CellLayerReport&)>& before_finish = {},
                            const CellIdTexts* id_texts = nullptr, const VoronoiDiagram* diagram = nullptr);

}  // namespace geovor::tools
