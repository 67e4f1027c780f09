// The service's handlers against the library's own answers (Locator, k_nearest) and every kind
// of bad request (400 naming the parameter).
#include "nearest_service.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <cstdio>
#include <string>

#include "geovor/geo/site_encoder.hpp"
#include "geovor/locate/knn.hpp"
#include "geovor/locate/locator.hpp"
#include "geovor/layers/nearest_join.hpp"
#include "support/generators.hpp"

namespace geovor::service {
namespace {

SiteTable make_table(std::size_t n, bool weighted) {
  SiteTable t;
  t.source = "generated.csv";
  t.columns = {"id", "lat", "lon", "name"};
  t.id_column = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const LatLon ll = SiteEncoder::to_lat_lon(testing::uniform_on_sphere(n, 5)[i]);
    InputSite s;
    s.row = i + 1;
    s.id = "s" + std::to_string(i);
    s.lat_deg = ll.lat_deg;
    s.lon_deg = ll.lon_deg;
    s.unit = SiteEncoder::from_lat_lon(s.lat_deg, s.lon_deg);
    s.weight_m = weighted ? 1000.0 * static_cast<double>(i % 50) : 0;
    s.fields = {s.id, std::to_string(s.lat_deg), std::to_string(s.lon_deg), "site \"" + std::to_string(i) + "\""};
    t.sites.push_back(std::move(s));
  }
  t.rows_read = n;
  t.weighted = weighted;
  return t;
}

// "site_index":N of the k-th feature of a body.
long site_index(const std::string& body, int k) {
  std::size_t at = 0;
  for (int i = 0; i <= k; ++i) {
    at = body.find("\"site_index\":", at);
    if (at == std::string::npos) return -1;
    at += 13;
  }
  return std::stol(body.substr(at));
}

std::string error_parameter(const Response& r) {
  EXPECT_EQ(r.status, 400) << r.body;
  EXPECT_EQ(r.content_type, "application/json");
  const std::size_t at = r.body.find("\"parameter\":\"");
  return at == std::string::npos ? "" : r.body.substr(at + 13, r.body.find('"', at + 13) - at - 13);
}

TEST(NearestService, AnswersAsTheLocator) {
  const SiteIndex index = build_site_index(make_table(800, false));
  Locator locator(index.hierarchy);
  const NearestService service(build_site_index(make_table(800, false)));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1), lon(-180, 180);
  std::vector<NearestResult> k3;
  for (int i = 0; i < 200; ++i) {
    const double la = std::asin(u(rng)) * 180 / M_PI, lo = lon(rng);
    char lat_text[40], lon_text[40];
    std::snprintf(lat_text, sizeof lat_text, "%.17g", la);
    std::snprintf(lon_text, sizeof lon_text, "%.17g", lo);
    const Response one = service.nearest({{"lat", lat_text}, {"lon", lon_text}});
    ASSERT_EQ(one.status, 200) << one.body;
    EXPECT_EQ(one.content_type, "application/geo+json");
    EXPECT_EQ(site_index(one.body, 0), locator.nearest(SiteEncoder::from_lat_lon(la, lo)).site);
    const Response three = service.nearest({{"lat", lat_text}, {"lon", lon_text}, {"k", "3"}, {"metric", "geodesic"}});
    k_nearest(locator, la, lo, 3, Metric::Geodesic, k3);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(site_index(three.body, k), k3[static_cast<std::size_t>(k)].site);
  }
  // Fields: all columns by default, escaped; or those named.
  const Response all = service.nearest({{"lat", "10"}, {"lon", "20"}});
  EXPECT_NE(all.body.find("\"name\":\"site \\\""), std::string::npos) << all.body;
  const Response named = service.nearest({{"lat", "10"}, {"lon", "20"}, {"fields", "NAME"}});
  EXPECT_EQ(named.body.find("\"lat\":"), std::string::npos);
  EXPECT_NE(named.body.find("\"name\":"), std::string::npos);
  // Beyond max_distance_m: an empty collection.
  EXPECT_EQ(service.nearest({{"lat", "10"}, {"lon", "20"}, {"max_distance_m", "0"}}).body,
            "{\"type\":\"FeatureCollection\",\"features\":[]}");
  EXPECT_EQ(service.health().body, "{\"status\":\"ok\",\"sites\":800}");
}

TEST(NearestService, BadRequestsNameTheParameter) {
  const NearestService service(build_site_index(make_table(100, false)));
  EXPECT_EQ(error_parameter(service.nearest({{"lon", "2"}})), "lat");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "2"}})), "lon");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "91"}, {"lon", "2"}})), "lat");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "abc"}, {"lon", "2"}})), "lat");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lon", "inf"}})), "lon");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lon", "nan"}})), "lon");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1e999"}, {"lon", "2"}})), "lat");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lon", "2"}, {"k", "0"}})), "k");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lon", "2"}, {"k", "101"}})), "k");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lon", "2"}, {"k", "2.5"}})), "k");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lon", "2"}, {"metric", "manhattan"}})), "metric");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lon", "2"}, {"max_distance_m", "-1"}})), "max_distance_m");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lon", "2"}, {"fields", "nope"}})), "fields");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lat", "1"}, {"lon", "2"}})), "lat");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lon", "2"}, {"radius", "3"}})), "radius");
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1\n"}, {"lon", "2"}})), "lat");
  const Response nameless = service.nearest({{"", "5"}, {"lat", "1"}, {"lon", "2"}});  // "?=5"
  EXPECT_EQ(nameless.status, 400);
  EXPECT_NE(nameless.body.find("\"parameter\":\"\""), std::string::npos) << nameless.body;
}

