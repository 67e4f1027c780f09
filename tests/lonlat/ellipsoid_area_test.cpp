/// \file ellipsoid_area_test.cpp
/// \brief The ellipsoid areas against GeographicLib (the oracle): geodesic_s12 against
/// Geodesic::GenInverse on random edges in every quadrant and at every scale, near the poles, the
/// equator and the antimeridian; ellipsoid_area_m2 and the edge sums (sum_s12,
/// prime_meridian_transit, ring_area_m2) against PolygonArea on rings around a pole, across the
/// antimeridian and the prime meridian, tiny and larger than half the ellipsoid.
#include "geovor/lonlat/ellipsoid_area.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace geovor {
namespace {

const double kEllipsoidArea = GeographicLib::Geodesic::WGS84().EllipsoidArea();

double oracle_s12(const GeodesicEdge& e) {
  double s12, t, area;
  GeographicLib::Geodesic::WGS84().GenInverse(e.lat1_deg, e.lon1_deg, e.lat2_deg, e.lon2_deg,
                                              GeographicLib::Geodesic::AREA, s12, t, t, t, t, t, area);
  return area;
}

// The header's bound: a few units in the last place of S12.
double tolerance(double s12) { return 2e-14 * std::fabs(s12) + 1e-3; }

// Random edges from (lat1, lon1) by steps of 10^-u degrees, u uniform in [0, digits], within
// the latitude band; longitudes wrap to [-180, 180].
std::vector<GeodesicEdge> random_edges(std::mt19937_64& rng, int count, double max_lat, double max_step_deg,
                                       double digits) {
  std::uniform_real_distribution<double> unit(-1, 1), expo(0, digits);
  std::vector<GeodesicEdge> edges;
  for (int i = 0; i < count; ++i) {
    const double lat1 = max_lat * unit(rng), lon1 = 180 * unit(rng);
    const double step = max_step_deg * std::pow(10.0, -expo(rng));
    const double lat2 = std::clamp(lat1 + step * unit(rng), -90.0, 90.0);
    double lon2 = lon1 + step * unit(rng);
    if (lon2 > 180) lon2 -= 360;
    if (lon2 < -180) lon2 += 360;
    edges.push_back({lat1, lon1, lat2, lon2});
  }
  return edges;
}

void expect_matches_oracle(const std::vector<GeodesicEdge>& edges) {
  std::vector<double> s12(edges.size());
  geodesic_s12(edges, s12);
  int failures = 0;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const double want = oracle_s12(edges[i]);
    if (std::fabs(s12[i] - want) > tolerance(want) && ++failures <= 5)
      ADD_FAILURE() << "edge (" << edges[i].lat1_deg << ", " << edges[i].lon1_deg << ") -> (" << edges[i].lat2_deg
                    << ", " << edges[i].lon2_deg << "): S12 " << s12[i] << " instead of " << want;
  }
  EXPECT_EQ(failures, 0);
}

TEST(GeodesicS12, MatchesGenInverseOnShortEdges) {
  std::mt19937_64 rng(20261122);
  expect_matches_oracle(random_edges(rng, 100000, 89, 2.5, 9));
}

TEST(GeodesicS12, MatchesGenInverseNearThePolesAndTheEquator) {
  std::mt19937_64 rng(7);
  auto near = [&](double lat, double spread) {
    auto edges = random_edges(rng, 20000, 1, 2.5, 8);
    for (GeodesicEdge& e : edges) {
      const double dlat = e.lat2_deg - e.lat1_deg;
      e.lat1_deg = std::clamp(lat + spread * e.lat1_deg, -90.0, 90.0);
      e.lat2_deg = std::clamp(e.lat1_deg + dlat, -90.0, 90.0);
    }
    return edges;
  };
  expect_matches_oracle(near(89, 1));   // around the domain's edge at 89 degrees, and past it
  expect_matches_oracle(near(-89, 1));
  expect_matches_oracle(near(0, 1e-3));  // across the equator
  // On the equator, on a meridian, through the antimeridian, and a point to itself.
  expect_matches_oracle({{0, 10, 0, 11}, {0, 10, 0, 9}, {10, 5, 11, 5}, {-10, 5, -10.5, 5}, {0.5, 179.5, 0.6, -179.6},
                         {-30, -179.9, -30.1, 179.9}, {45, 20, 45, 20}, {-89.5, 0, -89.6, 1}, {90, 0, 89, 1}});
}

