// VoronoiDiagram against independent oracles: brute force (every Voronoi vertex is the centre of
// an empty cap through its three sites), GeographicLib's polygon area on the unit sphere, Monte
// Carlo nearest-site areas, closed-form areas of lunes and symmetric sets, and 4 pi.
#include "geovor/voronoi/voronoi_diagram.hpp"

#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_reader.hpp"
#include "support/exact_geometry.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

constexpr double kPi = std::numbers::pi;

VoronoiDiagram diagram_of(const std::vector<Vec3>& pts, SphericalDelaunay* keep = nullptr) {
  SphericalDelaunay dt = SphericalDelaunay::build(pts);
  EXPECT_TRUE(dt.validate().ok());
  VoronoiDiagram vd(dt);
  if (keep) *keep = std::move(dt);
  return vd;
}

double total_area(const VoronoiDiagram& vd) {
  double sum = 0;
  for (SiteId s = 0; s < vd.site_capacity(); ++s) sum += vd.cell_area_sr(s);
  return sum;
}

std::vector<Vec3> weather_stations() {
  const SiteTable table =
      read_sites_csv_file(std::string(GEOVOR_SOURCE_DIR) + "/datasets/weather_stations.csv");
  std::vector<Vec3> pts;
  for (const InputSite& s : table.sites) pts.push_back(s.unit);
  return pts;
}

// Structural checks that hold for every diagram with triangles.
void expect_consistent(const VoronoiDiagram& vd, const SphericalDelaunay& dt) {
  ASSERT_EQ(vd.kind(), VoronoiDiagram::Kind::Cells);
  EXPECT_EQ(vd.num_cells(), dt.num_sites());
  EXPECT_EQ(vd.num_vertices(), dt.num_triangles());
  std::size_t entries = 0;
  std::set<std::pair<SiteId, SiteId>> edges;
  for (SiteId s = 0; s < vd.site_capacity(); ++s) {
    const auto tris = vd.cell_vertices(s);
    const auto nbrs = vd.cell_neighbors(s);
    ASSERT_EQ(tris.size(), nbrs.size());
    EXPECT_EQ(vd.has_cell(s), dt.is_live(s));
    if (!vd.has_cell(s)) {
      EXPECT_TRUE(tris.empty());
      continue;
    }
    EXPECT_GE(tris.size(), 2u);
    entries += tris.size();
    for (std::size_t i = 0; i < tris.size(); ++i) {
      const TriId t = tris[i], u = tris[(i + 1) % tris.size()];
      const SiteId w = nbrs[i];
      // Both triangles of the edge contain s and w (the dual Delaunay edge).
      for (const TriId x : {t, u}) {
        int found = 0;
        for (int j = 0; j < 3; ++j) found += dt.tri_site(x, j) == s || dt.tri_site(x, j) == w;
        EXPECT_EQ(found, 2) << "site " << s << " entry " << i;
      }
      edges.insert({s, w});
    }
  }
  EXPECT_EQ(entries, 3 * dt.num_triangles());
  for (const auto& [s, w] : edges) EXPECT_TRUE(edges.count({w, s})) << s << " " << w;
}

// Every Voronoi vertex is equidistant from its triangle's sites and no site is nearer (the cap is
// empty): the definition of the circumcentre, checked by brute force.
void expect_empty_caps(const VoronoiDiagram& vd, const SphericalDelaunay& dt, double tol) {
  for (TriId t = 0; t < vd.num_vertices(); ++t) {
    const Vec3& v = vd.vertex(t);
    EXPECT_NEAR(norm2(v), 1.0, 1e-15);
    const double d0 = dot(v, dt.site(dt.tri_site(t, 0)));
    EXPECT_NEAR(dot(v, dt.site(dt.tri_site(t, 1))), d0, tol) << t;
    EXPECT_NEAR(dot(v, dt.site(dt.tri_site(t, 2))), d0, tol) << t;
    double best = -2;
    for (SiteId s = 0; s < dt.site_capacity(); ++s)
      if (dt.is_live(s)) best = std::max(best, dot(v, dt.site(s)));
    EXPECT_LE(best, d0 + tol) << "a site is inside the cap of triangle " << t;
  }
}

