/// \file small_angle_test.cpp
/// \brief The small-angle polynomials against libm's atan, sin and cos over their whole range.
#include "geovor/core/small_angle.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace geovor {
namespace {

// The spacing of doubles at |v|.
double ulp(double v) { return std::nextafter(std::fabs(v), INFINITY) - std::fabs(v); }

// Within 2 ulps of the libm value (itself within an ulp of the truth) at 200,000 points of
// [-kSmallAngleMax, kSmallAngleMax], log-spaced down to 1e-12 and uniform, and at the ends.
TEST(SmallAngle, MatchesLibmOverTheRange) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int i = 0; i < 200000; ++i) {
    double x = i % 2 ? kSmallAngleMax * unit(rng) : kSmallAngleMax * std::pow(10.0, -12 * unit(rng));
    if (i == 0) x = kSmallAngleMax;
    for (const double v : {x, -x}) {
      EXPECT_NEAR(atan_small(v), std::atan(v), 2 * ulp(std::atan(v))) << v;
      EXPECT_NEAR(sin_small(v), std::sin(v), 2 * ulp(std::sin(v))) << v;
      EXPECT_NEAR(cos_small(v), std::cos(v), 2 * ulp(std::cos(v))) << v;
    }
  }
}

}  // namespace
}  // namespace geovor
