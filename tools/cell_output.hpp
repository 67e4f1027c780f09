// The cells of a triangulation written as `geovor cells` writes them (schema, attributes of the
// input rows, areas, neighbours, every OGR format), shared by the commands that output cells.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/lonlat/cell_geometry.hpp"

namespace geovor::tools {

/// The output options of the cells (the --output, --format, --densify-m, --precision, --overwrite,
/// --quiet and --threads options of `geovor cells`).
struct CellOutputArgs {
  std::string output;
  std::string format;
  double densify_m = 100;
  int precision = 7;
  bool overwrite = false;
  bool quiet = false;
  int threads = 0;  // 0: one per core
};

/// Each input row's id as the cells' GeoJSON output writes it: `text[row]`, the id as a JSON
/// string (site_id, the feature id), and `element[row]`, the id as an element of the ids and
/// neighbors lists, escaped again inside the lists' JSON strings. Views into `storage` (whose
/// strings are on the heap, so moving an IdTexts keeps them valid).
struct IdTexts {
  std::vector<std::string> storage;
  std::vector<std::string_view> text, element;
};

/// The IdTexts of table's rows, made on `threads` threads; write_cells() makes them itself when
/// not given them, so this is for making them earlier (while the triangulation is built).
IdTexts make_id_texts(const SiteTable& table, unsigned threads);

/// Whether args.output is GeoJSON or GeoJSONSeq (the formats written natively, which use IdTexts).
bool writes_geojson(const CellOutputArgs& args);

/// A cell written with an empty geometry: at the output's precision it collapsed, or its rounded
/// rings would have been invalid (CellStatus).
struct UnwrittenCell {
  SiteId site;
  CellStatus status;
};

/// Writes the Voronoi cell of every live site of `dt` (site s built from the rows
/// rows_of_sites(report) names) to args.output; returns the number of cells written.
/// Positions are written with args.precision decimals in GeoJSON (as doubles in the GDAL
/// formats); cells that cannot be written valid at that precision get an empty geometry, are
/// listed on stderr (unless quiet) and in `unwritten` (if given, by site id), before
/// `before_finish` runs.
/// `before_finish`, if given, runs after the last cell and before the file is moved into place
/// (so that a companion file that fails, such as the row report, leaves no cells file either).
/// `id_texts`, if given, is make_id_texts(table, ...) (used for GeoJSON output only).
/// @exception Error as open_feature_writer and the writer.
std::size_t write_cells(const CellOutputArgs& args, const SiteTable& table, const BuildReport& report,
                        const SphericalDelaunay& dt, const std::function<void()>& before_finish = {},
                        const IdTexts* id_texts = nullptr, std::vector<UnwrittenCell>* unwritten = nullptr);

}  // namespace geovor::tools
