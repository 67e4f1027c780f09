#include "nearest_service.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string_view>
#include <vector>

#include "geovor/core/ascii.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/io/json_text.hpp"
#include "geovor/io/number_format.hpp"
#include "geovor/locate/knn.hpp"
#include "geovor/locate/locator.hpp"

namespace geovor::service {
namespace {

// A parameter's problem: thrown inside nearest(), answered as 400.
struct BadParameter {
  std::string parameter, why;
};

constexpr const char* kKnown[] = {"lat", "lon", "k", "metric", "max_distance_m", "fields"};

// The one value of a parameter, or none; a repeated one is an error.
std::optional<std::string> single(const Params& params, const std::string& name) {
  const auto [first, last] = params.equal_range(name);
  if (first == last) return std::nullopt;
  if (std::next(first) != last) throw BadParameter{name, "given more than once"};
  return first->second;
}

double number(const std::string& name, const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(begin, &end);
  if (text.empty() || end != begin + text.size() || !std::isfinite(v) || errno == ERANGE)
    throw BadParameter{name, "'" + printable(text) + "' is not a finite number"};
  return v;
}

void append_real(std::string& out, double v) {
  char buf[40];
  out.append(buf, format_real(buf, v));
}

}  // namespace

Response error_response(int status, const std::string& why, const std::optional<std::string>& parameter) {
  Response r;
  r.status = status;
  r.content_type = "application/json";
  r.body = "{\"error\":";
  append_json_string(r.body, why);
  if (parameter) {
    r.body += ",\"parameter\":";
    append_json_string(r.body, *parameter);
  }
  r.body += "}";
  return r;
}

NearestService::NearestService(SiteIndex index, ServiceOptions options)
    : index_(std::move(index)), options_(options) {
  index_.hierarchy.walk_graph(0);  // the packed copy the Locators share, built once now
}

Response NearestService::health() const {
  Response r;
  r.content_type = "application/json";
  r.body = "{\"status\":\"ok\",\"sites\":" + std::to_string(index_.hierarchy.base().num_sites()) + "}";
  return r;
}

Response NearestService::nearest(const Params& params) const {
  try {
    for (const auto& [name, value] : params) {
      if (name.empty()) throw BadParameter{"", "a parameter without a name (\"&&\" or \"=value\")"};
      bool known = false;
      for (const char* k : kKnown) known = known || name == k;
      if (!known) throw BadParameter{name, "unknown parameter; /nearest takes lat, lon, k, metric, max_distance_m, fields"};
    }
    const std::optional<std::string> lat_text = single(params, "lat"), lon_text = single(params, "lon");
    if (!lat_text) throw BadParameter{"lat", "missing"};
    if (!lon_text) throw BadParameter{"lon", "missing"};
    double lat = number("lat", *lat_text), lon = number("lon", *lon_text);
    if (const std::string why = normalize_lat_lon(lat, lon); !why.empty())
      throw BadParameter{lat < -90 || lat > 90 ? "lat" : "lon", why};
    std::size_t k = 1;
    if (const auto t = single(params, "k")) {
      const double v = number("k", *t);
      if (v != std::floor(v) || v < 1 || v > static_cast<double>(options_.max_k))
        throw BadParameter{"k", "'" + printable(*t) + "' is not an integer in 1.." + std::to_string(options_.max_k)};
      k = static_cast<std::size_t>(v);
    }
    Metric metric = default_metric(index_.hierarchy);
    if (const auto t = single(params, "metric")) {
      try {
        metric = parse_metric(*t);
        check_metric(index_.hierarchy, metric);
      } catch (const Error& e) {
        throw BadParameter{"metric", e.what()};
      }
    }
    double max_distance_m = INFINITY;
    if (const auto t = single(params, "max_distance_m")) {
      max_distance_m = number("max_distance_m", *t);
      if (max_distance_m < 0) throw BadParameter{"max_distance_m", "must be at least 0"};
    }
    const SiteAttributes& a = index_.attributes;
    std::vector<std::size_t> columns;
    if (const auto t = single(params, "fields")) {
      std::string_view rest = *t;
      while (!rest.empty()) {
        const std::size_t comma = rest.find(',');
        const std::string name(rest.substr(0, comma));
        rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
        std::size_t c = 0;
        while (c < a.columns.size() && !ascii_iequals(a.columns[c], name)) ++c;
        if (c == a.columns.size()) throw BadParameter{"fields", "no site column '" + printable(name) + "'"};
        columns.push_back(c);
      }
    } else {
      for (std::size_t c = 0; c < a.columns.size(); ++c) columns.push_back(c);
    }

    Locator locator(index_.hierarchy);
    locator.prepare();
    std::vector<NearestResult> found;
    nearest_within(locator, lat, lon, k, metric, max_distance_m, found);

    Response r;
    r.body = "{\"type\":\"FeatureCollection\",\"features\":[";
    std::size_t rank = 0;
    for (const NearestResult& n : found) {
      const SiteAttributes::Row& row = a.rows[a.site_rows[n.site]];
      if (rank > 0) r.body += ",";
      r.body += "{\"type\":\"Feature\",\"geometry\":{\"type\":\"Point\",\"coordinates\":[";
      append_real(r.body, row.lon_deg);
      r.body += ",";
      append_real(r.body, row.lat_deg);
      r.body += "]},\"properties\":{\"site_index\":" + std::to_string(n.site) + ",\"site_id\":";
      append_json_string(r.body, a.site_id(n.site));
      r.body += ",\"rank\":" + std::to_string(++rank) + ",\"distance_m\":";
      append_real(r.body, n.dist_m);
      for (const std::size_t c : columns) {
        r.body += ",";
        append_json_string(r.body, a.columns[c]);
        r.body += ":";
        append_json_string(r.body, a.field(a.site_rows[n.site], c));
      }
      r.body += "}}";
    }
    r.body += "]}";
    return r;
  } catch (const BadParameter& bad) {
    return error_response(400, bad.parameter.empty() ? bad.why : bad.parameter + ": " + bad.why, bad.parameter);
  }
}

}  // namespace geovor::service