// Area of each cell estimated from N random points assigned to their nearest site (brute force);
// each estimate must be within 6 standard deviations.
void expect_monte_carlo_areas(const VoronoiDiagram& vd, std::size_t samples, std::uint64_t seed) {
  const std::vector<Vec3> q = testing::uniform_on_sphere(samples, seed);
  std::vector<std::size_t> count(vd.site_capacity(), 0);
  for (const Vec3& p : q) {
    SiteId best = kNoIndex;
    double bd = -2;
    for (SiteId s = 0; s < vd.site_capacity(); ++s)
      if (vd.has_cell(s) && dot(p, vd.site(s)) > bd) bd = dot(p, vd.site(s)), best = s;
    ++count[best];
  }
  for (SiteId s = 0; s < vd.site_capacity(); ++s) {
    if (!vd.has_cell(s)) continue;
    const double f = vd.cell_area_sr(s) / (4 * kPi);
    const double sigma = std::sqrt(f * (1 - f) / samples) + 1.0 / samples;
    EXPECT_NEAR(static_cast<double>(count[s]) / samples, f, 6 * sigma) << "site " << s;
  }
}

TEST(VoronoiDiagram, NoSite) {
  const VoronoiDiagram vd(SphericalDelaunay::build(std::vector<Vec3>{}));
  EXPECT_EQ(vd.kind(), VoronoiDiagram::Kind::Empty);
  EXPECT_EQ(vd.num_cells(), 0u);
  EXPECT_EQ(vd.num_vertices(), 0u);
  EXPECT_EQ(VoronoiDiagram().kind(), VoronoiDiagram::Kind::Empty);
}

TEST(VoronoiDiagram, OneSiteIsTheWholeSphere) {
  const VoronoiDiagram vd = diagram_of({{0, 0, 1}});
  EXPECT_EQ(vd.kind(), VoronoiDiagram::Kind::WholeSphere);
  EXPECT_EQ(vd.num_cells(), 1u);
  EXPECT_TRUE(vd.cell_vertices(0).empty());
  EXPECT_TRUE(vd.cell_neighbors(0).empty());
  EXPECT_DOUBLE_EQ(vd.cell_area_sr(0), 4 * kPi);
}

TEST(VoronoiDiagram, TwoSitesAreTwoHemispheres) {
  const Vec3 a = testing::normalized({1, 2, 3}), b = testing::normalized({-2, 1, 0.5});
  const VoronoiDiagram vd = diagram_of({a, b});
  EXPECT_EQ(vd.kind(), VoronoiDiagram::Kind::Hemispheres);
  for (SiteId s : {0u, 1u}) {
    ASSERT_EQ(vd.cell_neighbors(s).size(), 1u);
    EXPECT_EQ(vd.cell_neighbors(s)[0], 1 - s);
    EXPECT_TRUE(vd.cell_vertices(s).empty());
    EXPECT_DOUBLE_EQ(vd.cell_area_sr(s), 2 * kPi);
    // The pole of the hemisphere is closer to its own site.
    const Vec3 n = vd.hemisphere_normal(s);
    EXPECT_NEAR(norm2(n), 1, 1e-15);
    EXPECT_GT(dot(n, vd.site(s)), dot(n, vd.site(1 - s)));
    EXPECT_NEAR(dot(n, vd.site(s)), -dot(n, vd.site(1 - s)), 1e-15);
  }
}

TEST(VoronoiDiagram, ThreeSitesOnTheEquatorAreLunes) {
  // Lune of angle alpha has area 2 alpha. Sites at lon 0, 90, 200: bisectors at 45, 145, 280.
  std::vector<Vec3> pts;
  for (double lon : {0.0, 90.0, 200.0})
    pts.push_back({std::cos(lon * kPi / 180), std::sin(lon * kPi / 180), 0});
  SphericalDelaunay dt;
  const VoronoiDiagram vd = diagram_of(pts, &dt);
  expect_consistent(vd, dt);
  const double expected[3] = {125, 100, 135};  // lune angles (degrees)
  for (SiteId s = 0; s < 3; ++s) {
    EXPECT_EQ(vd.cell_vertices(s).size(), 2u);
    EXPECT_NEAR(vd.cell_area_sr(s), 2 * expected[s] * kPi / 180, 1e-13) << s;
  }
  // Both vertices are the poles.
  for (TriId t = 0; t < vd.num_vertices(); ++t) EXPECT_EQ(std::fabs(vd.vertex(t).z), 1.0);
}

TEST(VoronoiDiagram, ManySitesOnTheEquatorAreLunes) {
  const std::vector<Vec3> pts = testing::on_great_circle(200, 7);
  SphericalDelaunay dt;
  const VoronoiDiagram vd = diagram_of(pts, &dt);
  expect_consistent(vd, dt);
  // Closed form: the lune of a site spans half the gap to each neighbour in longitude.
  std::vector<std::pair<double, SiteId>> lon;
  for (SiteId s = 0; s < vd.site_capacity(); ++s)
    if (vd.has_cell(s)) lon.push_back({std::atan2(vd.site(s).y, vd.site(s).x), s});
  std::sort(lon.begin(), lon.end());
  const std::size_t n = lon.size();
  for (std::size_t i = 0; i < n; ++i) {
    double span = lon[(i + 1) % n].first - lon[(i + n - 1) % n].first;
    if (span <= 0) span += 2 * kPi;
    // 2 * (span / 2), up to the 1e-16 offsets of the stored points from the unit sphere, which
    // tilt the bisector of two sites 3e-4 apart by 3e-13.
    EXPECT_NEAR(vd.cell_area_sr(lon[i].second), span, 5e-12) << i;
  }
  EXPECT_NEAR(total_area(vd), 4 * kPi, 1e-12);
}

