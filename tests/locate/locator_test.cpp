// Every strategy against brute force, exactly; the geodesic metric against GeographicLib's
// NearestNeighbor over WGS84 geodesics.
#include "geovor/locate/locator.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/NearestNeighbor.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "geovor/core/error.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/kernel/predicates.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

constexpr LocateStrategy kAll[] = {LocateStrategy::Walk,         LocateStrategy::JumpWalk,
                                   LocateStrategy::KeepJumpWalk, LocateStrategy::Hierarchy,
                                   LocateStrategy::Climb,        LocateStrategy::KeepJumpClimb};

// Brute force: the largest dot product in doubles, then the exact order among the sites within
// rounding of it, ties to the lowest id.
SiteId brute_nearest(const SphericalDelaunay& dt, const Vec3& q) {
  double best = -3;
  for (SiteId s = 0; s < dt.site_capacity(); ++s)
    if (dt.is_live(s)) best = std::max(best, dot(q, dt.site(s)));
  SiteId win = kNoIndex;
  for (SiteId s = 0; s < dt.site_capacity(); ++s) {
    if (!dt.is_live(s) || dot(q, dt.site(s)) < best - 1e-12) continue;
    if (win == kNoIndex) {
      win = s;
      continue;
    }
    const Sign c = kernel::compare_dot(q, dt.site(s), dt.site(win));
    if (c == Sign::Positive) win = s;  // s < win never holds here with Zero: ids ascend
  }
  return win;
}

// Random queries, coherent queries (random walkers taking small steps) and special positions.
// Under ASan and UBSan (10x slower) a quarter of the queries: the same checks, in CI's time.
constexpr std::size_t kQueryDivisor = GEOVOR_TESTS_SANITIZED ? 4 : 1;

std::vector<Vec3> query_mix(const SphericalDelaunay& dt, std::size_t n_random, std::size_t n_coherent,
                            std::uint64_t seed) {
  n_random /= kQueryDivisor;
  n_coherent /= kQueryDivisor;
  std::vector<Vec3> q = testing::uniform_on_sphere(n_random, seed);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> step(0, 2e-3);
  std::vector<Vec3> walkers = testing::uniform_on_sphere(4, seed + 1);
  for (std::size_t i = 0; i < n_coherent; ++i) {
    Vec3& w = walkers[i % walkers.size()];
    w = testing::normalized(w + Vec3{step(rng), step(rng), step(rng)});
    q.push_back(w);
  }
  // On sites, at midpoints of edges, at Voronoi vertices (triangle circumcentres), poles, 180.
  for (SiteId s = 0; s < std::min<std::size_t>(dt.site_capacity(), 2000); ++s)
    if (dt.is_live(s)) q.push_back(dt.site(s));
  for (TriId t = 0; t < std::min<std::size_t>(dt.num_triangles(), 2000); ++t) {
    const Vec3 a = dt.site(dt.tri_site(t, 0)), b = dt.site(dt.tri_site(t, 1)), c = dt.site(dt.tri_site(t, 2));
    q.push_back(testing::normalized(a + b));
    q.push_back(testing::normalized(cross(b - a, c - a)));
  }
  for (const double lat : {90.0, -90.0, 0.0, 45.0, -60.0})
    for (const double lon : {180.0, -180.0, 179.9999999, 0.0}) {
      double la = lat, lo = lon;
      normalize_lat_lon(la, lo);
      q.push_back(SiteEncoder::from_lat_lon(la, lo));
    }
  return q;
}

