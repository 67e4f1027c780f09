// k nearest and radius search under both metrics against brute force over every site:
// great-circle metres on the mean-radius sphere (chord formula, long double) and WGS84 geodesic
// metres (GeographicLib Geodesic::Inverse), on random and degenerate site sets.
#include "geovor/locate/knn.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "geovor/core/error.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

constexpr double kTolM = 1e-6;  // far above both oracles' rounding, far below any site spacing

struct Oracle {
  const SphericalDelaunay& dt;
  // Distance from the query (lat, lon) to site s under `m`, computed independently of the search.
  double dist(double lat, double lon, SiteId s, Metric m) const {
    const Vec3& p = dt.site(s);
    if (m == Metric::Sphere) {
      const Vec3 q = SiteEncoder::from_lat_lon(lat, lon);
      const long double dx = (long double)q.x - p.x, dy = (long double)q.y - p.y, dz = (long double)q.z - p.z;
      const long double chord = std::sqrt(dx * dx + dy * dy + dz * dz);
      return static_cast<double>(2 * (long double)SiteEncoder::kEarthRadiusM * std::asin(std::min<long double>(1, chord / 2)));
    }
    const LatLon ll = SiteEncoder::to_lat_lon(p);  // the site's position as every metric sees it
    double s12 = 0;
    GeographicLib::Geodesic::WGS84().Inverse(lat, lon, ll.lat_deg, ll.lon_deg, s12);
    return s12;
  }
  // Every live site and its distance, nearest first.
  std::vector<std::pair<double, SiteId>> all(double lat, double lon, Metric m) const {
    std::vector<std::pair<double, SiteId>> v;
    for (SiteId s = 0; s < dt.site_capacity(); ++s)
      if (dt.is_live(s)) v.emplace_back(dist(lat, lon, s, m), s);
    std::sort(v.begin(), v.end());
    return v;
  }
};

// Checks k_nearest and within for one query against the oracle.
void check_query(Locator& locator, const Oracle& oracle, double lat, double lon, std::size_t k, double radius_m,
                 Metric m) {
  SCOPED_TRACE(::testing::Message() << to_string(m) << " query " << lat << "," << lon << " k " << k
                                    << " radius " << radius_m);
  const auto truth = oracle.all(lat, lon, m);
  std::vector<NearestResult> got;
  k_nearest(locator, lat, lon, k, m, got);
  ASSERT_EQ(got.size(), std::min(k, truth.size()));
  std::set<SiteId> seen;
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_TRUE(seen.insert(got[i].site).second) << "site " << got[i].site << " twice";
    // The i-th distance is the oracle's i-th, and the site is really at that distance.
    EXPECT_NEAR(got[i].dist_m, truth[i].first, kTolM) << "rank " << i;
    EXPECT_NEAR(oracle.dist(lat, lon, got[i].site, m), got[i].dist_m, kTolM) << "rank " << i;
    // Where the oracle's distances are well apart, the site is the oracle's.
    const bool clear = (i == 0 || truth[i].first - truth[i - 1].first > kTolM) &&
                       (i + 1 == truth.size() || truth[i + 1].first - truth[i].first > kTolM);
    if (clear) {
      EXPECT_EQ(got[i].site, truth[i].second) << "rank " << i;
    }
  }

  within(locator, lat, lon, radius_m, m, got);
  std::set<SiteId> in;
  for (std::size_t i = 0; i < got.size(); ++i) {
    in.insert(got[i].site);
    EXPECT_LE(got[i].dist_m, radius_m);
    EXPECT_NEAR(oracle.dist(lat, lon, got[i].site, m), got[i].dist_m, kTolM);
    if (i > 0) {  // the sphere's order is exact, its distances rounded: equidistant sites may differ by an ulp
      EXPECT_LE(got[i - 1].dist_m, got[i].dist_m + kTolM);
    }
  }
  EXPECT_EQ(in.size(), got.size()) << "a site twice";
  for (const auto& [d, s] : truth) {
    if (d < radius_m - kTolM) {
      EXPECT_TRUE(in.count(s)) << "site " << s << " at " << d << " m missing";
    }
    if (d > radius_m + kTolM) {
      EXPECT_FALSE(in.count(s)) << "site " << s << " at " << d << " m included";
    }
  }
}

