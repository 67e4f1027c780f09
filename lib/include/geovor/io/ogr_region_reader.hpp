/// \file ogr_region_reader.hpp
/// \brief Regions (basins, districts, countries, coastlines) from any OGR polygon layer, for
/// clipping cells to them (layers/region_clip.hpp): each feature's (Multi)Polygon in WGS84
/// longitude/latitude degrees, straight edges between its vertices as a GIS draws them,
/// reprojected when the layer has another CRS (a layer without one is taken as such), with its
/// attributes and their types.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "geovor/geo/site_reader.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/lonlat/geometry.hpp"

namespace geovor {

/// One region: a feature of the layer.
struct Region {
  std::uint64_t row = 0;  ///< 1-based feature number in reading order
  std::int64_t fid = 0;   ///< the layer's feature id
  std::string id;         ///< the id field's value as text, else the row number
  MultiPolygon geometry;  ///< rings closed, as read (not checked: the clip checks them)
  std::vector<FieldValue> values;  ///< by RegionTable::fields
};

/// A polygon layer's regions.
struct RegionTable {
  std::string source;         ///< the path, as given
  std::vector<Field> fields;  ///< the attributes, with their OGR types
  std::vector<Region> regions;
  /// Features that are no region, with their reason naming them ("feature 3 (FID 2): geometry is
  /// a LineString, not a Polygon"; a null or empty geometry; a point that cannot be transformed).
  std::vector<RejectedRow> rejected;
};

/// Reads the regions of `layer` ("" for the only layer) of the OGR source at `path`; `id_field`
/// ("" for none) names the attribute whose text is each region's id.
/// @exception Error(Io) when `path` cannot be opened; Error(BadData) when GDAL cannot read it as
///   vector data or its CRS cannot be transformed to WGS84; Error(InvalidArgument) for an unknown
///   layer or id field, or several layers and `layer` empty.
RegionTable read_regions_ogr(const std::string& path, const std::string& layer = "", const std::string& id_field = "");

}  // namespace geovor
