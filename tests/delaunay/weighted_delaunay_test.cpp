// SphericalDelaunay::build(points, lifts): the regular triangulation of weighted sites equals the
// exact convex hull of the lifted points computed by CGAL (Epeck), hides what the hull hides,
// keeps the larger circle of two at one position, and equal lifts give the unweighted build.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/kernel/predicates.hpp"
#include "support/cgal_hull_oracle.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

using Tri = std::array<std::uint32_t, 3>;

std::vector<Tri> triangles_of(const SphericalDelaunay& dt) {
  std::vector<Tri> out;
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    Tri x{dt.tri_site(t, 0), dt.tri_site(t, 1), dt.tri_site(t, 2)};
    std::rotate(x.begin(), std::min_element(x.begin(), x.end()), x.end());
    out.push_back(x);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Lifts of radii drawn up to max_rad radians (uniform), some sites unweighted.
std::vector<double> random_lifts(std::size_t n, double max_rad, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, max_rad);
  std::vector<double> c(n);
  for (double& x : c) x = (rng() % 4 == 0) ? 1.0 : std::cos(u(rng));
  return c;
}

void expect_matches_hull(std::span<const Vec3> pts, std::span<const double> lifts) {
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(pts, lifts, {}, &report);
  const Validation v = dt.validate(&report, pts.size() <= 400);
  ASSERT_TRUE(v.ok()) << v.errors.front();
  std::vector<std::uint32_t> vertices;
  const std::vector<Tri> hull = testing::cgal_lifted_hull(pts, lifts, &vertices);
  // No merge in these inputs: site ids are input indices.
  ASSERT_TRUE(report.merges.empty());
  ASSERT_EQ(dt.site_capacity(), pts.size());
  EXPECT_EQ(triangles_of(dt), hull);
  std::vector<std::uint32_t> live;
  for (SiteId s = 0; s < dt.site_capacity(); ++s) {
    if (dt.is_live(s)) live.push_back(s);
    EXPECT_EQ(dt.is_hidden(s), !dt.is_live(s)) << s;
  }
  EXPECT_EQ(live, vertices);
  EXPECT_EQ(report.hidden.size(), pts.size() - live.size());
  for (const Hidden& h : report.hidden) {
    ASSERT_TRUE(dt.is_live(h.by));
    // The hider's power at the hidden site's position is at least the hidden site's own.
    EXPECT_NE(kernel::compare_power(pts[h.site], pts[h.by], lifts[h.by], pts[h.site], lifts[h.site]),
              Sign::Negative);
  }
}

TEST(WeightedDelaunay, MatchesTheExactHullOfTheLiftedPoints) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const auto pts = testing::uniform_on_sphere(300, seed);
    expect_matches_hull(pts, random_lifts(pts.size(), 0.3, seed));
  }
}

TEST(WeightedDelaunay, HugeCirclesHideManySites) {
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const auto pts = testing::uniform_on_sphere(400, seed + 10);
    std::vector<double> lifts(pts.size(), 1.0);
    for (std::size_t i = 0; i < pts.size(); i += 37) lifts[i] = std::cos(1.2);  // radius 69 degrees
    expect_matches_hull(pts, lifts);
    // In input order, most sites are vertices before a huge circle hides them.
    DelaunayOptions in_order;
    in_order.spatial_sort = false;
    BuildReport report;
    const SphericalDelaunay dt = SphericalDelaunay::build(pts, lifts, in_order, &report);
    EXPECT_GT(report.hidden.size(), pts.size() / 2);
    EXPECT_TRUE(dt.validate(&report, true).ok());
  }
}

TEST(WeightedDelaunay, ClustersWithNestedCircles) {
  const auto pts = testing::clustered(400, 5, 0.05, 3);
  std::vector<double> lifts(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) lifts[i] = std::cos(0.001 * static_cast<double>(i % 50));
  expect_matches_hull(pts, lifts);
}

TEST(WeightedDelaunay, OneHemisphere) {
  const auto pts = testing::in_hemisphere(300, 4);
  expect_matches_hull(pts, random_lifts(pts.size(), 0.2, 4));
}

