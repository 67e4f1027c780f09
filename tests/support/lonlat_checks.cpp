#include "support/lonlat_checks.hpp"

#include <cpl_conv.h>
#include <ogr_geometry.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

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
  // A ring's points set at once: added one by one, OGR reallocates at each (quadratic under
  // ASan, whose realloc always copies: 600 s for a lune of 22,000 positions).
  std::vector<double> xs, ys;
  auto ogr_ring = [&](const Ring& r) {
    xs.clear(), ys.clear();
    for (const LonLat& q : r) xs.push_back(q.lon_deg), ys.push_back(q.lat_deg);
    auto* ring = new OGRLinearRing();
    ring->setPoints(static_cast<int>(xs.size()), xs.data(), ys.data());
    return ring;
  };
  OGRMultiPolygon g;
  for (const Polygon& poly : mp) {
    auto* p = new OGRPolygon();
    p->addRingDirectly(ogr_ring(poly.exterior));
    for (const Ring& h : poly.holes) p->addRingDirectly(ogr_ring(h));
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
