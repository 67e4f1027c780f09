/// \file index_file.hpp
/// \brief A built nearest-site index (the DelaunayHierarchy and the attributes of its sites),
/// saved to and loaded from a binary file (`geovor index`, `geovor nearest --sites FILE.gvi`).
///
/// File format, version 1, and version 2 for weighted sites (docs/weighted.md: version 1 plus
/// the lifts and the hidden sites, so that a geovor reading only version 1 refuses weights rather
/// than answer without them). Every integer and double is little-endian (IEEE 754 doubles).
///
///     offset  size  field
///          0     8  magic "GEOVORIX"
///          8     4  u32 format version (1; 2 with weighted sites)
///         12     4  u32 number of sections S
///         16     8  u64 file size in bytes
///         24     8  u64 header checksum: XXH64 (seed 0) of bytes 0..32 + 32 S with this field
///                   zeroed (the header and the section table)
///         32  32 S  section table, one entry per section:
///                   u32 kind, u32 level, u64 offset, u64 size (bytes), u64 XXH64 of the bytes
///
/// The sections follow the table in the table's order, each at the next multiple of 8 bytes
/// (zero padding), the last one ending at the file size. Kinds (level is 0 unless said):
///
///     1  meta, 80 bytes: u32 levels, u32 ratio, u32 max_levels, u32 flags (bit 0 spatial_sort,
///        bit 1 brio, bit 2 weighted sites: version 2), u64 hierarchy seed, u64 delaunay seed, f64 merge distance (unit sphere),
///        u64 rows read, u64 rows rejected, i32 id column (-1: row numbers), u32 columns,
///        u64 rows, u64 sites (level-0 site capacity)
///     2  names: the source, then each column name; each as u64 length and the bytes
///    10  sites of a level: 3 f64 per site (unit vector)          } one of each per level,
///    11  triangles of a level: 3 u32 per triangle                } see
///    12  half-edge twins of a level: u32 per half-edge           } SphericalDelaunay::Arrays
///    13  site_edge of a level: u32 per site                      }
///    14  up links of a level: u32 per site (kNoIndex: none)      }
///    15  down links of a level >= 1: u32 per site                }
///    16  lifts of a level with weights: f64 per site (weighted: level 0, and each level above
///        whose sample has unequal lifts)
///    17  hidden sites (weighted, level 0): u32 per site, the site hiding it or kNoIndex
///    20  site rows: u64 per level-0 site + 1 (the rows of site s are [v[s], v[s+1]))
///    21  rows: per row u64 row number, u64 line, f64 lat_deg, f64 lon_deg, f64 height_m
///    22  text offsets: u64 per row and field + 1 (row r: its id, then each column's field)
///    23  text: the bytes of every id and field, concatenated
///
/// Loading checks, in this order and before allocating anything sized by the file: the magic,
/// the version, the file size against the header's, the section table against the file size,
/// the header checksum, each section's size against what the meta section implies, then each
/// section's checksum as it is read, SphericalDelaunay::from_arrays() on every level (structural
/// checks) and DelaunayHierarchy::from_parts() (links), and the attributes' offsets. Any failure
/// is Error(BadData) naming the file and the problem, e.g. "index.gvi: truncated: expected 1200
/// bytes, found 1000", "index.gvi: section 3 (triangles, level 0): checksum mismatch",
/// "index.gvi: unsupported version 7, this geovor reads 1 and 2"; never a crash, and never an
/// allocation larger than the file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/locate/delaunay_hierarchy.hpp"

namespace geovor {

/// The input rows behind the level-0 sites of an index: every accepted row of the site table,
/// grouped by site. A site's first row is the one whose position it has; the rows merged into it
/// (same position, or closer than the merge distance) follow in input order.
struct SiteAttributes {
  /// Position and numbers of one row (40 bytes, saved as is).
  struct Row {
    std::uint64_t row = 0;   ///< 1-based data row number in the source (SiteTable numbering)
    std::uint64_t line = 0;  ///< 1-based line where the row starts (0 for non-CSV sources)
    double lat_deg = 0, lon_deg = 0, height_m = 0;  ///< as read, normalised (InputSite)
  };

