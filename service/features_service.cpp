#include "features_service.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>

#include "geovor/core/ascii.hpp"
#include "geovor/io/json_text.hpp"
#include "geovor/io/number_format.hpp"

namespace geovor::service {
namespace {

constexpr std::size_t kDefaultLimit = 10, kMaxLimit = 10000;
constexpr const char* kOpenApiType = "application/vnd.oai.openapi+json;version=3.0";
constexpr const char* kCrs84 = "http://www.opengis.net/def/crs/OGC/1.3/CRS84";

struct BadParameter {
  std::string parameter, why;
};

std::string json_string(std::string_view s) {
  std::string out;
  append_json_string(out, s);
  return out;
}

std::string link(const std::string& href, const char* rel, const char* type, const char* title) {
  return "{\"href\":" + json_string(href) + ",\"rel\":\"" + rel + "\",\"type\":\"" + type + "\",\"title\":\"" + title + "\"}";
}

Response json(std::string body, const char* type = "application/json") {
  Response r;
  r.content_type = type;
  r.body = std::move(body);
  return r;
}

// An unsigned integer parameter in [lo, hi].
std::size_t integer(const std::string& name, const std::string& text, std::size_t lo, std::size_t hi) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || text[0] == '-' || text[0] == '+' || *end != '\0' || errno == ERANGE || v < lo || v > hi)
    throw BadParameter{name, "'" + printable(text) + "' is not an integer in " + std::to_string(lo) + ".." + std::to_string(hi)};
  return static_cast<std::size_t>(v);
}

// bbox=west,south,east,north (degrees; four numbers: no heights).
std::array<double, 4> parse_bbox(const std::string& text) {
  std::array<double, 4> b{};
  const char* p = text.c_str();
  for (int i = 0; i < 4; ++i) {
    char* end = nullptr;
    b[i] = std::strtod(p, &end);
    if (end == p || !std::isfinite(b[i]) || *end != (i < 3 ? ',' : '\0'))
      throw BadParameter{"bbox", "'" + printable(text) + "' is not west,south,east,north in degrees"};
    p = end + 1;
  }
  if (b[1] > b[3] || b[1] < -90 || b[3] > 90 || b[0] < -180 || b[0] > 180 || b[2] < -180 || b[2] > 180)
    throw BadParameter{"bbox", "'" + printable(text) + "': longitudes in [-180, 180], latitudes in [-90, 90], south <= north"};
  return b;
}

// Whether two longitude ranges meet (west > east: across the antimeridian).
bool longitudes_meet(double w1, double e1, double w2, double e2) {
  auto parts = [](double w, double e) {
    return w <= e ? std::vector<std::pair<double, double>>{{w, e}}
                  : std::vector<std::pair<double, double>>{{w, 180}, {-180, e}};
  };
  for (const auto& [a0, a1] : parts(w1, e1))
    for (const auto& [b0, b1] : parts(w2, e2))
      if (a0 <= b1 && b0 <= a1) return true;
  return false;
}

bool meets(const std::array<double, 4>& f, const std::array<double, 4>& q) {
  return f[1] <= q[3] && q[1] <= f[3] && longitudes_meet(f[0], f[2], q[0], q[2]);
}

Response bad(const BadParameter& b) { return error_response(400, b.parameter + ": " + b.why, b.parameter); }

}  // namespace

Collection sites_collection(const SiteIndex& index) {
  const SiteAttributes& a = index.attributes;
  Collection c{"sites", "Sites", "The sites served by /nearest: one point per site, at its first row's position.", {}};
  c.features.reserve(a.num_sites());
  for (std::size_t s = 0; s < a.num_sites(); ++s) {
    const std::size_t r = a.site_rows[s];
    const SiteAttributes::Row& row = a.rows[r];
    CollectionFeature f;
    f.id = std::to_string(s);
    f.bbox = {row.lon_deg, row.lat_deg, row.lon_deg, row.lat_deg};
    f.json = "{\"type\":\"Feature\",\"id\":" + f.id + ",\"geometry\":{\"type\":\"Point\",\"coordinates\":[";
    append_real(f.json, row.lon_deg);
    f.json += ",";
    append_real(f.json, row.lat_deg);
    f.json += "]},\"properties\":{\"site_index\":" + f.id + ",\"site_id\":";
    append_json_string(f.json, a.site_id(s));
    for (std::size_t col = 0; col < a.columns.size(); ++col) {
      f.json += ",";
      append_json_string(f.json, a.columns[col]);
      f.json += ":";
      append_json_string(f.json, a.field(r, col));
    }
    f.json += "}}";
    c.features.push_back(std::move(f));
  }
  return c;
}

