/// \file csv_site_scan.hpp
/// \brief CsvSiteScan: a CSV table of sites read in two stages, so that a caller can start on
/// the positions (the triangulation) on one core while the rows' strings are made on another.
///
/// open()/read() read the whole input into one buffer, split it at record boundaries into one
/// chunk per thread (a chunk never starts inside a quoted field nor between the CR and LF of a
/// CRLF), tokenise each chunk on its own thread and locate its rows there (numbers parsed,
/// normalize_lat_lon, unit vectors), then number rows and lines by prefix sums. Quoted fields are
/// decoded in place in the buffer, so that every row's fields stay one byte range. finish() makes
/// the InputSites' strings from those byte ranges without tokenising again.
///
/// The result is the same, field by field, as the streaming reader that came before (CsvReader
/// record by record; tests/support/reference_site_reader.cpp keeps it as the oracle) on the
/// comma-delimited UTF-8 tables that reader knew: the CSV dialect of csv_reader.hpp, the columns,
/// reasons, row and line numbers of site_reader.hpp. What came after it (site_reader.hpp): the
/// sniffed delimiter (a template argument of the tokeniser, so ',' costs what it did), decimal
/// commas, --encoding, the UTF-8 check (the raw text of each chunk checked once, a record field
/// by field only when it holds an invalid byte), the header's checks and the column ranks.
///
/// Costs on the 171,075 GeoNames cities (5.6 MB; geovor_bench_csv_read, 2 cores): open() with 2
/// threads 14 ms when the second core is free (1 ms reading, 12-13 ms tokenising and locating on
/// each thread, mostly from_chars and the ellipsoid's trigonometry; 0.7 ms joining the
/// positions), ~25 ms on one thread; finish() 13-14 ms on one thread (a vector of field strings
/// and an id per site, and the sites' fresh pages). The streaming reader took 42-45 ms in the same
/// process. Memory: the input's bytes, plus per accepted row 48 bytes until finish() returns and
/// 24 bytes (positions()) until the scan is destroyed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/geo/site_reader.hpp"

namespace geovor {

/// How open()/read() split the input between threads; only tests need to change it.
struct CsvScanTuning {
  /// The least bytes of data rows per thread: a smaller input uses fewer threads.
  /// DEFAULT: 256 KiB (starting a thread costs about as much as tokenising ~100 KB).
  std::size_t min_chunk_bytes = std::size_t{1} << 18;
  /// If not empty: byte offsets in the input (BOM and header included) where chunks should start,
  /// each moved forward to the next record start; options.threads is then ignored. Lets tests put
  /// a chunk boundary at every byte.
  std::vector<std::size_t> cuts;
};

/// A CSV table of sites read in two stages: open() reads and tokenises the whole input and
/// locates every row (positions, rejections); finish() makes the rows' strings. A caller can
/// start on positions() (the triangulation) while finish() runs on another core.
class CsvSiteScan {
 public:
  /// Reads `path` ("-": standard input, source "<stdin>") on up to options.threads threads.
  /// \throw Error exactly as read_sites_csv_file (unreadable file, empty file, bad header or
  ///   columns, bad options); never for a single row's problem.
  static CsvSiteScan open(const std::string& path, const SiteReaderOptions& options = {},
                          const CsvScanTuning& tuning = {});
  /// Same, from a stream read to its end (as read_sites_csv); `source` names it in messages.
  static CsvSiteScan read(std::istream& in, const std::string& source,
                          const SiteReaderOptions& options = {}, const CsvScanTuning& tuning = {});

  CsvSiteScan(CsvSiteScan&&) noexcept;
  CsvSiteScan& operator=(CsvSiteScan&&) noexcept;
  ~CsvSiteScan();

  /// The accepted rows' unit vectors, in row order: finish().sites[i].unit. Valid until the scan
  /// is destroyed (finish() does not touch them), so a triangulation may read them meanwhile.
  std::span<const Vec3> positions() const { return positions_; }

  /// Data rows seen (accepted and rejected); known after open().
  std::uint64_t rows_read() const;

  /// The complete table, equal field by field to the streaming reader's. Call once; it reads
  /// positions() but does not change them, so it may run while other threads read them.
  /// Single-threaded: per site one vector of field strings copied from the buffer, and the id;
  /// frees the buffer and the per-row data of open() before it returns.
  SiteTable finish() &&;

 private:
  struct State;
  explicit CsvSiteScan(std::unique_ptr<State> state);
  // open()'s work once the input is read: header, chunks, threads, numbering.
  void scan(const SiteReaderOptions& options, const CsvScanTuning& tuning);

  std::unique_ptr<State> state_;
  std::vector<Vec3> positions_;
};

}  // namespace geovor
