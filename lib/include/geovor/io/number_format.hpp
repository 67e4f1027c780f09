/// \file number_format.hpp
/// \brief Numbers as the GeoJSON writers write them: coordinates with a fixed number of decimals
/// (trailing zeros trimmed), reals in shortest round-trip form that stay Real for readers.
#pragma once

#include <string>

namespace geovor {

/// Largest number of characters format_coordinate() writes.
inline constexpr int kMaxCoordinateChars = 40;
/// Largest number of characters format_coordinate() writes (past the returned end too) for a
/// value of magnitude at most 180 (a longitude or latitude) at `precision` decimals (0 to 17):
/// a sign, three digits, the point, and the decimals or the 8 written at once when fewer.
constexpr int coordinate_chars_bound(int precision) { return 5 + (precision > 8 ? precision : 8); }
/// Largest number of characters format_real() writes.
inline constexpr int kMaxRealChars = 32;

/// Writes `value` with exactly `precision` decimals (correctly rounded, ties to even, the same
/// digits as std::to_chars(fixed, precision)), then trims trailing zeros and a trailing '.';
/// "-0" becomes "0". It computes round(value * 10^precision) exactly in 128-bit integers, which
/// is several times faster than std::to_chars and matters for large outputs. Values of magnitude
/// >= 2^52 (never a coordinate) are written in shortest round-trip form instead.
/// `value` must be finite and 0 <= precision <= 17. `out` must have room for
/// kMaxCoordinateChars characters, all of which may be written (past the returned end: scratch).
/// @return one past the last character of the number (at most kMaxCoordinateChars).
char* format_coordinate(char* out, double value, int precision);

/// Writes `value` (finite) in the shortest form that reads back to the same double
/// (std::to_chars), with ".0" appended when that form has no '.' or exponent, so that readers
/// keep the field Real. At most kMaxRealChars characters. @return one past the last character.
char* format_real(char* out, double value);

/// Appends format_real(value) to `out`.
void append_real(std::string& out, double value);

}  // namespace geovor
