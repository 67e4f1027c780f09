// The packed copy against the hierarchy it copies: the same points bit for bit, the same
// neighbours, links and ids, nodes in Hilbert order; staleness and sharing.
#include "geovor/locate/walk_graph.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "geovor/delaunay/spatial_sort.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

// The nodes of a level in node order (walking the records one after the other).
std::vector<std::uint32_t> nodes_in_order(const WalkGraph& g, int l) {
  std::vector<std::uint32_t> out;
  std::uint32_t v = 0;
  for (std::uint32_t i = 0; i < g.num_nodes(l); ++i) {
    out.push_back(v);
    v += (36 + 4 * g.degree(l, v) + 7) / 8;  // the record layout of walk_graph.hpp
  }
  return out;
}

void expect_copy_of(const WalkGraph& g, const DelaunayHierarchy& h) {
  ASSERT_EQ(g.num_levels(), h.num_levels());
  ASSERT_TRUE(g.matches(h));
  std::vector<std::vector<SiteId>> site_of(static_cast<std::size_t>(h.num_levels()));
  // Site of each node, level by level: through node_of on the base, through down links above.
  for (int l = 0; l < h.num_levels(); ++l) {
    const SphericalDelaunay& dt = h.level(l);
    ASSERT_EQ(g.num_nodes(l), dt.num_sites());
    const std::vector<std::uint32_t> nodes = nodes_in_order(g, l);
    std::vector<SiteId> sites;
    for (const std::uint32_t v : nodes) {
      SiteId s;
      if (l == 0) {
        s = g.site_of(v);
        EXPECT_EQ(g.node_of(s), v);
      } else {
        // The level-l site whose down link is the site below.
        const SiteId below = site_of[static_cast<std::size_t>(l) - 1][g.down(l, v)];
        s = h.up(l - 1, below);
        ASSERT_NE(s, kNoIndex);
      }
      sites.push_back(s);
    }
    std::vector<SiteId>& map = site_of[static_cast<std::size_t>(l)];
    map.assign(nodes.back() + 1, kNoIndex);
    for (std::size_t i = 0; i < nodes.size(); ++i) map[nodes[i]] = sites[i];
    // Hilbert order, every live site once, same doubles, same neighbours (counter-clockwise, as a cycle).
    std::set<SiteId> seen;
    std::vector<Vec3> in_order;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const std::uint32_t v = nodes[i];
      const SiteId s = sites[i];
      ASSERT_TRUE(dt.is_live(s));
      EXPECT_TRUE(seen.insert(s).second);
      const Vec3 p = g.point(l, v);
      EXPECT_EQ(p, dt.site(s));
      in_order.push_back(p);
      EXPECT_GE(g.degree(l, v), std::min<std::uint32_t>(g.num_nodes(l) - 1, 3));
    }
    // Nodes along the Hilbert curve: the base by hilbert_key(), the others as hilbert_order().
    if (l == 0) {
      for (std::size_t i = 1; i < in_order.size(); ++i) ASSERT_LE(hilbert_key(in_order[i - 1]), hilbert_key(in_order[i]));
    } else {
      const std::vector<std::uint32_t> order = hilbert_order(in_order);
      for (std::uint32_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], i) << "level " << l;
    }
    // Now that every node of the level is mapped, compare the lists exactly.
    for (std::size_t i = 0; i < nodes.size(); ++i) {
      const SiteId s = sites[i];
      std::vector<SiteId> expected, got;
      if (dt.num_triangles() == 0) {
        for (SiteId t = 0; t < dt.site_capacity(); ++t)
          if (t != s && dt.is_live(t)) expected.push_back(t);
      } else {
        const HalfedgeId e0 = dt.site_edge(s);
        HalfedgeId e = e0;
        do {
          expected.push_back(dt.triangles()[next_halfedge(e)]);
          e = dt.next_around_site(e);
        } while (e != e0);
      }
      g.for_each_neighbour(l, nodes[i], [&](std::uint32_t w, const Vec3&) { got.push_back(map[w]); });
      EXPECT_EQ(got, expected) << "level " << l << " site " << s;
      // Up links: the node above holds the same site.
      const std::uint32_t up = g.up(l, nodes[i]);
      if (l + 1 < h.num_levels() && h.up(l, s) != kNoIndex) {
        ASSERT_NE(up, kNoIndex);
        EXPECT_EQ(g.down(l + 1, up), nodes[i]);
      } else {
        EXPECT_EQ(up, kNoIndex);
      }
    }
  }
}

TEST(WalkGraph, IsACopyOfTheHierarchy) {
  const DelaunayHierarchy h = DelaunayHierarchy::build(testing::uniform_on_sphere(30000, 71));
  ASSERT_GE(h.num_levels(), 3);
  const WalkGraph g(h);
  expect_copy_of(g, h);
  const double bytes_per_site = static_cast<double>(g.memory_bytes()) / static_cast<double>(h.base().num_sites());
  EXPECT_LT(bytes_per_site, 80.0);
  EXPECT_GT(bytes_per_site, 56.0);
}

