/// \file nearest_join.hpp
/// \brief The nearest-site join (`geovor nearest`): a spatial join of every query (a CSV stream
/// or a table read from an OGR layer) to its nearest site (or k nearest) of a SiteIndex, written
/// in the input's order as CSV or as point features (any FeatureWriter).
///
/// Input: query lines `lat,lon[,id]` with or without a header (geo/query_line.hpp; columns named
/// by NearestJoinOptions::columns), an optional UTF-8 byte order mark, LF or CRLF line ends,
/// empty lines skipped (but counted); or a SiteTable (read_sites_ogr of a point layer).
///
/// Fields, in this order (nearest_join_fields()): query_id (the query's id column, else its line
/// number, or its feature number for a table), rank (with options.rank_column), site_index,
/// site_id (the site's id, its first row's: SiteAttributes::site_id), distance_m (metres, the
/// shortest round-trip decimal: std::to_chars), then every column of the query's header as read
/// (a stream without a header has none), named as in the input or src_NAME when the name equals
/// a field before it (ASCII case-insensitively, repeated until unique), then options.site_fields
/// (the site's first row's values) named likewise, or site_NAME. CSV fields are quoted when they
/// hold a comma, a quote or a line break; a query's own fields are copied as written. In
/// features an OGR query table's columns keep its column_types; stream columns and site fields
/// are String.
///
/// One row per answer, nearest first, and at least one per query, so that no query is lost:
/// - no site within options.max_distance_m: one row with an empty match (site_index, site_id,
///   distance_m, rank and the site fields empty; null in features);
/// - a malformed query (reported as a MalformedQuery too): one row with its query_id (the id
///   field when the line has the header's number of fields, else the line number), an empty
///   match, and its fields as written when it has the header's number of fields (else empty);
///   as a feature, its point is null (FeatureWriter: a LonLat of NaNs).
/// Memory is constant in the number of queries of a stream.
///
/// The stream is cut into blocks of whole lines and run as a core/parallel.hpp ordered_pipeline:
/// blocks are read one at a time, parsed, located (one Locator per worker, kept from block to
/// block so that its landmarks stay warm) and formatted in parallel, then written in order on the
/// calling thread. The output does not depend on the number of threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <string_view>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "geovor/geo/query_line.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/locate/index_file.hpp"
#include "geovor/locate/knn.hpp"
#include "geovor/locate/locator.hpp"

