/// \file site_input.hpp
/// \brief The sites of a job (every geovor command that reads sites, the service): where they
/// come from, how they are read, how they are built into a triangulation or a nearest-site
/// index, and what became of their rows, said on a log stream (row_accounting.hpp).
///
/// Reading: a CSV table or any OGR point layer (read_sites(); read_sites_ogr() when a layer is
/// named), then the radii of weighted sites (read_site_weights()). The rejected rows are listed
/// on the log, then a table without a site is Error(BadData) (require_sites()), then repeated ids
/// are said once. Building: each merged row is listed on the log unless `quiet`, each hidden
/// weighted site always (an empty cell must not pass unseen). StagedSiteInput
/// (staged_site_input.hpp) reads the same table in two stages.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <string>

#include "geovor/core/types.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/locate/index_file.hpp"

namespace geovor {

/// Where the sites come from, how they are read and built, and where their rows are accounted for.
struct SiteInput {
  /// A site table: CSV with a header ("-": standard input; any stream is read as CSV) or any OGR
  /// point layer (is_csv_site_path() tells them apart).
  std::string input;
  /// The columns, types, encoding and coordinate system (site_reader.hpp).
  SiteReaderOptions reader;
  /// The layer of a multi-layer OGR source; "" (DEFAULT) for the only one. A CSV input has one
  /// table: a layer is then Error(InvalidArgument).
  std::string layer;
  /// The column of weighted sites' radii in metres (read_site_weights()); "" (DEFAULT): unweighted.
  std::string weight_field;
  /// Merge sites closer than this many metres (DelaunayOptions::merge_distance, never below
  /// SphericalDelaunay::kMinSeparation); 0 (DEFAULT): the minimum separation, 0.38 m.
  double merge_m = 0;
  /// Where the rows are accounted for (row_accounting.hpp); null: nowhere. DEFAULT: stderr.
  std::FILE* log = stderr;
  /// Leave the merged rows out of the log (they stay in every count). DEFAULT: false.
  bool quiet = false;
  /// What the caller's users call `layer` and SiteReaderOptions::id_field, in messages (the geovor
  /// command: --layer, --id-field). DEFAULT: the names of the library's options.
  std::string layer_name = "layer", id_field_name = "id_field";
};

/// Whether reading the sites needs GDAL: a layer, a coordinate system (reader.s_srs), or an input
/// that is not CSV.
bool site_input_needs_gdal(const SiteInput& input);

/// Refuses a layer for a CSV input, naming input.layer_name: "INPUT: layer is for OGR sources; a CSV
/// file has one table". @exception Error(InvalidArgument).
void check_site_input(const SiteInput& input);

/// Reads the sites (the file comment), `duplicates` (optional) getting the ids that repeat.
/// @exception Error as check_site_input(), the readers and read_site_weights(); Error(BadData) when
///   no site remains (require_sites(), after the rejected rows are listed).
SiteTable read_site_input(const SiteInput& input, DuplicateIds* duplicates = nullptr);

/// DelaunayOptions with the merge distance of input.merge_m.
DelaunayOptions delaunay_options(const SiteInput& input);

/// The triangulation of `points` with delaunay_options(input), weighted when `lifts` is not empty
/// (SphericalDelaunay::build).
SphericalDelaunay build_sites(std::span<const Vec3> points, std::span<const double> lifts, const SiteInput& input,
                              BuildReport& report);

/// Lists what the build of `table`'s sites did on input.log: the merged rows (unless input.quiet),
/// then the hidden sites.
void list_build(const SiteInput& input, const SiteTable& table, const BuildReport& report);

/// What build_index_from_table() read and built, for a summary.
struct TableBuild {
  std::string source;
  std::uint64_t rows = 0, sites = 0, merged = 0, rejected = 0;
  std::optional<std::uint64_t> hidden;  ///< weighted sites only
  double read_seconds = 0, build_seconds = 0;
};

/// Reads the sites (read_site_input()), builds their nearest-site index (build_site_index() with
/// delaunay_options(input)) and lists the build on the log (list_build()); `summary` (optional)
/// gets the counts and times. @exception as read_site_input() and build_site_index().
SiteIndex build_index_from_table(const SiteInput& input, TableBuild* summary = nullptr);

/// The index of input.input: load_index() of an index file (is_index_path(), `threads` loading it),
/// else build_index_from_table().
SiteIndex load_site_index(const SiteInput& input, unsigned threads = 1);

}  // namespace geovor
