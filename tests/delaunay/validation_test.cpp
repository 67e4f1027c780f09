// SphericalDelaunay::validate(): passes on every triangulation built, fails on a broken
// structure, a non-Delaunay edge or a build report that does not account for every input.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "support/generators.hpp"
#include "support/triangulation_checks.hpp"

namespace geovor {
namespace {

using testing::build_checked;
using testing::expect_as_rebuilt;
using testing::jitter;
using testing::triangle_set;
using testing::Tri;
using testing::weather_station_sites;

TEST(Validation, BruteForceNoSiteInAnyCircumcircle) {
  // validate(global) tests every triangle against every site, exactly.
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const auto pts = testing::uniform_on_sphere(300, seed);
    build_checked(pts, nullptr, true);
  }
}

TEST(Validation, ValidateCatchesCorruption) {
  // validate() must fail on a broken structure: flip one triangle's orientation by hand.
  const auto pts = testing::uniform_on_sphere(50, 3);
  SphericalDelaunay dt = SphericalDelaunay::build(pts);
  auto* tris = const_cast<SiteId*>(dt.triangles().data());
  std::swap(tris[0], tris[1]);
  EXPECT_FALSE(dt.validate().ok());
  std::swap(tris[0], tris[1]);
  EXPECT_TRUE(dt.validate().ok());
  // A non-Delaunay but combinatorially valid triangulation: flip one edge by hand.
  SphericalDelaunay flipped = SphericalDelaunay::build(pts);
  auto* t2 = const_cast<SiteId*>(flipped.triangles().data());
  auto* h2 = const_cast<HalfedgeId*>(flipped.halfedges().data());
  const HalfedgeId a = 0, b = h2[0];
  // Triangles (p0 p1 p2) and (p1 p0 p3) become (p3 p2 p0) and (p2 p3 p1): rewrite both.
  const SiteId p0 = t2[a], p1 = t2[next_halfedge(a)], p2 = t2[prev_halfedge(a)], p3 = t2[prev_halfedge(b)];
  const HalfedgeId a1 = h2[next_halfedge(a)], a2 = h2[prev_halfedge(a)], b1 = h2[next_halfedge(b)], b2 = h2[prev_halfedge(b)];
  const TriId ta = tri_of(a), tb = tri_of(b);
  t2[3 * ta] = p3, t2[3 * ta + 1] = p2, t2[3 * ta + 2] = p0;
  t2[3 * tb] = p2, t2[3 * tb + 1] = p3, t2[3 * tb + 2] = p1;
  auto link = [&](HalfedgeId x, HalfedgeId y) { h2[x] = y, h2[y] = x; };
  link(3 * ta, 3 * tb);
  link(3 * ta + 1, a2);  // p2 -> p0
  link(3 * ta + 2, b1);  // p0 -> p3
  link(3 * tb + 1, b2);  // p3 -> p1
  link(3 * tb + 2, a1);  // p1 -> p2
  const Validation v = flipped.validate();
  EXPECT_FALSE(v.ok());
}


TEST(Validation, ReportMustAccountForEveryInput) {
  auto pts = testing::uniform_on_sphere(100, 5);
  pts.push_back(pts[3]);  // an exact duplicate, merged into site 3
  BuildReport rep;
  const SphericalDelaunay dt = SphericalDelaunay::build(pts, {}, &rep);
  ASSERT_TRUE(dt.validate(&rep).ok());
  BuildReport unlisted = rep;
  unlisted.merges.clear();
  EXPECT_FALSE(dt.validate(&unlisted).ok());
  BuildReport wrong_site = rep;
  wrong_site.merges[0].site = 4;
  EXPECT_FALSE(dt.validate(&wrong_site).ok());
  BuildReport lost = rep;
  lost.site_of_input[7] = kNoIndex;
  EXPECT_FALSE(dt.validate(&lost).ok());
}

// On several threads (slices of 2^16 edges): the same errors in the same order. Sites moved
// across their neighbours leave the structure valid and some edges not locally Delaunay.
TEST(Validation, TheSameErrorsOnAnyThreads) {
  const auto pts = testing::uniform_on_sphere(150000, 6);
  const SphericalDelaunay dt = SphericalDelaunay::build(pts);
  ASSERT_TRUE(dt.validate(nullptr, false, 3).ok());
  SphericalDelaunay::Arrays a = dt.arrays();
  for (std::size_t i = 7; i < a.sites.size(); i += 1500) a.sites[i] = a.sites[(i * 7919) % a.sites.size()];
  for (std::size_t i = 11; i < a.sites.size(); i += 1500)
    a.sites[i] = testing::normalized(a.sites[i] + Vec3{0.01, -0.01, 0.005});
  const SphericalDelaunay moved = SphericalDelaunay::from_arrays(std::move(a));
  const Validation serial = moved.validate();
  ASSERT_EQ(serial.errors.size(), 50u);  // at most 50 are kept
  for (const unsigned threads : {2u, 3u, 0u}) EXPECT_EQ(moved.validate(nullptr, false, threads).errors, serial.errors) << threads;
}

}  // namespace
}  // namespace geovor
