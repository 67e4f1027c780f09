/// \file query_line.hpp
/// \brief One line of a query stream (`geovor nearest --queries`): its fields, then its
/// latitude, longitude and id, or the reason it is malformed. Allocation-free per line once warm
/// (the nearest command parses more than a million lines per second with it).
///
/// A query stream is CSV lines `lat,lon[,id]` without a header, or a header line whose columns
/// are detected by name as the site reader's (geo/coordinate_columns.hpp; id: query_id, id, icao,
/// code, name), the header checked as a site table's (check_header_names). Unlike a site
/// table, a query cannot span lines: a quoted field must close on its line.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace geovor {

/// Where the columns of a query line are.
struct QueryFormat {
  bool header = false;               ///< the first line is a header (and is not a query)
  std::vector<std::string> columns;  ///< the header's names, trimmed; empty without a header
  std::size_t fields = 0;            ///< fields per line with a header (0 without)
  int lat = 0, lon = 1, id = -1;     ///< column indices (without a header: 0, 1, and 2 if present)
};

/// The format of a query stream from its first line (line end excluded; a trailing CR is
/// ignored): without a header when its first two fields are numbers, else a header.
/// \param[in] first the first line of the stream, after any UTF-8 byte order mark.
/// \param[in] source the stream's name, for the message.
/// \throw Error (ErrorCode::BadData) when a header has no latitude/longitude columns.
QueryFormat detect_query_format(std::string_view first, const std::string& source);

/// The columns a query stream's header is read with; empty names mean "detect by name".
struct QueryColumns {
  std::string lat_field;  ///< latitude column, e.g. "pickup_latitude"
  std::string lon_field;  ///< longitude column
  std::string id_field;   ///< id column (default: query_id, id, icao, code or name, if any)
  bool any() const { return !lat_field.empty() || !lon_field.empty() || !id_field.empty(); }
};

/// As detect_query_format, with columns named by `names`: a named column makes the first line a
/// header (even of numbers); the others are detected by name as usual.
/// \throw Error (ErrorCode::InvalidArgument) when a named column is not in the header, naming
///   the stream, the option's column and the header's columns; Error (ErrorCode::BadData) as
///   detect_query_format.
QueryFormat detect_query_format(std::string_view first, const std::string& source, const QueryColumns& names);

/// A number as the site reader takes it: spaces or tabs around, an optional leading '+', then
/// what std::from_chars reads (decimal or exponent form, inf, nan).
/// \param[in] text the field.
/// \param[out] value the number (unspecified on failure).
/// \return "" or the reason: "empty value", "is out of the range of a double", "is not a number".
const char* parse_query_number(std::string_view text, double& value);

/// Splits one line (no line end) at commas, with RFC 4180 quoting within the line ("" is a
/// quote, "ab"c is abc, a quote inside an unquoted field is kept). Unquoted fields view `line`,
/// quoted ones view `scratch` (valid until scratch is next modified).
/// \return "" or the reason, e.g. an unterminated quoted field.
const char* split_query_fields(std::string_view line, std::vector<std::string_view>& out, std::string& scratch);

/// One query parsed from a line.
struct QueryLine {
  double lat_deg = 0;  ///< geodetic latitude (degrees), normalised by normalize_lat_lon
  double lon_deg = 0;  ///< longitude (degrees) in [-180, 180), normalised likewise
  /// The id field as written (quotes removed); null data() when the format has no id column.
  /// Views the line, or the parser's buffer when the field was quoted (id_quoted): valid until
  /// the next parse().
  std::string_view id;
  bool id_quoted = false;  ///< id views the parser's buffer, not the line
};

/// Parses query lines of one format; keeps its buffers from line to line.
class QueryLineParser {
 public:
  explicit QueryLineParser(QueryFormat format) : fmt_(std::move(format)) {}

  /// Parses one line (line end and trailing CR excluded, not empty).
  /// \param[out] out the query when the line is valid.
  /// \param[out] reason why the line is malformed, naming the column, e.g.
  ///   "lat: 'abc' is not a number", "expected 2 or 3 (lat,lon[,id]) fields, found 1",
  ///   "latitude 91 is beyond +-90"; left alone when the line is valid.
  /// \return true when the line is a valid query.
  bool parse(std::string_view line, QueryLine& out, std::string& reason);

  const QueryFormat& format() const { return fmt_; }

 private:
  QueryFormat fmt_;
  std::vector<std::string_view> fields_;
  std::string scratch_;
};

}  // namespace geovor
