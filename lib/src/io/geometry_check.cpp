#include "geovor/io/geometry_check.hpp"

#include <cmath>

namespace geovor {
namespace {

std::string position_problem(const LonLat& p) {
  if (!std::isfinite(p.lon_deg) || !std::isfinite(p.lat_deg)) return "a coordinate is not finite";
  if (p.lon_deg < -180.0 || p.lon_deg > 180.0) {
    return "longitude " + std::to_string(p.lon_deg) + " is outside [-180, 180]";
  }
  if (p.lat_deg < -90.0 || p.lat_deg > 90.0) {
    return "latitude " + std::to_string(p.lat_deg) + " is outside [-90, 90]";
  }
  return "";
}

std::string positions_problem(const std::vector<LonLat>& ps) {
  // One branch-free pass first (NaN fails every comparison); the message only on failure.
  bool ok = true;
  for (const LonLat& p : ps) {
    ok &= (p.lon_deg >= -180.0) & (p.lon_deg <= 180.0) & (p.lat_deg >= -90.0) & (p.lat_deg <= 90.0);
  }
  if (ok) return "";
  for (const LonLat& p : ps) {
    if (auto why = position_problem(p); !why.empty()) return why;
  }
  return "";
}

std::string ring_problem(const Ring& ring) {
  if (ring.size() < 4) {
    return "a ring has " + std::to_string(ring.size()) + " positions, fewer than 4";
  }
  if (auto why = positions_problem(ring); !why.empty()) return why;
  // RFC 7946 §3.1.6: the first and last positions "MUST contain identical values".
  if (!(ring.front() == ring.back())) {
    return "a ring is not closed (its last position differs from its first)";
  }
  return "";
}

}  // namespace

std::string geometry_problem(const Geometry& geometry) {
  if (const auto* p = std::get_if<LonLat>(&geometry)) return is_null_point(*p) ? "" : position_problem(*p);
  if (const auto* lines = std::get_if<MultiLineString>(&geometry)) {
    for (const LineString& line : *lines) {
      if (line.size() < 2) {
        return "a line string has " + std::to_string(line.size()) + " positions, fewer than 2";
      }
      if (auto why = positions_problem(line); !why.empty()) return why;
    }
    return "";
  }
  for (const Polygon& poly : std::get<MultiPolygon>(geometry)) {
    if (auto why = ring_problem(poly.exterior); !why.empty()) return why;
    for (const Ring& hole : poly.holes) {
      if (auto why = ring_problem(hole); !why.empty()) return why;
    }
  }
  return "";
}

}  // namespace geovor