TEST(GeodesicS12, LongEdgesGoToGenInverseItself) {
  std::mt19937_64 rng(3);
  std::vector<GeodesicEdge> edges;
  for (const GeodesicEdge& e : random_edges(rng, 4000, 90, 180, 0.3))
    if (std::fabs(e.lat2_deg - e.lat1_deg) > 2.5 || std::fabs(std::remainder(e.lon2_deg - e.lon1_deg, 360.0)) > 2.5)
      edges.push_back(e);
  ASSERT_GT(edges.size(), 3000u);
  std::vector<double> s12(edges.size());
  geodesic_s12(edges, s12);
  for (std::size_t i = 0; i < edges.size(); ++i) EXPECT_EQ(s12[i], oracle_s12(edges[i]));
}

TEST(GeodesicS12, ResultsDoNotDependOnTheBatch) {
  std::mt19937_64 rng(11);
  const auto edges = random_edges(rng, 1000, 89, 3, 6);  // some outside the domain too
  std::vector<double> together(edges.size()), alone(1);
  geodesic_s12(edges, together);
  for (std::size_t i = 0; i < edges.size(); ++i) {
    geodesic_s12(std::span(&edges[i], 1), alone);
    EXPECT_EQ(alone[0], together[i]) << i;
  }
}

// A whole ring: the S12 sum of a small densified polygon gives PolygonArea's area.
TEST(GeodesicS12, RingSumGivesPolygonArea) {
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  for (int ring = 0; ring < 200; ++ring) {
    const double lat0 = 80 * unit(rng), lon0 = 180 * unit(rng), radius = std::pow(10.0, -3 * std::fabs(unit(rng)));
    std::vector<std::pair<double, double>> pts;
    for (int k = 0; k < 12; ++k) {
      const double a = 2 * 3.141592653589793 * k / 12;
      pts.push_back({lat0 + radius * std::sin(a), lon0 + radius * std::cos(a) / std::cos(lat0 * 3.141592653589793 / 180)});
    }
    GeographicLib::PolygonArea pa(geod);
    std::vector<GeodesicEdge> edges;
    for (std::size_t k = 0; k < pts.size(); ++k) {
      pa.AddPoint(pts[k].first, pts[k].second);
      const auto& q = pts[(k + 1) % pts.size()];
      edges.push_back({pts[k].first, pts[k].second, q.first, q.second});
    }
    double perimeter, want;
    pa.Compute(false, true, perimeter, want);
    std::vector<double> s12(edges.size());
    geodesic_s12(edges, s12);
    double sum = 0;
    for (const double s : s12) sum += s;
    const double whole = geod.EllipsoidArea();
    sum = std::remainder(sum, whole);
    // PolygonArea's counter-clockwise rings give -sum (its S12 sum is clockwise-positive).
    EXPECT_NEAR(-sum, want, 1e-9 * std::fabs(want) + 0.25) << "ring " << ring << " radius " << radius;
  }
}