TEST(VoronoiDiagram, UniformSitesAgainstBruteForceAndGeographicLib) {
  const std::vector<Vec3> pts = testing::uniform_on_sphere(1500, 11);
  SphericalDelaunay dt;
  const VoronoiDiagram vd = diagram_of(pts, &dt);
  expect_consistent(vd, dt);
  expect_empty_caps(vd, dt, 1e-14);
  // Counter-clockwise: each fan triangle (site, v_i, v_i+1) turns positively.
  for (SiteId s = 0; s < vd.site_capacity(); ++s) {
    const auto tris = vd.cell_vertices(s);
    for (std::size_t i = 0; i < tris.size(); ++i) {
      const Vec3& a = vd.vertex(tris[i]);
      const Vec3& b = vd.vertex(tris[(i + 1) % tris.size()]);
      EXPECT_GT(dot(vd.site(s), cross(a, b)), 0) << s;
    }
  }
  // GeographicLib on the unit sphere (geodesics = great circles) as the area oracle.
  const GeographicLib::Geodesic sphere(1, 0);
  double sum = 0;
  for (SiteId s = 0; s < vd.site_capacity(); ++s) {
    GeographicLib::PolygonArea pa(sphere);
    for (const TriId t : vd.cell_vertices(s)) {
      const Vec3& v = vd.vertex(t);
      pa.AddPoint(std::atan2(v.z, std::hypot(v.x, v.y)) * 180 / kPi,
                  std::atan2(v.y, v.x) * 180 / kPi);
    }
    double perimeter = 0, area = 0;
    pa.Compute(false, false, perimeter, area);
    EXPECT_NEAR(vd.cell_area_sr(s), area, 1e-12) << s;
    sum += vd.cell_area_sr(s);
  }
  EXPECT_NEAR(sum / (4 * kPi), 1, 1e-13);
  expect_monte_carlo_areas(vd, 200000, 5);
}

TEST(VoronoiDiagram, DegenerateSetsTileTheSphere) {
  struct Case {
    const char* name;
    std::vector<Vec3> pts;
  };
  const std::vector<Case> cases = {
      {"three",
       {testing::normalized({1, 0, 0}), testing::normalized({0, 1, 0}),
        testing::normalized({1, 1, 1})}},
      {"cube corners", testing::cube_corners()},
      {"small circle (one plane, ghosts)", testing::on_small_circle(24, 40, 3)},
      {"hemisphere (ghosts)", testing::in_hemisphere(300, 4)},
      {"great circle", testing::on_great_circle(50, 5)},
      {"grid 15 deg", testing::lat_lon_grid(15)},
      {"grid without poles", testing::lat_lon_grid(20, -80, 80)},
      {"skinny", testing::skinny_set(40)},
      {"poles with longitudes", testing::poles_with_longitudes(6)},
      {"clustered", testing::clustered(400, 5, 0.02, 6)},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    SphericalDelaunay dt;
    const VoronoiDiagram vd = diagram_of(c.pts, &dt);
    expect_consistent(vd, dt);
    expect_empty_caps(vd, dt, 1e-12);
    for (SiteId s = 0; s < vd.site_capacity(); ++s) {
      if (vd.has_cell(s)) {
        EXPECT_GT(vd.cell_area_sr(s), 0) << s;
      }
    }
    EXPECT_NEAR(total_area(vd) / (4 * kPi), 1, 1e-12);
    expect_monte_carlo_areas(vd, 60000, 9);
  }
}

TEST(VoronoiDiagram, SymmetricSetsHaveEqualCells) {
  const VoronoiDiagram cube = diagram_of(testing::cube_corners());
  for (SiteId s = 0; s < 8; ++s) EXPECT_NEAR(cube.cell_area_sr(s), kPi / 2, 1e-13);
  // Grid: cells in one latitude row are congruent.
  const std::vector<Vec3> grid = testing::lat_lon_grid(10);
  const VoronoiDiagram vd = diagram_of(grid);
  std::map<long, std::vector<double>> rows;
  for (SiteId s = 0; s < vd.site_capacity(); ++s)
    rows[std::lround(std::asin(vd.site(s).z) * 180 / kPi)].push_back(vd.cell_area_sr(s));
  for (const auto& [lat, areas] : rows) {
    const auto [lo, hi] = std::minmax_element(areas.begin(), areas.end());
    EXPECT_NEAR(*lo, *hi, 1e-13) << "row " << lat;
  }
  EXPECT_NEAR(total_area(vd), 4 * kPi, 1e-12);
}

