// Lon/lat Delaunay triangles and edges against independent oracles: GEOS validity (OGR IsValid),
// the WGS84 ellipsoid's area (GeographicLib), 4 pi, exact point location by brute force (the
// triangle holding a random point contains it in lon/lat too), haversine lengths from lon/lat,
// and the identity that ghost faces cover the sites' convex hull exactly as the proper ones do.
#include "geovor/lonlat/delaunay_geometry.hpp"

#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <utility>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/kernel/predicates.hpp"
#include "geovor/lonlat/cell_geometry.hpp"
#include "support/exact_geometry.hpp"
#include "support/generators.hpp"
#include "support/lonlat_checks.hpp"

namespace geovor {
namespace {

constexpr double kPi = std::numbers::pi;
const double kEllipsoidArea = GeographicLib::Geodesic::WGS84().EllipsoidArea();

std::vector<Vec3> csv_sites(const std::string& relative) {
  const SiteTable table = read_sites_csv_file(std::string(GEOVOR_SOURCE_DIR) + "/" + relative);
  std::vector<Vec3> pts;
  for (const InputSite& s : table.sites) pts.push_back(s.unit);
  return pts;
}

// Great-circle distance (haversine on geocentric latitude and longitude), independent of the
// code under test.
double haversine_m(const LonLat& a, const LonLat& b) {
  const Vec3 u = testing::unit_of(a), v = testing::unit_of(b);
  const double phi1 = std::atan2(u.z, std::hypot(u.x, u.y)), phi2 = std::atan2(v.z, std::hypot(v.x, v.y));
  const double lam1 = std::atan2(u.y, u.x), lam2 = std::atan2(v.y, v.x);
  const double h = std::pow(std::sin((phi2 - phi1) / 2), 2) +
                   std::cos(phi1) * std::cos(phi2) * std::pow(std::sin((lam2 - lam1) / 2), 2);
  return 2 * SiteEncoder::kEarthRadiusM * std::asin(std::min(1.0, std::sqrt(h)));
}

struct Summary {
  double ellipsoid = 0, sphere = 0, ghost_sphere = 0;
  std::size_t proper = 0, ghost = 0, great_circle = 0, edges = 0;
};

// The RFC 7946 invariants and GEOS validity of every triangle and edge, bit-identical positions
// between an edge's line and its triangles, lengths against haversine, and the area sums.
Summary check_all(const SphericalDelaunay& dt, const DelaunayGeometryOptions& opt = {}) {
  const DelaunayGeometry g(dt, opt);
  Summary sum;
  std::vector<MultiPolygon> polys(dt.num_triangles());
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    SCOPED_TRACE("triangle " + std::to_string(t));
    g.triangle_polygon(t, polys[t]);
    const MultiPolygon& mp = polys[t];
    EXPECT_FALSE(mp.empty());
    EXPECT_EQ(testing::geos_invalid(mp), "");
    for (const Polygon& p : mp) {
      EXPECT_TRUE(p.holes.empty());
      EXPECT_GE(p.exterior.size(), 4u);
      if (p.exterior.size() < 4) continue;
      EXPECT_TRUE(p.exterior.front() == p.exterior.back());
      EXPECT_GT(planar_area_deg2(p.exterior), 0) << "not counter-clockwise";
      for (const LonLat& q : p.exterior) EXPECT_TRUE(std::fabs(q.lon_deg) <= 180 && std::fabs(q.lat_deg) <= 90);
    }
    const FaceKind k = g.kind(t);
    const double area_sr = g.triangle_area_sr(t);
    EXPECT_GT(area_sr, 0);
    if (k == FaceKind::Ghost) {
      ++sum.ghost;
      EXPECT_TRUE(dt.is_ghost(t));
      sum.ghost_sphere += area_sr;
    } else {
      EXPECT_FALSE(dt.is_ghost(t));
      k == FaceKind::Proper ? ++sum.proper : ++sum.great_circle;
      sum.sphere += area_sr;
      sum.ellipsoid += ellipsoid_area_m2(mp);
    }
    // The written polygon has the stated solid angle: the ellipsoidal area over the authalic
    // sphere's is within 1% of it (GeographicLib on the lon/lat ring, an independent path).
    const double rel = ellipsoid_area_m2(mp) / kEllipsoidArea * 4 * kPi / area_sr;
    EXPECT_NEAR(rel, 1, 0.01) << to_string(k);
  }
  MultiLineString lines;
  for (HalfedgeId e = 0; e < dt.halfedges().size(); ++e) {
    const HalfedgeId twin = dt.halfedges()[e];
    if (twin < e) continue;
    ++sum.edges;
    SCOPED_TRACE("edge " + std::to_string(e));
    g.edge_line(e, lines);
    EXPECT_FALSE(lines.empty());
    if (lines.empty()) continue;
    const SiteId a = dt.tri_site(e / 3, static_cast<int>(e % 3));
    const SiteId b = dt.tri_site(e / 3, static_cast<int>((e + 1) % 3));
    const LatLon la = SiteEncoder::to_lat_lon(dt.site(a)), lb = SiteEncoder::to_lat_lon(dt.site(b));
    if (std::fabs(la.lat_deg) < 89.9) {  // a site within 1 m of a pole is drawn at the pole
      EXPECT_EQ(lines.front().front().lat_deg, la.lat_deg);
    }
    if (std::fabs(lb.lat_deg) < 89.9) {
      EXPECT_EQ(lines.back().back().lat_deg, lb.lat_deg);
    }
    EXPECT_NEAR(g.edge_length_m(e), haversine_m({la.lon_deg, la.lat_deg}, {lb.lon_deg, lb.lat_deg}), 1e-6);
    // The twin gives the same line backwards; every position is a position of both triangles.
    MultiLineString back;
    g.edge_line(twin, back);
    std::vector<LonLat> fwd, rev;
    for (const auto& part : lines) fwd.insert(fwd.end(), part.begin(), part.end());
    for (const auto& part : back) rev.insert(rev.end(), part.begin(), part.end());
    std::reverse(rev.begin(), rev.end());
    EXPECT_EQ(fwd.size(), rev.size());
    for (const auto& part : lines) {
      for (std::size_t i = 0; i + 1 < part.size(); ++i)
        EXPECT_LE(std::fabs(part[i + 1].lon_deg - part[i].lon_deg), 180) << "jump in a line";
      for (const LonLat& q : part) {
        if (std::fabs(q.lat_deg) == 90 || std::fabs(q.lon_deg) == 180) continue;  // cut points
        for (const TriId t : {e / 3, twin / 3}) {
          if (g.kind(t) != FaceKind::Proper) continue;
          bool found = false;
          for (const Polygon& p : polys[t])
            found = found || std::find(p.exterior.begin(), p.exterior.end(), q) != p.exterior.end();
          EXPECT_TRUE(found) << "line position " << q.lon_deg << "," << q.lat_deg << " not in triangle " << t;
        }
      }
    }
  }
  return sum;
}

// Each random point lies, in lon/lat, in the polygon of the proper triangle that holds it
// exactly on the sphere, unless it is within `margin_m` of that triangle's boundary.
void check_point_location(const SphericalDelaunay& dt, std::size_t queries, double margin_m, std::uint64_t seed) {
  const DelaunayGeometry g(dt);
  const std::vector<Vec3> qs = testing::uniform_on_sphere(queries, seed);
  MultiPolygon mp;
  std::size_t checked = 0;
  for (const Vec3& q : qs) {
    TriId holder = kNoIndex;
    for (TriId t = 0; t < dt.num_triangles() && holder == kNoIndex; ++t) {
      if (g.kind(t) != FaceKind::Proper) continue;
      const Vec3 &a = dt.site(dt.tri_site(t, 0)), &b = dt.site(dt.tri_site(t, 1)), &c = dt.site(dt.tri_site(t, 2));
      if (kernel::orient(a, b, q) != Sign::Negative && kernel::orient(b, c, q) != Sign::Negative &&
          kernel::orient(c, a, q) != Sign::Negative)
        holder = t;
    }
    if (holder == kNoIndex) continue;  // outside the hull (sites in one hemisphere)
    double closest = 1e300;
    for (int i = 0; i < 3; ++i) {
      const Vec3 n = cross(dt.site(dt.tri_site(holder, i)), dt.site(dt.tri_site(holder, (i + 1) % 3)));
      closest = std::min(closest, std::asin(std::fabs(dot(q, n)) / std::sqrt(norm2(n))) * SiteEncoder::kEarthRadiusM);
    }
    if (closest < margin_m) continue;
    const LatLon ll = SiteEncoder::to_lat_lon(q);
    g.triangle_polygon(holder, mp);
    bool boundary = false;
    EXPECT_TRUE(testing::in_multipolygon(mp, {ll.lon_deg, ll.lat_deg}, boundary))
        << "point " << ll.lat_deg << "," << ll.lon_deg << " not in triangle " << holder;
    ++checked;
  }
  EXPECT_GT(checked, queries / 4);  // sites in one hemisphere: half the points are off the hull
}

TEST(DelaunayGeometry, UniformTrianglesTileTheEllipsoid) {
  const SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(3000, 5));
  const Summary s = check_all(dt);
  EXPECT_EQ(s.proper, 2 * 3000u - 4);
  EXPECT_EQ(s.ghost + s.great_circle, 0u);
  EXPECT_EQ(s.edges, 3 * 3000u - 6);
  EXPECT_NEAR(s.sphere / (4 * kPi), 1, 1e-12);
  EXPECT_NEAR(s.ellipsoid / kEllipsoidArea, 1, 1e-9);
  check_point_location(dt, 3000, 150, 9);
}

