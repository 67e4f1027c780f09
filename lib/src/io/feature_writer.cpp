// open_feature_writer: the schema check and the choice of writer. GeoJSON and GeoJSONSeq are
// written natively (geojson_writer.cpp); every other format through GDAL (gdal_writer.cpp).
#include "geovor/io/feature_writer.hpp"

#include <filesystem>
#include <set>

#include "geovor/core/ascii.hpp"
#include "geovor/core/error.hpp"
#include "geovor/io/geojson_writer.hpp"
#include "io/gdal_writer.hpp"

namespace geovor {
namespace {

std::string extension(const std::string& path) {
  return ascii_lower(std::filesystem::path(path).extension().string());
}

// Field names must be non-empty and unique; case-insensitively, because GPKG (SQLite), DBF and
// most other formats compare column names that way.
void check_schema(const std::vector<Field>& schema) {
  std::set<std::string> seen;
  for (const Field& f : schema) {
    if (f.name.empty()) throw Error(ErrorCode::InvalidArgument, "a field has an empty name");
    if (!seen.insert(ascii_lower(f.name)).second) {
      throw Error(ErrorCode::InvalidArgument, "field name '" + f.name + "' is used twice");
    }
  }
}

// The format open_feature_writer() writes `path` in: `format`, else the extension's.
std::string resolve_format(const std::string& path, const std::string& format) {
  if (!format.empty()) return format;
  std::string f = path == "-" ? "GeoJSON" : format_from_extension(path);
  if (f.empty()) f = gdal_detail::driver_for_extension(path);
  if (f.empty()) throw Error(ErrorCode::InvalidArgument, path + ": cannot tell the output format from the extension; use --format");
  return f;
}

bool is_native(const std::string& format) {  // of a resolved format: resolve_format()
  const std::string f = ascii_lower(format);
  return f == "geojson" || f == "geojsonseq";
}

// GDAL creation options are NAME=VALUE; the natively written formats take none, and hold one layer.
void check_output_model(const std::string& path, const std::string& format, GeometryType geometry_type,
                        const WriterOptions& options) {
  for (const auto* list : {&options.layer_options, &options.dataset_options})
    for (const std::string& o : *list)
      if (o.find('=') == std::string::npos || o.front() == '=')
        throw Error(ErrorCode::InvalidArgument, path + ": creation option '" + o + "' is not of the form NAME=VALUE");
  if (!is_native(format)) {
    if (const std::string why = gdal_detail::format_refusal(format, geometry_type, options); !why.empty())
      throw Error(ErrorCode::InvalidArgument, path + ": " + why);
    return;
  }
  if (options.update)
    throw Error(ErrorCode::InvalidArgument, path + ": --update adds a layer to a data source that holds several (GPKG, SQLite, ...); " +
                                                format + " holds one: use --overwrite to replace the file");
  if (!options.layer_options.empty() || !options.dataset_options.empty())
    throw Error(ErrorCode::InvalidArgument, path + ": --lco and --dsco are GDAL creation options; " + format +
                                                " is written by geovor itself (its option: --precision)");
}

}  // namespace

void check_writer_options(const std::string& path, GeometryType geometry_type, const WriterOptions& options) {
  check_output_model(path, resolve_format(path, options.format), geometry_type, options);
}

bool format_holds_layers(const std::string& path, const std::string& format) {
  const std::string f = resolve_format(path, format);
  return !is_native(f) && gdal_detail::driver_holds_layers(f);
}

void FeatureWriter::next_layer(const std::string& layer, GeometryType geometry_type, const std::vector<Field>& schema) {
  check_schema(schema);
  start_layer(layer, geometry_type, schema);
}

void FeatureWriter::start_layer(const std::string& layer, GeometryType, const std::vector<Field>&) {
  throw Error(ErrorCode::InvalidArgument, "layer '" + layer + "': this output format holds one layer; write it to another file, or to a format that holds several (GPKG, SQLite, ...)");
}

std::string format_from_extension(const std::string& path) {
  const std::string ext = extension(path);
  if (ext == ".geojson" || ext == ".json") return "GeoJSON";
  if (ext == ".geojsons" || ext == ".geojsonl" || ext == ".geojsonseq") return "GeoJSONSeq";
  if (ext == ".gpkg") return "GPKG";
  if (ext == ".fgb") return "FlatGeobuf";
  if (ext == ".shp") return "ESRI Shapefile";
  if (ext == ".csv") return "CSV";
  return "";
}

OutputKind output_kind(const std::string& path, const std::string& format, bool text_allowed) {
  if (text_allowed) {
    if (!format.empty()) {
      if (ascii_iequals(format, "CSV")) return OutputKind::Text;
    } else {
      const std::string name = path.substr(path.rfind('/') + 1);
      const std::size_t dot = name.rfind('.');
      if (path == "-" || dot == std::string::npos || dot == 0) return OutputKind::Text;
      const std::string ext = ascii_lower(name.substr(dot + 1));
      if (ext == "csv" || ext == "txt") return OutputKind::Text;
    }
  }
  const std::string f = ascii_lower(!format.empty() ? format : path == "-" ? std::string("GeoJSON") : format_from_extension(path));
  return f == "geojson" || f == "geojsonseq" ? OutputKind::Native : OutputKind::Gdal;
}

bool output_needs_gdal(const std::string& path, const std::string& format) {
  return output_kind(path, format) == OutputKind::Gdal;
}

std::unique_ptr<FeatureWriter> open_feature_writer(const std::string& path, GeometryType geometry_type,
                                                   const std::vector<Field>& schema,
                                                   const WriterOptions& options) {
  if (path.empty()) throw Error(ErrorCode::InvalidArgument, "empty output path");
  check_schema(schema);
  const std::string format = resolve_format(path, options.format);
  check_output_model(path, format, geometry_type, options);
  const std::string f = ascii_lower(format);
  if (f == "geojson") {
    return open_geojson_writer(path, GeoJsonFraming::FeatureCollection, geometry_type, schema,
                               options);
  }
  if (f == "geojsonseq") {
    // RFC 8142 record separators for ".geojsons" (GDAL's rule); newline-delimited otherwise.
    const GeoJsonFraming framing = extension(path) == ".geojsons" ? GeoJsonFraming::RecordSeparated
                                                                  : GeoJsonFraming::NewlineDelimited;
    return open_geojson_writer(path, framing, geometry_type, schema, options);
  }
  return gdal_detail::open_gdal_writer(path, format, geometry_type, schema, options);
}

void FeatureWriter::write_encoded(const EncodedFeatures&) {
  throw Error(ErrorCode::InvalidArgument, "this output format has no encoder; write features one by one");
}

const char* to_string(GeometryType t) {
  switch (t) {
    case GeometryType::Point:
      return "Point";
    case GeometryType::MultiLineString:
      return "MultiLineString";
    case GeometryType::MultiPolygon:
      return "MultiPolygon";
  }
  return "?";
}

}  // namespace geovor