TEST(VoronoiDiagram, RemovedSitesHaveNoCell) {
  SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(300, 21));
  for (SiteId s = 0; s < 300; s += 3) dt.remove(s);
  const VoronoiDiagram vd(dt);
  expect_consistent(vd, dt);
  EXPECT_EQ(vd.num_cells(), 200u);
  EXPECT_FALSE(vd.has_cell(0));
  EXPECT_EQ(vd.cell_area_sr(0), 0);
  EXPECT_NEAR(total_area(vd) / (4 * kPi), 1, 1e-13);
  // Down to two, then one site.
  SphericalDelaunay small = SphericalDelaunay::build(testing::uniform_on_sphere(4, 22));
  small.remove(0);
  small.remove(1);
  const VoronoiDiagram two(small);
  EXPECT_EQ(two.kind(), VoronoiDiagram::Kind::Hemispheres);
  EXPECT_EQ(two.cell_neighbors(2)[0], 3u);
  EXPECT_EQ(two.cell_neighbors(3)[0], 2u);
  EXPECT_NEAR(total_area(two), 4 * kPi, 1e-15);
  small.remove(2);
  EXPECT_EQ(VoronoiDiagram(small).kind(), VoronoiDiagram::Kind::WholeSphere);
}

// prefetch() is a hint: any stage on any id (removed sites, past the end), in every kind of
// diagram, leaves the diagram consistent (the sanitizer build checks its reads).
TEST(VoronoiDiagram, PrefetchChangesNothing) {
  SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(300, 23));
  for (SiteId s = 0; s < 300; s += 3) dt.remove(s);
  SphericalDelaunay one = SphericalDelaunay::build(std::vector<Vec3>{{0, 0, 1}});
  SphericalDelaunay two = SphericalDelaunay::build(std::vector<Vec3>{{0, 0, 1}, {1, 0, 0}});
  for (const SphericalDelaunay* t : {&dt, &one, &two}) {
    const VoronoiDiagram vd(*t);
    for (SiteId s = 0; s < vd.site_capacity() + 3; ++s)
      for (int stage = 0; stage < 2; ++stage) vd.prefetch(s, stage);
    if (t == &dt) expect_consistent(vd, *t);
    EXPECT_EQ(vd.kind(), t == &dt ? VoronoiDiagram::Kind::Cells
                                  : (t == &one ? VoronoiDiagram::Kind::WholeSphere : VoronoiDiagram::Kind::Hemispheres));
    EXPECT_NEAR(total_area(vd) / (4 * kPi), 1, 1e-13);
  }
}

TEST(VoronoiDiagram, WeatherStations) {
  SphericalDelaunay dt;
  const VoronoiDiagram vd = diagram_of(weather_stations(), &dt);
  expect_consistent(vd, dt);
  const double sum = total_area(vd);
  std::printf("weather stations: %zu cells, sum of areas / 4 pi - 1 = %.3g\n", vd.num_cells(),
              sum / (4 * kPi) - 1);
  EXPECT_NEAR(sum / (4 * kPi), 1, 1e-13);
  // The Amundsen-Scott station (lat -89.9999985) is the southernmost site, and the south pole is
  // inside its cell: every fan triangle of its cell turns positively around the pole too.
  SiteId south = 0;
  for (SiteId s = 0; s < vd.site_capacity(); ++s)
    if (vd.site(s).z < vd.site(south).z) south = s;
  EXPECT_LT(vd.site(south).z, -0.99999999);
  const auto tris = vd.cell_vertices(south);
  for (std::size_t i = 0; i < tris.size(); ++i)
    EXPECT_GT(
        dot(Vec3{0, 0, -1}, cross(vd.vertex(tris[i]), vd.vertex(tris[(i + 1) % tris.size()]))), 0);
}

TEST(VoronoiDiagram, LargeUniformSetSumsTo4Pi) {
  const std::vector<Vec3> pts = testing::uniform_on_sphere(1 << 17, 31);
  const SphericalDelaunay dt = SphericalDelaunay::build(pts);
  const VoronoiDiagram vd(dt);
  EXPECT_NEAR(total_area(vd) / (4 * kPi), 1, 1e-12);
}