TEST(WeightedDelaunay, RadiiNearTheLimit) {
  const auto pts = testing::uniform_on_sphere(200, 8);
  std::vector<double> lifts(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) lifts[i] = i % 2 ? 1e-6 * static_cast<double>(i) : 1.0;
  expect_matches_hull(pts, lifts);
}

TEST(WeightedDelaunay, EqualLiftsGiveTheUnweightedTriangulation) {
  // Co-circular and great-circle ties included: the perturbation decides them alike.
  for (const auto& pts : {testing::lat_lon_grid(15.0), testing::cube_corners(), testing::uniform_on_sphere(500, 2)}) {
    const SphericalDelaunay plain = SphericalDelaunay::build(pts);
    const std::vector<double> lifts(pts.size(), std::cos(0.01));
    const SphericalDelaunay w = SphericalDelaunay::build(pts, lifts);
    EXPECT_FALSE(w.is_weighted());
    EXPECT_EQ(triangles_of(w), triangles_of(plain));
  }
}

TEST(WeightedDelaunay, TiesOnAGridWithTwoLiftsAreValid) {
  // Grid sites share latitudes and lie on meridians (many exact ties) with two lifts.
  const auto pts = testing::lat_lon_grid(10.0);
  std::vector<double> lifts(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) lifts[i] = i % 3 ? 1.0 : std::cos(0.02);
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(pts, lifts, {}, &report);
  const Validation v = dt.validate(&report, true);
  EXPECT_TRUE(v.ok()) << v.errors.front();
  // The same triangulation from any insertion order.
  DelaunayOptions unsorted;
  unsorted.spatial_sort = false;
  const SphericalDelaunay again = SphericalDelaunay::build(pts, lifts, unsorted);
  EXPECT_EQ(triangles_of(again), triangles_of(dt));
}

TEST(WeightedDelaunay, ASmallCircleInsideALargeOneIsHidden) {
  // The octahedron, +x with radius 0.1 rad, and e 0.001 rad from +x: cos(0.001) / cos(0.1) + sin(0.001)
  // < 1, so e's lifted point is below the faces around +x's.
  const std::vector<Vec3> pts{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}, {0, 0, -1},
                              testing::normalized({1, 0.001, 0})};
  const std::vector<double> lifts{std::cos(0.1), 1, 1, 1, 1, 1, 1};
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(pts, lifts, {}, &report);
  ASSERT_TRUE(dt.validate(&report, true).ok());
  EXPECT_TRUE(dt.is_hidden(6));
  EXPECT_EQ(dt.hidden_by(6), 0u);
  ASSERT_EQ(report.hidden.size(), 1u);
  EXPECT_EQ(report.hidden[0].site, 6u);
  EXPECT_EQ(dt.num_sites(), 6u);
  EXPECT_EQ(dt.num_hidden(), 1u);
  // Given first, e is a vertex until +x arrives and hides it inside its cavity.
  DelaunayOptions in_order;
  in_order.spatial_sort = false;
  const std::vector<Vec3> e_first{pts[6], pts[1], pts[2], pts[3], pts[4], pts[5], pts[0]};
  const std::vector<double> lifts2{1, 1, 1, 1, 1, 1, std::cos(0.1)};
  BuildReport report2;
  const SphericalDelaunay dt2 = SphericalDelaunay::build(e_first, lifts2, in_order, &report2);
  ASSERT_TRUE(dt2.validate(&report2, true).ok());
  EXPECT_TRUE(dt2.is_hidden(0));
  EXPECT_EQ(dt2.hidden_by(0), 6u);
}

TEST(WeightedDelaunay, SitesAtOnePositionKeepTheLargerCircle) {
  auto pts = testing::uniform_on_sphere(50, 5);
  std::vector<double> lifts(pts.size(), 1.0);
  pts.push_back(pts[7]);  // 50: a larger circle at site 7's position
  lifts.push_back(std::cos(0.05));
  pts.push_back(pts[7]);  // 51: a smaller one
  lifts.push_back(std::cos(0.01));
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(pts, lifts, {}, &report);
  ASSERT_TRUE(dt.validate(&report, true).ok());
  ASSERT_EQ(report.merges.size(), 2u);
  const SiteId kept = report.site_of_input[50];
  EXPECT_EQ(report.site_of_input[7], kept);
  EXPECT_EQ(report.site_of_input[51], kept);
  EXPECT_EQ(dt.lift(kept), std::cos(0.05));
  EXPECT_TRUE(dt.is_live(kept));
}