TEST(DelaunayGeometry, WeatherStations) {
  const SphericalDelaunay dt = SphericalDelaunay::build(csv_sites("datasets/weather_stations.csv"));
  const Summary s = check_all(dt);
  EXPECT_EQ(s.ghost, 0u);
  EXPECT_NEAR(s.sphere / (4 * kPi), 1, 1e-12);
  EXPECT_NEAR(s.ellipsoid / kEllipsoidArea, 1, 1e-9);
  check_point_location(dt, 1000, 150, 11);
}

TEST(DelaunayGeometry, AntimeridianAndPoles) {
  for (const char* f : {"datasets/fixtures/antimeridian.csv", "datasets/fixtures/poles.csv",
                        "datasets/fixtures/cube_corners.csv"}) {
    SCOPED_TRACE(f);
    const SphericalDelaunay dt = SphericalDelaunay::build(csv_sites(f));
    const Summary s = check_all(dt);
    EXPECT_NEAR(s.sphere / (4 * kPi), 1, 1e-12);
    EXPECT_NEAR(s.ellipsoid / kEllipsoidArea, 1, 1e-9);
    check_point_location(dt, 2000, 150, 13);
  }
  // A 1-degree grid: many triangles cut at +-180 and around both poles.
  const SphericalDelaunay grid = SphericalDelaunay::build(testing::lat_lon_grid(10));
  const Summary s = check_all(grid);
  EXPECT_NEAR(s.sphere / (4 * kPi), 1, 1e-12);
  EXPECT_NEAR(s.ellipsoid / kEllipsoidArea, 1, 1e-9);
}