void expect_all_strategies_exact(const DelaunayHierarchy& h, const std::vector<Vec3>& queries,
                                 const char* what) {
  std::vector<SiteId> truth(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) truth[i] = brute_nearest(h.base(), queries[i]);
  for (const LocateStrategy strategy : kAll) {
    // Walking the packed copy from the first query, and walking the hierarchy itself (on a
    // prefix: the same templated code, another layout).
    Locator locator(h, {strategy});
    locator.prepare();
    LocatorOptions direct{strategy};
    direct.packed = false;
    Locator plain(h, direct);
    std::size_t wrong = 0, wrong_plain = 0;
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const NearestResult r = locator.nearest(queries[i]);
      if (r.site != truth[i]) ++wrong;
      if (i < 20000 && plain.nearest(queries[i]).site != truth[i]) ++wrong_plain;
    }
    EXPECT_NE(locator.walk_graph(), nullptr);
    EXPECT_EQ(plain.walk_graph(), nullptr);
    EXPECT_EQ(wrong, 0u) << what << ": " << to_string(strategy);
    EXPECT_EQ(wrong_plain, 0u) << what << ": " << to_string(strategy) << " on the hierarchy itself";
  }
}

TEST(Locator, EveryStrategyIsExactOnUniformSites) {
  const auto sites = testing::uniform_on_sphere(10000, 11);
  const DelaunayHierarchy h = DelaunayHierarchy::build(sites);
  expect_all_strategies_exact(h, query_mix(h.base(), 100000, 100000, 3), "uniform");
}

TEST(Locator, EveryStrategyIsExactOnClusteredSites) {
  const auto sites = testing::clustered(10000, 30, 0.02, 12);
  const DelaunayHierarchy h = DelaunayHierarchy::build(sites);
  expect_all_strategies_exact(h, query_mix(h.base(), 100000, 100000, 4), "clustered");
}

TEST(Locator, EveryStrategyIsExactOnWeatherStationsAndGrids) {
  const SiteTable table = read_sites_csv_file(std::string(GEOVOR_SOURCE_DIR) + "/datasets/weather_stations.csv");
  std::vector<Vec3> pts;
  for (const auto& s : table.sites) pts.push_back(s.unit);
  const DelaunayHierarchy h = DelaunayHierarchy::build(pts);
  expect_all_strategies_exact(h, query_mix(h.base(), 100000, 100000, 5), "weather stations");
  // A grid: queries on cell boundaries are exact ties between sites, broken by the lowest id.
  const DelaunayHierarchy g = DelaunayHierarchy::build(testing::lat_lon_grid(5));
  expect_all_strategies_exact(g, query_mix(g.base(), 20000, 20000, 6), "5 degree grid");
}

TEST(Locator, EveryStrategyIsExactOnCities) {
  const std::string path = std::string(GEOVOR_SOURCE_DIR) + "/datasets/geonames_cities.csv.gz";
  const auto pts = testing::load_lat_lon_csv_gz_unit_vectors(path);
  ASSERT_EQ(pts.size(), 171075u);
  const DelaunayHierarchy h = DelaunayHierarchy::build(pts);
  expect_all_strategies_exact(h, query_mix(h.base(), 3000, 3000, 7), "cities");
}

TEST(Locator, TiesGoToTheLowestId) {
  // Two sites symmetric about the equator: every point of the equator is a tie.
  const std::vector<Vec3> sites{testing::normalized({1, 0, 1}), testing::normalized({1, 0, -1}),
                                testing::normalized({-1, 0.2, 0.3}), testing::normalized({-1, -0.5, -0.1})};
  const DelaunayHierarchy h = DelaunayHierarchy::build(sites);
  Locator locator(h);
  EXPECT_EQ(locator.nearest({1, 0, 0}).site, 0u);
  EXPECT_EQ(locator.nearest(testing::normalized({1, 0, 1e-300})).site, 0u);
  EXPECT_EQ(locator.nearest(testing::normalized({1, 0, -1e-17})).site, 1u);
}

TEST(Locator, FewSites) {
  for (std::size_t n : {1u, 2u, 3u}) {
    const auto sites = testing::uniform_on_sphere(n, 9);
    const DelaunayHierarchy h = DelaunayHierarchy::build(sites);
    Locator locator(h);
    for (const Vec3& q : testing::uniform_on_sphere(200, 10)) EXPECT_EQ(locator.nearest(q).site, brute_nearest(h.base(), q));
  }
  const DelaunayHierarchy empty = DelaunayHierarchy::build(std::vector<Vec3>{});
  Locator none(empty);
  EXPECT_EQ(none.nearest({0, 0, 1}).site, kNoIndex);
}