TEST(WeightedDelaunay, NearDuplicatesKeepTheLargerCircleInEitherOrder) {
  // Two points 2^-26 apart (0.09 m on the Earth, below the merge distance) with radii 1 and 5 km.
  const auto base = testing::uniform_on_sphere(60, 9);
  const Vec3 p = base[0];
  const Vec3 q = testing::normalized({p.x + 0x1p-26, p.y, p.z});
  for (const bool larger_first : {false, true}) {
    std::vector<Vec3> pts(base.begin() + 1, base.end());
    std::vector<double> lifts(pts.size(), 1.0);
    const double small = std::cos(1000 / 6371008.771415), large = std::cos(5000 / 6371008.771415);
    pts.push_back(larger_first ? q : p), lifts.push_back(larger_first ? large : small);
    pts.push_back(larger_first ? p : q), lifts.push_back(larger_first ? small : large);
    for (const bool sorted : {false, true}) {
      DelaunayOptions options;
      options.spatial_sort = sorted;
      BuildReport report;
      const SphericalDelaunay dt = SphericalDelaunay::build(pts, lifts, options, &report);
      ASSERT_TRUE(dt.validate(&report, true).ok());
      ASSERT_EQ(report.merges.size(), 1u);
      EXPECT_TRUE(report.hidden.empty());  // merged, not hidden
      const SiteId kept = report.merges[0].site;
      EXPECT_EQ(dt.lift(kept), large);
      EXPECT_GT(report.merges[0].chord, 0);
      EXPECT_EQ(lifts[report.merges[0].input], small);
    }
  }
}

TEST(WeightedDelaunay, CirclesThroughOnePointOnTheEquator) {
  // Sites on the equator at longitude l with radius |l| (radians): every circle passes through
  // (0, 0) and the lifted points (1, tan l, 0) lie (up to rounding) on one line; with sites off
  // the equator, the build must stay valid whatever the perturbation decides.
  std::vector<Vec3> pts;
  std::vector<double> lifts;
  for (int k = -8; k <= 8; ++k) {
    const double l = 0.15 * k;
    pts.push_back({std::cos(l), std::sin(l), 0});
    lifts.push_back(std::cos(std::fabs(l)));
  }
  for (const Vec3& p : testing::uniform_on_sphere(40, 17)) pts.push_back(p), lifts.push_back(1.0);
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(pts, lifts, {}, &report);
  const Validation v = dt.validate(&report, true);
  EXPECT_TRUE(v.ok()) << v.errors.front();
  DelaunayOptions in_order;
  in_order.spatial_sort = false;
  EXPECT_EQ(triangles_of(SphericalDelaunay::build(pts, lifts, in_order)), triangles_of(dt));
}

TEST(WeightedDelaunay, RejectsBadLiftsAndEdits) {
  const auto pts = testing::uniform_on_sphere(20, 1);
  std::vector<double> lifts(pts.size(), 1.0);
  EXPECT_THROW(SphericalDelaunay::build(pts, std::span<const double>(lifts).first(3)), Error);
  for (const double bad : {0.0, -0.5, 1.0000001, std::nan("")}) {
    lifts[3] = bad;
    EXPECT_THROW(SphericalDelaunay::build(pts, lifts), Error) << bad;
  }
  lifts[3] = 0.5;
  SphericalDelaunay dt = SphericalDelaunay::build(pts, lifts);
  EXPECT_TRUE(dt.is_weighted());
  EXPECT_THROW(dt.remove(0), Error);
  EXPECT_THROW(dt.insert(testing::normalized({1, 2, 3})), Error);
  EXPECT_THROW(dt.move(0, pts[0]), Error);
}

}  // namespace
}  // namespace geovor