// Random queries, queries at the poles, on the antimeridian and at every kind of site position.
void check_set(const std::vector<Vec3>& sites, std::uint64_t seed, int random_queries = 60) {
  const DelaunayHierarchy h = DelaunayHierarchy::build(sites);
  const Oracle oracle{h.base()};
  Locator locator(h);
  std::vector<std::pair<double, double>> queries = {{90, 0},   {-90, 17}, {0, 180},      {0, -180},
                                                    {45, 180}, {-30, -179.9999999}, {89.9999, 180}};
  for (std::size_t i = 0; i < sites.size(); i += std::max<std::size_t>(1, sites.size() / 10)) {
    const LatLon ll = SiteEncoder::to_lat_lon(sites[i]);
    queries.emplace_back(ll.lat_deg, ll.lon_deg);
  }
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), lon(-180, 180);
  for (int i = 0; i < random_queries; ++i) queries.emplace_back(std::asin(u(rng)) * 180 / M_PI, lon(rng));
  std::uniform_int_distribution<int> kd(1, 20);
  std::uniform_real_distribution<double> rd(0, 3e6);
  for (const auto& [lat, lo] : queries)
    for (const Metric m : {Metric::Sphere, Metric::Geodesic}) check_query(locator, oracle, lat, lo, kd(rng), rd(rng), m);
}

TEST(Knn, UniformSites) { check_set(testing::uniform_on_sphere(2000, 3), 1); }

TEST(Knn, ClusteredSites) { check_set(testing::clustered(2000, 5, 0.05, 4), 2); }

// Equidistant sites everywhere: the grid's rows and columns, the poles given once.
TEST(Knn, LatLonGrid) { check_set(testing::lat_lon_grid(10), 3); }

// Many longitudes at both poles (merged into one site each) and rings next to them.
TEST(Knn, PolesWithLongitudes) { check_set(testing::poles_with_longitudes(40), 4); }

// Sites on both sides of the antimeridian, and repeated sites (merged into the first).
TEST(Knn, AntimeridianAndDuplicates) {
  std::vector<Vec3> sites;
  for (double lat = -80; lat <= 80; lat += 5)
    for (const double lon : {179.9, 179.999999, 180.0, -179.999999, -179.9, -179.0, 179.0}) {
      sites.push_back(SiteEncoder::from_lat_lon(lat, lon));
      sites.push_back(SiteEncoder::from_lat_lon(lat, lon));  // a duplicate
    }
  for (const Vec3& p : testing::uniform_on_sphere(200, 6)) sites.push_back(p);
  check_set(sites, 5);
}

TEST(Knn, FewSitesAndKBeyondThem) {
  const std::vector<Vec3> sites = {SiteEncoder::from_lat_lon(10, 20), SiteEncoder::from_lat_lon(-5, 100),
                                   SiteEncoder::from_lat_lon(60, -30)};
  const DelaunayHierarchy h = DelaunayHierarchy::build(sites);
  const Oracle oracle{h.base()};
  Locator locator(h);
  for (const Metric m : {Metric::Sphere, Metric::Geodesic}) {
    check_query(locator, oracle, 0, 0, 5, 2e7, m);
    check_query(locator, oracle, 90, 0, 3, 1e6, m);
  }
  std::vector<NearestResult> got;
  within(locator, 10, 20, -1, Metric::Geodesic, got);
  EXPECT_TRUE(got.empty());
  within(locator, 10, 20, NAN, Metric::Sphere, got);
  EXPECT_TRUE(got.empty());
  k_nearest(locator, 10, 20, 0, Metric::Sphere, got);
  EXPECT_TRUE(got.empty());
}