TEST(VoronoiDiagram, ArcMidpointHandles180DegreeArcs) {
  const Vec3 a{1, 0, 0}, b{-1, 0, 0};
  // Positive rotation about +z from +x passes through +y; about -z through -y.
  const Vec3 m1 = VoronoiDiagram::arc_midpoint(a, b, {0, 0, 1});
  const Vec3 m2 = VoronoiDiagram::arc_midpoint(a, b, {0, 0, -1});
  EXPECT_NEAR(m1.y, 1, 1e-15);
  EXPECT_NEAR(m2.y, -1, 1e-15);
  // 150 degrees.
  const Vec3 c{std::cos(5 * kPi / 6), std::sin(5 * kPi / 6), 0};
  const Vec3 m3 = VoronoiDiagram::arc_midpoint(a, c, {0, 0, 1});
  EXPECT_NEAR(std::atan2(m3.y, m3.x), 5 * kPi / 12, 1e-15);
  EXPECT_NEAR(VoronoiDiagram::triangle_area_sr({1, 0, 0}, {0, 1, 0}, {0, 0, 1}), kPi / 2, 1e-15);
  EXPECT_NEAR(VoronoiDiagram::triangle_area_sr({1, 0, 0}, {0, 0, 1}, {0, 1, 0}), -kPi / 2, 1e-15);
}

// Tiny triangles and the slivers of a cell's fan keep their digits. The expected values are the
// solid angles of the stored doubles from exact rational det and denominator (Python fractions),
// then one atan.
TEST(VoronoiDiagram, TriangleAreaOfTinyTrianglesAndSlivers) {
  // (-30, 20), (-30, 20.000001), (-29.999999, 20.0000005) degrees: 1.3e-16 sr.
  const Vec3 a{0x1.a0aa16f5e991bp-1, 0x1.2f4e9034c7357p-2, -0x1.fffffffffffffp-2};
  const Vec3 b{0x1.a0aa16c9816d2p-1, 0x1.2f4e9128caa35p-2, -0x1.fffffffffffffp-2};
  const Vec3 c{0x1.a0aa1726264a8p-1, 0x1.2f4e90e20fb93p-2, -0x1.fffffefc538ccp-2};
  const double tiny = 1.319032123889599e-16;  // a . (b x c) gave 1.3308e-16: 1% off
  EXPECT_NEAR(VoronoiDiagram::triangle_area_sr(a, b, c), tiny, 1e-12 * tiny);
  EXPECT_NEAR(VoronoiDiagram::triangle_area_sr(b, c, a), tiny, 1e-12 * tiny);
  EXPECT_NEAR(VoronoiDiagram::triangle_area_sr(c, a, b), tiny, 1e-12 * tiny);
  EXPECT_NEAR(VoronoiDiagram::triangle_area_sr(a, c, b), -tiny, 1e-12 * tiny);
  // A fan triangle: the apex at (10, 10), a Voronoi edge of 1e-6 degrees 45 degrees away.
  const Vec3 apex{0x1.f08fb2129168dp-1, 0x1.5e3a8748a0bf4p-3, 0x1.63a1a7e0b7389p-3};
  const double fan = 5.477570588633589e-09;  // a . (b x c) gave 5.4775705895e-09: 1.6e-10 off
  EXPECT_NEAR(VoronoiDiagram::triangle_area_sr(apex, a, b), fan, 1e-13 * fan);
  EXPECT_NEAR(VoronoiDiagram::triangle_area_sr(b, apex, a), fan, 1e-13 * fan);
}

// cell_area_sr shares each vertex's side from the apex between the fan's two triangles through
// it: bit for bit the sum of triangle_area_sr over the fan, in order (cells whose apex is their
// site and whose edges are all shorter than 90 degrees, the others' fans being split).
TEST(VoronoiDiagram, CellAreaIsTheSumOfItsFanTrianglesBitForBit) {
  const std::vector<std::vector<Vec3>> sets = {testing::uniform_on_sphere(20000, 3), testing::clustered(3000, 7, 1e-4, 4),
                                               testing::lat_lon_grid(2.5), testing::on_great_circle(40, 5),
                                               testing::skinny_set(60), testing::in_hemisphere(500, 6)};
  std::size_t checked = 0;
  for (std::size_t k = 0; k < sets.size(); ++k) {
    SphericalDelaunay dt;
    const VoronoiDiagram vd = diagram_of(sets[k], &dt);
    for (SiteId s = 0; s < vd.site_capacity(); ++s) {
      const std::span<const TriId> tris = vd.cell_vertices(s);
      if (tris.empty()) continue;
      const Vec3& site = vd.site(s);
      bool simple = true;
      for (std::size_t i = 0; i < tris.size(); ++i)
        simple = simple && dot(site, vd.vertex(tris[i])) >= -0.5 &&
                 dot(vd.vertex(tris[i]), vd.vertex(tris[(i + 1) % tris.size()])) >= 0;
      if (!simple) continue;
      double sum = 0;
      for (std::size_t i = 0; i < tris.size(); ++i)
        sum += VoronoiDiagram::triangle_area_sr(site, vd.vertex(tris[i]), vd.vertex(tris[(i + 1) % tris.size()]));
      ASSERT_EQ(vd.cell_area_sr(s), sum) << "set " << k << ", site " << s;
      ++checked;
    }
  }
  EXPECT_GT(checked, 25000u);
}

