// Fuzz target: arbitrary bytes as a CSV site table (read_sites_csv, with lat/lon detection and
// with ECEF columns X,Y,Z). The reader must return a table or throw geovor::Error; every data
// row must be a site or a rejected row (checked against CsvReader's count of records), each
// site a valid position; small tables are triangulated and validated with their report.
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
#include "geovor/geo/site_reader.hpp"

namespace {

using namespace geovor;

// Records of the text after the header, as CsvReader counts them (the independent count).
std::uint64_t csv_records(const std::string& text) {
  std::istringstream in(text);
  CsvReader reader(in);
  std::vector<std::string> fields;
  std::uint64_t n = 0;
  while (reader.next(fields)) ++n;
  return n > 0 ? n - 1 : 0;
}

void check_table(const SiteTable& t, const std::string& text) {
  FUZZ_CHECK(t.rows_read == t.sites.size() + t.rejected.size(), "rows %llu, sites %zu, rejected %zu",
             static_cast<unsigned long long>(t.rows_read), t.sites.size(), t.rejected.size());
  const std::uint64_t records = csv_records(text);
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

void read(const std::string& text, const SiteReaderOptions& options) {
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
