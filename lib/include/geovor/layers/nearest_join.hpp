/// \file nearest_join.hpp
/// \brief The nearest-site join (`geovor nearest`): every query of a CSV stream joined to its
/// nearest site (or k nearest) of a SiteIndex, written as CSV in the input's order.
///
/// Input: query lines `lat,lon[,id]` with or without a header (geo/query_line.hpp), an optional
/// UTF-8 byte order mark, LF or CRLF line ends, empty lines skipped (but counted). Output: the
/// header `query_id,site_index,site_id,distance_m` (with options.rank_column:
/// `query_id,rank,site_index,site_id,distance_m`), then one row per answer, nearest first:
/// query_id is the query's id column or its line number, site_id the site's id (its first row's,
/// SiteAttributes::site_id), both CSV-quoted when they hold a comma, a quote or a line break, and
/// distance_m the shortest round-trip decimal of the distance (std::to_chars). Memory is constant
/// in the number of queries.
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
  /// DEFAULT: Metric::Sphere.
  Metric metric = Metric::Sphere;
  /// The locators' options (strategy). DEFAULT: LocatorOptions{} (Keep, Jump & Climb).
  LocatorOptions locator;
  /// Worker threads; 0 means one per core. At most 4 per core are started (more would only
  /// queue for the cores, each holding blocks); fewer when the system refuses threads. DEFAULT: 1.
  unsigned threads = 1;
  /// Stop at the first malformed line (the answers before it are written). DEFAULT: false.
  bool strict = false;
  /// Bytes per block, the unit read, answered by one worker and written at once (a longer line
  /// makes a longer block). DEFAULT: 1 MiB.
  std::size_t block_bytes = std::size_t{1} << 20;
};

/// A query line that is not a query: a data problem, reported as a value.
struct MalformedQuery {
  std::uint64_t line = 0;  ///< 1-based line number in the stream
  std::string reason;      ///< QueryLineParser's reason, e.g. "lat: 'abc' is not a number"
};

/// What nearest_join did.
struct NearestJoinReport {
  std::uint64_t answered = 0;   ///< queries answered (their rows are written)
  std::uint64_t malformed = 0;  ///< malformed lines (each passed to on_malformed)
  bool stopped = false;         ///< options.strict and a malformed line: nothing after it is read
};

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

}  // namespace geovor