Collection layer_collection(const JsonLayer& layer, std::string id, std::string title, std::string description) {
  Collection c{std::move(id), std::move(title), std::move(description), {}};
  c.features.reserve(layer.features.size());
  for (const JsonFeature& f : layer.features) {
    const std::string fid = std::to_string(f.fid);
    c.features.push_back({fid, f.bbox,
                          "{\"type\":\"Feature\",\"id\":" + fid + ",\"geometry\":" + f.geometry +
                              ",\"properties\":" + f.properties + "}"});
  }
  return c;
}

FeaturesService::FeaturesService(std::vector<Collection> collections) : collections_(std::move(collections)) {
  for (const Collection& c : collections_) {
    auto& ids = by_id_.emplace_back();
    for (std::size_t i = 0; i < c.features.size(); ++i) ids.emplace(c.features[i].id, i);
  }
}

const Collection* FeaturesService::find(const std::string& id) const {
  for (const Collection& c : collections_)
    if (c.id == id) return &c;
  return nullptr;
}

Response FeaturesService::landing(const std::string& base) const {
  return json("{\"title\":\"geovor serve\",\"description\":\"Nearest sites and their cells (OGC API - Features)\",\"links\":[" +
              link(base + "/", "self", "application/json", "This document") + "," +
              link(base + "/conformance", "conformance", "application/json", "Conformance classes") + "," +
              link(base + "/collections", "data", "application/json", "Collections") + "," +
              link(base + "/api", "service-desc", kOpenApiType, "The API definition (OpenAPI 3.0)") + "," +
              link(base + "/map", "alternate", "text/html", "Map") + "]}");
}

Response FeaturesService::api(const std::string& base) const {
  // The paths and the items' parameters, so that clients (QGIS, GDAL) learn the page limits.
  const std::string json_response = R"({"200":{"description":"OK","content":{"application/json":{}}}})";
  const std::string geojson_response = R"({"200":{"description":"OK","content":{"application/geo+json":{}}}})";
  const std::string id_parameter = R"({"name":"collectionId","in":"path","required":true,"schema":{"type":"string"}})";
  std::string j = R"({"openapi":"3.0.2","info":{"title":"geovor serve","version":"1.0"},"servers":[{"url":)" + json_string(base) +
                  R"(}],"paths":{)";
  j += R"("/":{"get":{"summary":"Landing page","responses":)" + json_response + "}},";
  j += R"("/conformance":{"get":{"summary":"Conformance classes","responses":)" + json_response + "}},";
  j += R"("/collections":{"get":{"summary":"Collections","responses":)" + json_response + "}},";
  j += R"("/collections/{collectionId}":{"get":{"summary":"A collection","parameters":[)" + id_parameter +
       R"(],"responses":)" + json_response + "}},";
  j += R"("/collections/{collectionId}/items":{"get":{"summary":"Features","parameters":[)" + id_parameter +
       R"(,{"name":"limit","in":"query","schema":{"type":"integer","minimum":1,"maximum":)" + std::to_string(kMaxLimit) +
       R"(,"default":)" + std::to_string(kDefaultLimit) +
       R"(}},{"name":"offset","in":"query","schema":{"type":"integer","minimum":0,"default":0}},)"
       R"({"name":"bbox","in":"query","style":"form","explode":false,"schema":{"type":"array","minItems":4,"maxItems":4,"items":{"type":"number"}}}],"responses":)" +
       geojson_response + "}},";
  j += R"("/collections/{collectionId}/items/{featureId}":{"get":{"summary":"A feature","parameters":[)" + id_parameter +
       R"(,{"name":"featureId","in":"path","required":true,"schema":{"type":"string"}}],"responses":)" + geojson_response +
       "}}}}";
  return json(j, kOpenApiType);
}

Response FeaturesService::conformance() const {
  return json(
      "{\"conformsTo\":[\"http://www.opengis.net/spec/ogcapi-features-1/1.0/conf/core\","
      "\"http://www.opengis.net/spec/ogcapi-features-1/1.0/conf/geojson\"]}");
}

