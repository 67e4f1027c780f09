/// \file cell_file.hpp
/// \brief write_cell_file(): the cell layer of a triangulation written to a file as `geovor
/// cells`, `relax` and `balance` write it: with progress on a terminal, the cells written with an
/// empty geometry listed on a log, and a companion output (such as the row report, row_report.hpp)
/// completed before the cells are moved into place.
#pragma once

#include <cstdio>
#include <functional>
#include <string>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/layers/cell_layer.hpp"

namespace geovor {

/// Options of write_cell_file(); every default is documented.
struct CellFileOptions {
  /// The output's format, layer, precision, overwrite, update, creation options and id field
  /// (open_cell_layer_writer()). DEFAULT: WriterOptions{} (layer "cells").
  WriterOptions writer;
  /// write_cell_layer()'s options; its precision is writer.precision, and its progress is printed
  /// on the log's terminal (Progress::on_terminal) unless quiet. DEFAULT: CellLayerOptions{}.
  CellLayerOptions layer;
  /// Where the cells written with an empty geometry are listed (and the progress printed when it
  /// is a terminal); null: nowhere. DEFAULT: stderr.
  std::FILE* log = stderr;
  /// No progress. DEFAULT: false.
  bool quiet = false;
  /// What the caller's users call WriterOptions::precision and the row report, in messages (the
  /// geovor command: --precision, --report). DEFAULT: the library's names.
  std::string precision_name = "precision", report_name = "write_row_report()";
};

/// Writes the cell layer of `dt` (write_cell_layer() of `table`'s sites built with `report`) to
/// `path`; lists at most 20 cells written with an empty geometry on the log ("N cell(s) written
/// with an empty geometry: at PRECISION N they collapse or would not be valid polygons (raise
/// PRECISION):", then one line per cell with its site, id and status); runs `before_finish` with
/// what was written (a companion file that fails then leaves no cells file either), and moves the
/// file into place (FeatureWriter::finish()).
/// @exception Error as open_cell_layer_writer(), write_cell_layer() and the writer; whatever
///   `before_finish` throws.
CellLayerReport write_cell_file(const std::string& path, const SiteTable& table, const BuildReport& report,
                                const SphericalDelaunay& dt, const CellFileOptions& options,
                                const std::function<void(const CellLayerReport&)>& before_finish = {});

}  // namespace geovor
