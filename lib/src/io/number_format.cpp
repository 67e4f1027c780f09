#include "geovor/io/number_format.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "geovor/core/coordinate_grid.hpp"

namespace geovor {
namespace {

char* write_scaled(char* out, bool negative, std::uint64_t digits_value, int precision);

constexpr std::uint64_t pow10u(int p) {
  std::uint64_t r = 1;
  for (int i = 0; i < p; ++i) r *= 10;
  return r;
}
constexpr std::uint64_t kPow10u[18] = {pow10u(0),  pow10u(1),  pow10u(2),  pow10u(3),  pow10u(4),  pow10u(5),
                                       pow10u(6),  pow10u(7),  pow10u(8),  pow10u(9),  pow10u(10), pow10u(11),
                                       pow10u(12), pow10u(13), pow10u(14), pow10u(15), pow10u(16), pow10u(17)};
// "00" to "99", for writing decimals two at a time.
constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

}  // namespace

char* format_coordinate(char* out, double value, int precision) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  const bool negative = (bits >> 63) != 0;
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  const int e = biased == 0 ? -1074 : biased - 1075;  // value = m * 2^e, m < 2^53
  if (biased == 0x7ff || e >= 0 || precision < 0 || precision > 17) {
    // |value| >= 2^52 (an integer), not finite, or a bad precision: shortest round trip.
    return std::to_chars(out, out + kMaxCoordinateChars, value).ptr;
  }
  std::uint64_t fast;
  if (scaled_decimal_away_from_tie(value, precision, fast)) return write_scaled(out, negative, fast, precision);
  const unsigned __int128 one = 1;
  const unsigned __int128 q = scaled_decimal(value, precision);
  if (q >= (one << 63)) {
    // |value| * 10^p beyond 2^63 (|value| < 2^52 here, so at most 36 characters).
    char tmp[64];
    char* end = std::to_chars(tmp, tmp + sizeof tmp, value, std::chars_format::fixed, precision).ptr;
    if (std::find(tmp, end, '.') != end) {
      while (end[-1] == '0') --end;
      if (end[-1] == '.') --end;
    }
    char* begin = tmp;
    if (end - begin == 2 && tmp[0] == '-' && tmp[1] == '0') ++begin;
    return std::copy(begin, end, out);
  }
  return write_scaled(out, negative, static_cast<std::uint64_t>(q), precision);
}

namespace {

// The 8 decimal digits of x < 10^8 as the bytes of a word, the most significant in the lowest
// byte (the first in memory), without division instructions: x is split into two halves of 4
// digits in 32-bit lanes, each into two pairs in 16-bit lanes, each into two digits in bytes
// (the multiply-shift pairs divide exactly by 100 and by 10 in their ranges).
std::uint64_t eight_digits(std::uint64_t x) {
  static_assert(std::endian::native == std::endian::little);
  const std::uint64_t halves = (x / 10000) | ((x % 10000) << 32);
  const std::uint64_t high_pairs = ((halves * 10486) >> 20) & ((0x7FULL << 32) | 0x7FULL);
  const std::uint64_t pairs = ((halves - 100 * high_pairs) << 16) + high_pairs;
  std::uint64_t tens = ((pairs * 103) >> 10) & ((0xFULL << 48) | (0xFULL << 32) | (0xFULL << 16) | 0xFULL);
  tens += (pairs - 10 * tens) << 8;
  return tens;
}

// Writes +-q / 10^P with trailing zeros trimmed; "0" (never "-0") for q == 0. P is a template
// argument so that the divisions by 10^P compile to multiplications.
template <int P>
char* write_scaled_p(char* out, bool negative, std::uint64_t digits_value) {
  if (digits_value == 0) {
    *out++ = '0';
    return out;
  }
  if (negative) *out++ = '-';
  // The whole part (coordinates: below 1000), then the P decimals without their trailing zeros,
  // written two at a time from the end (no temporary buffer to copy).
  constexpr std::uint64_t scale = pow10u(P);
  std::uint64_t decimals_value = digits_value % scale;
  const std::uint64_t whole = digits_value / scale;
  if (whole < 10) {
    *out++ = static_cast<char>('0' + whole);
  } else if (whole < 100) {
    std::memcpy(out, kDigitPairs + 2 * whole, 2);
    out += 2;
  } else if (whole < 1000) {
    *out++ = static_cast<char>('0' + whole / 100);
    std::memcpy(out, kDigitPairs + 2 * (whole % 100), 2);
    out += 2;
  } else {
    out = std::to_chars(out, out + 24, whole).ptr;
  }
  if constexpr (P >= 1 && P <= 8) {
    // The decimals as 8 digits (P, then zeros) in one word, and its trailing zeros dropped.
    if (decimals_value != 0) {
      std::uint64_t digits = eight_digits(decimals_value * pow10u(8 - P));
      const int kept = 8 - std::countl_zero(digits) / 8;  // the last digits are the high bytes
      digits += 0x3030303030303030;                        // '0' in every byte
      *out++ = '.';
      std::memcpy(out, &digits, 8);  // within kMaxCoordinateChars, the rest overwritten later
      out += kept;
    }
    return out;
  }
  if (decimals_value != 0) {
    int decimals = P;
    while (decimals_value % 10 == 0) decimals_value /= 10, --decimals;
    *out++ = '.';
    char* end = out + decimals;
    char* p = end;
    for (; p - out >= 2; decimals_value /= 100) {
      p -= 2;
      std::memcpy(p, kDigitPairs + 2 * (decimals_value % 100), 2);
    }
    if (p != out) *--p = static_cast<char>('0' + decimals_value);
    out = end;
  }
  return out;
}

template <int... P>
constexpr auto scaled_writers(std::integer_sequence<int, P...>) {
  return std::array<char* (*)(char*, bool, std::uint64_t), sizeof...(P)>{&write_scaled_p<P>...};
}
constexpr auto kScaledWriters = scaled_writers(std::make_integer_sequence<int, 18>());

char* write_scaled(char* out, bool negative, std::uint64_t digits_value, int precision) {
  if (precision == 7) return write_scaled_p<7>(out, negative, digits_value);  // the default, inlined
  return kScaledWriters[static_cast<std::size_t>(precision)](out, negative, digits_value);
}

}  // namespace

char* format_real(char* out, double value) {
  char* end = std::to_chars(out, out + kMaxRealChars, value).ptr;
  if (std::isfinite(value) && std::find_if(out, end, [](char c) {
                                return c == '.' || c == 'e' || c == 'E';
                              }) == end) {
    *end++ = '.';
    *end++ = '0';
  }
  return end;
}

void append_real(std::string& out, double value) {
  char buf[kMaxRealChars];
  out.append(buf, format_real(buf, value));
}

}  // namespace geovor
