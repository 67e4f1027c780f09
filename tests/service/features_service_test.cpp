// FeaturesService (OGC API - Features): paging by offset and links, bbox against brute force
// (the antimeridian included), items by id, and bad parameters named.
#include "features_service.hpp"

#include <gtest/gtest.h>

#include <string>

namespace geovor::service {
namespace {

// A collection of points on a 10-degree grid, ids "p0", "p1", ...
Collection grid() {
  Collection c{"points", "Points", "A grid", {}};
  for (int lat = -80; lat <= 80; lat += 10)
    for (int lon = -180; lon < 180; lon += 10) {
      const std::string id = "p" + std::to_string(c.features.size());
      c.features.push_back({id, {double(lon), double(lat), double(lon), double(lat)},
                            "{\"type\":\"Feature\",\"id\":\"" + id + "\",\"geometry\":null,\"properties\":{}}"});
    }
  return c;
}

std::size_t count(const std::string& body, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = body.find(what); at != std::string::npos; at = body.find(what, at + 1)) ++n;
  return n;
}

std::string member(const std::string& body, const std::string& name) {
  const std::size_t at = body.find("\"" + name + "\":");
  return at == std::string::npos ? "" : body.substr(at + name.size() + 3, body.find_first_of(",}", at + name.size() + 3) - at - name.size() - 3);
}

TEST(FeaturesService, PagesAndBoxes) {
  const Collection c = grid();
  const FeaturesService s({c});
  const std::string base = "http://h:1";
  const Response first = s.items("points", {{"limit", "100"}}, base);
  ASSERT_EQ(first.status, 200) << first.body;
  EXPECT_EQ(first.content_type, "application/geo+json");
  EXPECT_EQ(member(first.body, "numberMatched"), std::to_string(c.features.size()));
  EXPECT_EQ(member(first.body, "numberReturned"), "100");
  EXPECT_NE(first.body.find("\"href\":\"http://h:1/collections/points/items?limit=100&offset=100\",\"rel\":\"next\""), std::string::npos);
  const Response last = s.items("points", {{"limit", "100"}, {"offset", "600"}}, base);
  EXPECT_EQ(member(last.body, "numberReturned"), std::to_string(c.features.size() - 600));
  EXPECT_EQ(last.body.find("\"rel\":\"next\""), std::string::npos);
  EXPECT_NE(last.body.find("\"rel\":\"prev\""), std::string::npos);
  // bbox against brute force, across the antimeridian too.
  for (const auto& [box, w, s_, e, n] : {std::tuple{"0,0,30,20", 0, 0, 30, 20}, std::tuple{"170,-10,-170,10", 170, -10, -170, 10},
                                        std::tuple{"-180,75,180,90", -180, 75, 180, 90}}) {
    std::size_t want = 0;
    for (const CollectionFeature& f : c.features) {
      const double lon = f.bbox[0], lat = f.bbox[1];
      const bool in_lon = w <= e ? (lon >= w && lon <= e) : (lon >= w || lon <= e);
      want += in_lon && lat >= s_ && lat <= n;
    }
    const Response r = s.items("points", {{"bbox", box}, {"limit", "1000"}}, base);
    EXPECT_EQ(member(r.body, "numberMatched"), std::to_string(want)) << box;
    EXPECT_EQ(count(r.body, "\"type\":\"Feature\""), want) << box;
  }
  EXPECT_NE(s.item("points", "p7", base).body.find("\"id\":\"p7\""), std::string::npos);
  EXPECT_EQ(s.item("points", "p99999", base).status, 404);
  EXPECT_EQ(s.items("nope", {}, base).status, 404);
  EXPECT_EQ(s.collection("points", base).status, 200);
  EXPECT_NE(s.collections(base).body.find("\"id\":\"points\""), std::string::npos);
  EXPECT_NE(s.conformance().body.find("conf/core"), std::string::npos);
}

TEST(FeaturesService, BadParametersAreNamed) {
  const FeaturesService s({grid()});
  for (const auto& [name, value] : {std::pair{"limit", "0"}, std::pair{"limit", "10001"}, std::pair{"limit", "-1"},
                                    std::pair{"offset", "x"}, std::pair{"bbox", "1,2,3"}, std::pair{"bbox", "0,20,10,10"},
                                    std::pair{"bbox", "0,0,200,10"}, std::pair{"f", "html"}, std::pair{"zoom", "3"}}) {
    const Response r = s.items("points", {{name, value}}, "http://h");
    EXPECT_EQ(r.status, 400) << name << "=" << value;
    EXPECT_NE(r.body.find(std::string("\"parameter\":\"") + name + "\""), std::string::npos) << r.body;
  }
}

}  // namespace
}  // namespace geovor::service