TEST(EllipsoidArea, SimpleRings) {
  // The cut-ring form of a polar cap equals the cap as a ring around the pole.
  Ring cap;
  for (int lon = -180; lon <= 180; lon += 5) cap.push_back({static_cast<double>(lon), 80});
  cap.push_back({180, 90});
  cap.push_back({-180, 90});
  cap.push_back(cap.front());
  const double a = ellipsoid_area_m2({Polygon{cap, {}}});
  Ring rest(cap.rbegin(), cap.rend());
  for (LonLat& p : rest)
    if (p.lat_deg == 90) p.lat_deg = -90;
  EXPECT_NEAR(a + ellipsoid_area_m2({Polygon{rest, {}}}), kEllipsoidArea, 1);
  EXPECT_GT(a, 0);
  // A small counter-clockwise square, and the same as a hole.
  const Ring sq{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
  const double s = ellipsoid_area_m2({Polygon{sq, {}}});
  EXPECT_NEAR(s, 12308778361.5, 1e3);
  const Ring hole(sq.rbegin(), sq.rend());
  const Ring big{{-2, -2}, {3, -2}, {3, 3}, {-2, 3}, {-2, -2}};
  EXPECT_NEAR(ellipsoid_area_m2({Polygon{big, {hole}}}), ellipsoid_area_m2({Polygon{big, {}}}) - s,
              1e-3);
}

// A ring of n points on the circle of `radius` degrees about (lat0, lon0), counter-clockwise in
// lon/lat, closed, longitudes wrapped into [-180, 180] when `wrap` (GeographicLib does not mind).
Ring circle(double lat0, double lon0, double radius, int n, bool wrap = true) {
  Ring r;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * std::numbers::pi * k / n;
    double lon = lon0 + radius * std::cos(a) / std::cos(lat0 * std::numbers::pi / 180);
    if (wrap && lon > 180) lon -= 360;
    if (wrap && lon < -180) lon += 360;
    r.push_back({lon, lat0 + radius * std::sin(a)});
  }
  r.push_back(r.front());
  return r;
}

// PolygonArea's own area of a ring (counter-clockwise positive), the oracle.
double polygon_area(const Ring& ring, bool reverse = false) {
  GeographicLib::PolygonArea pa(GeographicLib::Geodesic::WGS84());
  for (std::size_t i = 0; i + 1 < ring.size(); ++i) pa.AddPoint(ring[i].lat_deg, ring[i].lon_deg);
  double perimeter = 0, area = 0;
  pa.Compute(reverse, true, perimeter, area);
  return area;
}

// The ring's area from its edges as CellGeometry sums them: S12 by geodesic_s12, crossings by
// prime_meridian_transit, then ring_area_m2.
double area_from_edges(const Ring& ring) {
  std::vector<GeodesicEdge> edges;
  int crossings = 0;
  for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
    edges.push_back({ring[i].lat_deg, ring[i].lon_deg, ring[i + 1].lat_deg, ring[i + 1].lon_deg});
    crossings += prime_meridian_transit(ring[i].lon_deg, ring[i + 1].lon_deg);
  }
  std::vector<double> s12(edges.size());
  geodesic_s12(edges, s12);
  CompensatedSum sum;
  sum += sum_s12(s12);
  return ring_area_m2(sum, crossings, ring);
}

double tolerance_m2(double area) { return 1e-9 * std::fabs(area) + 0.25; }

TEST(EllipsoidArea, TransitAsPolygonAreaCountsIt) {
  EXPECT_EQ(prime_meridian_transit(-1, 1), 1);
  EXPECT_EQ(prime_meridian_transit(1, -1), -1);
  EXPECT_EQ(prime_meridian_transit(-1, 0), 1);  // onto the meridian from the west counts
  EXPECT_EQ(prime_meridian_transit(0, 1), 0);
  EXPECT_EQ(prime_meridian_transit(179, -179), 0);  // the antimeridian is not the prime one
  EXPECT_EQ(prime_meridian_transit(-180, 180), 0);
  EXPECT_EQ(prime_meridian_transit(359, 1), 1);     // normalized: -1 -> 1
  EXPECT_EQ(prime_meridian_transit(10, 200), -1);   // normalized: 10 -> -160, westwards across 0
}

