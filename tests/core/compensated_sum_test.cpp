// CompensatedSum against GeographicLib::Accumulator<double> (its model), bit for bit.
#include "geovor/core/compensated_sum.hpp"

#include <GeographicLib/Accumulator.hpp>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

namespace geovor {
namespace {

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

// Terms of every kind: magnitudes from 1e-30 to 1e15, both signs, exact cancellations, zeros,
// repeated values (the S12 terms of a ring are of mixed sizes and cancel to a small area).
TEST(CompensatedSum, MatchesGeographicLibAccumulatorBitForBit) {
  std::mt19937_64 rng(2026);
  std::uniform_real_distribution<double> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-30, 15), kind(0, 9);
  const double whole = 510065621724088.4;  // WGS84 ellipsoid area, m^2
  for (int sequence = 0; sequence < 20000; ++sequence) {
    CompensatedSum ours;
    GeographicLib::Accumulator<double> theirs;
    double last = 0;
    const int length = 1 + sequence % 40;
    for (int i = 0; i < length; ++i) {
      double term = mantissa(rng) * std::pow(10.0, exponent(rng));
      switch (kind(rng)) {
        case 0: term = -last; break;  // cancels the previous term
        case 1: term = 0; break;
        case 2: term = last; break;
        default: break;
      }
      last = term;
      switch (kind(rng)) {
        case 0:
          ours -= term;
          theirs -= term;
          break;
        case 1:
          ours.remainder(whole);
          theirs.remainder(whole);
          break;
        case 2:
          ours *= -1;
          theirs *= -1;
          break;
        default:
          ours += term;
          theirs += term;
          break;
      }
      ASSERT_EQ(bits(ours()), bits(theirs())) << "sequence " << sequence << " step " << i;
      ASSERT_EQ(ours < term, theirs < term);
      ASSERT_EQ(ours > term, theirs > term);
      ASSERT_EQ(ours <= 0, theirs <= 0);
      ASSERT_EQ(ours >= 0, theirs >= 0);
    }
    // The hidden second word agrees too: it shows in the next addition of a tiny term.
    ours += 1e-300;
    theirs += 1e-300;
    ASSERT_EQ(bits(ours()), bits(theirs())) << "sequence " << sequence;
  }
}

// The point of the second word: 1 + 1e-17 - 1 is 1e-17, not 0.
TEST(CompensatedSum, KeepsWhatPlainAdditionLoses) {
  CompensatedSum s = 1;
  s += 1e-17;
  s -= 1;
  EXPECT_EQ(s(), 1e-17);
  double plain = 1;
  plain += 1e-17;
  plain -= 1;
  EXPECT_EQ(plain, 0);
}

}  // namespace
}  // namespace geovor
