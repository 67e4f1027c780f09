#include "geovor/geo/site_reader.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <functional>

#include "geovor/core/ascii.hpp"
#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/csv_site_scan.hpp"
#include "geo/trim.hpp"

namespace geovor {
namespace {

bool same_name(std::string_view column, std::string_view name) { return ascii_iequals(trim(column), trim(name)); }

}  // namespace

// Both read in two stages (csv_site_scan.hpp), one after the other.
SiteTable read_sites_csv(std::istream& in, const std::string& source, const SiteReaderOptions& options) {
  return CsvSiteScan::read(in, source, options).finish();
}

SiteTable read_sites_csv_file(const std::string& path, const SiteReaderOptions& options) {
  return CsvSiteScan::open(path, options).finish();
}

void require_sites(const SiteTable& table) {
  if (!table.sites.empty()) return;
  std::string message = table.source + ": no usable site (" + std::to_string(table.rows_read) + " rows, " +
                        std::to_string(table.rejected.size()) + " rejected)";
  if (table.rows_read == 0) message += ": the table has no data row";
  if (!table.rejected.empty()) {
    const RejectedRow& first = table.rejected.front();
    message += ": every row was rejected, the first (row " + std::to_string(first.row) + ") for " + first.reason;
    // Metres in degree columns: every rejection is a coordinate out of range.
    const bool all_out_of_range = std::all_of(table.rejected.begin(), table.rejected.end(), [](const RejectedRow& r) {
      return r.reason.find("is beyond +-90") != std::string::npos ||
             r.reason.find("is out of range [-540, 540]") != std::string::npos;
    });
    if (all_out_of_range) message += "; projected coordinates (metres)? give their CRS with --s-srs";
  }
  throw Error(ErrorCode::BadData, message);
}

std::vector<Vec3> site_points(const SiteTable& table) {
  std::vector<Vec3> points;
  points.reserve(table.sites.size());
  for (const InputSite& s : table.sites) points.push_back(s.unit);
  return points;
}

DuplicateIds find_duplicate_ids(const SiteTable& table) {
  DuplicateIds out;
  if (table.id_column < 0) return out;
  // Open addressing, no allocation per id: a slot holds the id's first site and the high half of
  // its hash, so that a probe reads another site's id (a cache miss) only when the halves match.
  const std::size_t n = table.sites.size();
  GEOVOR_ASSERT(n < 0xffffffffull);  // indices fit the low half, and no slot is all ones (kEmpty)
  std::size_t capacity = 16;
  while (capacity < 2 * n) capacity <<= 1;
  constexpr std::uint64_t kEmpty = ~std::uint64_t{0}, kTag = 0xffffffff00000000ull, kIndex = 0xffffffffull;
  std::vector<std::uint64_t> slots(capacity, kEmpty);
  const std::hash<std::string_view> hash;
  // The slots are scattered over megabytes: each is requested a few ids ahead of its probe.
  constexpr std::size_t kAhead = 8;
  std::uint64_t ahead[kAhead];
  for (std::size_t i = 0; i < std::min(n, kAhead); ++i) {
    ahead[i] = hash(table.sites[i].id);
    __builtin_prefetch(&slots[ahead[i] & (capacity - 1)]);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::string& id = table.sites[i].id;
    const std::uint64_t full = ahead[i % kAhead];
    if (i + kAhead < n) {
      ahead[i % kAhead] = hash(table.sites[i + kAhead].id);
      __builtin_prefetch(&slots[ahead[i % kAhead] & (capacity - 1)]);
    }
    const std::uint64_t tag = full & kTag;
    std::size_t h = full & (capacity - 1);
    while (slots[h] != kEmpty &&
           ((slots[h] & kTag) != tag || table.sites[slots[h] & kIndex].id != id))
      h = (h + 1) & (capacity - 1);
    if (slots[h] == kEmpty) {
      slots[h] = tag | i;
      continue;
    }
    ++out.rows;
    auto e = std::find_if(out.examples.begin(), out.examples.end(), [&](const auto& x) { return x.id == id; });
    if (e == out.examples.end() && out.examples.size() < 3) {
      out.examples.push_back({id, {table.sites[slots[h] & kIndex].row}});
      e = out.examples.end() - 1;
    }
    if (e != out.examples.end() && e->rows.size() < 3) e->rows.push_back(table.sites[i].row);
  }
  return out;
}

int find_column(const std::vector<std::string>& columns, std::string_view name) {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (same_name(columns[i], name)) return static_cast<int>(i);
  }
  return -1;
}

int find_column(const std::vector<std::string>& columns, std::span<const std::string_view> names) {
  for (const auto name : names) {
    if (const int c = find_column(columns, name); c >= 0) return c;
  }
  return -1;
}

}  // namespace geovor
