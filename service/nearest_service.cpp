#include "nearest_service.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "geovor/core/ascii.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/io/json_text.hpp"
#include "geovor/io/number_format.hpp"
#include "geovor/io/geojson_writer.hpp"
#include "geovor/io/ogr_site_reader.hpp"
#include "geovor/layers/nearest_join.hpp"
#include "geovor/locate/knn.hpp"
#include "geovor/locate/locator.hpp"

namespace geovor::service {
namespace {

// A parameter's problem: thrown inside a handler, answered as 400.
struct BadParameter {
  std::string parameter, why;
};

// Reads a request's parameters: each known one at most once, any other refused.
class ParamReader {
 public:
  ParamReader(const Params& params, std::initializer_list<const char*> known, const char* route) : params_(params) {
    for (const auto& [name, value] : params) {
      if (name.empty()) throw BadParameter{"", "a parameter without a name (\"&&\" or \"=value\")"};
      bool is_known = false;
      for (const char* k : known) is_known = is_known || name == k;
      if (!is_known) {
        std::string list;
        for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
        throw BadParameter{name, std::string("unknown parameter; ") + route + " takes " + list};
      }
    }
  }
  // The one value of a parameter, or none; a repeated one is an error.
  std::optional<std::string> single(const std::string& name) const {
    const auto [first, last] = params_.equal_range(name);
    if (first == last) return std::nullopt;
    if (std::next(first) != last) throw BadParameter{name, "given more than once"};
    return first->second;
  }
  std::size_t k(std::size_t max_k) const {
    const auto t = single("k");
    if (!t) return 1;
    const double v = number("k", *t);
    if (v != std::floor(v) || v < 1 || v > static_cast<double>(max_k))
      throw BadParameter{"k", "'" + printable(*t) + "' is not an integer in 1.." + std::to_string(max_k)};
    return static_cast<std::size_t>(v);
  }
  Metric metric(const DelaunayHierarchy& sites) const {
    const auto t = single("metric");
    if (!t) return default_metric(sites);
    try {
      const Metric m = parse_metric(*t);
      check_metric(sites, m);
      return m;
    } catch (const Error& e) {
      throw BadParameter{"metric", e.what()};
    }
  }
  double max_distance_m() const {
    const auto t = single("max_distance_m");
    if (!t) return INFINITY;
    const double d = number("max_distance_m", *t);
    if (d < 0) throw BadParameter{"max_distance_m", "must be at least 0"};
    return d;
  }
  // The site columns named by fields (comma-separated, ASCII case-insensitively), or every one.
  std::vector<std::size_t> fields(const SiteAttributes& a) const {
    std::vector<std::size_t> columns;
    const auto t = single("fields");
    if (!t) {
      for (std::size_t c = 0; c < a.columns.size(); ++c) columns.push_back(c);
      return columns;
    }
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
    return columns;
  }
  static double number(const std::string& name, const std::string& text) {
    const char* begin = text.c_str();
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(begin, &end);
    if (text.empty() || end != begin + text.size() || !std::isfinite(v) || errno == ERANGE)
      throw BadParameter{name, "'" + printable(text) + "' is not a finite number"};
    return v;
  }

 private:
  const Params& params_;
};

Response bad_parameter_response(const BadParameter& bad) {
  return error_response(400, bad.parameter.empty() ? bad.why : bad.parameter + ": " + bad.why, bad.parameter);
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
    const ParamReader read(params, {"lat", "lon", "k", "metric", "max_distance_m", "fields"}, "GET /nearest");
    const std::optional<std::string> lat_text = read.single("lat"), lon_text = read.single("lon");
    if (!lat_text) throw BadParameter{"lat", "missing"};
    if (!lon_text) throw BadParameter{"lon", "missing"};
    double lat = ParamReader::number("lat", *lat_text), lon = ParamReader::number("lon", *lon_text);
    if (const std::string why = normalize_lat_lon(lat, lon); !why.empty())
      throw BadParameter{lat < -90 || lat > 90 ? "lat" : "lon", why};
    const std::size_t k = read.k(options_.max_k);
    const Metric metric = read.metric(index_.hierarchy);
    const double max_distance_m = read.max_distance_m();
    const SiteAttributes& a = index_.attributes;
    const std::vector<std::size_t> columns = read.fields(a);

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
    return bad_parameter_response(bad);
  }
}

}  // namespace geovor::service

