// The cells file of `geovor cells` and `geovor relax`: the library's cell layer
// (geovor/layers/cell_layer.hpp) written to the --output path, with the tool's messages.
#pragma once

#include <functional>
#include <string>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/layers/cell_layer.hpp"
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

/// Whether args.output is GeoJSON or GeoJSONSeq (the formats written natively, which use CellIdTexts).
bool writes_geojson(const CellOutputArgs& args);

/// Writes the cell layer of `dt` to args.output (progress on stderr unless quiet); lists the
/// cells written with an empty geometry on stderr (even when quiet), then runs `before_finish`
/// (so that a companion file that fails, such as the row report, leaves no cells file either)
/// and moves the file into place. `id_texts`, if given, is make_cell_id_texts(table, ...);
/// `diagram`, if given, is VoronoiDiagram(dt) (CellLayerOptions).
/// @exception Error as open_feature_writer and the writer.
CellLayerReport write_cells(const CellOutputArgs& args, const SiteTable& table, const BuildReport& report,
                            const SphericalDelaunay& dt,
                            const std::function<void(const CellLayerReport&)>& before_finish = {},
                            const CellIdTexts* id_texts = nullptr, const VoronoiDiagram* diagram = nullptr);

}  // namespace geovor::tools
