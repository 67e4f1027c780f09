#include "geovor/core/coordinate_grid.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

namespace geovor {
namespace {

constexpr double kPow10[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,
                             1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17};
constexpr std::uint64_t kPow5[] = {1ull,
                                   5ull,
                                   25ull,
                                   125ull,
                                   625ull,
                                   3125ull,
                                   15625ull,
                                   78125ull,
                                   390625ull,
                                   1953125ull,
                                   9765625ull,
                                   48828125ull,
                                   244140625ull,
                                   1220703125ull,
                                   6103515625ull,
                                   30517578125ull,
                                   152587890625ull,
                                   762939453125ull};

}  // namespace

unsigned __int128 scaled_decimal(double value, int precision) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  const std::uint64_t fraction = bits & ((std::uint64_t{1} << 52) - 1);
  const std::uint64_t m = biased == 0 ? fraction : fraction | (std::uint64_t{1} << 52);
  const int e = biased == 0 ? -1074 : biased - 1075;  // |value| = m * 2^e exactly
  // |value| * 10^p = m * 5^p * 2^(e + p), and m * 5^p < 2^53 * 5^17 < 2^93.
  const unsigned __int128 one = 1;
  const unsigned __int128 n = static_cast<unsigned __int128>(m) * kPow5[precision];
  const int shift = -(e + precision);
  if (shift <= 0) return n << (-shift);  // -shift = e + p < p <= 17: exact, below 2^110
  if (shift >= 127) return 0;            // n < 2^93 < half of 2^shift: rounds to 0
  const unsigned __int128 rem = n & ((one << shift) - 1);
  const unsigned __int128 half = one << (shift - 1);
  unsigned __int128 q = n >> shift;
  if (rem > half || (rem == half && (q & 1) != 0)) ++q;  // ties to even, as printf
  return q;
}

double snap_to_decimals(double value, int precision) {
  if (precision < 0 || precision > 17 || !std::isfinite(value) || std::fabs(value) >= 0x1p52) return value;
  std::uint64_t fast;
  const unsigned __int128 q = scaled_decimal_away_from_tie(value, precision, fast) ? fast : scaled_decimal(value, precision);
  // Past 2^53 the decimals are finer than the doubles around `value`: it reads back as itself.
  if (q >= (static_cast<unsigned __int128>(1) << 53)) return value;
  // q and 10^p are exact doubles: the division is the correctly rounded decimal.
  const double r = static_cast<double>(static_cast<std::uint64_t>(q)) / kPow10[precision];
  return r == 0 ? 0.0 : (std::signbit(value) ? -r : r);
}

}  // namespace geovor