TEST(Locator, KNearestAndWithinMatchBruteForce) {
  const auto sites = testing::uniform_on_sphere(3000, 21);
  const DelaunayHierarchy h = DelaunayHierarchy::build(sites);
  Locator locator(h);
  for (const Vec3& q : testing::uniform_on_sphere(300, 22)) {
    std::vector<SiteId> order(sites.size());
    for (SiteId s = 0; s < order.size(); ++s) order[s] = s;
    std::sort(order.begin(), order.end(), [&](SiteId a, SiteId b) {
      const Sign c = kernel::compare_dot(q, sites[a], sites[b]);
      return c == Sign::Positive || (c == Sign::Zero && a < b);
    });
    const auto k = locator.k_nearest(q, 12);
    ASSERT_EQ(k.size(), 12u);
    for (std::size_t i = 0; i < k.size(); ++i) EXPECT_EQ(k[i].site, order[i]);
    const double radius_m = 500e3;
    const auto w = locator.within(q, radius_m);
    std::size_t expected = 0;
    for (SiteId s = 0; s < sites.size(); ++s) expected += great_circle_m(q, sites[s]) <= radius_m;
    ASSERT_EQ(w.size(), expected);
    for (std::size_t i = 0; i < w.size(); ++i) EXPECT_EQ(w[i].site, order[i]);
  }
}

TEST(Locator, DistancesAreGreatCircleMetres) {
  // A quarter of a great circle: pi/2 R.
  EXPECT_NEAR(great_circle_m({1, 0, 0}, {0, 1, 0}), M_PI / 2 * SiteEncoder::kEarthRadiusM, 1e-6);
  EXPECT_NEAR(great_circle_m({1, 0, 0}, testing::normalized({1, 1e-9, 0})), 1e-9 * SiteEncoder::kEarthRadiusM, 1e-9);
}

TEST(Locator, GeodesicMetricMatchesGeographicLibNearestNeighbor) {
  const SiteTable table = read_sites_csv_file(std::string(GEOVOR_SOURCE_DIR) + "/datasets/weather_stations.csv");
  std::vector<Vec3> pts;
  for (const auto& s : table.sites) pts.push_back(s.unit);
  BuildReport report;
  const DelaunayHierarchy h = DelaunayHierarchy::build(pts, {}, {}, &report);
  // The oracle's points: the sites' geodetic positions as the locator sees them.
  struct Pos {
    double lat, lon;
  };
  std::vector<Pos> site_pos;
  for (SiteId s = 0; s < h.base().site_capacity(); ++s) {
    const LatLon ll = SiteEncoder::to_lat_lon(h.base().site(s));
    site_pos.push_back({ll.lat_deg, ll.lon_deg});
  }
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  struct Dist {
    const GeographicLib::Geodesic* g;
    double operator()(const Pos& a, const Pos& b) const {
      double s12;
      g->Inverse(a.lat, a.lon, b.lat, b.lon, s12);
      return s12;
    }
  };
  const Dist dist{&geod};
  const GeographicLib::NearestNeighbor<double, Pos, Dist> tree(site_pos, dist);
  Locator locator(h);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1, 1), lon(-180, 180);
  std::size_t disagree_sphere = 0, mismatched = 0;
  constexpr int kQueries = 100000;
  for (int i = 0; i < kQueries; ++i) {
    const double lat = std::asin(u(rng)) * 180 / M_PI, lo = lon(rng);  // uniform in area
    const NearestResult r = locator.nearest_geodesic(lat, lo);
    std::vector<int> ind;
    const double d = tree.Search(site_pos, dist, Pos{lat, lo}, ind, 1);
    // Exact ties between two sites at equal geodesic distance are not expected on random queries.
    if (static_cast<int>(r.site) != ind[0] && std::fabs(d - r.dist_m) > 1e-6) ++mismatched;
    EXPECT_NEAR(r.dist_m, d, 1e-6);
    disagree_sphere += locator.nearest(SiteEncoder::from_lat_lon(lat, lo)).site != r.site;
  }
  EXPECT_EQ(mismatched, 0u);
  // The spherical answer differs near cell boundaries only (0.029% of the area, gis.md 7.3).
  EXPECT_GT(disagree_sphere, 0u);
  EXPECT_LT(disagree_sphere, kQueries / 200);
  std::printf("sphere vs geodesic nearest differ on %zu of %d queries\n", disagree_sphere, kQueries);
}

