#include "geovor/locate/delaunay_hierarchy.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "geovor/core/error.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

TEST(DelaunayHierarchy, LevelsShrinkByTheRatio) {
  const auto pts = testing::uniform_on_sphere(200000, 3);
  const DelaunayHierarchy h = DelaunayHierarchy::build(pts);
  ASSERT_TRUE(h.validate().ok()) << h.validate().errors.front();
  ASSERT_GE(h.num_levels(), 3);
  for (int l = 1; l < h.num_levels(); ++l) {
    const double ratio = static_cast<double>(h.level(l - 1).num_sites()) / h.level(l).num_sites();
    if (h.level(l).num_sites() > 100) {  // 30 on average; a binomial sample around it
      EXPECT_GT(ratio, 22.0) << "level " << l;
      EXPECT_LT(ratio, 40.0) << "level " << l;
    }
  }
}

TEST(DelaunayHierarchy, StaysRightUnderInsertAndRemove) {
  const auto pts = testing::uniform_on_sphere(20000, 5);
  DelaunayHierarchy h = DelaunayHierarchy::build(std::span(pts).first(10000));
  std::mt19937_64 rng(2);
  for (int round = 0; round < 4; ++round) {
    for (std::size_t i = 0; i < 2000; ++i) h.insert(pts[10000 + round * 2000 + i]);
    for (std::size_t i = 0; i < 1500; ++i) {
      const SiteId s = static_cast<SiteId>(rng() % h.base().site_capacity());
      if (h.base().is_live(s)) h.remove(s);
    }
    const Validation v = h.validate();
    ASSERT_TRUE(v.ok()) << v.errors.front();
  }
}

TEST(DelaunayHierarchy, SmallAndDegenerateInputs) {
  for (std::size_t n : {0u, 1u, 2u, 3u, 40u}) {
    const DelaunayHierarchy h = DelaunayHierarchy::build(testing::uniform_on_sphere(n, 1));
    EXPECT_TRUE(h.validate().ok());
    EXPECT_GE(h.num_levels(), 1);
  }
  HierarchyOptions bad;
  bad.ratio = 1;
  EXPECT_THROW(DelaunayHierarchy::build(testing::cube_corners(), {}, bad), Error);
}

}  // namespace
}  // namespace geovor
