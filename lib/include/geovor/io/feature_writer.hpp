/// \file feature_writer.hpp
/// \brief Writing features (geometry + attributes) to GIS files: a native streaming GeoJSON /
/// GeoJSONSeq writer, and every other OGR vector driver through GDAL.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "geovor/io/geometry.hpp"

namespace geovor {

enum class FieldType { Integer, Real, String };

struct Field {
  std::string name;
  FieldType type = FieldType::String;
};

/// A value of a field; monostate is null.
using FieldValue = std::variant<std::monostate, std::int64_t, double, std::string>;

enum class GeometryType { Point, MultiLineString, MultiPolygon };

/// Options of a writer; every default is documented.
struct WriterOptions {
  /// OGR driver name ("GeoJSON", "GeoJSONSeq", "GPKG", "FlatGeobuf", "ESRI Shapefile", "CSV",
  /// ...). DEFAULT: empty, chosen from the file extension.
  std::string format;
  /// Name of the layer. DEFAULT: "cells".
  std::string layer = "cells";
  /// Decimal digits of coordinates in text formats. DEFAULT: 7 (about 1.1 cm), RFC 7946 §11.2.
  int precision = 7;
  /// Replace an existing output. DEFAULT: false (an existing file is an error).
  bool overwrite = false;
  /// The field whose value becomes the feature id (GeoJSON "id"). DEFAULT: none.
  std::string id_field;
};

/// Streams features to a file. The output appears under its final name only when finish()
/// succeeds (written to a temporary file, then renamed); a failure leaves no partial file.
class FeatureWriter {
 public:
  virtual ~FeatureWriter() = default;
  /// Writes one feature; `values` follows the schema given to open_feature_writer().
  /// @exception Error(Io) when the output cannot be written.
  virtual void write(const Geometry& geometry, std::span<const FieldValue> values) = 0;
  /// Completes the file and moves it into place. @exception Error(Io).
  virtual void finish() = 0;
};

/// Opens `path` ("-" = stdout, GeoJSON/GeoJSONSeq only) for features of `geometry_type` with the
/// given schema. GeoJSON and GeoJSONSeq are written natively (RFC 7946 / RFC 8142, std::to_chars);
/// other formats through GDAL/OGR in EPSG:4326 with the traditional GIS axis order.
/// @exception Error(InvalidArgument) for an unknown format; Error(Io) if the path exists and
///   overwrite is false, or cannot be created.
std::unique_ptr<FeatureWriter> open_feature_writer(const std::string& path, GeometryType geometry_type,
                                                   const std::vector<Field>& schema,
                                                   const WriterOptions& options = {});

/// The OGR driver name for a path's extension (".geojson" -> "GeoJSON", ".geojsons"/".geojsonl"
/// -> "GeoJSONSeq", ".gpkg" -> "GPKG", ".fgb" -> "FlatGeobuf", ".shp" -> "ESRI Shapefile",
/// ".csv" -> "CSV"), or "" if unknown.
std::string format_from_extension(const std::string& path);

}  // namespace geovor