TEST(DelaunayGeometry, GhostFacesCoverTheHullAsTheProperOnesDo) {
  // Sites in one open hemisphere: every ray from the centre through the hull of the sites meets
  // one proper and one ghost face, so both families have the hull's area.
  for (const auto& pts : {testing::in_hemisphere(500, 3), csv_sites("datasets/fixtures/hemisphere.csv")}) {
    const SphericalDelaunay dt = SphericalDelaunay::build(pts);
    const Summary s = check_all(dt);
    EXPECT_GT(s.ghost, 0u);
    EXPECT_EQ(s.ghost, dt.num_ghost_triangles());
    EXPECT_NEAR(s.ghost_sphere, s.sphere, 1e-12 * 4 * kPi);
    EXPECT_LT(s.sphere, 2 * kPi);
    check_point_location(dt, 2000, 150, 17);
  }
}

TEST(DelaunayGeometry, GreatCircleFacesAreHemispheres) {
  const SphericalDelaunay dt = SphericalDelaunay::build(csv_sites("datasets/fixtures/equator.csv"));
  const DelaunayGeometry g(dt);
  MultiPolygon mp;
  double north = 0, south = 0;
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    EXPECT_EQ(g.kind(t), FaceKind::GreatCircle);
    EXPECT_EQ(g.triangle_area_sr(t), 2 * kPi);
    g.triangle_polygon(t, mp);
    EXPECT_EQ(testing::geos_invalid(mp), "");
    EXPECT_NEAR(ellipsoid_area_m2(mp) / kEllipsoidArea, 0.5, 1e-9);
    bool boundary = false;
    (testing::in_multipolygon(mp, {10, 45}, boundary) ? north : south) += 1;
  }
  EXPECT_EQ(north + south, static_cast<double>(dt.num_triangles()));
  EXPECT_GT(north, 0);
  EXPECT_GT(south, 0);
}

