/// \file number_format_test.cpp
/// \brief format_coordinate() against std::to_chars(fixed) (the reference), format_real() against
/// shortest round trip.
#include "geovor/io/number_format.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace geovor {
namespace {

std::string coord(double v, int p) {
  char buf[kMaxCoordinateChars];
  return std::string(buf, format_coordinate(buf, v, p));
}

// std::to_chars(fixed) with trailing zeros trimmed and "-0" as "0": the reference.
std::string reference(double v, int p) {
  char buf[400];
  char* end = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, p).ptr;
  std::string s(buf, end);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

TEST(FormatCoordinate, MatchesToCharsFixed) {
  EXPECT_EQ(coord(180, 7), "180");
  EXPECT_EQ(coord(-180, 7), "-180");
  EXPECT_EQ(coord(0.1, 7), "0.1");
  EXPECT_EQ(coord(-0.0, 7), "0");
  EXPECT_EQ(coord(-0.00000004, 7), "0");
  EXPECT_EQ(coord(-0.00000005, 7), reference(-0.00000005, 7));
  EXPECT_EQ(coord(-0.00000006, 7), "-0.0000001");
  EXPECT_EQ(coord(0.125, 2), "0.12");              // exact tie: to even
  EXPECT_EQ(coord(0.375, 2), "0.38");
  EXPECT_EQ(coord(2.5, 0), "2");
  EXPECT_EQ(coord(1e-300, 7), "0");
  EXPECT_EQ(coord(5e-324, 17), "0");
  EXPECT_EQ(coord(12.3456789012, 7), "12.3456789");
  // Every 7th value of the 7 decimals (all digit patterns and numbers of trailing zeros), with
  // whole parts of 0, 1, 2 and 3 digits.
  for (std::int64_t k = 1; k < 10000000; k += 7) {
    const double v = static_cast<double>(k) / 1e7 + static_cast<double>(k % 4 == 0 ? 0 : k % 4 == 1 ? 7 : k % 4 == 2 ? 42 : 179);
    ASSERT_EQ(coord(v, 7), reference(v, 7)) << v;
    ASSERT_EQ(coord(-v, 7), reference(-v, 7)) << v;
  }
  for (std::int64_t k = 1; k <= 9; ++k)
    for (std::int64_t z = 1; z < 10000000; z *= 10) {
      const double v = static_cast<double>(k * z) / 1e7;
      ASSERT_EQ(coord(v, 7), reference(v, 7)) << v;
    }
  // Whole parts of 1, 2, 3 and more digits, just below and at each power of ten, every precision.
  for (const double v : {9.0, 10.0, 99.0, 100.0, 999.0, 1000.0, 123456.0})
    for (int p = 0; p <= 17; ++p)
      for (const double w : {v, std::nextafter(v, 0.0), -v, -std::nextafter(v, 0.0), v + 0.5, v - 0.25})
        ASSERT_EQ(coord(w, p), reference(w, p)) << w << " precision " << p;
  EXPECT_EQ(coord(4503599627370495.5, 17), reference(4503599627370495.5, 17));  // slow path
  // Near-ties of the 7th decimal (the fast path must leave them to the exact path).
  for (int k = -100000; k < 100000; ++k) {
    const double v = (k * 17 + 0.5) / 1e7;
    ASSERT_EQ(coord(v, 7), reference(v, 7)) << v;
    ASSERT_EQ(coord(std::nextafter(v, 1e9), 7), reference(std::nextafter(v, 1e9), 7)) << v;
    ASSERT_EQ(coord(std::nextafter(v, -1e9), 7), reference(std::nextafter(v, -1e9), 7)) << v;
  }
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> deg(-180, 180);
  std::uniform_int_distribution<int> prec(0, 17);
  std::uniform_int_distribution<std::uint64_t> bits;
  for (int i = 0; i < 200000; ++i) {
    const int p = prec(rng);
    double v = deg(rng);
    if (i % 4 == 1) v = std::ldexp(v, -static_cast<int>(rng() % 60));  // tiny values
    if (i % 4 == 2) v = std::round(v * 1024) / 1024 + std::ldexp(1.0, -11);  // binary ties
    if (i % 4 == 3) {  // any finite double below 2^52
      std::uint64_t b = bits(rng);
      std::memcpy(&v, &b, sizeof v);
      if (!std::isfinite(v) || std::abs(v) >= 4503599627370496.0) continue;
    }
    ASSERT_EQ(coord(v, p), reference(v, p)) << v << " precision " << p;
  }
}

// The GeoJSON encoder makes room per coordinate by coordinate_chars_bound: for a longitude or a
// latitude, format_coordinate writes nothing past it (its end included: it may write ahead).
TEST(FormatCoordinate, WritesWithinItsBoundForLonLat) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> deg(-180, 180);
  std::vector<double> values = {180, -180, 179.99999999999997, -179.99999999999997, 100, -100, 99.99999999,
                                -0.0, 0, 5e-324, 1e-300, 0.5, 123.456789012345678, -92.00000000000001};
  for (int i = 0; i < 20000; ++i) values.push_back(i % 2 ? deg(rng) : std::ldexp(deg(rng), -static_cast<int>(rng() % 40)));
  for (int p = 0; p <= 17; ++p) {
    const int bound = coordinate_chars_bound(p);
    ASSERT_LE(bound, kMaxCoordinateChars);
    for (const double v : values) {
      char buf[2 * kMaxCoordinateChars];
      std::memset(buf, '#', sizeof buf);
      char* end = format_coordinate(buf, v, p);
      ASSERT_EQ(std::string(buf, end), reference(v, p)) << v << " precision " << p;
      for (int k = bound; k < static_cast<int>(sizeof buf); ++k) ASSERT_EQ(buf[k], '#') << v << " precision " << p;
    }
  }
}

TEST(FormatReal, ShortestRoundTripWithDecimalPoint) {
  auto real = [](double v) {
    char buf[kMaxRealChars];
    return std::string(buf, format_real(buf, v));
  };
  EXPECT_EQ(real(2.0), "2.0");
  EXPECT_EQ(real(-0.0), "-0.0");
  EXPECT_EQ(real(0.1), "0.1");
  EXPECT_EQ(real(1e300), "1e+300");
  EXPECT_EQ(real(123456789012.0), "123456789012.0");
  EXPECT_EQ(real(-1.7976931348623157e308), "-1.7976931348623157e+308");
}

}  // namespace
}  // namespace geovor
