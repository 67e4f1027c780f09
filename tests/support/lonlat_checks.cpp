#include "support/lonlat_checks.hpp"

#include <cpl_conv.h>
#include <ogr_geometry.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor::testing {

Vec3 unit_of(const LonLat& p) {
  double lat = p.lat_deg, lon = p.lon_deg;
  const std::string why = normalize_lat_lon(lat, lon);
  if (!why.empty()) throw std::invalid_argument("unit_of: " + why);
  return SiteEncoder::from_lat_lon(lat, lon);
}

bool in_ring(const Ring& r, const LonLat& p, bool& boundary) {
  bool inside = false;
  boundary = false;
  for (std::size_t i = 0; i + 1 < r.size(); ++i) {
    const LonLat& a = r[i];
    const LonLat& b = r[i + 1];
    if (p.lon_deg >= std::min(a.lon_deg, b.lon_deg) - 1e-12 && p.lon_deg <= std::max(a.lon_deg, b.lon_deg) + 1e-12 &&
        p.lat_deg >= std::min(a.lat_deg, b.lat_deg) - 1e-12 && p.lat_deg <= std::max(a.lat_deg, b.lat_deg) + 1e-12) {
      const double cr =
          (b.lon_deg - a.lon_deg) * (p.lat_deg - a.lat_deg) - (b.lat_deg - a.lat_deg) * (p.lon_deg - a.lon_deg);
      const double len = std::hypot(b.lon_deg - a.lon_deg, b.lat_deg - a.lat_deg);
      if (std::fabs(cr) <= 1e-12 * len) {
        boundary = true;
        return true;
      }
    }
    if ((a.lat_deg > p.lat_deg) != (b.lat_deg > p.lat_deg)) {
      const double x = a.lon_deg + (p.lat_deg - a.lat_deg) * (b.lon_deg - a.lon_deg) / (b.lat_deg - a.lat_deg);
      if (p.lon_deg < x) inside = !inside;
    }
  }
  return inside;
}

bool in_multipolygon(const MultiPolygon& mp, const LonLat& p, bool& boundary) {
  boundary = false;
  for (const Polygon& poly : mp) {
    bool b = false;
    if (in_ring(poly.exterior, p, b)) {
      boundary = b;
      return true;
    }
  }
  return false;
}

std::string geos_invalid(const MultiPolygon& mp) {
  OGRMultiPolygon g;
  for (const Polygon& poly : mp) {
    auto* p = new OGRPolygon();
    auto* ring = new OGRLinearRing();
    for (const LonLat& q : poly.exterior) ring->addPoint(q.lon_deg, q.lat_deg);
    p->addRingDirectly(ring);
    for (const Ring& h : poly.holes) {
      auto* hole = new OGRLinearRing();
      for (const LonLat& q : h) hole->addPoint(q.lon_deg, q.lat_deg);
      p->addRingDirectly(hole);
    }
    g.addGeometryDirectly(p);
  }
  if (g.IsValid()) return {};
  char* wkt = nullptr;
  g.exportToWkt(&wkt);
  std::string out = wkt ? std::string(wkt).substr(0, 2000) : "(no WKT)";
  CPLFree(wkt);
  return out.empty() ? "(empty)" : out;
}

}  // namespace geovor::testing