// Oracle of the hull edges, by brute force over the sites and independent of the face kinds:
// (i, j) is an edge of the boundary of the sites' spherical convex hull iff every other site lies
// on one closed side of the great circle through i and j, not all on it, and none of those on it
// lies strictly inside the minor arc i-j (with `strict`, every other site must be strictly on one
// side: the textbook rule, the same for sites in general position).
bool oracle_hull_edge(const std::vector<Vec3>& s, std::size_t i, std::size_t j, bool strict) {
  int pos = 0, neg = 0, on = 0;
  const Vec3 n = cross(s[i], s[j]);
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (k == i || k == j) continue;
    const Sign o = kernel::orient(s[i], s[j], s[k]);
    if (o == Sign::Positive) ++pos;
    if (o == Sign::Negative) ++neg;
    if (o != Sign::Zero) continue;
    ++on;
    if (dot(cross(s[i], s[k]), n) > 0 && dot(cross(s[k], s[j]), n) > 0) return false;  // inside the arc
  }
  if (strict && on > 0) return false;
  return (pos == 0 || neg == 0) && pos + neg > 0;
}

// The hull edges DelaunayGeometry reports are those of the oracle, as site pairs; the outer
// edges (both faces outside the hull's triangulation) join two hull vertices, are not hull
// edges, and triangulate the outside of the hull polygon: h - 3 of them for h hull edges.
// Returns the number of hull edges.
std::size_t check_hull_edges(const std::vector<Vec3>& pts, bool strict) {
  const SphericalDelaunay dt = SphericalDelaunay::build(pts);
  EXPECT_EQ(dt.num_sites(), pts.size());
  const DelaunayGeometry g(dt);
  std::vector<Vec3> s(pts.size());
  for (SiteId k = 0; k < pts.size(); ++k) s[k] = dt.site(k);
  std::set<std::pair<SiteId, SiteId>> expected, got;
  std::vector<bool> on_hull(s.size(), false);
  for (std::size_t i = 0; i < s.size(); ++i)
    for (std::size_t j = i + 1; j < s.size(); ++j)
      if (oracle_hull_edge(s, i, j, strict)) {
        expected.insert({static_cast<SiteId>(i), static_cast<SiteId>(j)});
        on_hull[i] = on_hull[j] = true;
      }
  std::size_t outer = 0;
  for (HalfedgeId e = 0; e < dt.halfedges().size(); ++e) {
    const HalfedgeId twin = dt.halfedges()[e];
    const SiteId a = dt.tri_site(e / 3, static_cast<int>(e % 3)), b = dt.tri_site(e / 3, static_cast<int>((e + 1) % 3));
    EXPECT_EQ(g.is_hull_edge(e), g.is_hull_edge(twin));
    EXPECT_EQ(g.is_outer_edge(e), g.is_outer_edge(twin));
    if (twin < e) continue;
    if (g.is_hull_edge(e)) got.insert({std::min(a, b), std::max(a, b)});
    if (g.is_outer_edge(e)) {
      ++outer;
      EXPECT_FALSE(g.is_hull_edge(e));
      EXPECT_TRUE(on_hull[a] && on_hull[b]) << "outer edge " << a << "-" << b << " off the hull";
      EXPECT_FALSE(expected.count({std::min(a, b), std::max(a, b)}));
    }
  }
  EXPECT_EQ(got, expected);
  EXPECT_EQ(outer, expected.empty() ? 0 : expected.size() - 3);
  return expected.size();
}