// The circumcentre of a cap (three sites 11 m apart on the meridian 37.7, nearly collinear)
// against the plane's normal in binary128. The plain cross product was up to 7e-11 radians
// (0.4 mm) off; within 1e-15 now.
TEST(VoronoiDiagram, CircumcentreOfACapIsAccurate) {
  const Vec3 pts[3] = {SiteEncoder::from_lat_lon(45, 37.7), SiteEncoder::from_lat_lon(45.0001, 37.7),
                       SiteEncoder::from_lat_lon(45.0002, 37.7)};
  for (int k = 0; k < 3; ++k) {
    const Vec3 &a = pts[k], &b = pts[(k + 1) % 3], &c = pts[(k + 2) % 3];
    EXPECT_LT(std::sqrt(norm2(VoronoiDiagram::circumcenter(a, b, c) - testing::exact_circumcentre(a, b, c))), 1e-15) << k;
  }
}

// Sites on one great circle, two of them close and the third far: from the far corner the two
// sides are long, rounded and nearly parallel. Three sites of a fuzz_cells input (0.7 m apart on
// the meridian 29 at latitude -52.02, the third on the meridian -151, 76 degrees away) gave a
// vertex 4e-10 radians (3 mm) off the bisector of the close two when the far one came first
// (the smallest id); their lunes' sides, 1e-10 radians apart there, then crossed. And random
// great circles, sites 6 mm to 6 km apart with a third 1 to 179 degrees away, in every order.
TEST(VoronoiDiagram, CircumcentreOfTwoCloseSitesAndAFarOneIsAccurate) {
  const Vec3 far = SiteEncoder::from_lat_lon(-52.022427512188145, -150.99290455481801);
  const Vec3 p = SiteEncoder::from_lat_lon(-52.022424262188146, 29.007095445181989);
  const Vec3 q = SiteEncoder::from_lat_lon(-52.022417762188141, 29.007095445181989);
  const Vec3 exact = testing::exact_circumcentre(far, p, q);
  const Vec3 v = VoronoiDiagram::circumcenter(far, p, q);
  EXPECT_LT(std::sqrt(norm2(v - exact)), 1e-15);
  EXPECT_LT(std::fabs(dot(v, p - q)) / std::sqrt(norm2(p - q)), 1e-15);  // on their bisector
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> unit(-1, 1), log_gap(-9, -3), far_deg(1, 179);
  double worst = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Vec3 axis{unit(rng), unit(rng), unit(rng)};
    axis = (1 / std::sqrt(norm2(axis))) * axis;
    Vec3 e1 = cross(axis, Vec3{unit(rng), unit(rng), unit(rng)});
    e1 = (1 / std::sqrt(norm2(e1))) * e1;
    const Vec3 e2 = cross(axis, e1);
    auto on_circle = [&](double t) { return std::cos(t) * e1 + std::sin(t) * e2; };
    const double t0 = unit(rng) * std::numbers::pi, gap = std::pow(10.0, log_gap(rng));
    const double far = far_deg(rng) * std::numbers::pi / 180;
    const Vec3 sites[3] = {on_circle(t0), on_circle(t0 + gap), on_circle(t0 - far)};
    // The far side's rounding, over the sine of the angle at the close pair (180 - far / 2).
    const double bound = 4 * 0x1p-53 / std::sin(far / 2);
    for (int k = 0; k < 3; ++k) {
      const Vec3 &a = sites[k], &b = sites[(k + 1) % 3], &c = sites[(k + 2) % 3];
      const double error = std::sqrt(norm2(VoronoiDiagram::circumcenter(a, b, c) - testing::exact_circumcentre(a, b, c)));
      worst = std::max(worst, error * std::sin(far / 2));
      ASSERT_LT(error, bound) << trial << " " << k << " gap " << gap << " far " << far;
    }
  }
  std::printf("worst circumcentre error times sin(far / 2): %.3g radians (2^-53 = 1.1e-16)\n", worst);
}

