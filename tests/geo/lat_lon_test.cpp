/// \file lat_lon_test.cpp
/// \brief Tests of normalize_lat_lon: canonical form of accepted points, reasons for rejected ones.
#include "geovor/geo/lat_lon.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace geovor {
namespace {

struct Normalised {
  std::string reason;
  double lat, lon;
};

Normalised normalise(double lat, double lon) {
  std::string reason = normalize_lat_lon(lat, lon);
  return {reason, lat, lon};
}

TEST(NormalizeLatLon, AcceptsOrdinaryPointsUnchanged) {
  const auto r = normalise(48.8566, 2.3522);
  EXPECT_EQ(r.reason, "");
  EXPECT_EQ(r.lat, 48.8566);
  EXPECT_EQ(r.lon, 2.3522);
}

TEST(NormalizeLatLon, AntimeridianIsMinus180) {
  for (double lon : {180.0, -180.0, 540.0, -540.0}) {
    const auto r = normalise(10, lon);
    EXPECT_EQ(r.reason, "") << lon;
    EXPECT_EQ(r.lon, -180.0) << lon;
  }
}

TEST(NormalizeLatLon, ReducesLongitudeExactly) {
  // Quarter degrees are exact in binary, so the expected value is computed in integers.
  for (int q = -540 * 4; q <= 540 * 4; ++q) {
    const double lon = q / 4.0;
    int expected_q = ((q + 180 * 4) % (360 * 4) + 360 * 4) % (360 * 4) - 180 * 4;
    const auto r = normalise(-33.5, lon);
    ASSERT_EQ(r.reason, "") << lon;
    ASSERT_EQ(r.lon, expected_q / 4.0) << lon;
    ASSERT_FALSE(std::signbit(r.lon) && r.lon == 0) << lon;
    ASSERT_EQ(r.lat, -33.5);
  }
}

TEST(NormalizeLatLon, ReductionKeepsFractionalDigits) {
  const auto r = normalise(0, 359.123456789);
  EXPECT_EQ(r.reason, "");
  // 359.123456789 - 360 is exact (Sterbenz), so equality is the right check.
  EXPECT_EQ(r.lon, 359.123456789 - 360.0);
}

TEST(NormalizeLatLon, PolesHaveLongitudeZero) {
  for (double lon = -540; lon <= 540; lon += 7.25) {
    auto n = normalise(90, lon);
    EXPECT_EQ(n.reason, "");
    EXPECT_EQ(n.lat, 90.0);
    EXPECT_EQ(n.lon, 0.0);
    EXPECT_FALSE(std::signbit(n.lon));
    auto s = normalise(-90, lon);
    EXPECT_EQ(s.lat, -90.0);
    EXPECT_EQ(s.lon, 0.0);
    EXPECT_FALSE(std::signbit(s.lon));
  }
}

TEST(NormalizeLatLon, NegativeZeroBecomesPositiveZero) {
  const auto r = normalise(-0.0, -0.0);
  EXPECT_EQ(r.reason, "");
  EXPECT_FALSE(std::signbit(r.lat));
  EXPECT_FALSE(std::signbit(r.lon));
  const auto t = normalise(5, -360.0);  // remainder(-360, 360) is -0.0
  EXPECT_EQ(t.lon, 0.0);
  EXPECT_FALSE(std::signbit(t.lon));
}

TEST(NormalizeLatLon, BoundariesAreAccepted) {
  EXPECT_EQ(normalise(90, 0).reason, "");
  EXPECT_EQ(normalise(-90, 0).reason, "");
  EXPECT_EQ(normalise(0, 540).reason, "");
  EXPECT_EQ(normalise(0, -540).reason, "");
}

TEST(NormalizeLatLon, RejectsNonFinite) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(normalise(nan, 0).reason, "latitude is not a finite number");
  EXPECT_EQ(normalise(inf, 0).reason, "latitude is not a finite number");
  EXPECT_EQ(normalise(-inf, 0).reason, "latitude is not a finite number");
  EXPECT_EQ(normalise(0, nan).reason, "longitude is not a finite number");
  EXPECT_EQ(normalise(0, -inf).reason, "longitude is not a finite number");
}

TEST(NormalizeLatLon, RejectsLatitudeBeyond90) {
  EXPECT_EQ(normalise(91.5, 0).reason, "latitude 91.5 is beyond +-90");
  EXPECT_EQ(normalise(-91, 0).reason, "latitude -91 is beyond +-90");
  EXPECT_EQ(normalise(1e308, 0).reason, "latitude 1e+308 is beyond +-90");
  // The digit that makes the value wrong must be visible in the reason.
  const auto r = normalise(90.00000000001, 0);
  EXPECT_EQ(r.reason, "latitude 90.00000000001 is beyond +-90");
  EXPECT_NE(normalise(std::nextafter(90.0, 91.0), 0).reason, "");
}

TEST(NormalizeLatLon, RejectsAbsurdLongitude) {
  EXPECT_EQ(normalise(0, 1000).reason, "longitude 1000 is out of range [-540, 540]");
  EXPECT_EQ(normalise(0, -541).reason, "longitude -541 is out of range [-540, 540]");
  EXPECT_EQ(normalise(0, 261234.5).reason, "longitude 261234.5 is out of range [-540, 540]");
  EXPECT_NE(normalise(0, std::nextafter(540.0, 541.0)).reason, "");
}

TEST(NormalizeLatLon, RejectedValuesAreLeftUnchanged) {
  double lat = 91, lon = 720;
  EXPECT_NE(normalize_lat_lon(lat, lon), "");
  EXPECT_EQ(lat, 91.0);
  EXPECT_EQ(lon, 720.0);
}

}  // namespace
}  // namespace geovor
