/// \file geodesic_area_test.cpp
/// \brief geodesic_s12 against GeographicLib's own Geodesic::GenInverse (the oracle), on random
/// edges in every quadrant and at every scale, near the poles, the equator and the antimeridian.
#include "geovor/lonlat/ellipsoid_area.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace geovor {
namespace {

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

TEST(GeodesicArea, MatchesGenInverseOnShortEdges) {
  std::mt19937_64 rng(20261122);
  expect_matches_oracle(random_edges(rng, 100000, 89, 2.5, 9));
}

TEST(GeodesicArea, MatchesGenInverseNearThePolesAndTheEquator) {
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

TEST(GeodesicArea, LongEdgesGoToGenInverseItself) {
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

TEST(GeodesicArea, ResultsDoNotDependOnTheBatch) {
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
TEST(GeodesicArea, RingSumGivesPolygonArea) {
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

}  // namespace
}  // namespace geovor
