/// \file feature_writer.hpp
/// \brief Writing features (geometry + attributes) to GIS files: a native streaming GeoJSON /
/// GeoJSONSeq writer, and every other OGR vector driver through GDAL.
///
/// What each format does with the features (details in geojson_writer.hpp and
/// lib/src/io/gdal_writer.hpp):
/// - GeoJSON / GeoJSONSeq (native): RFC 7946, coordinates with WriterOptions::precision
///   decimals, a per-feature and per-collection "bbox", no "crs"; GeoJSONSeq is RFC 8142
///   (RS-separated) for ".geojsons" and newline-delimited otherwise.
/// - GDAL drivers: EPSG:4326 with the traditional GIS axis order (longitude first), layer type
///   wkbPoint / wkbMultiLineString / wkbMultiPolygon, one transaction per layer when the driver has them
///   (GPKG). Each field in its own type where the driver lists it (DMD_CREATIONFIELDDATATYPES),
///   else the nearest it has, as ogr2ogr maps them: Integer to Integer64 to Real (an integer
///   beyond 2^53 then refused), Real, Date and DateTime to String (ISO 8601 text); JSON fields
///   are Strings of the JSON subtype. A value a field cannot hold whole is refused with
///   Error(BadData) naming the feature, the field and the limit, and the writer fails (the
///   output removed): Shapefile and MapInfo text over 254 bytes, and anything a driver warns
///   it truncated. Coordinates are stored as doubles (the CSV
///   driver writes WKT with GDAL's own 15 significant digits; precision does not apply).
///   - ESRI Shapefile: field names cut to 10 bytes and made unique ("population_2020" ->
///     "population", "population_2021" -> "populati_1"; each renaming said as a GDAL warning), UTF-8 with a .cpg, widths shrunk to
///     the data (RESIZE=YES), Integer64 fields up to 20 characters wide (GDAL reads fields
///     wider than 18 back as Real), Real fields 33 wide with 15 decimals (values from 1e17 on
///     cannot be written: GDAL warns); the layer is named after the file, not
///     WriterOptions::layer; the driver rewinds exterior rings clockwise.
///   - FlatGeobuf: written with its spatial index, so readers get the features in the index's
///     (Hilbert) order, not in the order written.
///   - CSV: GEOMETRY=AS_WKT, the WKT in the first column.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/lonlat/geometry.hpp"

