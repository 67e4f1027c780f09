// Fuzz target: cells clipped to regions (layers/region_clip.hpp). The first byte picks the sites
// (uniform points, a lat/lon grid with both poles and +-180, or clusters at the poles and along
// the antimeridian), the second the precision (4 to 9 decimals, or doubles); the rest are up to
// 3 regions of up to 2 polygons of 3 to 12 vertices each, anywhere (on +-180 and +-90 too, on a
// coarse or a fine lattice), self-intersecting or not. Every piece must be valid (GEOS) and on
// the grid, with an area above 0 (or reported: a region's edges meeting at a pole askew fold on
// the sphere), the shares of each region with pieces must sum to 1 within 1e-9, and the pieces of a
// region must cover the (repaired, snapped) region: their planar areas sum to its area within
// 1e-6. Never a crash or a hang. FUZZ_CLIP_DUMP=1 prints the regions decoded (for triage).
#include <geos_c.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "fuzz_bytes.hpp"
#include "fuzz_check.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/layers/region_clip.hpp"

namespace {

using namespace geovor;

std::vector<Vec3> sites(int recipe) {
  std::vector<Vec3> p;
  std::uint64_t x = 88172645463325252ull;
  auto next = [&] {
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    return static_cast<double>(x >> 11) * 0x1p-53;
  };
  // One call of next() per statement: the order of a call's arguments is unspecified.
  auto at = [&](double lat, double lon) { p.push_back(SiteEncoder::from_lat_lon(lat, lon)); };
  if (recipe == 0) {
    for (int i = 0; i < 300; ++i) {
      const double lat = std::asin(2 * next() - 1) * 180 / M_PI;
      const double lon = 360 * next() - 180;
      at(lat, lon);
    }
  } else if (recipe == 1) {
    for (int lat = -90; lat <= 90; lat += 15)
      for (int lon = -180; lon < 180; lon += (lat == -90 || lat == 90) ? 360 : 20) p.push_back(SiteEncoder::from_lat_lon(lat, lon));
  } else {
    for (int i = 0; i < 100; ++i) {
      const double north = 89 + next();
      const double north_lon = 360 * next() - 180;
      const double south = -89 - next();
      const double south_lon = 360 * next() - 180;
      const double lat = 60 * next() - 30;
      const bool east = next() < 0.5;
      const double lon = east ? 179.5 + 0.5 * next() : -180 + 0.5 * next();
      at(north, north_lon);
      at(south, south_lon);
      at(lat, lon);
    }
  }
  return p;
}

double coordinate(Bytes& in, double limit, bool fine) {
  const std::uint8_t b = in.u8();
  return fine ? in.range(-limit, limit) : -limit + (2 * limit) * (b % 9) / 8.0;  // coarse: the edges and the middle
}

Ring ring(Bytes& in) {
  const int n = 3 + in.u8() % 10;
  const bool fine = in.u8() & 1;
  Ring r;
  for (int i = 0; i < n; ++i) r.push_back({coordinate(in, 180, fine), coordinate(in, 90, fine)});
  r.push_back(r.front());
  return r;
}

double planar_area(const MultiPolygon& mp) {
  double total = 0;
  for (const Polygon& p : mp)
    for (std::size_t k = 0; k <= p.holes.size(); ++k) {
      const Ring& r = k == 0 ? p.exterior : p.holes[k - 1];
      double a = 0;
      for (std::size_t i = 0; i + 1 < r.size(); ++i) a += r[i].lon_deg * r[i + 1].lat_deg - r[i + 1].lon_deg * r[i].lat_deg;
      total += k == 0 ? std::abs(a) / 2 : -std::abs(a) / 2;
    }
  return total;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  static const std::vector<Vec3> site_sets[3] = {sites(0), sites(1), sites(2)};
  const std::vector<Vec3>& points = site_sets[in.u8() % 3];
  const int p = in.u8() % 7;
  const int precision = p == 6 ? kFullPrecision : 4 + p;
  RegionTable regions;
  const int n_regions = 1 + in.u8() % 3;
  for (int r = 0; r < n_regions && !in.empty(); ++r) {
    Region region;
    region.id = std::to_string(r);
    const int parts = 1 + in.u8() % 2;
    for (int k = 0; k < parts; ++k) region.geometry.push_back({ring(in), {}});
    regions.regions.push_back(std::move(region));
  }
  if (std::getenv("FUZZ_CLIP_DUMP"))
    for (const Region& region : regions.regions)
      for (const Polygon& poly : region.geometry) {
        std::fprintf(stderr, "region %s part:", region.id.c_str());
        for (const LonLat& v : poly.exterior) std::fprintf(stderr, " (%.17g %.17g)", v.lon_deg, v.lat_deg);
        std::fprintf(stderr, "\n");
      }
  const SphericalDelaunay dt = SphericalDelaunay::build(points);
  const VoronoiDiagram diagram(dt);
  CellGeometryOptions options;
  options.precision = precision;
  const CellGeometry cells(diagram, options);
  RegionClipReport report;
  const std::vector<ClipPiece> pieces = clip_cells_to_regions(diagram, cells, regions, {.threads = 1}, report);

  if (std::getenv("FUZZ_CLIP_DUMP"))
    std::fprintf(stderr, "pieces %zu, cells tested %zu, outside %zu\n", pieces.size(), report.cells_tested, report.sites_outside.size());
  if (std::getenv("FUZZ_CLIP_DUMP"))
    for (const RegionProblem& problem : report.problems) std::fprintf(stderr, "problem: region %u: %s\n", problem.region, problem.reason.c_str());
  GEOSContextHandle_t h = GEOS_init_r();
  std::vector<double> shares(regions.regions.size(), 0), planar(regions.regions.size(), 0);
  std::vector<int> count(regions.regions.size(), 0);
  const double scale = precision < 0 ? 0 : std::pow(10.0, precision);
  for (const ClipPiece& piece : pieces) {
    shares[piece.region] += piece.region_share;
    planar[piece.region] += planar_area(piece.geometry);
    ++count[piece.region];
    std::vector<GEOSGeometry*> polys;
    for (const Polygon& poly : piece.geometry) {
      std::vector<GEOSGeometry*> holes;
      auto make = [&](const Ring& r) {
        GEOSCoordSequence* s = GEOSCoordSeq_create_r(h, static_cast<unsigned>(r.size()), 2);
        for (unsigned i = 0; i < r.size(); ++i) {
          GEOSCoordSeq_setXY_r(h, s, i, r[i].lon_deg, r[i].lat_deg);
          if (scale > 0)
            FUZZ_CHECK(std::round(r[i].lon_deg * scale) / scale == r[i].lon_deg, "off the grid: %.17g", r[i].lon_deg);
        }
        return GEOSGeom_createLinearRing_r(h, s);
      };
      for (const Ring& r : poly.holes) holes.push_back(make(r));
      polys.push_back(GEOSGeom_createPolygon_r(h, make(poly.exterior), holes.data(), static_cast<unsigned>(holes.size())));
    }
    GEOSGeometry* g = GEOSGeom_createCollection_r(h, GEOS_MULTIPOLYGON, polys.data(), static_cast<unsigned>(polys.size()));
    FUZZ_CHECK(GEOSisValid_r(h, g) == 1, "invalid piece of site %u in region %u", piece.site, piece.region);
    GEOSGeom_destroy_r(h, g);
    if (std::getenv("FUZZ_CLIP_DUMP") && !(piece.area_m2 > 0)) {
      std::fprintf(stderr, "piece of site %u:", piece.site);
      for (const Polygon& poly : piece.geometry)
        for (const LonLat& v : poly.exterior) std::fprintf(stderr, " (%.17g %.17g)", v.lon_deg, v.lat_deg);
      std::fprintf(stderr, "\n");
    }
    bool reported = false;
    for (const RegionProblem& problem : report.problems)
      reported = reported || (problem.region == piece.region &&
                              problem.reason.find("piece of site " + std::to_string(piece.site) + " measures") != std::string::npos);
    FUZZ_CHECK((piece.area_m2 > 0 || reported) && std::isfinite(piece.region_share), "piece area %g share %g, not reported",
               piece.area_m2, piece.region_share);
  }
  for (std::size_t r = 0; r < regions.regions.size(); ++r) {
    if (count[r] == 0) continue;
    bool no_area = false;
    for (const RegionProblem& problem : report.problems)
      no_area = no_area || (problem.region == r && problem.reason.find("measure no area") != std::string::npos);
    FUZZ_CHECK(std::abs(shares[r] - 1) <= 1e-9 || (no_area && shares[r] == 0), "region %zu: shares sum to %.17g", r, shares[r]);
    // The pieces cover the region as GEOS repairs and snaps it, within the grid's rounding.
    std::vector<GEOSGeometry*> polys;
    for (const Polygon& poly : regions.regions[r].geometry) {
      GEOSCoordSequence* s = GEOSCoordSeq_create_r(h, static_cast<unsigned>(poly.exterior.size()), 2);
      for (unsigned i = 0; i < poly.exterior.size(); ++i) GEOSCoordSeq_setXY_r(h, s, i, poly.exterior[i].lon_deg, poly.exterior[i].lat_deg);
      polys.push_back(GEOSGeom_createPolygon_r(h, GEOSGeom_createLinearRing_r(h, s), nullptr, 0));
    }
    GEOSGeometry* g = GEOSGeom_createCollection_r(h, GEOS_MULTIPOLYGON, polys.data(), static_cast<unsigned>(polys.size()));
    GEOSGeometry* valid = GEOSMakeValid_r(h, g);
    GEOSGeometry* snapped = scale > 0 ? GEOSGeom_setPrecision_r(h, valid, 1 / scale, 0) : GEOSGeom_clone_r(h, valid);
    double area = 0, length = 0;
    GEOSArea_r(h, snapped, &area);
    GEOSLength_r(h, snapped, &length);
    const double slack = 1e-6 * area + (scale > 0 ? 2 * length / scale : 1e-9);
    if (std::getenv("FUZZ_CLIP_DUMP") && std::abs(planar[r] - area) > slack) {
      char* wkt = GEOSGeomToWKT_r(h, snapped);
      std::fprintf(stderr, "region %zu as GEOS repairs it: %.2000s\n", r, wkt);
      GEOSFree_r(h, wkt);
      for (SiteId site = 0; site < diagram.site_capacity(); ++site) {
        MultiPolygon mp;
        double a = 0;
        if (cells.polygon(site, mp, a) != CellStatus::Written) continue;
        std::vector<GEOSGeometry*> cp;
        for (const Polygon& poly : mp) {
          GEOSCoordSequence* s = GEOSCoordSeq_create_r(h, static_cast<unsigned>(poly.exterior.size()), 2);
          for (unsigned i = 0; i < poly.exterior.size(); ++i) GEOSCoordSeq_setXY_r(h, s, i, poly.exterior[i].lon_deg, poly.exterior[i].lat_deg);
          cp.push_back(GEOSGeom_createPolygon_r(h, GEOSGeom_createLinearRing_r(h, s), nullptr, 0));
        }
        GEOSGeometry* cell = GEOSGeom_createCollection_r(h, GEOS_MULTIPOLYGON, cp.data(), static_cast<unsigned>(cp.size()));
        GEOSGeometry* i = GEOSIntersection_r(h, snapped, cell);
        double ia = 0;
        if (i) GEOSArea_r(h, i, &ia);
        bool have = false;
        double mine = 0;
        for (const ClipPiece& piece : pieces)
          if (piece.site == site && piece.region == r) have = true, mine += planar_area(piece.geometry);
        if (have && std::abs(mine - ia) > 1e-6) {
          const LatLon ll = SiteEncoder::to_lat_lon(diagram.site(site));
          std::fprintf(stderr, "site %u at (%g, %g): piece %g square degrees, GEOS %g\n", site, ll.lat_deg, ll.lon_deg, mine, ia);
        }
        if (ia > 1e-6 && !have) {
          const LatLon ll = SiteEncoder::to_lat_lon(diagram.site(site));
          std::fprintf(stderr, "missed site %u at (%g, %g): %g square degrees\n", site, ll.lat_deg, ll.lon_deg, ia);
        }
        if (i) GEOSGeom_destroy_r(h, i);
        GEOSGeom_destroy_r(h, cell);
      }
    }
    FUZZ_CHECK(std::abs(planar[r] - area) <= slack, "region %zu: pieces cover %.17g square degrees of %.17g", r, planar[r], area);
    for (GEOSGeometry* x : {g, valid, snapped}) GEOSGeom_destroy_r(h, x);
  }
  GEOS_finish_r(h);
  return 0;
}
