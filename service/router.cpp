#include "router.hpp"

#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "geovor/io/json_text.hpp"
#include "map_page.hpp"

namespace geovor::service {
namespace {

// The path's segments: "/collections/sites/items" -> {"collections", "sites", "items"}.
std::vector<std::string> segments(const std::string& path) {
  std::vector<std::string> parts;
  std::size_t start = 1;
  while (start <= path.size()) {
    const std::size_t end = std::min(path.find('/', start), path.size());
    parts.push_back(path.substr(start, end - start));
    start = end + 1;
  }
  return parts;
}

Response text(std::string body, const char* type) {
  Response r;
  r.content_type = type;
  r.body = std::move(body);
  return r;
}

std::string prometheus_gauges(const ServedData& data) {
  return "# HELP geovor_sites Sites served.\n# TYPE geovor_sites gauge\ngeovor_sites " +
         std::to_string(data.nearest.index().hierarchy.base().num_sites()) + "\n";
}

const char* static_type(const std::string& name) {
  const auto ends = [&name](std::string_view tail) { return name.size() >= tail.size() && name.ends_with(tail); };
  if (ends(".js")) return "application/javascript";
  if (ends(".css")) return "text/css";
  if (ends(".png")) return "image/png";
  if (ends(".svg")) return "image/svg+xml";
  return "application/octet-stream";
}

// A file of Debian's Leaflet (/static/leaflet/NAME); found false for a name that climbs out of it
// or is not there.
Response leaflet_file(const std::string& name, bool& found) {
  found = !name.empty() && name.find("..") == std::string::npos && name.find('\0') == std::string::npos;
  if (!found) return {};
  std::ifstream in(std::string(kLeafletDir) + "/" + name, std::ios::binary);
  found = static_cast<bool>(in);
  if (!found) return {};
  return text(std::string(std::istreambuf_iterator<char>(in), {}), static_type(name));
}

// The methods answered at a path known to the router ("" for an unknown path), for 405's Allow.
std::string allowed_methods(const std::string& path) {
  if (path == "/nearest") return "GET, HEAD, POST";
  if (path == "/admin/reload") return "POST";
  if (path == "/healthz" || path == "/metrics" || path == "/" || path == "/api" || path == "/conformance" ||
      path == "/map" || path == "/static/countries.geojson" || path.starts_with("/collections") ||
      path.starts_with("/static/leaflet/"))
    return "GET, HEAD";
  return "";
}

}  // namespace

const std::vector<std::string>& Router::metric_routes() {
  static const std::vector<std::string> routes = {"GET /nearest", "POST /nearest", "GET /healthz", "GET /metrics",
                                                  "POST /admin/reload", "GET /", "GET /collections", "GET /map"};
  return routes;
}

bool Router::is_slow(const HttpRequest& request) {
  return request.method == "POST";
}

ReloadResult Router::reload() const {
  ReloadResult r = data_.reload();
  metrics_.record_reload(r.ok);
  return r;
}

Response Router::features(const HttpRequest& request, bool& found) const {
  const std::string base = "http://" + request.host;
  const std::vector<std::string> parts = segments(request.path);
  const FeaturesService& f = data_.current()->features;
  found = true;
  if (request.path == "/") return f.landing(base);
  if (request.path == "/api") return f.api(base);
  if (request.path == "/conformance") return f.conformance();
  found = parts[0] == "collections" && parts.size() <= 4 && (parts.size() < 3 || parts[2] == "items");
  for (std::size_t i = 1; found && i < parts.size(); ++i) found = !parts[i].empty();
  if (!found) return {};
  if (parts.size() == 1) return f.collections(base);
  if (parts.size() == 2) return f.collection(parts[1], base);
  if (parts.size() == 3) return f.items(parts[1], request.params, base);
  return f.item(parts[1], parts[3], base);
}

Response Router::get(const HttpRequest& request, bool& found) const {
  found = true;
  const std::string& path = request.path;
  if (path == "/nearest") return data_.current()->nearest.nearest(request.params);
  if (path == "/healthz") return data_.current()->nearest.health();
  if (path == "/metrics") return text(metrics_.text(prometheus_gauges(*data_.current())), "text/plain; version=0.0.4");
  if (path == "/map") return text(std::string(map_page()), "text/html; charset=utf-8");
  if (path == "/static/countries.geojson") return text(std::string(countries_geojson()), "application/geo+json");
  if (path.starts_with("/static/leaflet/")) return leaflet_file(path.substr(16), found);
  return features(request, found);
}

Response Router::post(const HttpRequest& request, bool& found) const {
  found = true;
  if (request.path == "/nearest") return data_.current()->nearest.join(request.params, request.body, request.content_type);
  found = request.path == "/admin/reload";
  if (!found) return {};
  const ReloadResult r = reload();
  if (!r.ok) return error_response(500, "reload failed, the previous data are still served: " + r.message);
  Response ok = text("{\"status\":\"reloaded\",\"served\":", "application/json");
  append_json_string(ok.body, r.message);
  ok.body += "}";
  return ok;
}

Routed Router::route(const HttpRequest& request) const {
  Routed out;
  const bool get = request.method == "GET" || request.method == "HEAD";
  out.route = (get ? "GET " : request.method + " ") + request.path;
  bool found = false;
  if (get) out.response = this->get(request, found);
  if (request.method == "POST") out.response = post(request, found);
  if (found) return out;
  out.allow = allowed_methods(request.path);
  const bool allowed = (", " + out.allow + ",").find(", " + request.method + ",") != std::string::npos;
  if (out.allow.empty() || allowed) {
    out.allow.clear();
    out.response = error_response(404, request.path + ": no such resource");
  } else {
    out.response = error_response(405, request.method + " " + request.path + ": method not allowed (allowed: " + out.allow + ")");
  }
  return out;
}

}  // namespace geovor::service