// Rings of every kind against PolygonArea: the edge sums give its area, and so does
// ellipsoid_area_m2 (which calls it; the larger-than-half rule and the whole rectangle aside).
TEST(EllipsoidArea, MatchesPolygonAreaOnVariedRings) {
  std::vector<std::pair<const char*, Ring>> rings = {
      {"small square", {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}},
      {"tiny (1e-7 degree)", circle(45, 7, 1e-7, 8)},
      {"across the prime meridian", circle(-30, 0.5, 3, 40)},
      {"across the antimeridian", circle(10, 179.5, 2, 40)},
      {"around the antimeridian, unwrapped", circle(-60, 180, 5, 40, false)},
      {"near the north pole", circle(89.5, 30, 0.4, 24)},
      {"large (30 degrees)", circle(20, -100, 30, 400)},
  };
  for (const auto& [name, ring] : rings) {
    const double want = polygon_area(ring);
    ASSERT_GT(want, 0) << name;
    EXPECT_NEAR(area_from_edges(ring), want, tolerance_m2(want)) << name;
    EXPECT_NEAR(ellipsoid_area_m2({Polygon{ring, {}}}), want, tolerance_m2(want)) << name;
  }
  // Around the north pole, the cut-ring form (through (180, 90) and (-180, 90)): PolygonArea of
  // the plain parallel ring, which encircles the pole, is the oracle.
  Ring cap, parallel;
  for (int lon = -180; lon <= 180; lon += 2) cap.push_back({static_cast<double>(lon), 75});
  for (int lon = -180; lon < 180; lon += 2) parallel.push_back({static_cast<double>(lon), 75});
  parallel.push_back(parallel.front());
  cap.push_back({180, 90});
  cap.push_back({-180, 90});
  cap.push_back(cap.front());
  const double cap_want = polygon_area(parallel);
  ASSERT_GT(cap_want, 1e12);
  EXPECT_NEAR(area_from_edges(cap), cap_want, tolerance_m2(cap_want));
  EXPECT_NEAR(ellipsoid_area_m2({Polygon{cap, {}}}), cap_want, tolerance_m2(cap_want));
  // Larger than half the ellipsoid: the lon/lat box [-170, 170] x [-80, 80] densified by a degree
  // (so that its edges follow the parallels). The oracle: PolygonArea of its two halves, each
  // smaller than half the ellipsoid, summed.
  auto densified_box = [](double w, double s, double e, double n) {
    Ring r;
    for (double lon = w; lon < e; ++lon) r.push_back({lon, s});
    for (double lat = s; lat < n; ++lat) r.push_back({e, lat});
    for (double lon = e; lon > w; --lon) r.push_back({lon, n});
    for (double lat = n; lat > s; --lat) r.push_back({w, lat});
    r.push_back(r.front());
    return r;
  };
  const Ring huge = densified_box(-170, -80, 170, 80);
  const double huge_want = polygon_area(densified_box(-170, -80, 0, 80)) + polygon_area(densified_box(0, -80, 170, 80));
  ASSERT_GT(huge_want, wgs84_area_m2() / 2);
  EXPECT_NEAR(area_from_edges(huge), huge_want, tolerance_m2(huge_want));
  EXPECT_NEAR(ellipsoid_area_m2({Polygon{huge, {}}}), huge_want, tolerance_m2(huge_want));
  // The whole lon/lat rectangle is the whole ellipsoid.
  const Ring whole{{-180, -90}, {180, -90}, {180, 90}, {-180, 90}, {-180, -90}};
  EXPECT_EQ(ellipsoid_area_m2({Polygon{whole, {}}}), wgs84_area_m2());
  EXPECT_EQ(wgs84_area_m2(), GeographicLib::Geodesic::WGS84().EllipsoidArea());
}

TEST(EllipsoidArea, PlanarArea) {
  EXPECT_EQ(planar_area_deg2({{0, 0}, {2, 0}, {2, 3}, {0, 3}, {0, 0}}), 6);
  EXPECT_EQ(planar_area_deg2({{0, 0}, {0, 3}, {2, 3}, {2, 0}, {0, 0}}), -6);
  EXPECT_EQ(planar_area_deg2({{-180, -90}, {180, -90}, {180, 90}, {-180, 90}, {-180, -90}}), 64800);
  EXPECT_EQ(planar_area_deg2({{0, 0}, {1, 1}, {0, 0}}), 0);  // fewer than 4 positions
}

}  // namespace
}  // namespace geovor
