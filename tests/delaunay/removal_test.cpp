// SphericalDelaunay::remove(): the hole is filled as a fresh build of the survivors would have
// it, ties included, down to no site at all.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "geovor/core/error.hpp"
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

TEST(Removal, DynamicInsertAndRemoveEqualAFreshBuild) {
  const auto pts = testing::uniform_on_sphere(3000, 33);
  const auto grid = testing::lat_lon_grid(15);  // co-circular ties: removal must use the same perturbation
  for (const auto& set : {pts, grid}) {
    SphericalDelaunay dt = build_checked(set);
    std::mt19937_64 rng(4);
    std::vector<char> removed(set.size(), 0);
    for (std::size_t k = 0; k < set.size() / 2; ++k) {
      const SiteId s = static_cast<SiteId>(rng() % set.size());
      if (removed[s]) continue;
      dt.remove(s);
      removed[s] = 1;
      if (k % 97 == 0) {
        ASSERT_TRUE(dt.validate().ok());
      }
    }
    ASSERT_TRUE(dt.validate(nullptr, set.size() < 1000).ok());
    // A fresh build of the survivors, in id order, has the same priorities: identical triangles.
    std::vector<Vec3> rest;
    std::vector<std::uint32_t> label;
    for (SiteId s = 0; s < set.size(); ++s) {
      if (!removed[s]) rest.push_back(set[s]), label.push_back(s);
    }
    EXPECT_EQ(triangle_set(dt), triangle_set(build_checked(rest), label));
    // Stations come back online: new ids, the triangulation stays valid.
    for (SiteId s = 0; s < set.size(); s += 3) {
      if (!removed[s]) continue;
      const InsertResult r = dt.insert(set[s]);
      EXPECT_FALSE(r.merged);
    }
    EXPECT_TRUE(dt.validate().ok());
    // Inserting the position of a live site merges into it.
    SiteId live = 0;
    while (!dt.is_live(live)) ++live;
    const InsertResult again = dt.insert(dt.site(live));
    EXPECT_TRUE(again.merged);
    EXPECT_EQ(again.site, live);
  }
}

TEST(Removal, RemoveDownToNothing) {
  const auto pts = testing::uniform_on_sphere(12, 2);
  SphericalDelaunay dt = build_checked(pts);
  for (SiteId s = 0; s < pts.size(); ++s) {
    dt.remove(s);
    ASSERT_TRUE(dt.validate(nullptr, true).ok()) << "after removing " << s;
    EXPECT_EQ(dt.num_triangles(), dt.num_sites() >= 3 ? 2 * dt.num_sites() - 4 : 0);
  }
  EXPECT_EQ(dt.num_sites(), 0u);
  for (const Vec3& p : pts) dt.insert(p);
  EXPECT_TRUE(dt.validate(nullptr, true).ok());
  EXPECT_EQ(dt.num_triangles(), 20u);
  EXPECT_THROW(dt.remove(0), Error);  // already removed
}

}  // namespace
}  // namespace geovor
