// clip_cells_to_regions against oracles that share no code with it: random points of each region
// assigned to their nearest site by brute force fall in that site's piece of the region (GEOS's
// point-in-polygon), every piece is valid (GEOS), its area is GeographicLib's PolygonArea of its
// rings, the shares of a region sum to 1; on sites with poles, the antimeridian and clusters,
// and regions across +-180, around a pole, with holes, several parts, and a bow tie.
#include "geovor/layers/region_clip.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>
#include <geos_c.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

Ring box_ring(double w, double s, double e, double n) { return {{w, s}, {e, s}, {e, n}, {w, n}, {w, s}}; }

Region region(std::string id, MultiPolygon g) {
  Region r;
  r.id = std::move(id);
  r.geometry = std::move(g);
  return r;
}

RegionTable test_regions() {
  RegionTable t;
  t.source = "test regions";
  t.regions.push_back(region("box", {{box_ring(10, 40, 30, 55), {}}}));
  // Across the antimeridian: two parts, as a GIS stores Fiji.
  t.regions.push_back(region("fiji", {{box_ring(170, -25, 180, -10), {}}, {box_ring(-180, -25, -175, -10), {}}}));
  // Around the south pole, as Natural Earth's Antarctica: along -90 from 180 to -180.
  t.regions.push_back(region("antarctica", {{{{-180, -90}, {180, -90}, {180, -70}, {90, -65}, {0, -72}, {-90, -66}, {-180, -70}, {-180, -90}}, {}}}));
  // A hole.
  t.regions.push_back(region("ring", {{box_ring(-60, -10, -30, 20), {{{-50, 0}, {-50, 10}, {-40, 10}, {-40, 0}, {-50, 0}}}}}));
  // A bow tie (invalid: self-intersecting), repaired and reported.
  t.regions.push_back(region("bowtie", {{{{60, 0}, {80, 20}, {80, 0}, {60, 20}, {60, 0}}, {}}}));
  return t;
}

std::vector<Vec3> test_sites() {
  std::vector<Vec3> p = testing::uniform_on_sphere(1500, 35);
  for (const Vec3& c : testing::clustered(300, 3, 0.02, 36)) p.push_back(c);
  for (const double lat : {-89.999, -85.0, -80.0, 89.9, 0.0, -15.0})
    for (const double lon : {-180.0, -179.99, 179.99, 0.0}) p.push_back(SiteEncoder::from_lat_lon(lat, lon));
  p.push_back(SiteEncoder::from_lat_lon(-90, 0));
  return p;
}

double polygon_area(const MultiPolygon& mp) {
  const GeographicLib::Geodesic& g = GeographicLib::Geodesic::WGS84();
  double total = 0;
  for (const Polygon& p : mp)
    for (std::size_t k = 0; k <= p.holes.size(); ++k) {
      const Ring& r = k == 0 ? p.exterior : p.holes[k - 1];
      GeographicLib::PolygonArea area(g);
      for (std::size_t i = 0; i + 1 < r.size(); ++i) area.AddPoint(r[i].lat_deg, r[i].lon_deg);
      double perimeter = 0, a = 0;
      area.Compute(false, true, perimeter, a);  // counter-clockwise positive; holes come negative
      total += a;
    }
  return total;
}

struct GeosScope {
  GEOSContextHandle_t h = GEOS_init_r();
  ~GeosScope() { GEOS_finish_r(h); }
  GEOSGeometry* ring(const Ring& r) {
    GEOSCoordSequence* s = GEOSCoordSeq_create_r(h, static_cast<unsigned>(r.size()), 2);
    for (unsigned i = 0; i < r.size(); ++i) GEOSCoordSeq_setXY_r(h, s, i, r[i].lon_deg, r[i].lat_deg);
    return GEOSGeom_createLinearRing_r(h, s);
  }
  GEOSGeometry* geometry(const MultiPolygon& mp) {
    std::vector<GEOSGeometry*> polys;
    for (const Polygon& p : mp) {
      std::vector<GEOSGeometry*> holes;
      for (const Ring& r : p.holes) holes.push_back(ring(r));
      polys.push_back(GEOSGeom_createPolygon_r(h, ring(p.exterior), holes.data(), static_cast<unsigned>(holes.size())));
    }
    return GEOSGeom_createCollection_r(h, GEOS_MULTIPOLYGON, polys.data(), static_cast<unsigned>(polys.size()));
  }
};