Vec3 unit_lat_lon(double lat, double lon) { return testing::unit_of({lon, lat}); }

TEST(DelaunayGeometry, HullEdgesAreThoseOfTheConvexHull) {
  // The sites of issue 14: b-e crosses a-c; the hull is e, a, b, d (c inside), and b-e, between
  // two ghost faces, is no hull edge.
  const std::vector<Vec3> five = {unit_lat_lon(0, 10), unit_lat_lon(10, 10), unit_lat_lon(5, 3),
                                  unit_lat_lon(5, -2), unit_lat_lon(0, 0)};
  EXPECT_EQ(check_hull_edges(five, true), 4u);
  // Sites in one open hemisphere, in general position.
  for (std::uint64_t seed : {3, 4, 5}) {
    SCOPED_TRACE(seed);
    for (std::size_t n : {4u, 5u, 8u, 30u, 300u}) EXPECT_GT(check_hull_edges(testing::in_hemisphere(n, seed), true), 2u);
  }
  EXPECT_EQ(check_hull_edges(csv_sites("datasets/fixtures/hemisphere.csv"), true), 10u);
  // Three sites: the three edges, between the proper face and the ghost.
  EXPECT_EQ(check_hull_edges(csv_sites("datasets/fixtures/three_sites.csv"), true), 3u);
  // Sites in no hemisphere: no hull edge.
  EXPECT_EQ(check_hull_edges(testing::uniform_on_sphere(200, 7), true), 0u);
  EXPECT_EQ(check_hull_edges(csv_sites("datasets/fixtures/cube_corners.csv"), true), 0u);
  // All sites on one great circle: great-circle faces only, no hull.
  EXPECT_EQ(check_hull_edges(csv_sites("datasets/fixtures/equator.csv"), false), 0u);
  std::vector<Vec3> arc;  // on 60 degrees of the equator: in one open hemisphere too
  for (int k = 0; k <= 6; ++k) arc.push_back(unit_lat_lon(0, 10 * k));
  EXPECT_EQ(check_hull_edges(arc, false), 0u);
}

