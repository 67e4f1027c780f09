/// \file coordinate_grid_test.cpp
/// \brief snap_to_decimals against what a reader really gets: strtod of the text printf writes.
#include "geovor/core/coordinate_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>

#include "geovor/io/geojson_writer.hpp"

namespace geovor {
namespace {

// The double read back from `value` written with `precision` decimals by printf (correctly
// rounded by glibc), then parsed by strtod (correctly rounded).
double printed(double value, int precision) {
  char text[512];
  std::snprintf(text, sizeof text, "%.*f", precision, value);
  return std::strtod(text, nullptr);
}

// The double read back from what the GeoJSON writer writes.
double written(double value, int precision) {
  char text[kMaxCoordinateChars + 1] = {};
  *format_coordinate(text, value, precision) = '\0';
  return std::strtod(text, nullptr);
}

TEST(CoordinateGrid, IsWhatAReaderGetsBackAndIdempotent) {
  std::mt19937_64 rng(14);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::uniform_int_distribution<int> exponent(-30, 0);
  for (int i = 0; i < 200000; ++i) {
    const int p = i % 18;
    // Coordinates of every magnitude up to 180, halves of the grid (ties), grid points.
    double x = 180 * unit(rng) * std::pow(2.0, exponent(rng) * (i % 3 == 0));
    if (i % 7 == 0) x = (std::round(x * std::pow(10.0, p)) + 0.5) / std::pow(10.0, p);
    if (i % 11 == 0) x = std::round(x * std::pow(10.0, p)) / std::pow(10.0, p);
    const double r = snap_to_decimals(x, p);
    ASSERT_EQ(r, printed(x, p) == 0 ? 0.0 : printed(x, p)) << x << " at " << p;
    ASSERT_EQ(r, written(x, p) == 0 ? 0.0 : written(x, p)) << x << " at " << p;
    ASSERT_EQ(snap_to_decimals(r, p), r) << x << " at " << p;
    ASSERT_EQ(written(r, p), r) << x << " at " << p;
    ASSERT_FALSE(std::signbit(r) && r == 0);
  }
}

// The fast path gives scaled_decimal's integer whenever it answers, near ties too (values a few
// ulps either side of a half step), and answers for ordinary coordinates up to 9 decimals.
TEST(CoordinateGrid, FastPathIsScaledDecimalWhereItAnswers) {
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> unit(-180, 180);
  std::uniform_int_distribution<int> ulps(-64, 64);
  int answered = 0, total = 0;
  for (int i = 0; i < 300000; ++i) {
    const int p = i % 12;
    double x = unit(rng);
    if (i % 3 == 0) {  // near a tie of the grid
      x = (std::round(x * std::pow(10.0, p)) + 0.5) / std::pow(10.0, p);
      for (int k = ulps(rng); k != 0; k += k > 0 ? -1 : 1) x = std::nextafter(x, k > 0 ? 1e300 : -1e300);
    }
    std::uint64_t q = 0;
    const bool fast = scaled_decimal_away_from_tie(x, p, q);
    if (p <= 9 && i % 3 != 0) ++total, answered += fast;
    if (!fast) continue;
    ASSERT_EQ(static_cast<unsigned __int128>(q), scaled_decimal(x, p)) << x << " at " << p;
  }
  std::uint64_t unused = 0;
  EXPECT_FALSE(scaled_decimal_away_from_tie(0.5, 0, unused));  // a tie
  EXPECT_FALSE(scaled_decimal_away_from_tie(170.0000005001, 6, unused));  // within 2^-12 of one
  EXPECT_GT(answered, total - total / 1000);  // all but about 5e-4 of ordinary coordinates
}

TEST(CoordinateGrid, EdgesAndFullPrecision) {
  EXPECT_EQ(snap_to_decimals(180, 7), 180);
  EXPECT_EQ(snap_to_decimals(-90, 3), -90);
  EXPECT_EQ(snap_to_decimals(179.99999996, 7), 180);
  EXPECT_EQ(snap_to_decimals(-0.00000004, 7), 0);
  EXPECT_FALSE(std::signbit(snap_to_decimals(-0.00000004, 7)));
  EXPECT_EQ(snap_to_decimals(0.1 + 0.2, kFullPrecision), 0.1 + 0.2);
  EXPECT_EQ(snap_to_decimals(12.25, 1), 12.2);  // ties to even
  EXPECT_EQ(snap_to_decimals(12.35, 1), printed(12.35, 1));
  EXPECT_TRUE(std::isnan(snap_to_decimals(NAN, 7)));
}

}  // namespace
}  // namespace geovor
