/// \file ogr_feature_json.hpp
/// \brief The features of any OGR vector layer (a layer of `geovor cells`: GeoJSON, GeoPackage,
/// FlatGeobuf, ...) as GeoJSON text, for a service to send as they are (service/: OGC API -
/// Features). Read through GDAL; a build without GDAL throws.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace geovor {

/// One feature as GeoJSON pieces.
struct JsonFeature {
  std::int64_t fid = 0;  ///< the layer's feature id (GDAL's FID)
  /// West, south, east, north in degrees (the geometry's envelope in longitude/latitude; a layer
  /// cut at +-180 has no part across it, so west <= east); all 0 for a feature without geometry.
  std::array<double, 4> bbox{};
  std::string geometry;    ///< GeoJSON geometry object, 17 significant digits (round trip), or "null"
  std::string properties;  ///< JSON object: every attribute, numbers as numbers, null when unset
};

/// A layer's features in reading order.
struct JsonLayer {
  std::string name;
  std::vector<JsonFeature> features;
};

/// Reads `layer` ("" for the only one) of the OGR source at `path`; geometries in another CRS
/// are transformed to WGS84 longitude/latitude (a layer without a CRS is taken as such).
/// @exception Error(Io) when `path` cannot be opened; Error(BadData) when GDAL cannot read it as
///   vector data or a geometry cannot be transformed (naming the feature); Error(InvalidArgument)
///   for an unknown layer or several layers and `layer` empty.
JsonLayer read_json_features(const std::string& path, const std::string& layer = "");

}  // namespace geovor
