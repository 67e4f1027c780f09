/// \file site_encoder_test.cpp
/// \brief Tests of SiteEncoder against closed-form WGS84 formulas written out independently.
#include "geovor/geo/site_encoder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "geovor/geo/lat_lon.hpp"

namespace geovor {
namespace {

constexpr double kA = 6378137.0;          // WGS84 equatorial radius (metres)
constexpr double kF = 1 / 298.257223563;  // WGS84 flattening
constexpr double kE2 = kF * (2 - kF);     // first eccentricity squared
constexpr double kDeg = std::numbers::pi / 180;

// Geocentric direction from the textbook relation tan(theta) = (1 - f)^2 tan(phi).
Vec3 expected_unit(double lat_deg, double lon_deg) {
  const double theta = std::atan((1 - kF) * (1 - kF) * std::tan(lat_deg * kDeg));
  const double lam = lon_deg * kDeg;
  return {std::cos(theta) * std::cos(lam), std::cos(theta) * std::sin(lam), std::sin(theta)};
}

// ECEF position of (lat, lon, h) with the prime vertical radius N = a / sqrt(1 - e^2 sin^2 phi).
Vec3 expected_ecef(double lat_deg, double lon_deg, double h_m) {
  const double phi = lat_deg * kDeg, lam = lon_deg * kDeg;
  const double n = kA / std::sqrt(1 - kE2 * std::sin(phi) * std::sin(phi));
  return {(n + h_m) * std::cos(phi) * std::cos(lam), (n + h_m) * std::cos(phi) * std::sin(lam),
          (n * (1 - kE2) + h_m) * std::sin(phi)};
}

bool has_negative_zero(const Vec3& u) {
  return (u.x == 0 && std::signbit(u.x)) || (u.y == 0 && std::signbit(u.y)) ||
         (u.z == 0 && std::signbit(u.z));
}

TEST(SiteEncoder, MatchesGeocentricLatitudeFormula) {
  for (double lat = -89.75; lat < 90; lat += 1.25) {
    for (double lon = -180; lon < 180; lon += 2.5) {
      const Vec3 u = SiteEncoder::from_lat_lon(lat, lon);
      const Vec3 e = expected_unit(lat, lon);
      ASSERT_NEAR(u.x, e.x, 1e-15) << lat << ", " << lon;
      ASSERT_NEAR(u.y, e.y, 1e-15) << lat << ", " << lon;
      ASSERT_NEAR(u.z, e.z, 1e-15) << lat << ", " << lon;
      ASSERT_LE(std::fabs(norm2(u) - 1), 0x1p-49);
      ASSERT_FALSE(has_negative_zero(u));
    }
  }
}

TEST(SiteEncoder, GeocentricLatitudeDiffersFromGeodeticAt45) {
  // The largest difference is 0.19242 degrees near 45 (gis.md 7.3): guards against a naive mapping.
  const Vec3 u = SiteEncoder::from_lat_lon(45, 0);
  const double theta_deg = std::atan2(u.z, std::hypot(u.x, u.y)) / kDeg;
  EXPECT_NEAR(45 - theta_deg, 0.19242, 5e-5);
}

TEST(SiteEncoder, AxesAreExact) {
  EXPECT_EQ(SiteEncoder::from_lat_lon(0, 0), (Vec3{1, 0, 0}));
  EXPECT_EQ(SiteEncoder::from_lat_lon(0, 90), (Vec3{0, 1, 0}));
  EXPECT_EQ(SiteEncoder::from_lat_lon(0, -90), (Vec3{0, -1, 0}));
  EXPECT_EQ(SiteEncoder::from_lat_lon(0, -180), (Vec3{-1, 0, 0}));
  EXPECT_EQ(SiteEncoder::from_lat_lon(90, 0), (Vec3{0, 0, 1}));
  EXPECT_EQ(SiteEncoder::from_lat_lon(-90, 0), (Vec3{0, 0, -1}));
}

TEST(SiteEncoder, PolesAreBitIdenticalForEveryLongitude) {
  for (double pole : {90.0, -90.0}) {
    const Vec3 reference = SiteEncoder::from_lat_lon(pole, 0);
    for (double lon = -180; lon <= 180; lon += 0.5) {
      double lat = pole, l = lon;
      ASSERT_EQ(normalize_lat_lon(lat, l), "");
      const Vec3 u = SiteEncoder::from_lat_lon(lat, l);
      ASSERT_EQ(u, reference) << lon;
      ASSERT_FALSE(has_negative_zero(u)) << lon;
      // Even without normalisation the pole does not depend on the longitude.
      ASSERT_EQ(SiteEncoder::from_lat_lon(pole, lon), reference) << lon;
    }
  }
}

TEST(SiteEncoder, AntimeridianIsOnePoint) {
  for (double lat = -90; lat <= 90; lat += 0.75) {
    const Vec3 east = SiteEncoder::from_lat_lon(lat, 180);
    const Vec3 west = SiteEncoder::from_lat_lon(lat, -180);
    ASSERT_EQ(east, west) << lat;
    ASSERT_FALSE(has_negative_zero(west)) << lat;
  }
}

TEST(SiteEncoder, RoundTripThroughToLatLon) {
  for (double lat = -90; lat <= 90; lat += 0.37) {
    for (double lon = -180; lon < 180; lon += 1.13) {
      double la = lat, lo = lon;
      ASSERT_EQ(normalize_lat_lon(la, lo), "");
      const LatLon p = SiteEncoder::to_lat_lon(SiteEncoder::from_lat_lon(la, lo));
      ASSERT_NEAR(p.lat_deg, la, 1e-9) << la << ", " << lo;
      ASSERT_NEAR(p.lon_deg, lo, 1e-9) << la << ", " << lo;
    }
  }
  for (double lat : {-90.0, -89.999999, 89.999999, 90.0}) {
    const LatLon p = SiteEncoder::to_lat_lon(SiteEncoder::from_lat_lon(lat, 0));
    EXPECT_NEAR(p.lat_deg, lat, 1e-9);
    EXPECT_EQ(p.lon_deg, 0.0);
  }
}

TEST(SiteEncoder, ToLatLonMatchesInverseFormulaAndIsCanonical) {
  // A direction at geocentric latitude theta has geodetic latitude atan(tan(theta) / (1-f)^2).
  for (double theta_deg = -80; theta_deg <= 80; theta_deg += 10) {
    const double t = theta_deg * kDeg, lam = 30 * kDeg;
    const Vec3 u{std::cos(t) * std::cos(lam), std::cos(t) * std::sin(lam), std::sin(t)};
    const LatLon p = SiteEncoder::to_lat_lon(u);
    EXPECT_NEAR(p.lat_deg, std::atan(std::tan(t) / ((1 - kF) * (1 - kF))) / kDeg, 1e-12);
    EXPECT_NEAR(p.lon_deg, 30, 1e-12);
  }
  // Length does not matter; the antimeridian comes back as -180; the poles with longitude 0.
  const LatLon w = SiteEncoder::to_lat_lon(Vec3{-2, 0, 0});
  EXPECT_EQ(w.lat_deg, 0.0);
  EXPECT_EQ(w.lon_deg, -180.0);
  const LatLon n = SiteEncoder::to_lat_lon(Vec3{0, 0, 3});
  EXPECT_EQ(n.lat_deg, 90.0);
  EXPECT_EQ(n.lon_deg, 0.0);
  const LatLon s = SiteEncoder::to_lat_lon(Vec3{0, 0, -1});
  EXPECT_EQ(s.lat_deg, -90.0);
  EXPECT_EQ(s.lon_deg, 0.0);
}

TEST(SiteEncoder, FromEcefOfParis) {
  const double lat = 48.8566, lon = 2.3522, h = 35;
  const Vec3 x = expected_ecef(lat, lon, h);
  const SiteEncoder::Geodetic g = SiteEncoder::from_ecef(x.x, x.y, x.z);
  EXPECT_NEAR(g.lat_deg, lat, 1e-9);
  EXPECT_NEAR(g.lon_deg, lon, 1e-9);
  EXPECT_NEAR(g.height_m, h, 1e-6);  // ECEF coordinates near 6.4e6 m carry 1e-9 m rounding
}

TEST(SiteEncoder, FromEcefAtPolesAndAntimeridian) {
  const SiteEncoder::Geodetic n = SiteEncoder::from_ecef(0, 0, 6356752.314245 + 100);
  EXPECT_EQ(n.lat_deg, 90.0);
  EXPECT_NEAR(n.height_m, 100, 1e-5);
  const SiteEncoder::Geodetic w = SiteEncoder::from_ecef(-kA, 0, 0);
  EXPECT_EQ(w.lat_deg, 0.0);
  EXPECT_EQ(std::fabs(w.lon_deg), 180.0);
  EXPECT_NEAR(w.height_m, 0, 1e-9);
}

TEST(SiteEncoder, HeightNeverMovesASite) {
  for (double lat : {-60.0, -12.5, 0.0, 33.3, 71.0}) {
    const Vec3 low = expected_ecef(lat, 100, 0);
    const Vec3 high = expected_ecef(lat, 100, 8848);
    const auto gl = SiteEncoder::from_ecef(low.x, low.y, low.z);
    const auto gh = SiteEncoder::from_ecef(high.x, high.y, high.z);
    EXPECT_NEAR(gh.height_m - gl.height_m, 8848, 1e-6);
    const Vec3 ul = SiteEncoder::from_lat_lon(gl.lat_deg, gl.lon_deg);
    const Vec3 uh = SiteEncoder::from_lat_lon(gh.lat_deg, gh.lon_deg);
    EXPECT_NEAR(ul.x, uh.x, 1e-14);
    EXPECT_NEAR(ul.y, uh.y, 1e-14);
    EXPECT_NEAR(ul.z, uh.z, 1e-14);
  }
}

TEST(SiteEncoder, EarthRadiusIsWgs84MeanRadius) {
  const double b = kA * (1 - kF);
  EXPECT_NEAR(SiteEncoder::kEarthRadiusM, (2 * kA + b) / 3, 1e-6);
}

}  // namespace
}  // namespace geovor