// Built on several threads, the same diagram: vertices, cell lists and neighbours, bit for bit.
TEST(VoronoiDiagram, ThreadsGiveTheSameDiagram) {
  const SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(100000, 31));
  const VoronoiDiagram one(dt), two(dt, 2), three(dt, 3);
  ASSERT_EQ(one.num_vertices(), three.num_vertices());
  ASSERT_EQ(one.num_vertices(), two.num_vertices());
  for (TriId t = 0; t < one.num_vertices(); ++t) ASSERT_EQ(one.vertex(t), three.vertex(t)) << t;
  for (TriId t = 0; t < one.num_vertices(); ++t) ASSERT_EQ(one.vertex(t), two.vertex(t)) << t;
  for (SiteId s = 0; s < one.site_capacity(); ++s) {
    const auto a = one.cell_neighbors(s), b = two.cell_neighbors(s);
    ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << s;
  }
  for (SiteId s = 0; s < one.site_capacity(); ++s) {
    const auto a = one.cell_vertices(s), b = three.cell_vertices(s);
    ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << s;
    const auto na = one.cell_neighbors(s), nb = three.cell_neighbors(s);
    ASSERT_TRUE(std::equal(na.begin(), na.end(), nb.begin(), nb.end())) << s;
  }
  EXPECT_EQ(one.storage_order().size(), three.storage_order().size());
}

// assign() reusing one diagram's storage gives what a fresh construction gives, whatever the
// diagram held before: more sites, fewer, the degenerate kinds, and removed sites.
TEST(VoronoiDiagram, AssignGivesTheDiagramOfAFreshBuild) {
  auto expect_same = [](const VoronoiDiagram& a, const VoronoiDiagram& b, const std::string& what) {
    ASSERT_EQ(a.kind(), b.kind()) << what;
    ASSERT_EQ(a.num_cells(), b.num_cells()) << what;
    ASSERT_EQ(a.site_capacity(), b.site_capacity()) << what;
    ASSERT_EQ(a.num_vertices(), b.num_vertices()) << what;
    for (TriId t = 0; t < a.num_vertices(); ++t) ASSERT_EQ(a.vertex(t), b.vertex(t)) << what << " vertex " << t;
    for (SiteId s = 0; s < a.site_capacity(); ++s) {
      ASSERT_EQ(a.has_cell(s), b.has_cell(s)) << what << " site " << s;
      const auto va = a.cell_vertices(s), vb = b.cell_vertices(s);
      ASSERT_TRUE(std::equal(va.begin(), va.end(), vb.begin(), vb.end())) << what << " site " << s;
      const auto na = a.cell_neighbors(s), nb = b.cell_neighbors(s);
      ASSERT_TRUE(std::equal(na.begin(), na.end(), nb.begin(), nb.end())) << what << " site " << s;
      ASSERT_EQ(a.cell_area_sr(s), b.cell_area_sr(s)) << what << " site " << s;
    }
    const auto oa = a.storage_order(), ob = b.storage_order();
    ASSERT_TRUE(std::equal(oa.begin(), oa.end(), ob.begin(), ob.end())) << what;
  };
  SphericalDelaunay with_removed = SphericalDelaunay::build(testing::uniform_on_sphere(500, 5));
  for (SiteId s = 0; s < 500; s += 7) with_removed.remove(s);
  const std::vector<std::pair<std::string, SphericalDelaunay>> cases = {
      {"3000 sites", SphericalDelaunay::build(testing::uniform_on_sphere(3000, 1))},
      {"200 sites", SphericalDelaunay::build(testing::uniform_on_sphere(200, 2))},
      {"one site", SphericalDelaunay::build(testing::uniform_on_sphere(1, 3))},
      {"two sites", SphericalDelaunay::build(testing::uniform_on_sphere(2, 4))},
      {"removed sites", with_removed},
      {"5000 sites", SphericalDelaunay::build(testing::uniform_on_sphere(5000, 6))},
      {"no site", SphericalDelaunay{}},
      {"four sites", SphericalDelaunay::build(testing::uniform_on_sphere(4, 7))}};
  VoronoiDiagram reused;
  for (const auto& [name, dt] : cases) {
    reused.assign(dt, name == "5000 sites" ? 2 : 1);
    expect_same(reused, VoronoiDiagram(dt), name);
  }
}

}  // namespace
}  // namespace geovor

