#include "geovor/geo/lat_lon.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

namespace geovor {
namespace {

// Shortest text that reads back as the same double, so a reason never hides the offending digit.
std::string shortest(double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return r.ec == std::errc() ? std::string(buf, r.ptr) : std::string("?");
}

}  // namespace

std::string normalize_lat_lon(double& lat_deg, double& lon_deg) {
  if (!std::isfinite(lat_deg)) return "latitude is not a finite number";
  if (!std::isfinite(lon_deg)) return "longitude is not a finite number";
  if (std::fabs(lat_deg) > 90) return "latitude " + shortest(lat_deg) + " is beyond +-90";
  if (std::fabs(lon_deg) > 540) {
    return "longitude " + shortest(lon_deg) + " is out of range [-540, 540]";
  }
  // std::remainder is exact, so reduction never moves a point; the result lies in [-180, 180].
  double lon = std::remainder(lon_deg, 360.0);
  if (lon == 180) lon = -180;
  if (std::fabs(lat_deg) == 90) lon = 0;
  // -0.0 == 0.0, so this assignment turns -0.0 into +0.0: one bit pattern per point.
  if (lat_deg == 0) lat_deg = 0;
  if (lon == 0) lon = 0;
  lon_deg = lon;
  return "";
}

}  // namespace geovor
