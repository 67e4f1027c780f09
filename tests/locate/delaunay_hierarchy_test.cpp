#include "geovor/locate/delaunay_hierarchy.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/locate/walk_graph.hpp"
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

// Moves keep every level right: each validates, copies stay the same point, links unchanged,
// and level 0 is the triangulation of the moved sites.
TEST(DelaunayHierarchy, StaysRightUnderMoves) {
  const auto pts = testing::uniform_on_sphere(20000, 8);
  DelaunayHierarchy h = DelaunayHierarchy::build(pts, {}, {.ratio = 10});
  ASSERT_GE(h.num_levels(), 3);
  std::mt19937_64 rng(4);
  std::normal_distribution<double> g(0.0, 1.0);
  const double spacing = std::sqrt(4 * M_PI / 20000);
  for (const double rel : {1e-4, 1e-2, 0.3, 3.0, 1e-3}) {
    std::vector<Vec3> target(h.base().sites().begin(), h.base().sites().end());
    for (Vec3& p : target) p = testing::normalized(p + rel * spacing * Vec3{g(rng), g(rng), g(rng)});
    const MoveStats st = h.move_all(target);
    EXPECT_EQ(st.moved, st.filtered + st.flipped + st.reinserted + st.rebuilt);
    EXPECT_EQ(st.moved + st.refused, target.size());
    const Validation v = h.validate();
    ASSERT_TRUE(v.ok()) << rel << ": " << v.errors.front();
    for (SiteId s = 0; s < target.size(); ++s) ASSERT_EQ(h.base().site(s), target[s]);
    const SphericalDelaunay fresh = SphericalDelaunay::build(target);
    ASSERT_EQ(fresh.num_triangles(), h.base().num_triangles());
    // Same triangles: compare each site's neighbour set.
    for (SiteId s = 0; s < target.size(); s += 97) {
      auto ring = [s](const SphericalDelaunay& dt) {
        std::vector<SiteId> r;
        const HalfedgeId e0 = dt.site_edge(s);
        HalfedgeId e = e0;
        do {
          r.push_back(dt.triangles()[next_halfedge(e)]);
          e = dt.next_around_site(e);
        } while (e != e0);
        std::sort(r.begin(), r.end());
        return r;
      };
      ASSERT_EQ(ring(h.base()), ring(fresh)) << "site " << s << ", step " << rel;
    }
  }
  // Single moves, inserts and removes mixed; a refused move changes no level.
  for (int i = 0; i < 3000; ++i) {
    const SiteId s = static_cast<SiteId>(rng() % h.base().site_capacity());
    if (!h.base().is_live(s)) continue;
    if (i % 50 == 0) {
      h.remove(s);
      h.insert(testing::normalized({g(rng), g(rng), g(rng)}));
      continue;
    }
    if (i % 10 == 0) {  // onto another site: refused
      const SiteId t = static_cast<SiteId>(rng() % h.base().site_capacity());
      if (t == s || !h.base().is_live(t)) continue;
      const Vec3 before = h.base().site(s);
      const MoveStats st = h.move(s, h.base().site(t));
      EXPECT_EQ(st.refused, 1u);
      EXPECT_EQ(h.base().site(s), before);
      continue;
    }
    const double rel = std::pow(10.0, -4 + 4 * std::uniform_real_distribution<double>(0, 1)(rng));
    const Vec3 p = testing::normalized(h.base().site(s) + rel * spacing * Vec3{g(rng), g(rng), g(rng)});
    const MoveStats st = h.move(s, p);
    EXPECT_EQ(st.moved, 1u);
    EXPECT_EQ(h.base().site(s), p);
  }
  const Validation v = h.validate();
  ASSERT_TRUE(v.ok()) << v.errors.front();
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

TEST(DelaunayHierarchy, OwnsTheWalkGraphOfItsCurrentState) {
  const auto pts = testing::uniform_on_sphere(2000, 73);
  DelaunayHierarchy h = DelaunayHierarchy::build(std::span(pts).first(1500));
  const auto a = h.walk_graph();
  EXPECT_EQ(h.walk_graph().get(), a.get());  // built once
  EXPECT_TRUE(a->matches(h));
  h.insert(pts[1600]);
  const auto b = h.walk_graph();
  EXPECT_NE(a.get(), b.get());
  EXPECT_FALSE(a->matches(h));  // the old one stays with its holder, stale
  EXPECT_TRUE(b->matches(h));
  h.remove(7);
  EXPECT_TRUE(h.walk_graph()->matches(h));
  RelocationOptions opt;
  h.move(3, pts[1700], opt);
  EXPECT_TRUE(h.walk_graph()->matches(h));
  // A copy and a moved-to hierarchy are other objects: each builds its own.
  const DelaunayHierarchy copy = h;
  const auto c = copy.walk_graph();
  EXPECT_NE(c.get(), h.walk_graph().get());
  EXPECT_TRUE(c->matches(copy));
  DelaunayHierarchy moved = std::move(h);
  EXPECT_TRUE(moved.walk_graph()->matches(moved));
  h = DelaunayHierarchy::build(std::span(pts).first(1500));  // same object, new content
  EXPECT_TRUE(h.walk_graph()->matches(h));
}

TEST(DelaunayHierarchy, WalkGraphIsBuiltOnceForConcurrentCallers) {
  const auto pts = testing::uniform_on_sphere(20000, 74);
  const DelaunayHierarchy h = DelaunayHierarchy::build(pts);
  std::vector<std::shared_ptr<const WalkGraph>> got(8);
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < got.size(); ++i) threads.emplace_back([&, i] { got[i] = h.walk_graph(); });
  for (std::thread& t : threads) t.join();
  for (const auto& g : got) {
    ASSERT_NE(g, nullptr);
    EXPECT_EQ(g.get(), got[0].get());
  }
  EXPECT_TRUE(got[0]->matches(h));
}

}  // namespace
}  // namespace geovor