// Power cells of weighted sites, against brute force over all sites in long double.
namespace geovor {
namespace {

struct WeightedSet {
  std::vector<Vec3> pts;
  std::vector<double> lifts;
};

WeightedSet weighted_set(std::size_t n, std::uint64_t seed, double max_rad) {
  WeightedSet w{testing::uniform_on_sphere(n, seed), {}};
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, max_rad);
  for (std::size_t i = 0; i < n; ++i) w.lifts.push_back(i % 5 == 0 ? 1.0 : std::cos(u(rng)));
  return w;
}

long double power(const Vec3& x, const Vec3& p, double c) {
  return (static_cast<long double>(x.x) * p.x + static_cast<long double>(x.y) * p.y +
          static_cast<long double>(x.z) * p.z) / c;
}

TEST(PowerDiagram, EveryVertexHasTheLargestPowerForItsThreeSites) {
  for (const double max_rad : {0.05, 0.5}) {
    const WeightedSet w = weighted_set(400, 3, max_rad);
    const SphericalDelaunay dt = SphericalDelaunay::build(w.pts, w.lifts);
    const VoronoiDiagram vd(dt);
    ASSERT_EQ(vd.kind(), VoronoiDiagram::Kind::Cells);
    for (TriId t = 0; t < dt.num_triangles(); ++t) {
      const Vec3& v = vd.vertex(t);
      const long double own = power(v, w.pts[dt.tri_site(t, 0)], w.lifts[dt.tri_site(t, 0)]);
      for (int i = 1; i < 3; ++i)
        EXPECT_NEAR(static_cast<double>(power(v, w.pts[dt.tri_site(t, i)], w.lifts[dt.tri_site(t, i)]) - own), 0, 1e-13);
      for (SiteId s = 0; s < w.pts.size(); ++s)
        EXPECT_LE(static_cast<double>(power(v, w.pts[s], w.lifts[s]) - own), 1e-13) << "triangle " << t << " site " << s;
    }
  }
}

TEST(PowerDiagram, AreasMatchMonteCarloAndSumToTheSphere) {
  const WeightedSet w = weighted_set(60, 8, 0.6);
  const SphericalDelaunay dt = SphericalDelaunay::build(w.pts, w.lifts);
  const VoronoiDiagram vd(dt);
  const auto samples = testing::uniform_on_sphere(400000, 99);
  std::vector<double> hits(w.pts.size(), 0);
  for (const Vec3& x : samples) {
    SiteId best = 0;
    for (SiteId s = 1; s < w.pts.size(); ++s)
      if (power(x, w.pts[s], w.lifts[s]) > power(x, w.pts[best], w.lifts[best])) best = s;
    hits[best] += 1;
  }
  double total = 0;
  int outside_own_cell = 0;
  for (SiteId s = 0; s < w.pts.size(); ++s) {
    const double area = vd.cell_area_sr(s), frac = hits[s] / static_cast<double>(samples.size());
    total += area;
    // Five binomial standard deviations.
    EXPECT_NEAR(area / (4 * kPi), frac, 5 * std::sqrt(frac * (1 - frac) / samples.size()) + 1e-6) << s;
    if (dt.is_hidden(s)) EXPECT_EQ(hits[s], 0) << s;
    outside_own_cell += vd.has_cell(s) && [&] {
      for (SiteId o = 0; o < w.pts.size(); ++o)
        if (power(w.pts[s], w.pts[o], w.lifts[o]) > power(w.pts[s], w.pts[s], w.lifts[s])) return true;
      return false;
    }();
  }
  EXPECT_NEAR(total, 4 * kPi, 1e-12);
  EXPECT_GT(outside_own_cell, 0);  // the set exercises sites outside their cells
  EXPECT_GT(dt.num_hidden(), 0u);
}

TEST(PowerDiagram, EqualLiftsGiveTheVoronoiVerticesBitForBit) {
  const auto pts = testing::uniform_on_sphere(300, 4);
  const VoronoiDiagram plain(SphericalDelaunay::build(pts));
  const std::vector<double> lifts(pts.size(), std::cos(0.3));
  const VoronoiDiagram same(SphericalDelaunay::build(pts, lifts));
  ASSERT_EQ(plain.num_vertices(), same.num_vertices());
  for (TriId t = 0; t < plain.num_vertices(); ++t) EXPECT_EQ(plain.vertex(t), same.vertex(t));
}

TEST(PowerDiagram, TwoWeightedSitesSplitAtTheirPowerBisector) {
  const std::vector<Vec3> pts{{1, 0, 0}, {0, 1, 0}};
  const std::vector<double> lifts{std::cos(0.5), 1.0};
  const VoronoiDiagram vd(SphericalDelaunay::build(pts, lifts));
  ASSERT_EQ(vd.kind(), VoronoiDiagram::Kind::Hemispheres);
  const Vec3 n = vd.hemisphere_normal(0);
  // The boundary: x . p0 / c0 = x . p1, i.e. the normal is along p0 - c0 p1.
  const double c0 = std::cos(0.5), len = std::sqrt(1 + c0 * c0);
  EXPECT_NEAR(n.x, 1 / len, 1e-15);
  EXPECT_NEAR(n.y, -c0 / len, 1e-15);
}

}  // namespace
}  // namespace geovor
