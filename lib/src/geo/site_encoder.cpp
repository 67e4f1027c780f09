#include "geovor/geo/site_encoder.hpp"

#include <GeographicLib/Ellipsoid.hpp>
#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/Math.hpp>
#include <cmath>
#include <string>

#include "geovor/core/assert.hpp"

namespace geovor {
namespace {

// -0.0 == 0.0, so the assignment turns -0.0 into +0.0: equal points get equal bit patterns.
double positive_zero(double v) { return v == 0 ? 0.0 : v; }

}  // namespace

Vec3 SiteEncoder::from_lat_lon(double lat_deg, double lon_deg) {
  using GeographicLib::Math;
  // The ECEF direction (cos lat cos lon, cos lat sin lon, (1 - e^2) sin lat) scaled by a length
  // that depends on the latitude alone, so that z depends on the latitude alone: sites sharing a
  // latitude are exactly coplanar (z = const) and their common Voronoi vertex is exactly a pole.
  // Dividing by the rounded length of (x, y, z) instead made z vary by ulps with the longitude,
  // which moved such a vertex up to metres off the pole (issue 14).
  static const double one_minus_e2 = [] {
    const double f1 = 1 - GeographicLib::Geocentric::WGS84().Flattening();
    return f1 * f1;
  }();
  double sin_lat = 0, cos_lat = 0, sin_lon = 0, cos_lon = 0;
  Math::sincosd(lat_deg, sin_lat, cos_lat);
  Math::sincosd(lon_deg, sin_lon, cos_lon);
  const double zs = one_minus_e2 * sin_lat;
  const double n = std::sqrt(cos_lat * cos_lat + zs * zs);
  const double c = cos_lat / n;
  const Vec3 u{positive_zero(c * cos_lon), positive_zero(c * sin_lon), positive_zero(zs / n)};
  // Predicates treat sites as exactly on the sphere; a few ulps of slack is all they tolerate.
  GEOVOR_ASSERT(std::fabs(u.x * u.x + u.y * u.y + u.z * u.z - 1) <= 0x1p-49);
  return u;
}

SiteEncoder::Geodetic SiteEncoder::from_ecef(double x_m, double y_m, double z_m) {
  Geodetic g{0, 0, 0};
  GeographicLib::Geocentric::WGS84().Reverse(x_m, y_m, z_m, g.lat_deg, g.lon_deg, g.height_m);
  return g;
}

LatLon SiteEncoder::to_lat_lon(const Vec3& u) {
  using GeographicLib::Math;
  // The geodetic latitude of the direction: tan(lat) = z / ((1 - e^2) rho), (1 - e^2) = (1 - f)^2,
  // in one atan2d (exact at multiples of 45 degrees, so the poles and the equator come out exact;
  // GeographicLib's geocentric-to-geodetic conversion takes three trigonometric calls instead).
  // sqrt rather than hypot (three times slower): |u| is far from overflow, and both are exact on
  // the axes.
  static const double one_minus_e2 = [] {
    const double f1 = 1 - GeographicLib::Ellipsoid::WGS84().Flattening();
    return f1 * f1;
  }();
  double lat = Math::atan2d(u.z, one_minus_e2 * std::sqrt(u.x * u.x + u.y * u.y));
  double lon = Math::atan2d(u.y, u.x);
  // normalize_lat_lon's canonical form (without its checks: atan2d's results are in range).
  if (lon == 180) lon = -180;
  if (std::fabs(lat) == 90) lon = 0;
  return {positive_zero(lat), positive_zero(lon)};
}

}  // namespace geovor
