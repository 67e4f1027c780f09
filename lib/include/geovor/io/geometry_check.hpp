/// \file geometry_check.hpp
/// \brief The check every writer applies to a geometry before writing it.
#pragma once

#include <string>

#include "geovor/lonlat/geometry.hpp"

namespace geovor {

/// Why a geometry cannot be written, or "" if it can: every coordinate finite, longitudes in
/// [-180, 180], latitudes in [-90, 90]; every ring closed (last position bit-identical to the
/// first) with at least 4 positions; every line string with at least 2 positions. Orientation is
/// not checked (it is written as given).
std::string geometry_problem(const Geometry& geometry);

}  // namespace geovor