TEST(RegionClip, PiecesMatchBruteForceAndTileTheRegions) {
  const std::vector<Vec3> sites = test_sites();
  const SphericalDelaunay dt = SphericalDelaunay::build(sites);
  const VoronoiDiagram diagram(dt);
  CellGeometryOptions cell_options;
  cell_options.precision = 7;
  const CellGeometry cells(diagram, cell_options);
  const RegionTable regions = test_regions();
  RegionClipReport report;
  const std::vector<ClipPiece> pieces = clip_cells_to_regions(diagram, cells, regions, {.threads = 2}, report);

  GeosScope geos;
  std::vector<double> share_sum(regions.regions.size(), 0);
  std::vector<std::vector<const ClipPiece*>> of_region(regions.regions.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const ClipPiece& p = pieces[i];
    if (i > 0) EXPECT_LE(pieces[i - 1].site, p.site) << "ordered by site";
    GEOSGeometry* g = geos.geometry(p.geometry);
    EXPECT_TRUE(GEOSisValid_r(geos.h, g)) << "piece of site " << p.site << " in region " << p.region;
    GEOSGeom_destroy_r(geos.h, g);
    EXPECT_NEAR(p.area_m2, polygon_area(p.geometry), 1e-9 * p.area_m2 + 1e-3) << "PolygonArea of the piece";
    share_sum[p.region] += p.region_share;
    of_region[p.region].push_back(&p);
    for (const Polygon& poly : p.geometry)
      for (const LonLat& v : poly.exterior) EXPECT_EQ(v.lon_deg, std::round(v.lon_deg * 1e7) / 1e7) << "on the grid";
  }
  for (std::size_t r = 0; r < regions.regions.size(); ++r) {
    EXPECT_NEAR(share_sum[r], 1.0, 1e-9) << regions.regions[r].id;
    if (regions.regions[r].id == "bowtie") continue;
    // The pieces union to the region (GEOS, planar areas in square degrees, at the grid's
    // rounding), and their measure is the region's as drawn (PolygonArea of its straight edges
    // split in 1,000).
    double planar = 0;
    for (const ClipPiece* p : of_region[r]) {
      GEOSGeometry* g = geos.geometry(p->geometry);
      double a = 0;
      GEOSArea_r(geos.h, g, &a);
      planar += a;
      GEOSGeom_destroy_r(geos.h, g);
    }
    GEOSGeometry* whole = geos.geometry(regions.regions[r].geometry);
    double region_planar = 0;
    GEOSArea_r(geos.h, whole, &region_planar);
    GEOSGeom_destroy_r(geos.h, whole);
    EXPECT_NEAR(planar, region_planar, 1e-6 * region_planar) << regions.regions[r].id << ": the pieces union to the region";
    MultiPolygon fine = regions.regions[r].geometry;
    for (Polygon& p : fine)
      for (Ring* ring : [&] { std::vector<Ring*> all{&p.exterior}; for (Ring& h : p.holes) all.push_back(&h); return all; }()) {
        Ring split;
        for (std::size_t i = 0; i + 1 < ring->size(); ++i)
          for (int k = 0; k < 1000; ++k) {
            const double t = k / 1000.0;
            split.push_back({(*ring)[i].lon_deg + t * ((*ring)[i + 1].lon_deg - (*ring)[i].lon_deg),
                             (*ring)[i].lat_deg + t * ((*ring)[i + 1].lat_deg - (*ring)[i].lat_deg)});
          }
        split.push_back(ring->back());
        *ring = split;
      }
    // Within what 100 m of densification leaves (as for the cells themselves): under 3e-5 here.
    EXPECT_NEAR(report.region_area_m2[r], polygon_area(fine), 3e-5 * report.region_area_m2[r]) << regions.regions[r].id;
    EXPECT_FALSE(of_region[r].empty()) << regions.regions[r].id;
  }
  ASSERT_EQ(report.problems.size(), 1u);
  EXPECT_EQ(regions.regions[report.problems[0].region].id, "bowtie");
  EXPECT_NE(report.problems[0].reason.find("Self-intersection"), std::string::npos) << report.problems[0].reason;
  EXPECT_LT(report.cells_tested, sites.size() * regions.regions.size() / 4) << "candidates walked, not every cell";
  EXPECT_GT(report.sites_outside.size(), sites.size() / 2);

  // Random points of each region (GEOS: inside it) belong to the piece of their nearest site
  // (brute force), unless a second site is within 300 m of as near (the written cell is
  // densified to 100 m).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::size_t r = 0; r < regions.regions.size(); ++r) {
    if (regions.regions[r].id == "bowtie") continue;
    GEOSGeometry* shape = geos.geometry(regions.regions[r].geometry);
    const GEOSPreparedGeometry* prepared = GEOSPrepare_r(geos.h, shape);
    double w = 180, s = 90, e = -180, n = -90;
    for (const Polygon& p : regions.regions[r].geometry)
      for (const LonLat& v : p.exterior) w = std::min(w, v.lon_deg), e = std::max(e, v.lon_deg), s = std::min(s, v.lat_deg), n = std::max(n, v.lat_deg);
    int checked = 0;
    for (int tries = 0; tries < 20000 && checked < 300; ++tries) {
      const double lon = w + (e - w) * u(rng), lat = s + (n - s) * u(rng);
      GEOSGeometry* pt = GEOSGeom_createPointFromXY_r(geos.h, lon, lat);
      if (!GEOSPreparedContainsProperly_r(geos.h, prepared, pt)) {
        GEOSGeom_destroy_r(geos.h, pt);
        continue;
      }
      const Vec3 q = SiteEncoder::from_lat_lon(lat, lon);
      double best = -2, second = -2;
      SiteId nearest = kNoIndex;
      for (SiteId i = 0; i < dt.num_sites(); ++i) {
        if (!diagram.has_cell(i)) continue;
        const double d = dot(diagram.site(i), q);
        if (d > best) second = best, best = d, nearest = i;
        else if (d > second) second = d;
      }
      const bool near_tie = (std::acos(std::min(1.0, second)) - std::acos(std::min(1.0, best))) * SiteEncoder::kEarthRadiusM < 300;
      bool found = false;
      for (const ClipPiece* p : of_region[r]) {
        if (p->site != nearest) continue;
        GEOSGeometry* g = geos.geometry(p->geometry);
        found = found || GEOSIntersects_r(geos.h, g, pt);
        GEOSGeom_destroy_r(geos.h, g);
      }
      EXPECT_TRUE(found || near_tie) << regions.regions[r].id << ": (" << lat << ", " << lon << ") not in the piece of site " << nearest;
      GEOSGeom_destroy_r(geos.h, pt);
      ++checked;
    }
    EXPECT_GE(checked, 100) << regions.regions[r].id;
    GEOSPreparedGeom_destroy_r(geos.h, prepared);
    GEOSGeom_destroy_r(geos.h, shape);
  }
}

TEST(RegionClip, SameOnAnyNumberOfThreads) {
  const std::vector<Vec3> sites = testing::uniform_on_sphere(800, 9);
  const SphericalDelaunay dt = SphericalDelaunay::build(sites);
  const VoronoiDiagram diagram(dt);
  CellGeometryOptions cell_options;
  cell_options.precision = 6;
  const CellGeometry cells(diagram, cell_options);
  RegionClipReport r1, r3;
  const auto one = clip_cells_to_regions(diagram, cells, test_regions(), {.threads = 1}, r1);
  const auto three = clip_cells_to_regions(diagram, cells, test_regions(), {.threads = 3}, r3);
  ASSERT_EQ(one.size(), three.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].site, three[i].site);
    EXPECT_EQ(one[i].region, three[i].region);
    EXPECT_EQ(one[i].area_m2, three[i].area_m2);
  }
  EXPECT_EQ(r1.sites_outside, r3.sites_outside);
}

}  // namespace
}  // namespace geovor