TEST(Locator, BatchOverThreadsEqualsOneThread) {
  const auto sites = testing::uniform_on_sphere(20000, 31);
  const DelaunayHierarchy h = DelaunayHierarchy::build(sites);
  const auto queries = testing::uniform_on_sphere(50000, 32);
  std::vector<NearestResult> one(queries.size()), four(queries.size());
  nearest_batch(h, queries, one, 1);
  nearest_batch(h, queries, four, 4);
  for (std::size_t i = 0; i < queries.size(); ++i) ASSERT_EQ(one[i].site, four[i].site);
  Locator locator(h);
  for (std::size_t i = 0; i < 1000; ++i) EXPECT_EQ(one[i].site, brute_nearest(h.base(), queries[i]));
}

TEST(Locator, AfterInsertAndRemove) {
  const auto pts = testing::uniform_on_sphere(6000, 41);
  DelaunayHierarchy h = DelaunayHierarchy::build(std::span(pts).first(4000));
  for (std::size_t i = 4000; i < 6000; ++i) h.insert(pts[i]);
  for (SiteId s = 0; s < 3000; s += 2) h.remove(s);
  for (const LocateStrategy strategy : kAll) {
    Locator locator(h, {strategy});
    for (const Vec3& q : testing::uniform_on_sphere(3000, 42)) ASSERT_EQ(locator.nearest(q).site, brute_nearest(h.base(), q));
  }
}

// The packed copy is a cache of the hierarchy: every change must be noticed at the next query
// (answers from the hierarchy itself), and the copy rebuilt once queries come without changes.
TEST(Locator, StaysExactWhileTheHierarchyChanges) {
  const auto pts = testing::uniform_on_sphere(8000, 61);
  const auto queries = testing::uniform_on_sphere(4000, 62);
  DelaunayHierarchy h = DelaunayHierarchy::build(std::span(pts).first(5000));
  for (const LocateStrategy strategy : {LocateStrategy::KeepJumpClimb, LocateStrategy::Hierarchy, LocateStrategy::Walk}) {
    LocatorOptions options{strategy};
    options.rebuild_after = 50;
    Locator locator(h, options);
    locator.prepare();
    ASSERT_NE(locator.walk_graph(), nullptr);
    std::size_t next_point = 5000, qi = 0;
    SiteId next_removal = 0;
    for (int round = 0; round < 12; ++round) {
      // One change per query for a while (insert, remove, alternately), then calm.
      for (int k = 0; k < 40; ++k, ++qi) {
        if (k % 2 == 0 && next_point < pts.size()) {
          h.insert(pts[next_point++]);
        } else {
          while (!h.base().is_live(next_removal)) ++next_removal;
          h.remove(next_removal++);
        }
        const Vec3& q = queries[qi % queries.size()];
        ASSERT_EQ(locator.nearest(q).site, brute_nearest(h.base(), q)) << "round " << round << " after a change";
        EXPECT_EQ(locator.walk_graph(), nullptr);  // stale copy dropped
      }
      for (int k = 0; k < 120; ++k, ++qi) {
        const Vec3& q = queries[qi % queries.size()];
        ASSERT_EQ(locator.nearest(q).site, brute_nearest(h.base(), q)) << "round " << round << " calm";
      }
      ASSERT_NE(locator.walk_graph(), nullptr);  // rebuilt after rebuild_after calm queries
      EXPECT_TRUE(locator.walk_graph()->matches(h));
    }
    // A whole new hierarchy in the same object.
    h = DelaunayHierarchy::build(std::span(pts).subspan(1000, 3000));
    for (int k = 0; k < 200; ++k) {
      const Vec3& q = queries[k];
      ASSERT_EQ(locator.nearest(q).site, brute_nearest(h.base(), q)) << "after the hierarchy was replaced";
    }
    h = DelaunayHierarchy::build(std::span(pts).first(5000));
  }
}