TEST(DelaunayGeometry, HullEdgesWithSitesOnTheHullsGreatCircle) {
  // Four sites on the equator and one north of it: the equator polygon is a flat face of the
  // 3D hull (great-circle faces), outside the hull's triangulation (the fan from the north site).
  std::vector<Vec3> pts = {unit_lat_lon(0, 0), unit_lat_lon(0, 10), unit_lat_lon(0, 20), unit_lat_lon(0, 30),
                           unit_lat_lon(10, 15)};
  EXPECT_EQ(check_hull_edges(pts, false), 5u);
  {
    const SphericalDelaunay dt = SphericalDelaunay::build(pts);
    const DelaunayGeometry g(dt);
    std::size_t outer = 0, great_circle = 0;
    for (TriId t = 0; t < dt.num_triangles(); ++t) {
      outer += g.is_outer(t);
      great_circle += g.kind(t) == FaceKind::GreatCircle;
      EXPECT_EQ(g.is_outer(t), g.kind(t) != FaceKind::Proper);
    }
    EXPECT_EQ(outer, 3u);
    EXPECT_GT(great_circle, 0u);
  }
  // Three on the equator 120 degrees apart and one north: in a closed hemisphere only; the hull
  // is the northern hemisphere, bounded by the three equator edges.
  pts = {unit_lat_lon(0, 0), unit_lat_lon(0, 120), unit_lat_lon(0, -120), unit_lat_lon(30, 10)};
  EXPECT_EQ(check_hull_edges(pts, false), 3u);
  // The same with more sites north (and one on the equator between two others).
  pts.push_back(unit_lat_lon(0, 60));
  pts.push_back(unit_lat_lon(50, 100));
  pts.push_back(unit_lat_lon(20, -100));
  EXPECT_EQ(check_hull_edges(pts, false), 4u);
}

// Thin triangles (issue 14, bug 5): every triangle of a few nearly collinear sites is a valid,
// non-empty, counter-clockwise polygon in doubles, of about its spherical area. Each case has a
// fourth site far away so that the thin triangle is a proper face or a ghost's small triangle.
TEST(DelaunayGeometry, ThinTrianglesAreNotEmpty) {
  struct Case {
    const char* name;
    std::vector<LonLat> sites;  // lon, lat
  };
  const double cm = 1e-2 / 111195.0, m = 1 / 111195.0;  // degrees of latitude
  std::vector<Case> cases = {
      {"latitude row -30", {{20, -30}, {20.001, -30}, {20.002, -30}, {20, -29}}},
      {"latitude row 60", {{20, 60}, {20.001, 60}, {20.002, 60}, {20, 61}}},
      {"latitude row 60 other side", {{20, 60}, {20.001, 60}, {20.002, 60}, {20, 59}}},
      {"latitude row 85, 1 m", {{20, 85}, {20 + 1e-4, 85}, {20 + 2e-4, 85}, {20, 84}}},
      {"row across the antimeridian", {{179.999, 45}, {-180, 45}, {-179.999, 45}, {180, 46}}},
      {"1 km, middle 1 cm off, lat 45", {{10, 45}, {10.0063, 45 + cm}, {10.0127, 45}, {10, 46}}},
      {"1 km, middle 1 cm south, lat 45", {{10, 45}, {10.0063, 45 - cm}, {10.0127, 45}, {10, 44}}},
      {"1 km, middle 1 m off, lat 70", {{10, 70}, {10.013, 70 + m}, {10.026, 70}, {10, 71}}},
      {"two sites within 1 m of the pole", {{0, 90 - 0.44 * m}, {0, 90 - 0.89 * m}, {90, 89}, {-90, 89}, {180, 89}}},
      {"two sites near the south pole", {{30, -90 + 0.5 * m}, {-150, -90 + 0.3 * m}, {0, -89}, {120, -89}}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    std::vector<Vec3> pts;
    for (const LonLat& p : c.sites) pts.push_back(testing::unit_of(p));
    const SphericalDelaunay dt = SphericalDelaunay::build(pts);
    ASSERT_EQ(dt.num_sites(), pts.size());
    const DelaunayGeometry g(dt);
    MultiPolygon mp;
    for (TriId t = 0; t < dt.num_triangles(); ++t) {
      SCOPED_TRACE("triangle " + std::to_string(t) + " " + to_string(g.kind(t)));
      if (g.kind(t) == FaceKind::GreatCircle) continue;
      g.triangle_polygon(t, mp);
      ASSERT_FALSE(mp.empty());
      EXPECT_EQ(testing::geos_invalid(mp), "");
      for (const Polygon& p : mp) EXPECT_GT(planar_area_deg2(p.exterior), 0);
      // triangle_area_sr loses its digits below about 1e-17 sr (400 m^2) on such slivers.
      if (g.triangle_area_sr(t) < 1e-17) continue;
      const double rel = ellipsoid_area_m2(mp) / kEllipsoidArea * 4 * kPi / g.triangle_area_sr(t);
      EXPECT_NEAR(rel, 1, 0.5);
    }
  }
}

// A sliver (two sites 1 m apart, the third 2,600 km away) whose corner at the far site is
// thinner than a decimal step over its last 10 km: rounding folds that corner onto one point, and
// removing the spike would write a triangle without its site (oracle_check seed 1 case 18).
// Every written triangle passes through each of its three sites as written (printf's rounding).
TEST(DelaunayGeometry, WrittenTrianglesKeepTheirSites) {
  const std::vector<LonLat> sites = {
      {64.93604608695694, -37.38340987758078}, {64.93603592231648, -37.38341300834578},
      {64.93604091440096, -37.38341927502397}, {64.93604351110281, -37.38342264474254},
      {-152.35577851935213, 4.651352951316408}, {-85.75222770184473, 6.140191716453502},
      {133.1339311681808, -25.695943749550025}, {60.78995774501737, -13.37028917490187},
      {-147.05736811064142, -62.911937302446695}, {76.62040780034455, 12.426891871583878},
      {-110.05524540328338, -0.04380195226806453}, {139.64996434300917, -43.58567344598608},
      {-72.77297425274531, 28.438335168610685}};
  std::vector<Vec3> pts;
  for (const LonLat& p : sites) pts.push_back(testing::unit_of(p));
  const SphericalDelaunay dt = SphericalDelaunay::build(pts);
  ASSERT_EQ(dt.num_sites(), pts.size());
  DelaunayGeometryOptions o;
  o.precision = 7;
  const DelaunayGeometry g(dt, o);
  MultiPolygon mp;
  std::size_t checked = 0;
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    if (g.kind(t) != FaceKind::Proper || g.triangle_polygon(t, mp) != WrittenStatus::Written) continue;
    EXPECT_EQ(testing::geos_invalid(mp), "") << t;
    for (int i = 0; i < 3; ++i) {
      const SiteId s = dt.tri_site(t, i);
      char lon[64], lat[64];
      std::snprintf(lon, sizeof lon, "%.7f", sites[s].lon_deg);
      std::snprintf(lat, sizeof lat, "%.7f", sites[s].lat_deg);
      const LonLat at{std::strtod(lon, nullptr), std::strtod(lat, nullptr)};
      bool found = false;
      for (const Polygon& p : mp)
        for (const LonLat& q : p.exterior) found |= q.lon_deg == at.lon_deg && q.lat_deg == at.lat_deg;
      EXPECT_TRUE(found) << "triangle " << t << ": site " << s << " (" << lon << ", " << lat << ") not a vertex";
    }
    ++checked;
  }
  EXPECT_GE(checked, 10u);
}

