/// \file clipped_cell_layer.hpp
/// \brief The layer of `geovor cells --clip`: the cells cut by regions (layers/region_clip.hpp),
/// one MultiPolygon feature per non-empty (site, region) piece, with the site's and the region's
/// attributes, and the Thiessen weights table (`--no-geometry`).
///
/// Fields (clipped_cell_layer_schema()), in this order:
/// - site_index (Integer), site_id (String): the site, as in the cell layer;
/// - region_index (Integer): the region's 0-based feature number in reading order;
/// - region_id (String): the region's id (RegionTable: the id field's text, else its row number);
/// - area_m2 (Real): the piece's area on the WGS84 ellipsoid, as written;
/// - region_share (Real): area_m2 over the region's area (the sum of its pieces'), the Thiessen
///   weight of the site in the region;
/// - weight_m (Real), weighted sites only;
/// - the site table's columns (the site's first row), named as in the cell layer;
/// - the region layer's columns, each named `region_` + its name (then `src_` rule of
///   input_columns.hpp when that is taken), with the region's values and types.
/// The weights table (no geometry) has region_index, region_id, site_index, site_id,
/// region_share, area_m2, one row per piece, by region then site.
#pragma once

#include <functional>
#include <string_view>
#include <vector>

#include "geovor/delaunay/site_rows.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/io/ogr_region_reader.hpp"
#include "geovor/layers/region_clip.hpp"

namespace geovor {

/// The fields of the clipped layer of `table`'s sites and `regions` (the file comment).
std::vector<Field> clipped_cell_layer_schema(const SiteTable& table, const RegionTable& regions);

/// Writes each piece as a feature (the file comment) to `writer`, opened with
/// clipped_cell_layer_schema(); does not finish it. `rows` maps sites to the table's rows.
void write_clipped_cells(FeatureWriter& writer, const SiteTable& table, const SiteRows& rows, const RegionTable& regions,
                         const std::vector<ClipPiece>& pieces);

/// The weights table as CSV text (header, then a row per piece by region then site; fields quoted
/// when they hold a comma, a quote or a line break; numbers in shortest round-trip form),
/// handed to `write` in order.
void write_clip_weights_csv(const std::function<void(std::string_view)>& write, const SiteTable& table,
                            const SiteRows& rows, const RegionTable& regions, const std::vector<ClipPiece>& pieces);

}  // namespace geovor
