/// \file geojson_writer.hpp
/// \brief The native GeoJSON (RFC 7946) and GeoJSON text sequence (RFC 8142) writer, and the
/// pieces of it other code can use: RFC 7946 bounding boxes, number and string formatting, and
/// the geometry checks every writer applies.
///
/// This header is public (rather than private to lib/src/io) because the bounding-box rules and
/// the geometry check are useful to callers and are tested directly; it includes no GDAL header.
///
/// Output layout (stable, so it can be diffed and processed line by line):
/// - FeatureCollection: `{"type":"FeatureCollection","name":LAYER,"features":[` LF, one feature
///   per line separated by `,` LF, then `],"bbox":[w,s,e,n]}` LF. The collection bbox comes last
///   because the writer streams; JSON member order carries no meaning. "name" is the layer name
///   (a foreign member, as GDAL writes it). No "crs" member (RFC 7946 §4).
/// - Feature: `{"type":"Feature","id":ID,"bbox":[w,s,e,n],"properties":{...},"geometry":{...}}`;
///   "id" only when WriterOptions::id_field is set and its value is not null. Unlike GDAL's
///   ID_FIELD, the id field also stays in "properties", so every output format carries the same
///   attributes.
/// - Sequence (RFC 8142): each feature is one record `RS JSON LF` (RS = 0x1E) when the path ends
///   in ".geojsons"; otherwise (".geojsonl", any other name, stdout) newline-delimited `JSON LF`,
///   GDAL's GeoJSONSeq default. A sequence has no collection and no collection bbox.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "geovor/io/feature_writer.hpp"
#include "geovor/io/geometry.hpp"

namespace geovor {

/// How features are framed in a GeoJSON file.
enum class GeoJsonFraming {
  FeatureCollection,  ///< one RFC 7946 FeatureCollection
  NewlineDelimited,   ///< one feature per line (GeoJSONSeq without RS; ".geojsonl")
  RecordSeparated,    ///< RFC 8142: RS + feature + LF (".geojsons")
};

/// Opens a native GeoJSON writer; open_feature_writer() calls it for "GeoJSON" / "GeoJSONSeq".
/// `path` "-" writes to stdout (no temporary file: a failure there cannot be undone). Otherwise
/// the features go to a temporary file in the same directory (geovor/io/output_target.hpp: a
/// short name, removed on signals once install_output_cleanup() was called), renamed to `path` by
/// finish() without replacing a file that appeared meanwhile unless options.overwrite; the
/// temporary file is removed on any failure and by the destructor when finish() was not called. The temporary file is written with direct I/O (O_DIRECT, whole 4 KiB
/// blocks from an aligned 4 MB buffer, the last partial block normally) where its file system
/// allows it, which spares the kernel's copy into the page cache; otherwise normally.
/// @exception Error(InvalidArgument) for a bad schema, id_field or precision (0..17);
///   Error(Io) if `path` exists and !options.overwrite, or cannot be created.
std::unique_ptr<FeatureWriter> open_geojson_writer(const std::string& path, GeoJsonFraming framing,
                                                   GeometryType geometry_type,
                                                   const std::vector<Field>& schema,
                                                   const WriterOptions& options);

/// The RFC 7946 bbox of a geometry, or nullopt for an empty one.
/// Longitudes: each part (a polygon's exterior ring, a line string) spans the plain interval of
/// its longitudes (parts never cross the antimeridian, see geometry.hpp); the bbox is the
/// smallest arc of the circle of longitudes containing every part, -180 and 180 being the same
/// meridian. So a MultiPolygon cut at the antimeridian (parts touching both -180 and 180) gets
/// west > east (§5.2), and a ring around a pole, which spans [-180, 180], gets
/// [-180, south, 180, 90] (§5.3). When the whole circle is covered, west = -180 and east = 180;
/// on ties the arc that does not cross the antimeridian wins.
std::optional<BBox> geojson_bbox(const Geometry& geometry);

/// The union of RFC 7946 bboxes (a FeatureCollection's bbox): the smallest longitude arc
/// containing every box, with the same rules as geojson_bbox(). The pending intervals are merged
/// whenever they outnumber both 4,096 and the intervals merged so far (O(n log n) in all), and a
/// box inside the merged intervals costs one binary search (a tiling's boxes soon all are).
class BBoxUnion {
 public:
  void add(const BBox& box);
  /// nullopt if nothing was added.
  std::optional<BBox> result() const;

 private:
  struct Interval {
    double west, east;  // west <= east
  };
  void add_interval(double west, double east);
  void compact() const;
  mutable std::vector<Interval> merged_;     // sorted by west, disjoint
  mutable std::vector<Interval> intervals_;  // pending
  double south_ = 0, north_ = 0;
  bool empty_ = true;
};

/// Why a geometry cannot be written, or "" if it can: every coordinate finite, longitudes in
/// [-180, 180], latitudes in [-90, 90]; every ring closed (last position bit-identical to the
/// first) with at least 4 positions; every line string with at least 2 positions. Orientation is
/// not checked (it is written as given). Every writer applies this check before writing.
std::string geometry_problem(const Geometry& geometry);

/// Largest number of characters format_coordinate() writes.
inline constexpr int kMaxCoordinateChars = 40;
/// Largest number of characters format_real() writes.
inline constexpr int kMaxRealChars = 32;

/// Writes `value` with exactly `precision` decimals (correctly rounded, ties to even, the same
/// digits as std::to_chars(fixed, precision)), then trims trailing zeros and a trailing '.';
/// "-0" becomes "0". It computes round(value * 10^precision) exactly in 128-bit integers, which
/// is several times faster than std::to_chars and matters for large outputs. Values of magnitude
/// >= 2^52 (never a coordinate) are written in shortest round-trip form instead.
/// `value` must be finite and 0 <= precision <= 17. `out` must have room for
/// kMaxCoordinateChars characters, all of which may be written (past the returned end: scratch).
/// @return one past the last character of the number (at most kMaxCoordinateChars).
char* format_coordinate(char* out, double value, int precision);

/// Writes `value` (finite) in the shortest form that reads back to the same double
/// (std::to_chars), with ".0" appended when that form has no '.' or exponent, so that readers
/// keep the field Real. At most kMaxRealChars characters. @return one past the last character.
char* format_real(char* out, double value);

/// Appends `text` as a JSON string with its quotes: '"' and '\\' escaped, control characters as
/// \b \f \n \r \t or \u00XX, valid UTF-8 passed through, and each byte that is not part of valid
/// UTF-8 replaced by U+FFFD (JSON text must be UTF-8, RFC 8259 §8.1).
void append_json_string(std::string& out, std::string_view text);

/// Appends `value` as the GeoJSON writers write a property value: null for monostate and for a
/// non-finite double (JSON has neither NaN nor infinity), an integer in decimal, a double as
/// format_real(), a string as append_json_string().
void append_json_value(std::string& out, const FieldValue& value);

}  // namespace geovor
