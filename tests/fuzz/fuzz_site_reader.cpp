// Fuzz target: arbitrary bytes as a CSV site table (read_sites_csv, with lat/lon detection and
// with ECEF columns X,Y,Z). The reader must return a table or throw geovor::Error; every data
// row must be a site or a rejected row (checked against CsvReader's count of records), each
// site a valid position; small tables are triangulated and validated with their report.
// CsvSiteScan on 3 threads with chunks of any size must give what it gives on one thread in one
// chunk, member by member, or the same error. (The streaming reader it replaced,
// tests/support/reference_site_reader.cpp, knows neither sniffed delimiters, decimal commas,
// ranked column names nor header checks; csv_site_scan_test compares the two where it applies.)
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_check.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/csv_reader.hpp"
#include "geovor/geo/csv_site_scan.hpp"
#include "geovor/geo/site_reader.hpp"

namespace {

using namespace geovor;

// Records of the text after the header, as CsvReader counts them with the table's delimiter (the
// independent count; a quote is special only at a field's start, which the delimiter decides).
std::uint64_t csv_records(const std::string& text, char delimiter) {
  std::istringstream in(text);
  CsvReader reader(in, delimiter);
  std::vector<std::string> fields;
  std::uint64_t n = 0;
  while (reader.next(fields)) ++n;
  return n > 0 ? n - 1 : 0;
}

void check_table(const SiteTable& t, const std::string& text) {
  FUZZ_CHECK(t.rows_read == t.sites.size() + t.rejected.size(), "rows %llu, sites %zu, rejected %zu",
             static_cast<unsigned long long>(t.rows_read), t.sites.size(), t.rejected.size());
  const std::uint64_t records = csv_records(text, t.delimiter);
  FUZZ_CHECK(t.rows_read == records, "rows %llu, CsvReader records %llu", static_cast<unsigned long long>(t.rows_read),
             static_cast<unsigned long long>(records));
  // Rows 1..rows_read, each exactly once, in order within each list.
  std::vector<char> seen(t.rows_read + 1, 0);
  std::uint64_t prev = 0, prev_line = 0;
  for (const InputSite& s : t.sites) {
    FUZZ_CHECK(s.row > prev && s.row <= t.rows_read && !seen[s.row], "site row %llu", static_cast<unsigned long long>(s.row));
    FUZZ_CHECK(s.line > prev_line, "site line %llu", static_cast<unsigned long long>(s.line));
    seen[s.row] = 1;
    prev = s.row;
    prev_line = s.line;
    FUZZ_CHECK(std::isfinite(s.lat_deg) && std::fabs(s.lat_deg) <= 90, "latitude %.17g", s.lat_deg);
    FUZZ_CHECK(std::isfinite(s.lon_deg) && s.lon_deg >= -180 && s.lon_deg < 180, "longitude %.17g", s.lon_deg);
    const double r2 = norm2(s.unit);
    FUZZ_CHECK(std::isfinite(r2) && std::fabs(r2 - 1) <= 0x1p-49, "|unit|^2 - 1 = %g", r2 - 1);
    FUZZ_CHECK(!s.id.empty() || t.id_column >= 0, "empty id without an id column");
  }
  prev = 0;
  for (const RejectedRow& r : t.rejected) {
    FUZZ_CHECK(r.row > prev && r.row <= t.rows_read && !seen[r.row], "rejected row %llu",
               static_cast<unsigned long long>(r.row));
    FUZZ_CHECK(!r.reason.empty() && r.line >= 1, "rejected row %llu without a reason or line",
               static_cast<unsigned long long>(r.row));
    seen[r.row] = 1;
    prev = r.row;
  }
  // Every row is accounted for; small tables go through the triangulation too.
  if (t.sites.size() > 64) return;
  std::vector<Vec3> points;
  for (const InputSite& s : t.sites) points.push_back(s.unit);
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(points, {}, &report);
  const Validation v = dt.validate(&report, true);
  FUZZ_CHECK(v.ok(), "%s", v.errors.front().c_str());
  FUZZ_CHECK(dt.num_sites() + report.merges.size() == points.size(), "%zu sites + %zu merges != %zu points",
             dt.num_sites(), report.merges.size(), points.size());
}

// The first difference between two tables, or "" if every member is equal.
std::string difference(const SiteTable& a, const SiteTable& b) {
  if (a.source != b.source || a.columns != b.columns || a.delimiter != b.delimiter || a.lat_column != b.lat_column ||
      a.lon_column != b.lon_column || a.id_column != b.id_column || a.ecef_columns != b.ecef_columns ||
      a.rows_read != b.rows_read) {
    return "header or rows_read";
  }
  if (a.sites.size() != b.sites.size()) return "number of sites";
  auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
  for (std::size_t i = 0; i < a.sites.size(); ++i) {
    const InputSite& s = a.sites[i];
    const InputSite& t = b.sites[i];
    if (s.row != t.row || s.line != t.line || s.id != t.id || bits(s.lat_deg) != bits(t.lat_deg) ||
        bits(s.lon_deg) != bits(t.lon_deg) || bits(s.height_m) != bits(t.height_m) || !(s.unit == t.unit) ||
        s.fields != t.fields) {
      return "site " + std::to_string(i);
    }
  }
  if (a.rejected.size() != b.rejected.size()) return "number of rejected rows";
  for (std::size_t i = 0; i < a.rejected.size(); ++i) {
    const RejectedRow& r = a.rejected[i];
    const RejectedRow& q = b.rejected[i];
    if (r.row != q.row || r.line != q.line || r.reason != q.reason) return "rejected row " + std::to_string(i);
  }
  return "";
}

// CsvSiteScan on `threads` threads with chunks of `min_chunk_bytes` (0: the default): the table,
// or the error as "code message".
std::string scan(const std::string& text, const SiteReaderOptions& base, unsigned threads, std::size_t min_chunk_bytes,
                 SiteTable& table) {
  try {
    std::istringstream in(text);
    SiteReaderOptions options = base;
    options.threads = threads;
    CsvScanTuning tuning;
    if (min_chunk_bytes > 0) tuning.min_chunk_bytes = min_chunk_bytes;
    table = CsvSiteScan::read(in, "fuzz.csv", options, tuning).finish();
    return "";
  } catch (const Error& e) {
    return std::to_string(static_cast<int>(e.code())) + " " + e.what();
  }
}

// Three threads and tiny chunks against one thread and one chunk: the same table or error.
void compare_chunkings(const std::string& text, const SiteReaderOptions& base) {
  SiteTable want, got;
  const std::string want_error = scan(text, base, 1, 0, want);
  const std::string got_error = scan(text, base, 3, 1, got);
  FUZZ_CHECK(got_error == want_error, "3 threads: error '%s', 1 thread '%s'", got_error.c_str(), want_error.c_str());
  if (want_error.empty()) {
    const std::string d = difference(got, want);
    FUZZ_CHECK(d.empty(), "3 threads and tiny chunks differ from one thread at %s", d.c_str());
  }
}

void read(const std::string& text, const SiteReaderOptions& options) {
  compare_chunkings(text, options);
  std::istringstream in(text);
  SiteTable table;
  try {
    table = read_sites_csv(in, "fuzz.csv", options);
  } catch (const Error& e) {
    FUZZ_CHECK(e.code() != ErrorCode::Internal, "%s", e.what());
    return;  // a table that cannot be used at all: a clean error
  }
  check_table(table, text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  read(text, {});
  SiteReaderOptions ecef;
  ecef.ecef_fields = {"X", "Y", "Z"};
  read(text, ecef);
  return 0;
}