namespace geovor {

/// Options of nearest_join; every default is documented.
struct NearestJoinOptions {
  /// Sites per query, nearest first. DEFAULT: 1.
  std::size_t k = 1;
  /// Write a rank column (1 for the nearest). DEFAULT: false (geovor nearest sets it when --k is
  /// given, even --k 1).
  bool rank_column = false;
  /// The metric (locate/knn.hpp). DEFAULT: none, meaning default_metric(index): Power for an
  /// index of weighted sites (the site whose power cell holds the query), else Sphere.
  std::optional<Metric> metric;
  /// The locators' options (strategy). DEFAULT: LocatorOptions{} (Keep, Jump & Climb).
  LocatorOptions locator;
  /// Worker threads; 0 means one per core. At most 4 per core are started (more would only
  /// queue for the cores, each holding blocks); fewer when the system refuses threads. DEFAULT: 1.
  unsigned threads = 1;
  /// Stop at the first malformed line (the answers before it are written). DEFAULT: false.
  bool strict = false;
  /// The query stream's latitude, longitude and id columns (empty: detected by name).
  QueryColumns columns;
  /// A site farther than this (metres, in the metric's distance) is no match: a query without a
  /// site within it gets one row with an empty match. DEFAULT: infinity (every query matches).
  double max_distance_m = std::numeric_limits<double>::infinity();
  /// Columns of the index's site table joined to each match (the site's first row's values),
  /// each naming a column of SiteAttributes::columns (ASCII case-insensitively). DEFAULT: none.
  std::vector<std::string> site_fields;
  /// Declared types of a query stream's columns (--query-field-type; column_types.hpp) in the
  /// point features: each value read as declared_value() and written in its type; a value that is
  /// not of its type is Error(BadData) naming the line, and a name that is no column of the header
  /// Error(InvalidArgument). CSV text output has no types: Error(InvalidArgument). A table of
  /// queries keeps its own types (read it with SiteReaderOptions::field_types). DEFAULT: none.
  std::vector<FieldTypeOverride> query_field_types;
  /// Bytes per block, the unit read, answered by one worker and written at once (a longer line
  /// makes a longer block). DEFAULT: 1 MiB.
  std::size_t block_bytes = std::size_t{1} << 20;
};

/// A query line that is not a query: a data problem, reported as a value.
struct MalformedQuery {
  std::uint64_t line = 0;  ///< 1-based line number in the stream (0 for a table's row)
  std::uint64_t row = 0;   ///< a table's 1-based row (feature) number (0 for a stream's line)
  /// QueryLineParser's reason, e.g. "lat: 'abc' is not a number"; a table's RejectedRow reason.
  std::string reason;
};

/// What nearest_join did.
struct NearestJoinReport {
  std::uint64_t answered = 0;   ///< queries answered (their rows are written)
  std::uint64_t malformed = 0;  ///< malformed lines (each passed to on_malformed; each has a row)
  std::uint64_t unmatched = 0;  ///< queries answered with an empty match (no site within max_distance_m)
  bool stopped = false;         ///< options.strict and a malformed line: nothing after it is read
};

/// The join's fields (the file comment) for queries with the header `query_columns`, their types:
/// site_index and rank Integer, distance_m Real, the others String.
/// @exception Error(InvalidArgument) when a site field is not a column of index.attributes,
///   naming it and the columns, or the metric does not apply to the index (check_metric).
std::vector<Field> nearest_join_fields(const SiteIndex& index, const std::vector<std::string>& query_columns,
                                       const NearestJoinOptions& options);

/// Opens the writer of the join's point features: gets the fields, once the queries' header is
/// known, and returns the writer (open_feature_writer(path, GeometryType::Point, fields, ...)).
using OpenJoinWriter = std::function<std::unique_ptr<FeatureWriter>(const std::vector<Field>& fields)>;

/// Joins the query stream `queries` (read from its current position to its end; `source` names
/// it in messages) to its nearest sites in `index`, calling write() with the output CSV (the
/// header, then blocks of whole rows, in order) and on_malformed() for each malformed line in
/// line order; both run on the calling thread.
/// @exception Error(Io) "SOURCE: read error: REASON" when the stream cannot be read;
///   Error(BadData) from detect_query_format (a header without latitude/longitude columns);
///   whatever write() or on_malformed() throws. Rows written before the exception stay written.
NearestJoinReport nearest_join(const SiteIndex& index, std::FILE* queries, const std::string& source,
                               const NearestJoinOptions& options,
                               const std::function<void(std::string_view)>& write,
                               const std::function<void(const MalformedQuery&)>& on_malformed = {});

/// As above, writing each row as a point feature at the query's position (its normalised
/// latitude and longitude) to the writer open() returns, then finishing it (also after a
/// strict stop). @exception as above; Error from open() and the writer.
NearestJoinReport nearest_join(const SiteIndex& index, std::FILE* queries, const std::string& source,
                               const NearestJoinOptions& options, const OpenJoinWriter& open,
                               const std::function<void(const MalformedQuery&)>& on_malformed = {});

/// The join of a table of queries (read_sites_ogr of a point layer: its sites and rejected rows,
/// merged in row order; a rejected row is a malformed query with its row and reason, and its
/// fields are unknown), as CSV text to write(). query_id is the table's query_id column if it
/// has one, else the row's id (SiteTable rules: the id column, else the row number).
/// options.columns and block_bytes do not apply.
/// @exception Error(InvalidArgument) for an unknown site field; whatever write() throws.
NearestJoinReport nearest_join(const SiteIndex& index, const SiteTable& queries, const NearestJoinOptions& options,
                               const std::function<void(std::string_view)>& write,
                               const std::function<void(const MalformedQuery&)>& on_malformed = {});

/// The join of a table of queries as point features (as the stream's), finishing the writer.
NearestJoinReport nearest_join(const SiteIndex& index, const SiteTable& queries, const NearestJoinOptions& options,
                               const OpenJoinWriter& open,
                               const std::function<void(const MalformedQuery&)>& on_malformed = {});

}  // namespace geovor
