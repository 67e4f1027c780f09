#include "lonlat/thin_triangles.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace geovor::lonlat {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

// The unit vector at latitude and longitude (degrees) on the sphere.
Vec3 at(double lat_deg, double lon_deg) {
  const double phi = lat_deg * kDeg, lam = lon_deg * kDeg;
  return {std::cos(phi) * std::cos(lam), std::cos(phi) * std::sin(lam), std::sin(phi)};
}

// The circumcentre of the triangle p, q, r on the unit sphere, on the side of p.
Vec3 circumcentre(const Vec3& p, const Vec3& q, const Vec3& r) {
  Vec3 c = cross(q - p, r - p);
  c = (1 / std::sqrt(norm2(c))) * c;
  return dot(c, p) > 0 ? c : -1.0 * c;
}

TEST(ThinThresholds, TwoAndFourStepsAtSevenDecimals) {
  const ThinThresholds th = thin_thresholds(7, 100);
  // A step of 1e-7 degree is 1.11 cm on the Earth: an edge of 2 cm folds, one of 3 cm does not.
  const double metre = 1 / SiteEncoder::kEarthRadiusM;
  EXPECT_LT(std::pow(0.02 * metre, 2), th.fold2);
  EXPECT_GT(std::pow(0.03 * metre, 2), th.fold2);
  EXPECT_LT(std::pow(0.04 * metre, 2), th.small2);
  EXPECT_GT(std::pow(0.05 * metre, 2), th.small2);
}

// At densify_m 100 m, a chord can turn by a degree from latitude 84.02 (tan = 1.5e-4 R / 100).
TEST(ThinThresholds, PoleGuardFrom84DegreesAt100Metres) {
  const double pole_guard2 = thin_thresholds(7, 100).pole_guard2;
  EXPECT_FALSE(near_pole_for_chords(at(83.9, 10), pole_guard2));
  EXPECT_TRUE(near_pole_for_chords(at(84.2, 10), pole_guard2));
  EXPECT_TRUE(near_pole_for_chords(at(-84.2, -170), pole_guard2));
  // A finer tolerance turns chords less: 10 m, from 89.40 degrees; a coarser one more: 1 km,
  // from 43.7 degrees.
  EXPECT_FALSE(near_pole_for_chords(at(89.3, 10), thin_thresholds(7, 10).pole_guard2));
  EXPECT_TRUE(near_pole_for_chords(at(89.5, 10), thin_thresholds(7, 10).pole_guard2));
  EXPECT_FALSE(near_pole_for_chords(at(43.5, 10), thin_thresholds(7, 1000).pole_guard2));
  EXPECT_TRUE(near_pole_for_chords(at(43.9, 10), thin_thresholds(7, 1000).pole_guard2));
}

TEST(RoundDownToFloat, TheLargestFloatNotAbove) {
  for (const double d : {0.1, 1e-20, 3.0e-14, 0.5, 1.0 / 3, 7.0}) {
    const float f = round_down_to_float(d);
    EXPECT_LE(static_cast<double>(f), d) << d;
    EXPECT_GT(static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity())), d) << d;
  }
  EXPECT_EQ(round_down_to_float(0.5), 0.5f);  // exact: kept
  EXPECT_EQ(round_down_to_float(0.0), 0.0f);
  EXPECT_LT(round_down_to_float(0.1), 0.1f);  // 0.1f is above 0.1
}

TEST(NearStraight, WithinThreeDegreesSixOf180) {
  const Vec3 p = at(0, 0), q = at(0, 10);
  EXPECT_TRUE(near_straight(p, q, at(0, -10)));   // 180 degrees
  EXPECT_TRUE(near_straight(p, q, at(0.5, -10)));  // 177.1
  EXPECT_FALSE(near_straight(p, q, at(1, -10)));   // 174.3
  EXPECT_FALSE(near_straight(p, q, at(0.5, 10)));  // 2.9 degrees: acute
}

TEST(IsCap, ACircumradiusOver8TimesTheLongestSideOrAWideNearStraightAngle) {
  auto cap = [](const Vec3& s, const Vec3& u, const Vec3& w) {
    const double longest2 = std::max({norm2(s - u), norm2(s - w), norm2(u - w)});
    return is_cap(s, u, w, circumcentre(s, u, w), longest2);
  };
  // Small triangles (sides of 0.01 degree): an equilateral one, and three sites on a meridian,
  // the middle one 1e-5 degree off it (an angle of 179.9 degrees).
  EXPECT_FALSE(cap(at(0, 0), at(0, 0.01), at(0.00866, 0.005)));
  EXPECT_TRUE(cap(at(0, 0), at(0.01, 0.00001), at(0.02, 0)));
  EXPECT_FALSE(cap(at(0, 0), at(0.01, 0.002), at(0.02, 0)));  // 157 degrees
  // Sides over 5 degrees: the circumradius test does not reach, the angle does (177 degrees).
  const Vec3 s = at(0, 0), u = at(0, 10), w = at(0.5, -10);
  EXPECT_FALSE(norm2(circumcentre(s, u, w) - s) > 64 * norm2(u - w));
  EXPECT_TRUE(cap(s, u, w));
  EXPECT_FALSE(cap(s, u, at(3, -10)));  // 163 degrees
}

}  // namespace
}  // namespace geovor::lonlat