TEST(NearestService, WeightedSitesArePower) {
  const SiteIndex index = build_site_index(make_table(600, true));
  Locator locator(index.hierarchy);
  const NearestService service(build_site_index(make_table(600, true)));
  EXPECT_EQ(error_parameter(service.nearest({{"lat", "1"}, {"lon", "2"}, {"metric", "sphere"}})), "metric");
  for (const double la : {-60.0, 0.0, 33.3, 89.0}) {
    const std::string t = std::to_string(la);
    const Response r = service.nearest({{"lat", t}, {"lon", "17.5"}, {"metric", "power"}});
    EXPECT_EQ(site_index(r.body, 0), locator.nearest(SiteEncoder::from_lat_lon(std::stod(t), 17.5)).site);
  }
}

// geovor nearest's CSV of `queries` (the library's join on a stream), for comparison.
std::string command_join(const SiteIndex& index, const std::string& queries, const NearestJoinOptions& options) {
  std::FILE* in = fmemopen(const_cast<char*>(queries.data()), queries.size(), "r");
  std::string out;
  nearest_join(index, in, "queries.csv", options, [&](std::string_view s) { out.append(s); });
  std::fclose(in);
  return out;
}

TEST(NearestService, PostIsTheJoinOfGeovorNearest) {
  const SiteIndex index = build_site_index(make_table(500, false));
  const NearestService service(build_site_index(make_table(500, false)), {.max_k = 100, .join_threads = 2});
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1), lon(-180, 180);
  std::string queries = "id,lat,lon,note\n";
  for (int i = 0; i < 3000; ++i) {
    char line[120];
    std::snprintf(line, sizeof line, "q%d,%.17g,%.17g,\"a, b\"\n", i, std::asin(u(rng)) * 180 / M_PI, lon(rng));
    queries += line;
  }
  queries += "q-pole,90,0,x\r\nq-am,0,-180,y\n";
  NearestJoinOptions options;
  const Response one = service.join({}, queries, "text/csv; charset=utf-8");
  ASSERT_EQ(one.status, 200) << one.body;
  EXPECT_EQ(one.content_type, "text/csv");
  EXPECT_EQ(one.body, command_join(index, queries, options));
  options.k = 3;
  options.rank_column = true;
  options.site_fields = {"name"};
  options.metric = Metric::Geodesic;
  options.max_distance_m = 2e6;
  const Response three = service.join({{"k", "3"}, {"fields", "name"}, {"metric", "geodesic"}, {"max_distance_m", "2e6"}},
                                       queries, "");
  ASSERT_EQ(three.status, 200) << three.body;
  EXPECT_EQ(three.body, command_join(index, queries, options));
  // Columns named by parameters.
  const Response named = service.join({{"lat_field", "Y"}, {"lon_field", "X"}}, "X,Y\n2,1\n", "text/csv");
  ASSERT_EQ(named.status, 200) << named.body;
  EXPECT_EQ(named.body, command_join(index, "X,Y\n2,1\n", {.columns = {"Y", "X", ""}}));
}

TEST(NearestService, BadPostsSayWhy) {
  const NearestService service(build_site_index(make_table(100, false)), {.max_k = 100, .join_threads = 1});
  const Response malformed = service.join({}, "lat,lon\n1,2\n3,abc\n4,5\n91,0\n", "text/csv");
  EXPECT_EQ(malformed.status, 400);
  EXPECT_NE(malformed.body.find("2 malformed lines"), std::string::npos) << malformed.body;
  EXPECT_NE(malformed.body.find("\"line\":3,\"malformed\":[{\"line\":3,\"reason\":"), std::string::npos) << malformed.body;
  EXPECT_NE(malformed.body.find("{\"line\":5,"), std::string::npos) << malformed.body;
  const Response type = service.join({}, "lat,lon\n1,2\n", "application/x-www-form-urlencoded");
  EXPECT_EQ(type.status, 415);
  EXPECT_NE(type.body.find("\"parameter\":\"Content-Type\""), std::string::npos) << type.body;
  EXPECT_EQ(service.join({}, "", "text/csv").status, 400);
  const Response no_columns = service.join({}, "a,b\n1,2\n", "text/csv");
  EXPECT_EQ(no_columns.status, 400);
  EXPECT_EQ(no_columns.body.find("--query"), std::string::npos) << no_columns.body;  // names parameters, not flags
  EXPECT_NE(no_columns.body.find("lat_field"), std::string::npos) << no_columns.body;
  EXPECT_EQ(error_parameter(service.join({{"lat_field", "nope"}}, "lat,lon\n1,2\n", "text/csv")), "lat_field");
  EXPECT_EQ(error_parameter(service.join({{"lat", "1"}}, "lat,lon\n1,2\n", "text/csv")), "lat");
  EXPECT_EQ(error_parameter(service.join({{"k", "0"}}, "lat,lon\n1,2\n", "text/csv")), "k");
  EXPECT_EQ(error_parameter(service.join({{"fields", "zzz"}}, "lat,lon\n1,2\n", "text/csv")), "fields");
}

}  // namespace
}  // namespace geovor::service
