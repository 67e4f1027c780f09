// Fuzz target: the handlers of `geovor serve` (service/nearest_service.hpp) on any query
// parameters and POST bodies. The bytes up to the first line feed are split at '&' into NAME=VALUE
// pairs (as a query string decodes); with no line feed they are a GET /nearest, else the rest is a
// POST /nearest CSV body. Over a fixed index of 300 sites with columns, once unweighted and once
// weighted. A GET is a 200 GeoJSON FeatureCollection or a 400 naming a parameter; a POST a 200
// CSV with geovor nearest's header, or a 400 with its reason; never a crash or a hang. The same
// parameters go to the OGC API - Features items of the sites (200 or 400 naming the parameter).
// The first line is also a request target ("/" + line) decoded by parse_request_target and sent
// to the Router as a GET: 200, 400, 404 or 405, a file served only from Leaflet's folder.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "features_service.hpp"
#include "nearest_service.hpp"
#include "request_target.hpp"
#include "router.hpp"

namespace {

using namespace geovor;

SiteTable site_table(bool weighted) {
  SiteTable t;
  t.source = "fuzz.csv";
  t.columns = {"id", "name"};
  t.id_column = 0;
  for (int i = 0; i < 300; ++i) {
    InputSite s;
    s.row = static_cast<std::uint64_t>(i) + 1;
    s.lat_deg = -89.5 + (i * 37 % 179);
    s.lon_deg = -179.0 + (i * 53 % 358);
    s.unit = SiteEncoder::from_lat_lon(s.lat_deg, s.lon_deg);
    s.id = "s" + std::to_string(i);
    s.weight_m = weighted ? 5000.0 * (i % 7) : 0;
    s.fields = {s.id, "n\"" + std::to_string(i)};
    t.sites.push_back(std::move(s));
  }
  t.rows_read = t.sites.size();
  t.weighted = weighted;
  return t;
}

service::NearestService make_service(bool weighted) {
  return service::NearestService(build_site_index(site_table(weighted)), {.max_k = 100, .join_threads = 1});
}

// The first line as a GET through the router.
void route_target(const std::string& line) {
  static service::LiveData data([] { return service::make_served_data(build_site_index(site_table(false)), "", {.max_k = 100, .join_threads = 1}); });
  static service::RequestMetrics metrics(service::Router::metric_routes());
  static const service::Router router(data, metrics);
  std::optional<service::RequestTarget> target = service::parse_request_target("/" + line);
  if (!target) return;
  service::HttpRequest req{.method = "GET", .path = target->path, .params = target->query, .host = "fuzz"};
  const int status = router.route(req).response.status;
  FUZZ_CHECK(status == 200 || status == 400 || status == 404 || status == 405, "GET %s: status %d", line.c_str(), status);
  if (status == 200 && req.path.starts_with("/static/"))
    FUZZ_CHECK(req.path == "/static/countries.geojson" ||
                   (req.path.starts_with("/static/leaflet/") && req.path.find("..") == std::string::npos),
               "GET %s: a file outside Leaflet's folder", line.c_str());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const service::NearestService plain = make_service(false), weighted = make_service(true);
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::size_t line_feed = input.find('\n');
  const std::string text = input.substr(0, line_feed);
  route_target(text);
  service::Params params;
  std::size_t at = 0;
  while (at <= text.size() && params.size() < 16) {
    const std::size_t amp = std::min(text.find('&', at), text.size());
    const std::string pair = text.substr(at, amp - at);
    const std::size_t eq = pair.find('=');
    params.emplace(pair.substr(0, eq), eq == std::string::npos ? std::string() : pair.substr(eq + 1));
    at = amp + 1;
  }
  static const service::FeaturesService features({service::sites_collection(plain.index())});
  if (line_feed == std::string::npos) {
    const service::Response r = features.items("sites", params, "http://fuzz");
    FUZZ_CHECK(r.status == 200 || r.status == 400, "items: status %d", r.status);
    if (r.status == 200)
      FUZZ_CHECK(r.body.rfind("{\"type\":\"FeatureCollection\",\"numberMatched\":", 0) == 0 && r.body.back() == '}',
                 "items: body %s", r.body.c_str());
    else
      FUZZ_CHECK(r.body.find("\"parameter\":") != std::string::npos, "items: a 400 without its parameter: %s", r.body.c_str());
  }
  for (const service::NearestService* s : {&plain, &weighted}) {
    if (line_feed != std::string::npos) {
      const service::Response r = s->join(params, std::string_view(input).substr(line_feed + 1), "text/csv");
      FUZZ_CHECK(r.status == 200 || r.status == 400, "status %d: %s", r.status, r.body.c_str());
      if (r.status == 200)
        FUZZ_CHECK(r.content_type == "text/csv" && r.body.rfind("query_id,", 0) == 0, "body %s", r.body.c_str());
      else
        FUZZ_CHECK(r.body.rfind("{\"error\":", 0) == 0 && r.body.back() == '}', "a 400 without its reason: %s", r.body.c_str());
      continue;
    }
    const service::Response r = s->nearest(params);
    FUZZ_CHECK(r.status == 200 || r.status == 400, "status %d", r.status);
    if (r.status == 200)
      FUZZ_CHECK(r.body.rfind("{\"type\":\"FeatureCollection\",\"features\":[", 0) == 0 && r.body.back() == '}',
                 "body %s", r.body.c_str());
    else
      FUZZ_CHECK(r.body.find("\"parameter\":") != std::string::npos, "a 400 without its parameter: %s", r.body.c_str());
  }
  return 0;
}