TEST(Locator, ParsesStrategyNames) {
  for (const LocateStrategy s : kAll) EXPECT_EQ(parse_strategy(to_string(s)), s);
  EXPECT_THROW(parse_strategy("teleport"), Error);
}

}  // namespace
}  // namespace geovor

namespace geovor {
namespace {

// Regression (2026-11-21): removing every site of the top level left it empty, and the hierarchy
// strategy started its descent there, out of bounds.
TEST(Locator, TopLevelEmptiedByRemovals) {
  const auto pts = testing::uniform_on_sphere(20000, 51);
  DelaunayHierarchy h = DelaunayHierarchy::build(pts);
  const int levels = h.num_levels();
  ASSERT_GE(levels, 3);
  std::vector<SiteId> top_sites;
  for (SiteId s = 0; s < h.base().site_capacity(); ++s)
    if (h.drawn_level(s) >= levels - 1) top_sites.push_back(s);
  for (const SiteId s : top_sites) h.remove(s);
  EXPECT_LT(h.num_levels(), levels);
  ASSERT_TRUE(h.validate().ok());
  for (const LocateStrategy strategy : kAll) {
    Locator locator(h, {strategy});
    for (const Vec3& q : testing::uniform_on_sphere(500, 52)) ASSERT_EQ(locator.nearest(q).site, brute_nearest(h.base(), q));
  }
}

}  // namespace
}  // namespace geovor

