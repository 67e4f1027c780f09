/// \file degenerate_case.hpp
/// \brief Which degenerate case a triangulation's sites are, in the terms of docs/user-guide.md
/// (`geovor info`'s `degenerate`): fewer than three sites, all on one great circle, or all in one
/// open hemisphere (ghost triangles).
#pragma once

#include "geovor/delaunay/spherical_delaunay.hpp"

namespace geovor {

/// "no sites", "one site", "two sites", "all sites on one great circle" (every triangle's
/// orientation exactly zero), "all sites in one open hemisphere" (some ghost triangle), or "none".
const char* degenerate_case(const SphericalDelaunay& dt);

}  // namespace geovor
