/// \file site_reader.hpp
/// \brief read_sites_csv: a table of sites (latitude/longitude or ECEF columns) from CSV, with
/// every data row either accepted as a site or rejected with a reason.
///
/// The text: RFC 4180 records (csv_reader.hpp) whose delimiter is sniffed from the header line:
/// the most frequent of ',', ';', TAB and '|' outside quotes (ties in that order; none: ','),
/// unless SiteReaderOptions::delimiter names it. With ';', TAB or '|' as delimiter a coordinate
/// may use a decimal comma ("48,85"; one comma, no point). UTF-8 (an optional byte order mark);
/// SiteReaderOptions::encoding converts other text (iconv) first. Without it, a row holding
/// bytes that are not UTF-8 is rejected with the column ("name: not valid UTF-8 (byte 0xE9 at
/// byte 3); give the file's encoding, e.g. --encoding ISO-8859-1"), and so is the file when its
/// header holds them.
///
/// The header (coordinate_columns.hpp): a name that repeats another (trimmed, case-insensitive)
/// or an empty name is refused, except empty names in the last columns while every row leaves
/// those fields empty (a trailing delimiter from a spreadsheet): they are then dropped.
///
/// Column detection (names compared trimmed and case-insensitively):
/// - latitude and longitude: by the ranked words of coordinate_columns.hpp (lat, Latitude (deg),
///   stop_lat, decimalLatitude, latitude_deg, LAT, POINT_Y, y ...); several equally good
///   candidates are refused, naming them;
/// - id: id, icao, code, name (the first present in that order); without one, or with the id
///   field "#row", a site's id is its row number.
///
#pragma once

#include <cstdint>
#include <istream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "geovor/core/types.hpp"

namespace geovor {

/// One column's declared type: GDAL's CSV open option COLUMN_TYPES=NAME=TYPE (column_types.hpp).
struct FieldTypeOverride {
  std::string column;  ///< the column's name, compared trimmed and case-insensitively
  FieldType type = FieldType::String;
};

/// Which columns hold what; empty names mean "detect by name".
struct SiteReaderOptions {
  std::string lat_field;  ///< latitude column (degrees); empty: detect
  std::string lon_field;  ///< longitude column (degrees); empty: detect
  std::string id_field;   ///< id column; empty: detect id/icao/code/name, else the row number;
                          ///< kRowNumberId: the row number
  /// Exactly 3 column names (X, Y, Z earth-centred earth-fixed WGS84, metres), or empty for
  /// latitude/longitude input. Exclusive with lat_field/lon_field.
  std::vector<std::string> ecef_fields;
  /// Type the columns by their values (column_types.hpp; an OGR layer's columns keep their
  /// field types); false keeps every column String, as read. DEFAULT: true.
  bool detect_types = true;
  /// Declared column types (--field-type NAME=TYPE), over the detected ones, the id column's and
  /// detect_types = false included: apply_field_types() (column_types.hpp) for CSV and OGR input
  /// alike. A name that is no column is Error(InvalidArgument); a value that is not of its
  /// column's declared type is Error(BadData) naming the row. DEFAULT: none.
  std::vector<FieldTypeOverride> field_types;
  /// Threads tokenising the rows and converting their coordinates (parsing, normalising, unit
  /// vectors), each on its share of the input (0: one per core); see CsvSiteScan. DEFAULT: 1.
  /// The result does not depend on it.
  unsigned threads = 1;
  /// The field delimiter: ',', ';', '\t' or '|' (another is Error(InvalidArgument)); 0 (DEFAULT):
  /// sniffed from the header line (see above).
  char delimiter = 0;
  /// The text's encoding for iconv (ISO-8859-1, CP1252, UTF-16, ...); empty (DEFAULT): UTF-8.
  std::string encoding;
  /// The coordinate system of the coordinate columns (anything GDAL's SetFromUserInput takes:
  /// EPSG:2154, a WKT, a PROJ string), or empty (DEFAULT) for WGS84 degrees. Set, the columns are
  /// found as x/y (coordinate_columns.hpp), rows keep their x in lon_deg and y in lat_deg without
  /// any range check but finiteness, and reproject_sites() (ogr_site_reader.hpp, GDAL) makes them
  /// WGS84 sites; read_sites() does both.
  std::string s_srs;
};

/// The id field that makes a site's id its row number (--id-field '#row').
inline constexpr std::string_view kRowNumberId = "#row";

/// One accepted data row.
struct InputSite {
  std::uint64_t row = 0;   ///< 1-based data row number (the header is not a row)
  std::uint64_t line = 0;  ///< 1-based line number in the file where the row starts
  std::string id;          ///< value of the id column, or the row number as text
  double lat_deg = 0;      ///< geodetic latitude (degrees), normalised by normalize_lat_lon
  double lon_deg = 0;      ///< longitude (degrees), normalised by normalize_lat_lon
  double height_m = 0;     ///< height above the ellipsoid (metres); 0 unless ECEF input
  double weight_m = 0;     ///< radius of a weighted site (metres); 0 unless read_site_weights()
  Vec3 unit;               ///< SiteEncoder::from_lat_lon(lat_deg, lon_deg)
  std::vector<std::string> fields;  ///< every field of the row as read
};

/// One data row that is not a site, and why.
struct RejectedRow {
  std::uint64_t row = 0;   ///< 1-based data row number
  std::uint64_t line = 0;  ///< 1-based line number where the row starts
  std::string reason;      ///< human-readable, names the column at fault
};

/// The result of reading a table of sites.
struct SiteTable {
  std::string source;                ///< file name, or "<stdin>"
  std::vector<std::string> columns;  ///< header names, as read
  char delimiter = ',';              ///< the field delimiter, as given or sniffed
  /// The type of each column (column_types.hpp): empty, or one per column; an empty value of a
  /// column that is not String is null. Empty means every column is String.
  std::vector<FieldType> column_types;
  int lat_column = -1;               ///< index into columns; -1 for ECEF input
  int lon_column = -1;               ///< index into columns; -1 for ECEF input
  int id_column = -1;                ///< index into columns; -1: ids are row numbers
  std::vector<int> ecef_columns;     ///< X, Y, Z indices for ECEF input, else empty
  bool weighted = false;             ///< every site has its radius in weight_m (site_weights.hpp)
  std::uint64_t rows_read = 0;       ///< data rows seen == sites.size() + rejected.size()
  std::vector<InputSite> sites;
  std::vector<RejectedRow> rejected;

