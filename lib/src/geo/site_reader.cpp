#include "geovor/geo/site_reader.hpp"

#include <cstddef>

#include "geovor/core/ascii.hpp"
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