std::string FeaturesService::collection_json(const Collection& c, const std::string& base) const {
  double w = 180, s = 90, e = -180, n = -90;
  for (const CollectionFeature& f : c.features) {
    w = std::min(w, std::min(f.bbox[0], f.bbox[2]));
    e = std::max(e, std::max(f.bbox[0], f.bbox[2]));
    s = std::min(s, f.bbox[1]);
    n = std::max(n, f.bbox[3]);
  }
  if (c.features.empty()) w = -180, s = -90, e = 180, n = 90;
  std::string j = "{\"id\":" + json_string(c.id) + ",\"title\":" + json_string(c.title) +
                  ",\"description\":" + json_string(c.description) + ",\"itemType\":\"feature\",\"crs\":[\"" + kCrs84 +
                  "\"],\"extent\":{\"spatial\":{\"bbox\":[[";
  for (const double v : {w, s, e, n}) {
    append_real(j, v);
    j += ",";
  }
  j.back() = ']';
  j += "],\"crs\":\"" + std::string(kCrs84) + "\"}},\"links\":[" +
       link(base + "/collections/" + c.id, "self", "application/json", "This collection") + "," +
       link(base + "/collections/" + c.id + "/items", "items", "application/geo+json", "Its features") + "]}";
  return j;
}

Response FeaturesService::collections(const std::string& base) const {
  std::string j = "{\"links\":[" + link(base + "/collections", "self", "application/json", "The collections") + "],\"collections\":[";
  for (std::size_t i = 0; i < collections_.size(); ++i) j += (i ? "," : "") + collection_json(collections_[i], base);
  return json(j + "]}");
}

Response FeaturesService::collection(const std::string& id, const std::string& base) const {
  const Collection* c = find(id);
  if (!c) return error_response(404, "no collection '" + printable(id) + "'");
  return json(collection_json(*c, base));
}

Response FeaturesService::items(const std::string& id, const Params& params, const std::string& base) const {
  const Collection* c = find(id);
  if (!c) return error_response(404, "no collection '" + printable(id) + "'");
  try {
    std::size_t limit = kDefaultLimit, offset = 0;
    std::optional<std::array<double, 4>> box;
    std::string bbox_text;
    for (const auto& [name, value] : params) {
      if (params.count(name) > 1) throw BadParameter{name, "given more than once"};
      if (name == "limit") {
        limit = integer(name, value, 1, kMaxLimit);
      } else if (name == "offset") {
        offset = integer(name, value, 0, SIZE_MAX / 2);
      } else if (name == "bbox") {
        box = parse_bbox(value);
        bbox_text = value;
      } else if (name == "f") {
        if (value != "json" && value != "geojson") throw BadParameter{name, "'" + printable(value) + "': only json"};
      } else {
        throw BadParameter{name, "unknown parameter; items take limit, offset, bbox, f"};
      }
    }
    std::string features;
    std::size_t matched = 0, returned = 0;
    for (const CollectionFeature& f : c->features) {
      if (box && !meets(f.bbox, *box)) continue;
      if (matched++ < offset || returned >= limit) continue;
      features += (returned++ ? "," : "") + f.json;
    }
    const std::string self = base + "/collections/" + c->id + "/items?";
    auto page = [&](std::size_t at) {
      return self + "limit=" + std::to_string(limit) + "&offset=" + std::to_string(at) + (box ? "&bbox=" + bbox_text : "");
    };
    std::string links = link(page(offset), "self", "application/geo+json", "This page");
    if (offset + returned < matched) links += "," + link(page(offset + limit), "next", "application/geo+json", "Next page");
    if (offset > 0) links += "," + link(page(offset > limit ? offset - limit : 0), "prev", "application/geo+json", "Previous page");
    return json("{\"type\":\"FeatureCollection\",\"numberMatched\":" + std::to_string(matched) +
                    ",\"numberReturned\":" + std::to_string(returned) + ",\"links\":[" + links + "],\"features\":[" +
                    features + "]}",
                "application/geo+json");
  } catch (const BadParameter& b) {
    return bad(b);
  }
}

Response FeaturesService::item(const std::string& id, const std::string& feature_id, const std::string& base) const {
  const Collection* c = find(id);
  if (!c) return error_response(404, "no collection '" + printable(id) + "'");
  const auto& ids = by_id_[static_cast<std::size_t>(c - collections_.data())];
  if (const auto at = ids.find(feature_id); at != ids.end()) {
    const CollectionFeature& f = c->features[at->second];
    std::string j = f.json;
    j.pop_back();  // the Feature's closing brace: its links follow
    j += ",\"links\":[" + link(base + "/collections/" + c->id + "/items/" + f.id, "self", "application/geo+json", "This feature") +
         "," + link(base + "/collections/" + c->id, "collection", "application/json", "Its collection") + "]}";
    return json(j, "application/geo+json");
  }
  return error_response(404, "collection '" + c->id + "' has no feature '" + printable(feature_id) + "'");
}

}  // namespace geovor::service