// A column of sites 0.38 m apart down the meridian 179.99 from the north pole: slivers with a
// corner at the pole, and a site within 2^-36 rad of the antimeridian moved onto it. One of them
// (1.9e-34 sr) was written closed along the antimeridian through the south pole, the whole
// Earth (the oracle, seed 9). Every triangle written is at most its tiny lon/lat extent (planar
// shoelace area in square degrees, our own sum), or reported.
TEST(DelaunayGeometry, SliversAtThePoleAcrossTheAntimeridian) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 29; ++i) pts.push_back(SiteEncoder::from_lat_lon(90 - i * 3.44e-6, 179.99));
  const SphericalDelaunay dt = SphericalDelaunay::build(pts);
  ASSERT_EQ(dt.num_sites(), pts.size());
  for (const int precision : {7, 9, -1}) {
    SCOPED_TRACE(precision);
    DelaunayGeometryOptions o;
    o.precision = precision;
    const DelaunayGeometry g(dt, o);
    MultiPolygon mp;
    std::size_t slivers = 0;
    for (TriId t = 0; t < dt.num_triangles(); ++t) {
      if (g.kind(t) == FaceKind::GreatCircle) continue;
      ++slivers;
      if (g.triangle_polygon(t, mp) != WrittenStatus::Written) continue;
      EXPECT_EQ(testing::geos_invalid(mp), "") << t;
      double area_deg2 = 0;
      for (const Polygon& p : mp)
        for (std::size_t i = 0; i + 1 < p.exterior.size(); ++i)
          area_deg2 += 0.5 * (p.exterior[i].lon_deg * p.exterior[i + 1].lat_deg - p.exterior[i + 1].lon_deg * p.exterior[i].lat_deg);
      EXPECT_LT(std::fabs(area_deg2), 0.01) << "triangle " << t << " (" << to_string(g.kind(t)) << ")";
    }
    EXPECT_GE(slivers, 2u);
  }
}