namespace geovor {

/// A field of a layer (FieldType: geovor/core/types.hpp).
struct Field {
  std::string name;
  FieldType type = FieldType::String;
  /// A String field whose values are JSON text (the lists of ids): written as the JSON value
  /// itself in GeoJSON, as a String of the JSON subtype in GDAL formats (GeoPackage records it).
  bool json = false;
};

/// A value of a field; monostate is null. Integer and Integer64 fields take std::int64_t, Real
/// double, Date and DateTime their ISO 8601 text ("2024-02-29", "2024-02-29T13:05:00Z"),
/// String and JSON fields text.
using FieldValue = std::variant<std::monostate, std::int64_t, double, std::string>;

enum class GeometryType { Point, MultiLineString, MultiPolygon };

/// "Point", "MultiLineString" or "MultiPolygon".
const char* to_string(GeometryType t);

/// Options of a writer; every default is documented.
struct WriterOptions {
  /// OGR driver name ("GeoJSON", "GeoJSONSeq", "GPKG", "FlatGeobuf", "ESRI Shapefile", "CSV",
  /// ...; case-insensitive). GeoJSON and GeoJSONSeq are always written natively, GDAL's own
  /// drivers of those names are never used. DEFAULT: empty, chosen from the file extension
  /// (format_from_extension(), else the one GDAL driver that lists the extension, e.g. .sqlite);
  /// GeoJSON for "-".
  std::string format;
  /// Name of the layer (GeoJSON: the collection's "name" member). DEFAULT: "cells".
  std::string layer = "cells";
  /// Decimal digits of coordinates in GeoJSON/GeoJSONSeq, 0..17. DEFAULT: 7 (about 1.1 cm),
  /// RFC 7946 §11.2.
  int precision = 7;
  /// Replace an existing output (ogr2ogr -overwrite): for a format that holds one layer, the file
  /// (for Shapefile: any of its .shp/.shx/.dbf/.prj/.cpg/... files); for one that holds several
  /// (format_holds_layers(): GPKG, SQLite, ...), only the layer named `layer`, the data source's
  /// other layers kept, as with `update`. The old output stays in place until finish() renames
  /// the new one over it. A directory is never replaced. DEFAULT: false (an existing file is an
  /// error).
  bool overwrite = false;
  /// Add the layer to an existing data source of a format that holds several layers, its other
  /// layers untouched (ogr2ogr -update); a layer of the same name is refused (Error(Io)) unless
  /// `overwrite`; a missing data source is created. The existing file is copied into the
  /// temporary directory, the layer written into the copy, and the copy renamed over the
  /// original by finish(), only if the original is unchanged since it was copied: a failure, a
  /// signal or a concurrent change leaves the original as it was. A one-layer format:
  /// Error(InvalidArgument). DEFAULT: false.
  bool update = false;
  /// GDAL layer creation options, "NAME=VALUE" (ogr2ogr -lco), applied after geovor's own, which
  /// they override. GeoJSON and GeoJSONSeq (written natively): Error(InvalidArgument).
  /// DEFAULT: none.
  std::vector<std::string> layer_options;
  /// GDAL dataset creation options, "NAME=VALUE" (ogr2ogr -dsco), used when a data source is
  /// created (not when an existing one is updated). GeoJSON and GeoJSONSeq: Error(InvalidArgument).
  /// DEFAULT: none.
  std::vector<std::string> dataset_options;
  /// The field whose value becomes the feature id (GeoJSON "id"; the field also stays in
  /// "properties"; other formats ignore it). DEFAULT: none.
  std::string id_field;
};

/// Features encoded as text by a FeatureEncoder, in order: their text, framing included, and
/// the bounding box of each (which the writer adds to the file's own). clear() keeps the memory.
struct EncodedFeatures {
  std::string text;
  std::vector<std::optional<BBox>> boxes;  ///< one per feature
  void clear() {
    text.clear();
    boxes.clear();
  }
};

/// Encodes features as a text writer (GeoJSON, GeoJSONSeq) writes them, so that callers can
/// format features on several threads while the writer only writes the text, in order
/// (FeatureWriter::encoder(), FeatureWriter::write_encoded()). The bytes are those write()
/// would write.
class FeatureEncoder {
 public:
  virtual ~FeatureEncoder() = default;
  /// Appends feature number `number` (1-based: it names the feature in errors) to `out`.
  /// Thread-safe: const and without state, one encoder serves any number of threads at once.
  /// @exception Error(InvalidArgument) as FeatureWriter::write(), with `out` unchanged.
  virtual void encode(const Geometry& geometry, std::span<const FieldValue> values, std::uint64_t number,
                      EncodedFeatures& out) const = 0;
  /// As encode(), with each value given as the JSON text encode() writes for it
  /// (append_json_value() in geojson_writer.hpp), so that a caller can make the text of values
  /// repeated across features (ids, lists of ids) once. The texts are copied unchecked: each must
  /// be one JSON value. The feature gets an "id" unless the id field's text is "null".
  /// @exception Error(InvalidArgument) as encode().
  virtual void encode_json(const Geometry& geometry, std::span<const std::string_view> json_values,
                           std::uint64_t number, EncodedFeatures& out) const = 0;
};

/// Streams features to a file. The output appears under its final name only when finish()
/// succeeds (written to a temporary file or directory with a short name next to it, then
/// renamed: geovor/core/output_target.hpp); a failure, or destruction without finish(), removes
/// the temporary files, so no partial output is ever left, and so do SIGINT, SIGTERM and SIGHUP
/// once install_output_cleanup() was called (the geovor tool does). Without options.overwrite the
/// final rename never replaces a file, not even one that appeared while writing (Error(Io)).
/// An existing device or FIFO (/dev/null, /dev/stdout) is not replaced: GeoJSON and GeoJSONSeq
/// write to it in place, the GDAL formats refuse it with Error(Io).
/// After an Error(Io) the writer is dead: every later call throws. A feature refused with
/// Error(InvalidArgument) (checked before anything is written) leaves the writer usable.
class FeatureWriter {
 public:
  virtual ~FeatureWriter() = default;
  /// Writes one feature; `values` follows the schema given to open_feature_writer() (any
  /// alternative is accepted for any field type; monostate is null). A Point that is kNullPoint
  /// (lonlat/geometry.hpp) is written as a null geometry (FlatGeobuf: refused, Error(BadData)).
  /// @exception Error(BadData) when the format cannot hold a value whole (GDAL formats, above);
  ///   the writer has then failed.
  /// @exception Error(InvalidArgument) when the geometry is not of the layer's type, the number
  ///   of values differs from the schema, or geometry_problem() (geojson_writer.hpp) finds a
  ///   non-finite or out-of-range coordinate, an unclosed ring or a too short ring/line.
  /// @exception Error(Io) when the output cannot be written.
  virtual void write(const Geometry& geometry, std::span<const FieldValue> values) = 0;
  /// The writer's encoder (valid as long as the writer), or null for formats written through
  /// GDAL, which take write() only.
  virtual const FeatureEncoder* encoder() const { return nullptr; }
  /// Writes features encoded by encoder() (numbered from the count written so far), after
  /// those written so far.
  /// @exception Error(InvalidArgument) if the writer has no encoder; Error(Io) as write().
  virtual void write_encoded(const EncodedFeatures& features);
  /// Completes the file and moves it into place. @exception Error(Io).
  virtual void finish() = 0;
  /// Ends the layer being written and starts another, named `layer`, in the same data source
  /// (a format that holds several layers: GPKG, SQLite, ...): later write() calls go to it, and
  /// finish() moves the data source with every layer into place at once. With
  /// WriterOptions::update or overwrite, an existing layer of that name is handled as for the
  /// first layer.
  /// @exception Error(InvalidArgument) for a format that holds one layer, a schema refused as by
  ///   open_feature_writer(), or a layer name already written; Error(Io) as write().
  void next_layer(const std::string& layer, GeometryType geometry_type, const std::vector<Field>& schema);

