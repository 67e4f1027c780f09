// The cavity of an inserted point: decided exactly when the filter cannot (co-circular and
// flat configurations), grown past the scratch buffers' sizes (a point seeing most of the hull),
// and never a non-disk (a point on a site merges instead).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/kernel/predicates.hpp"
#include "support/generators.hpp"
#include "support/triangulation_checks.hpp"

namespace geovor {
namespace {

using testing::build_checked;
using testing::triangle_set;

TEST(Cavity, DegenerateCircles) {
  // All on the equator: every triangle is flat (a hemisphere), none is a ghost.
  const auto eq = testing::on_great_circle(200, 6);
  const SphericalDelaunay dt = build_checked(eq, nullptr, true);
  EXPECT_EQ(dt.num_triangles(), 2 * eq.size() - 4);
  for (TriId t = 0; t < dt.num_triangles(); ++t)
    EXPECT_EQ(kernel::orient(dt.site(dt.tri_site(t, 0)), dt.site(dt.tri_site(t, 1)), dt.site(dt.tri_site(t, 2))), Sign::Zero);
  // All on one small circle: one side is a hemisphere-plus cap (ghosts), the other solid.
  const auto sc = testing::on_small_circle(100, 40, 7);
  const SphericalDelaunay dc = build_checked(sc, nullptr, true);
  EXPECT_EQ(dc.num_triangles(), 2 * sc.size() - 4);
  EXPECT_EQ(dc.num_ghost_triangles(), sc.size() - 2);
}

// Sites on a circle at latitude 5 degrees and above it, then the south pole: it sees the whole
// triangulated disk of the circle (all ghosts), far more triangles than the scratch buffers hold
// at first.
TEST(Cavity, LargeCavityEqualsABuild) {
  auto pts = testing::in_hemisphere(500, 8);
  for (const Vec3& p : testing::on_small_circle(300, 5.0, 3)) pts.push_back(p);
  SphericalDelaunay dt = build_checked(pts);
  ASSERT_GT(dt.num_ghost_triangles(), 100u);
  const InsertResult r = dt.insert({0, 0, -1});
  ASSERT_FALSE(r.merged);
  pts.push_back({0, 0, -1});
  EXPECT_TRUE(dt.validate(nullptr, true).ok());
  EXPECT_EQ(dt.num_ghost_triangles(), 0u);
  EXPECT_EQ(triangle_set(dt), triangle_set(build_checked(pts)));
}

// A point exactly on a co-circular grid's site, or on the circumcircle of many: the cavity is
// decided by the perturbation, and a point on a site merges instead of making a non-disk.
TEST(Cavity, PointsOnSitesAndOnCircumcircles) {
  const auto grid = testing::lat_lon_grid(15);
  SphericalDelaunay dt = build_checked(grid);
  for (SiteId s = 0; s < grid.size(); s += 7) {
    const InsertResult r = dt.insert(grid[s]);
    EXPECT_TRUE(r.merged);
    EXPECT_EQ(r.site, s);
  }
  // The cell centres: each in the circumcircle of its four co-circular corners, the triangles
  // there chosen by the perturbation, which the new cavities must follow.
  const auto centres = testing::lat_lon_grid(15, -82.5, 82.5, -172.5, 172.5);
  std::vector<Vec3> all = grid;
  for (const Vec3& p : centres) {
    ASSERT_FALSE(dt.insert(p).merged);
    all.push_back(p);
  }
  EXPECT_TRUE(dt.validate().ok());
  EXPECT_EQ(triangle_set(dt), triangle_set(build_checked(all)));
}

}  // namespace
}  // namespace geovor