  /// column_types[c], or String when column_types is empty.
  FieldType column_type(std::size_t c) const { return c < column_types.size() ? column_types[c] : FieldType::String; }
};

/// Read sites from a CSV stream whose first record is the header: CsvSiteScan::read, then
/// finish() (csv_site_scan.hpp, for a caller that wants the positions before the strings).
/// \param[in] in the CSV text.
/// \param[in] source the name used in messages and kept in SiteTable::source.
/// \param[in] options column choices.
/// \throw Error as described in the file comment.
SiteTable read_sites_csv(std::istream& in, const std::string& source,
                         const SiteReaderOptions& options = {});

/// Read sites from a CSV file; "-" reads standard input (source "<stdin>").
/// \throw Error (ErrorCode::Io) naming the path and the system's reason when it cannot be read;
///   otherwise as read_sites_csv.
SiteTable read_sites_csv_file(const std::string& path, const SiteReaderOptions& options = {});

/// Throws Error(ErrorCode::BadData) when no site remains in `table` (an empty table, every row
/// rejected): "FILE: no usable site (N rows, M rejected)" and, when every row was rejected, the
/// first reason and a hint when all the rejected latitudes are beyond +-90 (projected metres).
void require_sites(const SiteTable& table);

/// Accepted rows whose id an earlier accepted row has (ids are kept as they are; this only says so).
struct DuplicateIds {
  std::uint64_t rows = 0;  ///< rows whose id is not the first use of that id
  struct Example {
    std::string id;
    std::vector<std::uint64_t> rows;  ///< its first rows (at most 3)
  };
  std::vector<Example> examples;  ///< the first repeated ids, in order of their repeat (at most 3)
};

/// The ids of `table.sites` that repeat; none when the ids are row numbers (id_column < 0).
DuplicateIds find_duplicate_ids(const SiteTable& table);

/// The unit vectors of `table.sites`, in order: the points a triangulation of the table is built from.
std::vector<Vec3> site_points(const SiteTable& table);

/// Index of the column whose name, trimmed and case-insensitive, is `name`; -1 if none.
int find_column(const std::vector<std::string>& columns, std::string_view name);
/// The first of `names` (in that order of preference) that is a column, as find_column; -1 if none.
int find_column(const std::vector<std::string>& columns, std::span<const std::string_view> names);

}  // namespace geovor
