/// \file lat_lon.hpp
/// \brief LatLon, a geodetic position on WGS84, and normalize_lat_lon, the one gate every
/// latitude/longitude passes before it becomes a site.
#pragma once

#include <string>

namespace geovor {

/// A geodetic position on the WGS84 ellipsoid: latitude and longitude (degrees).
struct LatLon {
  double lat_deg = 0;  ///< geodetic latitude (degrees), in [-90, 90]
  double lon_deg = 0;  ///< longitude (degrees), in [-180, 180)
};

/// Check a latitude/longitude pair and put it in canonical form, in place.
///
/// Accepted values are rewritten so that one point of the Earth has exactly one representation:
/// - the longitude is reduced into [-180, 180) with std::remainder (exact), so 180 becomes -180;
/// - at a pole (|lat| == 90) the longitude becomes 0, since every longitude there is one point;
/// - -0.0 becomes +0.0 in both.
///
/// Rejected values are left unchanged:
/// - NaN or infinite latitude or longitude;
/// - |lat| > 90;
/// - |lon| > 540: one extra turn is tolerated (e.g. 0..360 data), anything beyond is almost
///   certainly not a longitude in degrees (projected metres, radians times 1000, a typo).
///
/// \param[in,out] lat_deg geodetic latitude (degrees).
/// \param[in,out] lon_deg longitude (degrees).
/// \return "" when accepted, else the human-readable reason, e.g.
///   "latitude 91.5 is beyond +-90" or "longitude 1000 is out of range [-540, 540]".
std::string normalize_lat_lon(double& lat_deg, double& lon_deg);

}  // namespace geovor
