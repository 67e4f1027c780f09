/// \file site_weights.hpp
/// \brief The radius of each weighted site, read from a column of its table (docs/weighted.md).
///
/// A weighted site is a circle on the sphere: its row's radius r in metres, 0 <= r < pi R / 2 (a
/// quarter of the circumference, R = SiteEncoder::kEarthRadiusM), becomes the lift cos(r / R)
/// that SphericalDelaunay::build(points, lifts) takes.
#pragma once

#include <string>
#include <vector>

#include "geovor/geo/site_reader.hpp"

namespace geovor {

/// The lift cos(r_m / R) of a circle of radius r_m metres, rounded once: what the predicates use.
/// REQUIRES: 0 <= r_m < max_site_radius_m() (the lift is then in (0, 1]).
double site_lift(double r_m);

/// The largest radius allowed, exclusive: a quarter of the circumference (metres).
double max_site_radius_m();

/// Reads every accepted row's radius from the column `field` (name compared trimmed and
/// case-insensitively) into InputSite::weight_m and sets table.weighted. A row whose value is
/// empty, not a number or outside [0, max_site_radius_m()) moves to table.rejected with the reason
/// naming the column (rejected rows stay in row order; rows_read is unchanged). A decimal comma is
/// read as in the coordinates when the delimiter is not a comma.
/// @exception Error(InvalidArgument) naming the columns if none is `field`.
void read_site_weights(SiteTable& table, const std::string& field);

/// Why r_m is no radius (not finite, negative, or not below max_site_radius_m()); empty if it is.
std::string radius_problem(double r_m);

/// The lift cos(weight_m / R) of each site of a table read with read_site_weights, in order.
std::vector<double> site_lifts(const SiteTable& table);  // site_lift(weight_m) of each

}  // namespace geovor