namespace geovor::service {
namespace {

// The media type of a Content-Type header, lower case, without its parameters (";charset=...").
std::string media_type(std::string_view content_type) {
  std::string_view t = content_type.substr(0, content_type.find(';'));
  while (!t.empty() && t.back() == ' ') t.remove_suffix(1);
  return ascii_lower(t);
}

// The library names geovor nearest's options in a header's errors; the service names its parameters.
BadParameter query_column_error(const Error& e) {
  std::string why = e.what();
  std::string parameter;
  for (const auto& [option, name] : {std::pair{"--query-lat-field", "lat_field"}, std::pair{"--query-lon-field", "lon_field"},
                                     std::pair{"--query-id-field", "id_field"}}) {
    for (std::size_t at = why.find(option); at != std::string::npos; at = why.find(option))
      why.replace(at, std::string_view(option).size(), name);
    if (parameter.empty() && why.find(std::string(name) + " '") != std::string::npos) parameter = name;
  }
  return BadParameter{parameter, why};
}

constexpr std::size_t kMalformedListed = 100;  // malformed lines listed in a 400

// A 400 listing the first malformed lines of a POST body (their line numbers and reasons).
Response malformed_response(std::uint64_t count, const std::vector<MalformedQuery>& listed) {
  const MalformedQuery& first = listed.front();
  const bool lines = first.line > 0;  // a CSV body's lines, else a GeoJSON body's features (their reason names them)
  const char* key = lines ? "line" : "feature";
  Response r = error_response(400, "request body: " + std::to_string(count) + " malformed " + (lines ? "line" : "feature") +
                                       (count == 1 ? "" : "s") + " (nothing answered); " +
                                       (lines ? "line " + std::to_string(first.line) + ": " : "") + first.reason);
  r.body.pop_back();  // the closing brace: the lines follow
  r.body += ",\"" + std::string(key) + "\":" + std::to_string(lines ? first.line : first.row) + ",\"malformed\":[";
  for (std::size_t i = 0; i < listed.size(); ++i) {
    r.body += (i ? ",{\"" : "{\"") + std::string(key) + "\":" + std::to_string(lines ? listed[i].line : listed[i].row) + ",\"reason\":";
    append_json_string(r.body, listed[i].reason);
    r.body += "}";
  }
  r.body += "]}";
  return r;
}

}  // namespace

Response NearestService::join_points(std::string_view body, bool collection, const std::string& type,
                                     const NearestJoinOptions& options) const {
  SiteReaderOptions reader;
  reader.lat_field = options.columns.lat_field;  // attribute positions, when named
  reader.lon_field = options.columns.lon_field;
  reader.id_field = options.columns.id_field;
  SiteTable queries;
  try {
    queries = read_sites_ogr_bytes(body, "request body", collection ? ".geojson" : ".geojsonl", reader);
  } catch (const Error& e) {
    if (e.code() == ErrorCode::Internal) throw;
    return error_response(400, e.what());
  }
  if (!queries.rejected.empty()) {
    std::vector<MalformedQuery> listed;
    for (std::size_t i = 0; i < queries.rejected.size() && i < kMalformedListed; ++i)
      listed.push_back({0, queries.rejected[i].row, queries.rejected[i].reason});
    return malformed_response(queries.rejected.size(), listed);
  }
  // RFC 8142 records (RS before each) when the body has them, else one feature per line.
  const GeoJsonFraming framing = collection                ? GeoJsonFraming::FeatureCollection
                                 : body.find('\x1e') != std::string_view::npos ? GeoJsonFraming::RecordSeparated
                                                                               : GeoJsonFraming::NewlineDelimited;
  WriterOptions writer;
  writer.layer = "nearest";  // as geovor nearest
  Response r;
  r.content_type = type;
  const OpenJoinWriter open = [&](const std::vector<Field>& fields) {
    return open_geojson_writer([&r](std::string_view s) { r.body.append(s); }, framing, GeometryType::Point, fields, writer);
  };
  nearest_join(index_, queries, options, open);
  return r;
}

Response NearestService::join(const Params& params, std::string_view body, std::string_view content_type) const {
  try {
    const ParamReader read(params, {"k", "metric", "max_distance_m", "fields", "lat_field", "lon_field", "id_field"},
                           "POST /nearest");
    const std::string type = media_type(content_type);
    const bool csv = type.empty() || type == "text/csv" || type == "text/plain" || type == "application/csv" ||
                     type == "application/octet-stream";
    const bool collection = type == "application/geo+json" || type == "application/json";
    const bool sequence = type == "application/geo+json-seq" || type == "application/json-seq" ||
                          type == "application/x-ndjson" || type == "application/geojsonl";
    if (!csv && !collection && !sequence)
      return error_response(415, "Content-Type '" + printable(std::string(content_type)) +
                                     "': POST /nearest takes CSV (text/csv), a GeoJSON FeatureCollection "
                                     "(application/geo+json) or a GeoJSON text sequence (application/geo+json-seq), "
                                     "e.g. curl --data-binary @queries.csv -H 'Content-Type: text/csv'",
                            "Content-Type");
    if (body.empty()) return error_response(400, "the request body holds no queries (send CSV: lat,lon[,id] lines, with or without a header)");
    NearestJoinOptions options;
    options.k = read.k(options_.max_k);
    options.rank_column = read.single("k").has_value();  // as geovor nearest --k
    options.metric = read.metric(index_.hierarchy);
    options.max_distance_m = read.max_distance_m();
    if (read.single("fields"))
      for (const std::size_t c : read.fields(index_.attributes)) options.site_fields.push_back(index_.attributes.columns[c]);
    options.columns = {read.single("lat_field").value_or(""), read.single("lon_field").value_or(""),
                       read.single("id_field").value_or("")};
    options.threads = options_.join_threads;
    if (!csv) return join_points(body, collection, type, options);

    std::unique_ptr<std::FILE, int (*)(std::FILE*)> in(fmemopen(const_cast<char*>(body.data()), body.size(), "r"), std::fclose);
    if (!in) return error_response(500, "cannot read the request body");
    std::string out;
    out.reserve(body.size() * 2);
    std::vector<MalformedQuery> malformed;
    NearestJoinReport report;
    try {
      report = nearest_join(
          index_, in.get(), "request body", options, [&](std::string_view s) { out.append(s); },
          [&](const MalformedQuery& m) {
            if (malformed.size() < kMalformedListed) malformed.push_back(m);
          });
    } catch (const Error& e) {
      if (e.code() == ErrorCode::Io) throw;
      throw query_column_error(e);
    }
    if (report.malformed > 0) return malformed_response(report.malformed, malformed);
    Response r;
    r.content_type = "text/csv";
    r.body = std::move(out);
    return r;
  } catch (const BadParameter& bad) {
    return bad_parameter_response(bad);
  }
}

}  // namespace geovor::service