// Weighted sites: every strategy answers the site whose power cell holds q (never a hidden
// site); k_nearest and within take the sites by decreasing power.
namespace geovor {
namespace {

// Brute force: the largest power dot(q, p) / c in long double over the vertices, then the exact
// order among those within rounding of it, ties to the lowest id.
SiteId brute_power(const SphericalDelaunay& dt, const Vec3& q) {
  auto power = [&](SiteId s) {
    const Vec3& p = dt.site(s);
    return (static_cast<long double>(q.x) * p.x + static_cast<long double>(q.y) * p.y +
            static_cast<long double>(q.z) * p.z) / dt.lift(s);
  };
  long double best = -1e30L;
  for (SiteId s = 0; s < dt.site_capacity(); ++s)
    if (dt.is_live(s)) best = std::max(best, power(s));
  SiteId win = kNoIndex;
  for (SiteId s = 0; s < dt.site_capacity(); ++s) {
    if (!dt.is_live(s) || power(s) < best - 1e-12L * std::fabs(best)) continue;
    if (win == kNoIndex ||
        kernel::compare_power(q, dt.site(s), dt.lift(s), dt.site(win), dt.lift(win)) == Sign::Positive)
      win = s;
  }
  return win;
}

// Every vertex in the exact order of power at q, ties to the lower id.
std::vector<SiteId> by_power(const SphericalDelaunay& dt, const Vec3& q) {
  std::vector<SiteId> all;
  for (SiteId s = 0; s < dt.site_capacity(); ++s)
    if (dt.is_live(s)) all.push_back(s);
  std::sort(all.begin(), all.end(), [&](SiteId a, SiteId b) {
    const Sign c = kernel::compare_power(q, dt.site(a), dt.lift(a), dt.site(b), dt.lift(b));
    return c == Sign::Positive || (c == Sign::Zero && a < b);
  });
  return all;
}

std::vector<double> lifts_for(std::size_t n, double max_rad, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> r(0, max_rad);
  std::vector<double> lifts(n);
  for (double& c : lifts) c = std::cos(r(rng));
  return lifts;
}

void expect_power_answers(const DelaunayHierarchy& h, const std::vector<Vec3>& queries, const char* what) {
  ASSERT_TRUE(h.is_weighted()) << what;
  ASSERT_TRUE(h.validate().ok()) << what;
  const SphericalDelaunay& base = h.base();
  std::vector<SiteId> truth(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) truth[i] = brute_power(base, queries[i]);
  for (const LocateStrategy strategy : kAll) {
    Locator packed(h, {strategy});
    packed.prepare();
    LocatorOptions direct{strategy};
    direct.packed = false;
    Locator plain(h, direct);
    std::size_t wrong = 0, wrong_plain = 0, bad_distance = 0;
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const NearestResult r = packed.nearest(queries[i]);
      wrong += r.site != truth[i];
      bad_distance += r.site < base.site_capacity() && r.dist_m != great_circle_m(queries[i], base.site(r.site));
      wrong_plain += plain.nearest(queries[i]).site != truth[i];
    }
    EXPECT_EQ(wrong, 0u) << what << ": " << to_string(strategy);
    EXPECT_EQ(wrong_plain, 0u) << what << ": " << to_string(strategy) << " on the hierarchy itself";
    EXPECT_EQ(bad_distance, 0u) << what << ": distance_m is the distance to the site's centre";
  }
}

std::vector<Vec3> weighted_queries(const SphericalDelaunay& dt, std::uint64_t seed) {
  std::vector<Vec3> q = testing::uniform_on_sphere(4000 / kQueryDivisor, seed);
  // On every site, hidden ones included (a hidden site's position is in another's cell), at
  // midpoints of edges and triangle normals (where power bisectors meet).
  for (SiteId s = 0; s < std::min<std::size_t>(dt.site_capacity(), 1500); ++s) q.push_back(dt.site(s));
  for (TriId t = 0; t < std::min<std::size_t>(dt.num_triangles(), 1500); ++t) {
    const Vec3 a = dt.site(dt.tri_site(t, 0)), b = dt.site(dt.tri_site(t, 1)), c = dt.site(dt.tri_site(t, 2));
    q.push_back(testing::normalized(a + b));
    q.push_back(testing::normalized(cross(b - a, c - a)));
  }
  return q;
}

TEST(WeightedLocator, EveryStrategyAnswersTheSiteOfLargestPower) {
  const auto pts = testing::uniform_on_sphere(6000, 61);
  const DelaunayHierarchy h = DelaunayHierarchy::build(pts, lifts_for(pts.size(), 0.05, 62));
  EXPECT_GT(h.base().num_hidden(), 0u);  // radii up to 2.5 times the spacing hide some sites
  expect_power_answers(h, weighted_queries(h.base(), 63), "uniform, random radii");
}

TEST(WeightedLocator, HugeCirclesNestedCirclesAndGridTies) {
  {
    const auto pts = testing::uniform_on_sphere(4000, 64);
    std::vector<double> lifts(pts.size(), 1.0);
    for (std::size_t i = 0; i < pts.size(); i += 53) lifts[i] = std::cos(1.2);  // 69 degrees: each hides many
    const DelaunayHierarchy h = DelaunayHierarchy::build(pts, lifts);
    EXPECT_GT(h.base().num_hidden(), 1000u);
    expect_power_answers(h, weighted_queries(h.base(), 65), "huge circles");
  }
  {
    const auto pts = testing::clustered(5000, 8, 0.02, 66);
    std::vector<double> lifts(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) lifts[i] = std::cos(0.0005 * static_cast<double>(i % 40));
    const DelaunayHierarchy h = DelaunayHierarchy::build(pts, lifts);
    expect_power_answers(h, weighted_queries(h.base(), 67), "clusters of nested circles");
  }
  {
    // Sites sharing latitudes and meridians with two radii: exact ties of power everywhere.
    const auto pts = testing::lat_lon_grid(3);
    std::vector<double> lifts(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) lifts[i] = i % 3 ? 1.0 : std::cos(0.01);
    const DelaunayHierarchy h = DelaunayHierarchy::build(pts, lifts);
    expect_power_answers(h, weighted_queries(h.base(), 68), "grid with two radii");
  }
}

// Regression (fuzz_weighted, 2026-12-07): circles through the north pole put their lifted points
// on the plane z = 1, a face of the hull with a site inside it. At the south pole every site of
// that face ties, and the exact walk from the inner site stopped there (no neighbour strictly
// better) although the huge circles in the south have a far larger power.
TEST(WeightedLocator, APlateauOfTiesIsLeftForABetterNeighbour) {
  std::vector<Vec3> pts{{0, 0, 1}};  // site 0, inside the face
  std::vector<double> lifts{1};
  for (int k = 0; k < 6; ++k) {
    const double lon = k * std::numbers::pi / 3, z = 0.8 + 0.02 * k;
    const double r = std::sqrt(1 - z * z);
    pts.push_back(testing::normalized({r * std::cos(lon), r * std::sin(lon), z}));
    lifts.push_back(pts.back().z);  // the circle through the north pole
  }
  for (int k = 0; k < 4; ++k) {
    const double lon = 0.3 + k * std::numbers::pi / 2;
    pts.push_back(testing::normalized({std::cos(lon), std::sin(lon), -0.1 - 0.05 * k}));
    lifts.push_back(std::ldexp(1.0, -31));  // radii near the limit
  }
  const DelaunayHierarchy h = DelaunayHierarchy::build(pts, lifts);
  ASSERT_TRUE(h.validate().ok());
  std::vector<Vec3> queries{{0, 0, -1}, {0, 0, 1}};
  for (const Vec3& p : testing::uniform_on_sphere(200, 74)) queries.push_back(p);
  expect_power_answers(h, queries, "a plateau of ties");
  Locator walk(h, {LocateStrategy::Walk});
  EXPECT_NE(walk.nearest({0, 0, -1}).site, 0u);
}

TEST(WeightedLocator, KNearestAndWithinGoByPower) {
  const auto pts = testing::uniform_on_sphere(3000, 69);
  const DelaunayHierarchy h = DelaunayHierarchy::build(pts, lifts_for(pts.size(), 0.06, 70));
  const SphericalDelaunay& base = h.base();
  Locator locator(h);
  for (const Vec3& q : testing::uniform_on_sphere(150, 71)) {
    const std::vector<SiteId> order = by_power(base, q);
    const std::vector<NearestResult> k = locator.k_nearest(q, 12);
    ASSERT_EQ(k.size(), 12u);
    for (std::size_t i = 0; i < k.size(); ++i) {
      EXPECT_EQ(k[i].site, order[i]);
      EXPECT_FALSE(base.is_hidden(k[i].site));
    }
    const double radius_m = 600e3;
    std::vector<SiteId> want;
    for (const SiteId s : order)
      if (great_circle_m(q, base.site(s)) <= radius_m) want.push_back(s);
    std::vector<SiteId> got;
    for (const NearestResult& r : locator.within(q, radius_m)) got.push_back(r.site);
    EXPECT_EQ(got, want);
  }
}

TEST(WeightedLocator, GeodesicAnswersNeedUnweightedSites) {
  const auto pts = testing::uniform_on_sphere(500, 72);
  const DelaunayHierarchy h = DelaunayHierarchy::build(pts, lifts_for(pts.size(), 0.05, 73));
  Locator locator(h);
  EXPECT_THROW(locator.nearest_geodesic(10, 20), Error);
  // Equal radii are no weights: the ordinary index, every metric.
  const DelaunayHierarchy equal = DelaunayHierarchy::build(pts, std::vector<double>(pts.size(), std::cos(0.01)));
  EXPECT_FALSE(equal.is_weighted());
  Locator plain(equal);
  EXPECT_NO_THROW(plain.nearest_geodesic(10, 20));
}

}  // namespace
}  // namespace geovor
