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

}  // namespace geovor
