// Router: each route reaches its handler (the same answer as calling the handler), unknown paths
// are 404, known paths with another method 405 with Allow, HEAD is GET, and metrics count by route.
#include "router.hpp"

#include <gtest/gtest.h>

#include "served_sites.hpp"

namespace geovor::service {
namespace {

std::shared_ptr<const ServedData> sites() { return served_sites(50); }

struct RouterTest : ::testing::Test {
  LiveData data{[] { return sites(); }};
  RequestMetrics metrics{Router::metric_routes()};
  Router router{data, metrics};

  Routed call(const std::string& method, const std::string& path, Params params = {}, std::string_view body = {}) {
    HttpRequest r;
    r.method = method;
    r.path = path;
    r.params = std::move(params);
    r.host = "127.0.0.1:9";
    r.content_type = "text/csv";
    r.body = body;
    return router.route(r);
  }
};

TEST_F(RouterTest, RoutesReachTheirHandlers) {
  const Params at = {{"lat", "10"}, {"lon", "20"}, {"k", "3"}};
  EXPECT_EQ(call("GET", "/nearest", at).response.body, data.current()->nearest.nearest(at).body);
  EXPECT_EQ(call("HEAD", "/nearest", at).response.body, data.current()->nearest.nearest(at).body);
  const std::string csv = "lat,lon\n1,2\n-3,4\n";
  EXPECT_EQ(call("POST", "/nearest", {}, csv).response.body, data.current()->nearest.join({}, csv, "text/csv").body);
  EXPECT_EQ(call("GET", "/healthz").response.body, data.current()->nearest.health().body);
  EXPECT_EQ(call("GET", "/").response.body, data.current()->features.landing("http://127.0.0.1:9").body);
  EXPECT_EQ(call("GET", "/collections/sites/items", {{"limit", "5"}}).response.body,
            data.current()->features.items("sites", {{"limit", "5"}}, "http://127.0.0.1:9").body);
  EXPECT_EQ(call("GET", "/collections/sites/items/s7").response.body,
            data.current()->features.item("sites", "s7", "http://127.0.0.1:9").body);
  EXPECT_EQ(call("GET", "/collections/sites").response.status, 200);
  EXPECT_EQ(call("GET", "/collections/nope").response.status, 404);
  EXPECT_EQ(call("GET", "/map").response.content_type, "text/html; charset=utf-8");
  EXPECT_EQ(call("GET", "/static/countries.geojson").response.status, 200);
  EXPECT_EQ(call("POST", "/admin/reload").response.status, 200);
}

TEST_F(RouterTest, UnknownIs404KnownWithAnotherMethodIs405) {
  for (const char* path : {"/nope", "/nearest/x", "/collections/sites/items/s1/more", "/collections//items",
                           "/static/leaflet/../../etc/passwd", "/static/leaflet/missing.js"}) {
    const Routed r = call("GET", path);
    EXPECT_EQ(r.response.status, 404) << path;
    EXPECT_NE(r.response.body.find("\"error\""), std::string::npos);
  }
  const Routed del = call("DELETE", "/nearest");
  EXPECT_EQ(del.response.status, 405);
  EXPECT_EQ(del.allow, "GET, HEAD, POST");
  EXPECT_EQ(call("GET", "/admin/reload").allow, "POST");
  EXPECT_EQ(call("POST", "/healthz").response.status, 405);
  EXPECT_EQ(call("GE", "/healthz").response.status, 405);
}

TEST_F(RouterTest, OnlyPostsAreSlow) {
  HttpRequest r;
  r.method = "POST";
  EXPECT_TRUE(Router::is_slow(r));
  r.method = "GET";
  EXPECT_FALSE(Router::is_slow(r));
}

TEST_F(RouterTest, RoutesAreCountedByName) {
  EXPECT_EQ(call("GET", "/nearest", {{"lat", "1"}, {"lon", "1"}}).route, "GET /nearest");
  EXPECT_EQ(call("HEAD", "/healthz").route, "GET /healthz");
  EXPECT_EQ(call("POST", "/admin/reload").route, "POST /admin/reload");
  metrics.record("GET /healthz", 200, 0.001);
  router.reload();
  const std::string text = call("GET", "/metrics").response.body;
  EXPECT_NE(text.find("geovor_requests_total{route=\"GET /healthz\",code=\"200\"} 1"), std::string::npos) << text;
  EXPECT_NE(text.find("geovor_sites 50"), std::string::npos);
  EXPECT_NE(text.find("geovor_reloads_total{result=\"ok\"} 2"), std::string::npos) << text;
}

}  // namespace
}  // namespace geovor::service