 protected:
  /// next_layer() once the schema is checked; by default, Error(InvalidArgument) (one layer).
  virtual void start_layer(const std::string& layer, GeometryType geometry_type, const std::vector<Field>& schema);
};

/// Opens `path` ("-" = stdout, GeoJSON/GeoJSONSeq only) for features of `geometry_type` with the
/// given schema. GeoJSON and GeoJSONSeq are written natively (RFC 7946 / RFC 8142, std::to_chars);
/// other formats through GDAL/OGR in EPSG:4326 with the traditional GIS axis order.
/// @exception Error(InvalidArgument) for an unknown format, one that cannot hold such a layer
///   (check_writer_options()), a format other than GeoJSON or
///   GeoJSONSeq with "-", a creation option not of the form NAME=VALUE, update or creation
///   options with GeoJSON/GeoJSONSeq, an empty or duplicate (case-insensitively) field name, an id_field not
///   in the schema, a precision outside 0..17; Error(Io) if the path exists and overwrite is
///   false, or cannot be created.
std::unique_ptr<FeatureWriter> open_feature_writer(const std::string& path, GeometryType geometry_type,
                                                   const std::vector<Field>& schema,
                                                   const WriterOptions& options = {});

/// The checks open_feature_writer() makes on `options` before it opens anything, so that a caller
/// can refuse them before long work: the format known from `options.format` or the extension and
/// able to hold a layer of `geometry_type` with attribute fields (not ODS, XLSX, DXF, GPX polygons,
/// ...: the reason and a format that works), creation options of the form NAME=VALUE, neither
/// update nor creation options with GeoJSON or GeoJSONSeq. (GDAL formats that hold one layer
/// refuse update when opened.)
/// @exception Error(InvalidArgument) as open_feature_writer().
void check_writer_options(const std::string& path, GeometryType geometry_type, const WriterOptions& options);

/// Whether the format of `path` (`format`, or the one its extension names, as open_feature_writer()
/// chooses it) holds several layers in one data source (GDAL's DCAP_MULTIPLE_VECTOR_LAYERS: GPKG,
/// SQLite, ...); false for GeoJSON, GeoJSONSeq, FlatGeobuf, Shapefile, CSV.
/// @exception Error(InvalidArgument) as open_feature_writer() for a format it cannot tell or does not know.
bool format_holds_layers(const std::string& path, const std::string& format);

/// The OGR driver name for a path's extension, case-insensitively (".geojson"/".json" ->
/// "GeoJSON", ".geojsons"/".geojsonl"/".geojsonseq" -> "GeoJSONSeq", ".gpkg" -> "GPKG", ".fgb" ->
/// "FlatGeobuf", ".shp" -> "ESRI Shapefile", ".csv" -> "CSV"), or "" if unknown. (".json" is
/// added because GDAL reads it as GeoJSON too.)
std::string format_from_extension(const std::string& path);

/// How an output is written, decided in this one place for every command, Python and the service.
enum class OutputKind {
  Text,    ///< a caller's own CSV text (the nearest join's rows): "-", .csv, .txt, a name without
           ///< an extension (/dev/null) or format "CSV"; only where the caller has one (text_allowed)
  Native,  ///< GeoJSON or GeoJSONSeq, written by geovor itself (no GDAL): "-", .geojson, .json,
           ///< .geojsonl, .geojsons, .geojsonseq, or those formats named
  Gdal,    ///< any other format or extension, through GDAL (open_feature_writer)
};
/// The kind of output `path` with `format` (empty: from the extension) is. Needs no GDAL.
OutputKind output_kind(const std::string& path, const std::string& format, bool text_allowed = false);
/// Whether writing features to `path` in `format` needs GDAL: output_kind() is Gdal (the geovor
/// command hands such a job to geovor-gdal).
bool output_needs_gdal(const std::string& path, const std::string& format);

}  // namespace geovor
