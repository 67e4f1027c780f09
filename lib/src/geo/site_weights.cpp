#include "geovor/geo/site_weights.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string_view>

#include "geo/trim.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor {
namespace {

// The radius in `text`, or the reason it is none (without the column's name).
std::string parse_radius(std::string_view text, bool decimal_comma, double& r_m) {
  const std::string_view t = trim(text);
  if (t.empty()) return "empty: a weighted site needs its radius in metres";
  std::string s(t);
  if (decimal_comma && std::count(s.begin(), s.end(), ',') == 1 && s.find('.') == std::string::npos)
    std::replace(s.begin(), s.end(), ',', '.');
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data() + (s[0] == '+'), end, r_m);
  if (ec != std::errc() || ptr != end || !std::isfinite(r_m)) return "\"" + std::string(t) + "\" is not a number";
  if (std::string why = radius_problem(r_m); !why.empty()) return why;
  r_m += 0.0;  // -0 is 0
  return {};
}

}  // namespace

double site_lift(double r_m) { return std::cos(r_m / SiteEncoder::kEarthRadiusM); }

std::string radius_problem(double r_m) {
  if (std::isfinite(r_m) && r_m >= 0 && r_m < max_site_radius_m()) return {};
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", r_m);
  return "radius " + std::string(text) + " m is outside [0, " + std::to_string(max_site_radius_m()) +
         ") (a quarter of the circumference)";
}

double max_site_radius_m() { return std::numbers::pi / 2 * SiteEncoder::kEarthRadiusM; }

void read_site_weights(SiteTable& table, const std::string& field) {
  const int column = find_column(table.columns, field);
  if (column < 0) {
    std::string names;
    for (const std::string& c : table.columns) names += (names.empty() ? "" : ", ") + c;
    throw Error(ErrorCode::InvalidArgument,
                table.source + ": no weight column '" + field + "' (columns: " + names + ")");
  }
  table.weighted = true;
  const bool decimal_comma = table.delimiter != ',';
  std::vector<InputSite> kept;
  std::vector<RejectedRow> rejected;
  kept.reserve(table.sites.size());
  for (InputSite& s : table.sites) {
    const auto c = static_cast<std::size_t>(column);
    std::string reason = c < s.fields.size() ? parse_radius(s.fields[c], decimal_comma, s.weight_m)
                                             : std::string("empty: a weighted site needs its radius in metres");
    if (reason.empty())
      kept.push_back(std::move(s));
    else
      rejected.push_back({s.row, s.line, table.columns[c] + ": " + std::move(reason)});
  }
  if (rejected.empty()) {
    table.sites = std::move(kept);
    return;
  }
  table.sites = std::move(kept);
  std::vector<RejectedRow> all;
  all.reserve(table.rejected.size() + rejected.size());
  std::merge(table.rejected.begin(), table.rejected.end(), rejected.begin(), rejected.end(), std::back_inserter(all),
             [](const RejectedRow& a, const RejectedRow& b) { return a.row < b.row; });
  table.rejected = std::move(all);
}

std::vector<double> site_lifts(const SiteTable& table) {
  std::vector<double> lifts;
  lifts.reserve(table.sites.size());
  for (const InputSite& s : table.sites)
    lifts.push_back(site_lift(s.weight_m));
  return lifts;
}

}  // namespace geovor
