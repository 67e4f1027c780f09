/// \file nearest_join_files.hpp
/// \brief The nearest-site join (nearest_join.hpp) between files, as `geovor nearest` runs it:
/// the queries a CSV stream (a file, a pipe or standard input) or an OGR point layer; the answers
/// geovor's CSV or point features in any format, never left half-written (core/output_file.hpp,
/// the feature writers); each malformed query said on a log.
#pragma once

#include <cstdio>
#include <string>

#include "geovor/io/feature_writer.hpp"
#include "geovor/layers/nearest_join.hpp"
#include "geovor/locate/index_file.hpp"

namespace geovor {

/// Where the join reads and writes.
struct NearestJoinFiles {
  /// The queries: a CSV stream ("-", DEFAULT: standard input) or, for a path that is not CSV
  /// (is_csv_site_path()) or with a query_layer, an OGR point layer read whole.
  std::string queries = "-";
  /// The layer of a multi-layer OGR source of queries; "" (DEFAULT) for the only one.
  std::string query_layer;
  /// The answers: geovor's CSV when output_kind(output, writer.format, true) is Text ("-",
  /// DEFAULT: standard output), else point features.
  std::string output = "-";
  /// The options of the output: its format, overwrite (also for the CSV), and, for point
  /// features, the layer (DEFAULT "nearest"), update and creation options.
  WriterOptions writer = defaults();
  /// Where malformed queries are said ("SOURCE: line N: REASON"; "SOURCE: REASON" for a feature,
  /// its reason naming it); null: nowhere. DEFAULT: stderr.
  std::FILE* log = stderr;

  static WriterOptions defaults() {
    WriterOptions o;
    o.layer = "nearest";
    return o;
  }
};

/// Whether the queries are an OGR layer rather than a CSV stream (the NearestJoinFiles::queries rule).
bool queries_are_ogr(const NearestJoinFiles& files);

/// Whether the output is geovor's CSV rather than point features (the NearestJoinFiles::output rule).
bool writes_csv(const NearestJoinFiles& files);

/// The name of the queries in messages: "<stdin>" for "-", else the path.
std::string query_source(const NearestJoinFiles& files);

/// Joins files.queries to their nearest sites in `index` (nearest_join()) and writes the answers
/// to files.output, moved into place once complete (also after a strict stop: the answers before
/// the malformed query are kept). Queries read from an OGR layer take their columns from
/// options.columns and their declared types from options.query_field_types (through the reader).
/// @exception Error(Io) when the queries cannot be opened; as read_sites_ogr(), nearest_join(),
///   OutputFile and open_feature_writer().
NearestJoinReport nearest_join_files(const SiteIndex& index, const NearestJoinFiles& files,
                                     const NearestJoinOptions& options);

}  // namespace geovor
