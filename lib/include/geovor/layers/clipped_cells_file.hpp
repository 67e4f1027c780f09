/// \file clipped_cells_file.hpp
/// \brief What `geovor cells --clip` does: the cells of a job's sites cut by the regions of a
/// polygon layer (region_clip.hpp), written as one feature per (site, region) piece
/// (clipped_cell_layer.hpp) or, without geometry, as the Thiessen weights table (CSV).
#pragma once

#include <cstdio>
#include <string>

#include "geovor/io/feature_writer.hpp"
#include "geovor/layers/site_input.hpp"

namespace geovor {

/// Options of clip_cells_to_file(); every default is documented.
struct ClippedCellsOptions {
  /// The regions: any OGR polygon layer (read_regions_ogr), its layer ("" for the only one) and
  /// the field whose text is each region's id ("" for the row number). REQUIRED: path.
  std::string regions_path, regions_layer, region_id_field;
  /// The pieces' writer (format, layer name, overwrite, precision of GeoJSON text: the cells are
  /// cut and measured as written). DEFAULT: WriterOptions{} with layer "cells".
  WriterOptions writer;
  /// CellGeometryOptions::densify_m of the cells, and of the regions' edges. DEFAULT: 100.
  double densify_m = 100;
  /// Write the weights table as CSV (region_index, region_id, site_index, site_id, region_share,
  /// area_m2), no geometry. DEFAULT: false.
  bool no_geometry = false;
  /// Threads (0: one per core). DEFAULT: 0. The output does not depend on it.
  unsigned threads = 0;
  /// Where the regions' problems, the rejected region features, the sites outside every region
  /// and the summary are said (the sites' rows go to SiteInput::log). DEFAULT: stderr.
  std::FILE* log = stderr;
  /// No summary (problems and rejected features are still said). DEFAULT: false.
  bool quiet = false;
};

/// What clip_cells_to_file() did.
struct ClippedCellsReport {
  std::size_t sites = 0, regions = 0, pieces = 0;
  std::size_t rejected_regions = 0;  ///< features of the region layer that are no polygon
  std::size_t problems = 0;          ///< regions repaired or with a piece of no area (said on the log)
  std::size_t sites_outside = 0;     ///< live sites whose cell meets no region (listed on the log)
};

/// Reads `input`'s sites and the regions, builds and cuts the cells, and writes the pieces (or
/// the weights) to `output`, never half-written (a temporary file renamed at the end).
/// @exception Error as read_site_input, read_regions_ogr and the writers; Error(BadData) when no
///   region feature is a polygon.
ClippedCellsReport clip_cells_to_file(const SiteInput& input, const std::string& output, const ClippedCellsOptions& options);

}  // namespace geovor