TEST(DelaunayGeometry, CircumradiusIsTheDistanceToTheVoronoiVertex) {
  const SphericalDelaunay dt = SphericalDelaunay::build(testing::in_hemisphere(200, 21));
  const DelaunayGeometry g(dt);
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    const double r = g.circumradius_m(t);
    const double quarter = kPi / 2 * SiteEncoder::kEarthRadiusM;
    EXPECT_EQ(r > quarter, dt.is_ghost(t)) << t;
    // All three sites are at that distance from the circumcentre (equal within 1e-6 m).
    const Vec3 &a = dt.site(dt.tri_site(t, 0)), &b = dt.site(dt.tri_site(t, 1)), &c = dt.site(dt.tri_site(t, 2));
    const Vec3 n = cross(b - a, c - a);
    const double len = std::sqrt(norm2(n));
    for (const Vec3* p : {&a, &b, &c})
      EXPECT_NEAR(std::acos(std::clamp(dot(n, *p) / len, -1.0, 1.0)) * SiteEncoder::kEarthRadiusM, r, 1e-3);
  }
}

// Sites 0.36 m apart alternating between the meridians 29 and -151 (on one great circle, but
// doubles a hair off it): a triangle's plane, through two close sites and a far one, is tilted by
// 1e-9 radians, and its circumradius is 90 degrees give or take millimetres. Its axis had been
// computed from the triangle's first corner, for a far one two long, nearly parallel sides: 4e-10
// radians off (3 mm), more than the Voronoi vertex it must match (VoronoiDiagram::circumcenter).
TEST(DelaunayGeometry, CircumradiusOfSitesOnOneGreatCircleIsExact) {
  std::vector<Vec3> pts;
  for (int k = 0; k < 9; ++k)
    pts.push_back(SiteEncoder::from_lat_lon(-52.022430762188144 + k * 3.25e-6,
                                            k % 2 == 0 ? 29.007095445181989 : -150.99290455481801));
  const SphericalDelaunay dt = SphericalDelaunay::build(pts);
  const DelaunayGeometry g(dt);
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    const Vec3 &a = dt.site(dt.tri_site(t, 0)), &b = dt.site(dt.tri_site(t, 1)), &c = dt.site(dt.tri_site(t, 2));
    const Vec3 n = testing::exact_circumcentre(a, b, c);
    const double exact = SiteEncoder::kEarthRadiusM * std::atan2(std::sqrt(norm2(cross(n, a))), dot(n, a));
    EXPECT_NEAR(g.circumradius_m(t), exact, 1e-6) << t;
  }
}

TEST(DelaunayGeometry, RejectsBadOptions) {
  const SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(10, 1));
  DelaunayGeometryOptions o;
  o.densify_m = 0;
  EXPECT_THROW(DelaunayGeometry(dt, o), Error);
  o = {};
  o.max_step_deg = 200;
  EXPECT_THROW(DelaunayGeometry(dt, o), Error);
  o = {};
  o.max_depth = 0;
  EXPECT_THROW(DelaunayGeometry(dt, o), Error);
}

}  // namespace
}  // namespace geovor
