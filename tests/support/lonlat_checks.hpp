// Independent checks of lon/lat geometry shared by the geometry tests: a crossing-number point in
// polygon, the geocentric direction of a lon/lat position, and GEOS validity through OGR.
#pragma once

#include <string>

#include "geovor/core/types.hpp"
#include "geovor/lonlat/geometry.hpp"

namespace geovor::testing {

/// Geocentric unit direction of a lon/lat position (the inverse of SiteEncoder::to_lat_lon).
Vec3 unit_of(const LonLat& p);

/// Crossing-number point in ring in lon/lat; `boundary` is set when p is (numerically, 1e-12
/// degrees) on an edge of the ring, which then counts as inside.
bool in_ring(const Ring& r, const LonLat& p, bool& boundary);

/// Point in any exterior ring of the polygons (holes are not looked at).
bool in_multipolygon(const MultiPolygon& mp, const LonLat& p, bool& boundary);

/// Empty if GEOS (OGRGeometry::IsValid) finds the polygons valid, else the start of their WKT.
std::string geos_invalid(const MultiPolygon& mp);

}  // namespace geovor::testing
