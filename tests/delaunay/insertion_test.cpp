// SphericalDelaunay::insert(): one point at a time gives the triangulation build() gives (the
// perturbation follows the ids), a point within the merge distance of a site merges into it and
// gives its id back, and a point that is not a unit vector is an error.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "support/generators.hpp"
#include "support/triangulation_checks.hpp"

namespace geovor {
namespace {

using testing::build_checked;
using testing::triangle_set;

TEST(Insertion, OneAtATimeEqualsABuild) {
  for (const auto& pts : {testing::uniform_on_sphere(2000, 41), testing::lat_lon_grid(15),
                          testing::on_great_circle(60, 2), testing::cube_corners()}) {
    SphericalDelaunay dt;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const InsertResult r = dt.insert(pts[i]);
      ASSERT_FALSE(r.merged);
      ASSERT_EQ(r.site, i);
      if (i < 20 || i % 250 == 0) {
        ASSERT_TRUE(dt.validate(nullptr, i < 200).ok()) << "after " << i;
      }
    }
    EXPECT_TRUE(dt.validate().ok());
    EXPECT_EQ(triangle_set(dt), triangle_set(build_checked(pts)));
  }
}

TEST(Insertion, CloseToASiteMergesAndGivesTheIdBack) {
  const auto pts = testing::uniform_on_sphere(500, 42);
  SphericalDelaunay dt = build_checked(pts);
  for (SiteId s = 0; s < 50; ++s) {
    const Vec3 t = testing::normalized(cross(pts[s], {0.3, 0.5, 0.8}));
    const InsertResult r = dt.insert(testing::normalized(pts[s] + 0.5 * SphericalDelaunay::kMinSeparation * t));
    EXPECT_TRUE(r.merged);
    EXPECT_EQ(r.site, s);
    EXPECT_LT(r.chord, SphericalDelaunay::kMinSeparation);
  }
  EXPECT_EQ(dt.site_capacity(), pts.size());  // merged points take no id
  const InsertResult fresh = dt.insert(testing::uniform_on_sphere(1, 4242)[0]);
  EXPECT_FALSE(fresh.merged);
  EXPECT_EQ(fresh.site, pts.size());
  EXPECT_TRUE(dt.validate().ok());
}

TEST(Insertion, RejectsNonUnitVectors) {
  SphericalDelaunay dt = build_checked(testing::uniform_on_sphere(10, 1));
  EXPECT_THROW(dt.insert({1, 1, 0}), Error);
  EXPECT_THROW(dt.insert({NAN, 0, 0}), Error);
  EXPECT_EQ(dt.num_sites(), 10u);
  EXPECT_TRUE(dt.validate().ok());
}

}  // namespace
}  // namespace geovor