TEST(Knn, NoSites) {
  const DelaunayHierarchy h = DelaunayHierarchy::build(std::vector<Vec3>{});
  Locator locator(h);
  std::vector<NearestResult> got{{1, 2}};
  k_nearest(locator, 0, 0, 3, Metric::Geodesic, got);
  EXPECT_TRUE(got.empty());
  within(locator, 0, 0, 1e7, Metric::Sphere, got);
  EXPECT_TRUE(got.empty());
}

// k = 1 under the geodesic metric agrees with Locator::nearest_geodesic (both exact).
TEST(Knn, GeodesicKOneIsNearestGeodesic) {
  const DelaunayHierarchy h = DelaunayHierarchy::build(testing::uniform_on_sphere(5000, 9));
  Locator a(h), b(h);
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> u(-1, 1), lon(-180, 180);
  std::vector<NearestResult> got;
  for (int i = 0; i < 2000; ++i) {
    const double lat = std::asin(u(rng)) * 180 / M_PI, lo = lon(rng);
    k_nearest(a, lat, lo, 1, Metric::Geodesic, got);
    const NearestResult r = b.nearest_geodesic(lat, lo);
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].site, r.site);
    EXPECT_EQ(got[0].dist_m, r.dist_m);
  }
}

TEST(Knn, MetricNames) {
  EXPECT_EQ(parse_metric("sphere"), Metric::Sphere);
  EXPECT_EQ(parse_metric("geodesic"), Metric::Geodesic);
  EXPECT_STREQ(to_string(Metric::Geodesic), "geodesic");
  EXPECT_EQ(parse_metric("power"), Metric::Power);
  EXPECT_STREQ(to_string(Metric::Power), "power");
  EXPECT_THROW(parse_metric("manhattan"), Error);
}

TEST(Knn, PowerIsTheMetricOfWeightedSitesAndSphereOfOthers) {
  const auto pts = testing::uniform_on_sphere(1500, 11);
  std::vector<double> lifts(pts.size());
  for (std::size_t i = 0; i < lifts.size(); ++i) lifts[i] = std::cos(0.001 * static_cast<double>(i % 30));
  const DelaunayHierarchy weighted = DelaunayHierarchy::build(pts, lifts);
  const DelaunayHierarchy plain = DelaunayHierarchy::build(pts);
  EXPECT_EQ(default_metric(weighted), Metric::Power);
  EXPECT_EQ(default_metric(plain), Metric::Sphere);
  EXPECT_NO_THROW(check_metric(weighted, Metric::Power));
  EXPECT_NO_THROW(check_metric(plain, Metric::Power));
  for (const Metric m : {Metric::Sphere, Metric::Geodesic}) {
    try {
      check_metric(weighted, m);
      ADD_FAILURE() << to_string(m) << " accepted on weighted sites";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("power"), std::string::npos) << e.what();
    }
  }
  Locator wl(weighted), pl(plain), pl2(plain);
  std::vector<NearestResult> got, want;
  EXPECT_THROW(k_nearest(wl, 10, 20, 3, Metric::Sphere, got), Error);
  EXPECT_THROW(within(wl, 10, 20, 1e6, Metric::Geodesic, got), Error);
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1, 1), lon(-180, 180);
  for (int i = 0; i < 300; ++i) {
    const double lat = std::asin(u(rng)) * 180 / M_PI, lo = lon(rng);
    // Power on unweighted sites is the sphere metric.
    k_nearest(pl, lat, lo, 5, Metric::Power, got);
    k_nearest(pl2, lat, lo, 5, Metric::Sphere, want);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t j = 0; j < got.size(); ++j) EXPECT_EQ(got[j].site, want[j].site);
    // On weighted sites the first is the Locator's answer.
    k_nearest(wl, lat, lo, 8, Metric::Power, got);
    EXPECT_EQ(got.front().site, wl.nearest(SiteEncoder::from_lat_lon(lat, lo)).site);
  }
}

}  // namespace
}  // namespace geovor