  std::string source;                ///< the site table the index was built from
  std::vector<std::string> columns;  ///< its header
  int id_column = -1;                ///< the id column, -1 when ids are row numbers
  std::uint64_t rows_read = 0;       ///< data rows of the source
  std::uint64_t rejected = 0;        ///< rows that were not usable (not in the index)
  /// Size num_sites() + 1: the rows of site s are [site_rows[s], site_rows[s + 1]) (empty for a
  /// removed site).
  std::vector<std::uint64_t> site_rows{0};
  std::vector<Row> rows;
  /// Size rows.size() * (1 + columns.size()) + 1: field k of row r (k = 0 the id, k = c + 1
  /// column c) is text[text_offsets[i], text_offsets[i + 1]) with i = r (1 + columns) + k.
  std::vector<std::uint64_t> text_offsets{0};
  std::string text;

  std::size_t num_sites() const { return site_rows.size() - 1; }
  std::size_t num_rows() const { return rows.size(); }
  /// The id of row r (the id column's value, or its row number as text).
  std::string_view row_id(std::size_t r) const { return text_at(r * (1 + columns.size())); }
  /// Row r's field of column c, as read.
  std::string_view field(std::size_t r, std::size_t c) const { return text_at(r * (1 + columns.size()) + 1 + c); }
  /// The id of site s: its first row's id ("" for a site without rows).
  std::string_view site_id(SiteId s) const {
    return site_rows[s] == site_rows[s + 1] ? std::string_view{} : row_id(site_rows[s]);
  }
  /// Appends a row to the last site (see make_site_attributes for the usual way to fill this).
  void append_row(const InputSite& site);

 private:
  std::string_view text_at(std::size_t i) const {
    return std::string_view(text).substr(text_offsets[i], text_offsets[i + 1] - text_offsets[i]);
  }
};

/// The attributes of the sites built from `table` (one point per table.sites entry, in order)
/// with `report` (BuildReport of that build). REQUIRES: report.site_of_input has
/// table.sites.size() entries, each below site_capacity.
SiteAttributes make_site_attributes(const SiteTable& table, const BuildReport& report,
                                    std::size_t site_capacity);

/// A nearest-site index: the hierarchy over the sites and the rows behind them.
struct SiteIndex {
  DelaunayHierarchy hierarchy;
  SiteAttributes attributes;
};

/// Builds the index of a site table: DelaunayHierarchy::build over table.sites' unit vectors
/// (with their lifts site_lifts(table) when table.weighted), then make_site_attributes. `report` (optional) receives level 0's BuildReport.
/// @exception Error as DelaunayHierarchy::build.
SiteIndex build_site_index(const SiteTable& table, const DelaunayOptions& options = {},
                           const HierarchyOptions& hierarchy = {}, BuildReport* report = nullptr);

/// The magic bytes at the start of an index file, and the one version this library reads.
inline constexpr char kIndexMagic[8] = {'G', 'E', 'O', 'V', 'O', 'R', 'I', 'X'};
inline constexpr std::uint32_t kIndexVersion = 1;

/// Saves an index to `path`: writes a temporary file in the same directory and renames it
/// (geovor/core/output_target.hpp: a short name, removed on errors and signals; without overwrite
/// the rename never replaces a file that appeared meanwhile), so `path` is either untouched or
/// complete. Empty levels at the top of the hierarchy (after
/// removals) are not saved. With overwrite false, an existing `path` is refused.
/// @exception Error(InvalidArgument) if the attributes do not have one entry per level-0 site;
///   Error(Io) if the file cannot be written, exists and overwrite is false, or is not a
///   regular file (a device or FIFO would be replaced by the rename).
void save_index(const std::string& path, const DelaunayHierarchy& hierarchy,
                const SiteAttributes& attributes, bool overwrite = false);

/// Loads an index saved by save_index, with the checks described in the file comment, on
/// `threads` threads (0: one per core; core/parallel.hpp): the sections are read and their
/// checksums checked in parallel, then each level's structure beside the others and the
/// attributes'. The result, and the error reported (the first in the order above), do not
/// depend on `threads`.
/// @exception Error(Io) if the file cannot be read; Error(BadData) if it is not a valid index.
SiteIndex load_index(const std::string& path, unsigned threads = 1);

/// True if the regular file at `path` starts with kIndexMagic (false if it cannot be read, and for
/// a pipe or FIFO, whose first bytes would be consumed).
bool is_index_file(const std::string& path);

/// Whether a path given for sites names an index file rather than a site table: is_index_file(),
/// or a name ending in .gvi (so that a missing index is said to be one); never "-".
bool is_index_path(const std::string& path);

/// XXH64 of `size` bytes (Yann Collet's xxHash, 64-bit variant), the checksum of index files.
std::uint64_t xxh64(const void* data, std::size_t size, std::uint64_t seed = 0);

}  // namespace geovor
