/// \file geometry.hpp
/// \brief Geometry in longitude/latitude degrees, as GIS formats store it (RFC 7946 rules).
///
/// Rings are closed by a bit-exact copy of their first position; exterior rings run
/// counter-clockwise in (lon, lat), holes clockwise; no ring crosses the antimeridian (a cell
/// that does is cut into a MultiPolygon), longitudes are within [-180, 180] and latitudes within
/// [-90, 90]. A ring around a pole runs along the boundary from -180 to 180 and closes through
/// (180, +-90) and (-180, +-90).
#pragma once

#include <limits>
#include <variant>
#include <vector>

namespace geovor {

/// A position: longitude first, as in GeoJSON and OGR's traditional GIS axis order (degrees).
struct LonLat {
  double lon_deg = 0, lat_deg = 0;
  friend bool operator==(const LonLat&, const LonLat&) = default;
};

using Ring = std::vector<LonLat>;  ///< closed: back() == front()
struct Polygon {
  Ring exterior;
  std::vector<Ring> holes;
};
using MultiPolygon = std::vector<Polygon>;
using LineString = std::vector<LonLat>;
using MultiLineString = std::vector<LineString>;

/// RFC 7946 bounding box; west > east when it spans the antimeridian (§5.2).
struct BBox {
  double west = 0, south = 0, east = 0, north = 0;
};

/// One feature's geometry: a point (sites), lines (Delaunay edges) or polygons (cells, triangles).
using Geometry = std::variant<LonLat, MultiLineString, MultiPolygon>;

/// A Point without a position (a row that has none, e.g. a malformed query): written as a null
/// geometry. Test with is_null_point().
inline constexpr LonLat kNullPoint{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
inline bool is_null_point(const LonLat& p) { return p.lon_deg != p.lon_deg && p.lat_deg != p.lat_deg; }

}  // namespace geovor
