#include "geovor/relax/capacities.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <iterator>

#include "geovor/core/error.hpp"

namespace geovor {
namespace {

constexpr const char* kEmpty = "empty: a site needs a positive capacity";

// Rejected rows of both lists in row order.
std::vector<RejectedRow> merge_rejected(const std::vector<RejectedRow>& a, const std::vector<RejectedRow>& b) {
  std::vector<RejectedRow> all;
  std::merge(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(all),
             [](const RejectedRow& x, const RejectedRow& y) { return x.row < y.row; });
  return all;
}

}  // namespace

std::string parse_capacity(const std::string& text, bool decimal_comma, double& value) {
  std::string s = text;
  s.erase(0, s.find_first_not_of(" \t"));
  s.erase(s.find_last_not_of(" \t") + 1);
  if (s.empty()) return kEmpty;
  if (decimal_comma && std::count(s.begin(), s.end(), ',') == 1 && s.find('.') == std::string::npos)
    std::replace(s.begin(), s.end(), ',', '.');
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data() + (s[0] == '+'), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) return "\"" + s + "\" is not a number";
  if (!(value > 0)) return "capacity " + s + " is not positive";
  return {};
}

CapacityReport read_capacities(SiteTable& table, const std::string& column) {
  CapacityReport report;
  if (column.empty()) {
    report.capacities.assign(table.sites.size(), 1.0);
    return report;
  }
  const int found = find_column(table.columns, column);
  if (found < 0) {
    std::string names;
    for (const std::string& c : table.columns) names += (names.empty() ? "" : ", ") + c;
    throw Error(ErrorCode::InvalidArgument, table.source + ": no capacity column '" + column + "' (columns: " + names + ")");
  }
  const auto c = static_cast<std::size_t>(found);
  std::vector<InputSite> kept;
  for (InputSite& s : table.sites) {
    double value = 0;
    const std::string reason = c < s.fields.size() ? parse_capacity(s.fields[c], table.delimiter != ',', value) : kEmpty;
    if (reason.empty()) {
      kept.push_back(std::move(s));
      report.capacities.push_back(value);
    } else {
      report.rejected.push_back({s.row, s.line, table.columns[c] + ": " + reason});
    }
  }
  table.sites = std::move(kept);
  table.rejected = merge_rejected(table.rejected, report.rejected);
  return report;
}

}  // namespace geovor