// Built on several threads (keys, their sample sort, degrees, records): the same graph, record
// for record, as on one.
void expect_the_same_on_any_threads(const DelaunayHierarchy& h) {
  const WalkGraph one(h, 1);
  for (const unsigned threads : {2u, 3u, 7u}) {
    const WalkGraph many(h, threads);
    expect_copy_of(many, h);
    ASSERT_EQ(many.num_levels(), one.num_levels());
    for (int l = 0; l < one.num_levels(); ++l) {
      const std::vector<std::uint32_t> nodes = nodes_in_order(one, l);
      ASSERT_EQ(nodes, nodes_in_order(many, l));
      for (const std::uint32_t v : nodes) {
        ASSERT_EQ(one.point(l, v), many.point(l, v));
        ASSERT_EQ(one.up(l, v), many.up(l, v));
        ASSERT_EQ(one.down(l, v), many.down(l, v));
        std::vector<std::uint32_t> a, b;
        one.for_each_neighbour(l, v, [&](std::uint32_t w, const Vec3&) { a.push_back(w); });
        many.for_each_neighbour(l, v, [&](std::uint32_t w, const Vec3&) { b.push_back(w); });
        ASSERT_EQ(a, b);
      }
    }
    for (const Vec3& q : testing::uniform_on_sphere(200, 73)) ASSERT_EQ(one.curve_start(q), many.curve_start(q));
  }
}

TEST(WalkGraph, TheSameOnAnyNumberOfThreads) {
  expect_the_same_on_any_threads(DelaunayHierarchy::build(testing::uniform_on_sphere(40000, 72)));
  // Sites in order of latitude: each thread's slice of the keys lies on another part of the curve
  // (the sort's buckets are cut by samples of all of them), and a cluster around one point.
  std::vector<Vec3> by_latitude = testing::uniform_on_sphere(140000, 74);  // several slices of 2^16
  std::sort(by_latitude.begin(), by_latitude.end(), [](const Vec3& a, const Vec3& b) { return a.z < b.z; });
  expect_the_same_on_any_threads(DelaunayHierarchy::build(by_latitude));
  std::vector<Vec3> cluster = testing::uniform_on_sphere(30000, 75);
  for (std::size_t i = 0; i < 30000; i += 2) cluster[i] = testing::normalized(Vec3{1, 1e-3 * cluster[i].y, 1e-3 * cluster[i].z});
  expect_the_same_on_any_threads(DelaunayHierarchy::build(cluster));
}

// curve_start gives a base node, usually near q: within 8 mean spacings for most queries.
TEST(WalkGraph, CurveStartIsANearNodeMostOfTheTime) {
  const std::size_t n = 50000;
  const DelaunayHierarchy h = DelaunayHierarchy::build(testing::uniform_on_sphere(n, 74));
  const WalkGraph g(h);
  const double spacing = std::sqrt(4 * 3.14159265358979 / static_cast<double>(n));
  std::size_t near = 0;
  const auto queries = testing::uniform_on_sphere(2000, 75);
  for (const Vec3& q : queries) {
    const std::uint32_t v = g.curve_start(q);
    ASSERT_NE(v, kNoIndex);
    const SiteId s = g.site_of(v);
    ASSERT_TRUE(h.base().is_live(s));
    ASSERT_EQ(g.node_of(s), v);
    if (std::acos(std::min(1.0, dot(q, g.point(0, v)))) < 8 * spacing) ++near;
  }
  EXPECT_GT(near, queries.size() * 9 / 10);
  const DelaunayHierarchy empty = DelaunayHierarchy::build(std::vector<Vec3>{});
  EXPECT_EQ(WalkGraph(empty).curve_start(queries[0]), kNoIndex);
}

TEST(WalkGraph, AfterRemovalsAndFewSites) {
  const auto pts = testing::uniform_on_sphere(3000, 72);
  DelaunayHierarchy h = DelaunayHierarchy::build(pts);
  for (SiteId s = 0; s < 3000; s += 3) h.remove(s);
  expect_copy_of(WalkGraph(h), h);
  for (const std::size_t n : {1, 2, 3, 4}) {
    const DelaunayHierarchy few = DelaunayHierarchy::build(std::span(pts).first(n));
    expect_copy_of(WalkGraph(few), few);
  }
}

TEST(WalkGraph, StaleAfterAChange) {
  const auto pts = testing::uniform_on_sphere(2000, 73);
  DelaunayHierarchy h = DelaunayHierarchy::build(std::span(pts).first(1500));
  const WalkGraph a(h);
  EXPECT_TRUE(a.matches(h));
  h.insert(pts[1600]);
  EXPECT_FALSE(a.matches(h));
  const WalkGraph c(h);
  EXPECT_TRUE(c.matches(h));
  h.remove(7);
  EXPECT_FALSE(c.matches(h));
  const DelaunayHierarchy copy = h;  // a copy is another hierarchy
  EXPECT_FALSE(WalkGraph(h).matches(copy));
  EXPECT_TRUE(WalkGraph(copy).matches(copy));
  h = DelaunayHierarchy::build(std::span(pts).first(1500));  // same object, new content
  EXPECT_FALSE(a.matches(h));
}

}  // namespace
}  // namespace geovor
