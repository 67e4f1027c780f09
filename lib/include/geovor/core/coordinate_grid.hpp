/// \file coordinate_grid.hpp
/// \brief The coordinates a file holds: values rounded to a number of decimals, as a reader of the
/// written text gets them back.
///
/// A text format (GeoJSON) writes each coordinate with `precision` decimals, correctly rounded,
/// ties to even (io/geojson_writer.hpp's format_coordinate). What a reader gets back is the double
/// nearest to that decimal. snap_to_decimals() computes that double without any text, so that
/// geometry can be checked and measured as written: areas of the written rings, validity of the
/// written polygons (cell_geometry.hpp). Binary formats store doubles: kFullPrecision.
#pragma once

#include <cmath>
#include <cstdint>

namespace geovor {

/// The precision of binary formats, which store doubles as they are: no rounding.
inline constexpr int kFullPrecision = -1;

/// The double a reader parses from `value` written with `precision` decimals (0..17), i.e. the
/// double nearest to round_half_even(value * 10^precision) / 10^precision; `value` itself for
/// precision < 0, for a non-finite value and for |value| >= 2^52. The same double as parsing
/// format_coordinate(value, precision) back, and idempotent (ties of a half ulp aside): the result
/// snaps to itself, so writing it and reading it back gives it again. -0 becomes +0.
double snap_to_decimals(double value, int precision);

/// round_half_even(|value| * 10^precision), exactly (128-bit integers; no rounding of the
/// product), as printf rounds it: the digits snap_to_decimals and format_coordinate start from.
/// REQUIRES: value finite with |value| < 2^52, 0 <= precision <= 17 (the result is < 2^110).
unsigned __int128 scaled_decimal(double value, int precision);

/// scaled_decimal's common case without 128-bit arithmetic: true, with `q` set to the same
/// integer, when precision <= 9, |value| * 10^precision < 2^40 and that product is not within
/// 2^-12 of a tie; false otherwise (then call scaled_decimal). t = fl(|value| * 10^p) is within
/// half an ulp, at most 2^-14, of the exact product, so away from a tie both round alike.
/// REQUIRES: value finite, 0 <= precision.
inline bool scaled_decimal_away_from_tie(double value, int precision, std::uint64_t& q) {
  constexpr double kPow10[10] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  if (precision > 9) return false;
  const double t = std::fabs(value) * kPow10[precision];
  if (!(t < 0x1p40)) return false;
  // (t + 1.5 * 2^52) - 1.5 * 2^52 rounds t to an integer, ties to even; volatile: never folded.
  volatile double big = 6755399441055744.0;
  const double r = (t + big) - big;
  if (!(std::fabs(std::fabs(t - r) - 0.5) > 0x1p-12)) return false;
  q = static_cast<std::uint64_t>(r);
  return true;
}

}  // namespace geovor
