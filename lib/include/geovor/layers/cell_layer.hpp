/// \file cell_layer.hpp
/// \brief The cell layer: the Voronoi cell of every site of a triangulation as a MultiPolygon
/// feature carrying the attributes of the site's input rows, its areas and its neighbours,
/// written to any FeatureWriter in site order and computed in parallel (what `geovor cells` and
/// `geovor relax` write).
///
/// Fields (cell_layer_schema()), in this order:
/// - site_index (Integer): the site id;
/// - site_id (String): the id of the row the site was built from (the GeoJSON feature id);
/// - ids (String, JSON: an array in GeoJSON, JSON text elsewhere): the ids of every row of the
///   site, that row first, then the rows merged into it (SiteRows; element format in id_lists.hpp);
/// - n_rows (Integer): the number of those rows;
/// - area_m2 (Real): area on the WGS84 ellipsoid of the rings as written;
/// - area_sr (Real): area of the exact cell on the unit sphere (steradians);
/// - n_vertices (Integer): Voronoi vertices of the cell;
/// - neighbors (String, JSON as ids): the ids of the neighbouring sites, in the cell's order;
/// - weight_m (Real), weighted sites only (table.weighted, site_weights.hpp): the site's
///   radius in metres; the cells are then power cells (docs/weighted.md);
/// - then every input column, with its type and the value of the site's first row, named as in
///   the input or renamed by input_columns.hpp's rule (`fid` -> `src_fid`, `area_m2` ->
///   `src_area_m2`).
/// A cell that cannot be written valid at the output's precision gets an empty geometry and is
/// reported (CellLayerReport::unwritten), never dropped: the layer has one feature per live site,
/// and one with an empty geometry (areas 0, no neighbours) per hidden weighted site
/// (SphericalDelaunay::is_hidden; the caller reports those from BuildReport::hidden).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/layers/id_lists.hpp"
#include "geovor/lonlat/cell_geometry.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace geovor {

/// The fields of the cell layer of `table` (the file comment).
std::vector<Field> cell_layer_schema(const SiteTable& table);

/// open_feature_writer(path, MultiPolygon, cell_layer_schema(table), options) with
/// options.id_field set to "site_id" unless the caller chose another field, such as "site_index"
/// when ids repeat, so that feature ids stay unique (options.layer defaults to "cells").
/// @exception Error as open_feature_writer().
std::unique_ptr<FeatureWriter> open_cell_layer_writer(const std::string& path, const SiteTable& table,
                                                      WriterOptions options);

/// A cell written with an empty geometry: at the output's precision it collapsed, or its
/// rounded rings would have been invalid (CellStatus).
struct UnwrittenCell {
  SiteId site = kNoIndex;
  CellStatus status = CellStatus::Written;
};

/// Options of write_cell_layer(); every default is documented.
struct CellLayerOptions {
  /// Largest distance in metres between a written edge and the true great-circle arc
  /// (CellGeometryOptions::densify_m). DEFAULT: 100. REQUIRES: > 0.
  double densify_m = 100;
  /// The decimals of the writer's coordinates (its WriterOptions::precision) when it writes text
  /// (it has an encoder: GeoJSON, GeoJSONSeq): the cells are computed, checked valid and measured
  /// (area_m2) as written. A writer without an encoder (GDAL formats) stores doubles: full
  /// precision, whatever this is. DEFAULT: 7 (WriterOptions' default).
  int precision = 7;
  /// Threads computing the diagram, the cells' geometry and the features (0: one per core).
  /// DEFAULT: 0. The output does not depend on it.
  unsigned threads = 0;
  /// make_cell_id_texts(table) made earlier by the caller (e.g. while the triangulation is
  /// built); used only with an encoder. DEFAULT: null (made here when needed).
  const CellIdTexts* id_texts = nullptr;
  /// VoronoiDiagram(dt) built earlier by the caller (e.g. while the table's last columns are
  /// read); it must be dt's as dt is now. DEFAULT: null (built here).
  const VoronoiDiagram* diagram = nullptr;
  /// Called on the calling thread after each block of cells is written, with the number of
  /// cells written so far (of dt.num_sites()). DEFAULT: none.
  std::function<void(std::size_t cells_written)> progress;
};

/// What write_cell_layer() wrote.
struct CellLayerReport {
  std::size_t cells_written = 0;        ///< features written: every live or hidden site's
  std::vector<UnwrittenCell> unwritten;  ///< those with an empty geometry, by site id
};

/// Writes the cell of every live site of `dt` (built from table's rows with `report`, possibly
/// relocated since: site ids stay) to `writer`, in site id order, as the file comment says.
/// `writer` must have been opened with cell_layer_schema(table) (open_cell_layer_writer()
/// does); it is not finished, so that the caller can write companion files first. With an
/// encoder (GeoJSON) the workers encode the features as text and this thread only writes it.
/// @exception Error as the writer; Error(InvalidArgument) for an option out of range or a
/// diagram not of dt's sites.
CellLayerReport write_cell_layer(FeatureWriter& writer, const SiteTable& table, const BuildReport& report,
                                 const SphericalDelaunay& dt, const CellLayerOptions& options = {});

}  // namespace geovor
