// SphericalDelaunay::move()/move_all(): after any sequence of moves the triangulation validates
// exactly and equals a fresh build of the final positions (same triangles: ties are broken by
// id, which moves keep), whatever the strategy (filter, flips, reinsertion, rebuild).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
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

void expect_stats_add_up(const MoveStats& st, std::size_t asked, const std::string& what) {
  EXPECT_EQ(st.moved, st.filtered + st.flipped + st.reinserted + st.rebuilt) << what;
  EXPECT_EQ(st.moved + st.refused, asked) << what;
}

// Rounds of move_all with steps from tiny (filtered) to huge (reinserted), each checked.
void run_rounds(std::vector<Vec3> pts, const std::string& name, const RelocationOptions& opt = {},
                double fraction = 1.0) {
  SphericalDelaunay dt = SphericalDelaunay::build(pts);
  ASSERT_TRUE(dt.validate().ok());
  std::mt19937_64 rng(7);
  MoveStats all;
  const double spacing = std::sqrt(4 * M_PI / static_cast<double>(dt.num_sites()));
  for (const double rel : {1e-4, 1e-3, 1e-2, 0.1, 0.3, 1.0, 10.0, 1e-3}) {
    std::vector<Vec3> target(dt.sites().begin(), dt.sites().end());
    std::size_t asked = 0;
    for (Vec3& p : target) {
      if (std::uniform_real_distribution<double>(0, 1)(rng) >= fraction) continue;
      p = jitter(p, rel * spacing, rng);
      ++asked;
    }
    const MoveStats st = dt.move_all(target, opt);
    const std::string what = name + ", step " + std::to_string(rel) + " x spacing";
    expect_stats_add_up(st, asked, what);
    expect_as_rebuilt(dt, what);
    if (::testing::Test::HasFailure()) return;
    for (SiteId s = 0; s < dt.site_capacity(); ++s)
      if (dt.site(s) != target[s]) {
        ASSERT_GT(st.refused, 0u) << what << ": site " << s << " not moved";
      }
    all += st;
  }
  if (opt.filter) {
    EXPECT_GT(all.filtered, 0u) << name;
  }
  if (opt.flips) {
    EXPECT_GT(all.flipped, 0u) << name;
  }
  EXPECT_GT(all.reinserted, 0u) << name;
}

TEST(Relocation, RandomSites) { run_rounds(testing::uniform_on_sphere(3000, 11), "uniform"); }

TEST(Relocation, ClusteredSites) { run_rounds(testing::clustered(3000, 10, 0.02, 5), "clustered"); }

TEST(Relocation, WeatherStations) { run_rounds(weather_station_sites(), "weather stations"); }

TEST(Relocation, SitesInOneHemisphere) { run_rounds(testing::in_hemisphere(1500, 3), "hemisphere"); }

TEST(Relocation, PartOfTheSites) {
  run_rounds(testing::uniform_on_sphere(3000, 12), "1% of the sites", {}, 0.01);
  run_rounds(testing::uniform_on_sphere(3000, 13), "10% of the sites", {}, 0.1);
}

// move_all()'s policy: from 16384 sites, large moves rebuild in place (same ids, same triangles),
// small ones are filtered; the option off, nothing is rebuilt.
TEST(Relocation, RebuildWhenFaster) {
  const auto pts = testing::uniform_on_sphere(20000, 31);
  const double spacing = std::sqrt(4 * M_PI / 20000);
  for (const bool policy : {true, false}) {
    SphericalDelaunay dt = SphericalDelaunay::build(pts);
    RelocationOptions opt;
    opt.rebuild_when_faster = policy;
    std::mt19937_64 rng(9);
    MoveStats all;
    double last = 1;  // the policy looks at the previous batch (none at first: no tolerances)
    for (const double rel : {0.3, 0.3, 1e-4, 1e-4, 1e-4, 0.5, 0.5, 1e-4}) {
      std::vector<Vec3> target(dt.sites().begin(), dt.sites().end());
      for (Vec3& p : target) p = jitter(p, rel * spacing, rng);
      const MoveStats st = dt.move_all(target, opt);
      const std::string what = std::string(policy ? "policy" : "no policy") + ", step " + std::to_string(rel);
      expect_stats_add_up(st, target.size(), what);
      EXPECT_EQ(st.refused, 0u) << what;
      EXPECT_TRUE(std::equal(target.begin(), target.end(), dt.sites().begin())) << what;
      expect_as_rebuilt(dt, what);
      if (policy && rel > 0.1 && last > 0.1) {
        EXPECT_EQ(st.rebuilt, st.moved) << what;
      }
      if (rel > 0.1 && last < 0.1) {
        EXPECT_EQ(st.rebuilt, 0u) << what;  // relocated, then seen
      }
      if (rel < 0.1) {
        EXPECT_EQ(st.rebuilt, 0u) << what;
        EXPECT_GT(st.filtered, st.moved * 9 / 10) << what;
      }
      if (::testing::Test::HasFailure()) return;
      all += st;
      last = rel;
    }
    if (!policy) {
      EXPECT_EQ(all.rebuilt, 0u);
    }
  }
}

TEST(Relocation, EveryStrategyGivesTheSameTriangulation) {
  const auto pts = testing::uniform_on_sphere(2000, 21);
  for (const RelocationOptions opt : {RelocationOptions{true, true}, RelocationOptions{true, false},
                                      RelocationOptions{false, true}, RelocationOptions{false, false}}) {
    SphericalDelaunay dt = SphericalDelaunay::build(pts);
    std::mt19937_64 rng(1);
    MoveStats st;
    for (int round = 0; round < 3; ++round) {
      std::vector<Vec3> target(dt.sites().begin(), dt.sites().end());
      for (Vec3& p : target) p = jitter(p, 0.01, rng);
      st += dt.move_all(target, opt);
      expect_as_rebuilt(dt, "filter " + std::to_string(opt.filter) + " flips " + std::to_string(opt.flips));
    }
    if (!opt.filter) {
      EXPECT_EQ(st.filtered, 0u);
    }
    if (!opt.flips) {
      EXPECT_EQ(st.flipped, 0u);
    }
    if (!opt.filter && !opt.flips) {
      EXPECT_EQ(st.reinserted, st.moved);
    }
  }
}

// Sites moved onto a latitude-longitude grid (many four co-circular sites, on great and small
// circles), then nudged by one ulp-sized step: the ties go by id, as in a fresh build.
TEST(Relocation, OntoGridsAndCoCircularPositions) {
  const auto grid = testing::lat_lon_grid(10.0);
  for (const bool flips : {true, false}) {
    SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(grid.size(), 8));
    std::vector<Vec3> target(grid);
    std::mt19937_64 rng(5);
    std::shuffle(target.begin(), target.end(), rng);
    // First to nearby scattered positions, then exactly onto the grid, in two halves.
    for (std::size_t half = 0; half < 2; ++half) {
      std::vector<Vec3> now(dt.sites().begin(), dt.sites().end());
      for (std::size_t i = half; i < now.size(); i += 2) now[i] = target[i];
      const MoveStats st = dt.move_all(now, {true, flips});
      EXPECT_EQ(st.refused, 0u);
      expect_as_rebuilt(dt, "grid, half " + std::to_string(half));
    }
    for (int round = 0; round < 3; ++round) {
      std::vector<Vec3> now(dt.sites().begin(), dt.sites().end());
      for (std::size_t i = 0; i < now.size(); ++i) now[i] = round == 2 ? target[i] : jitter(target[i], 1e-14, rng);
      dt.move_all(now, {true, flips});
      expect_as_rebuilt(dt, "grid nudged, round " + std::to_string(round));
    }
  }
  // Exactly co-circular: sites moved onto one small circle (bit-identical z) and one great circle.
  for (const auto& ring : {testing::on_small_circle(200, 30.0, 2), testing::on_great_circle(200, 3)}) {
    auto start = testing::uniform_on_sphere(400, 6);
    SphericalDelaunay dt = SphericalDelaunay::build(start);
    std::vector<Vec3> now(dt.sites().begin(), dt.sites().end());
    for (std::size_t i = 0; i < ring.size(); ++i) now[2 * i] = ring[i];
    dt.move_all(now);
    expect_as_rebuilt(dt, "ring");
  }
}

TEST(Relocation, MovesWithinTheMergeDistanceAreRefused) {
  SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(500, 2));
  const double md = dt.options().merge_distance;
  std::mt19937_64 rng(4);
  for (int i = 0; i < 200; ++i) {
    const SiteId s = static_cast<SiteId>(rng() % 500), t = static_cast<SiteId>(rng() % 500);
    if (s == t) continue;
    const Vec3 before = dt.site(s);
    // Within the merge distance of t: refused, s unchanged.
    const Vec3 near = jitter(dt.site(t), 0.3 * md, rng);
    const MoveStats st = dt.move(s, near);
    EXPECT_EQ(st.refused, 1u);
    EXPECT_EQ(st.moved, 0u);
    EXPECT_EQ(dt.site(s), before);
    // Just beyond it: moved.
    const Vec3 away = testing::normalized(dt.site(t) + 4 * md * testing::normalized(cross(dt.site(t), {0.3, 0.5, 0.7})));
    const MoveStats st2 = dt.move(s, away);
    EXPECT_EQ(st2.moved, 1u);
    EXPECT_EQ(dt.site(s), away);
    // Back far away, so that t's surroundings stay ordinary.
    dt.move(s, testing::uniform_on_sphere(1, 1000 + i)[0]);
  }
  expect_as_rebuilt(dt, "after refusals");
  // Two sites sent to the same place: the second is refused.
  std::vector<Vec3> now(dt.sites().begin(), dt.sites().end());
  now[1] = now[3] = testing::normalized({0.1, 0.2, 0.3});
  const MoveStats st = dt.move_all(now);
  EXPECT_EQ(st.refused, 1u);
  EXPECT_EQ(dt.site(1), now[1]);
  expect_as_rebuilt(dt, "same target");
  // Filtered moves never come within the merge distance either: a pair of sites 1.5 merge
  // distances apart, moved toward each other by small steps.
  SphericalDelaunay pair = SphericalDelaunay::build(testing::uniform_on_sphere(100, 3));
  const Vec3 a = pair.site(0), axis = testing::normalized(cross(a, {0, 0, 1}));
  pair.move(1, testing::normalized(a + 1.5 * md * axis));
  for (int i = 1; i <= 20; ++i) {
    pair.move(0, testing::normalized(a + (0.05 * i) * md * axis));
    EXPECT_GE(std::sqrt(norm2(pair.site(0) - pair.site(1))), md);
  }
  expect_as_rebuilt(pair, "pair");
}

TEST(Relocation, FewSites) {
  for (std::size_t n : {1u, 2u, 3u, 4u, 5u, 6u}) {
    SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(n, 40 + n));
    std::mt19937_64 rng(n);
    for (int round = 0; round < 20; ++round) {
      std::vector<Vec3> now(dt.sites().begin(), dt.sites().end());
      for (Vec3& p : now) p = jitter(p, round % 2 ? 1.0 : 1e-3, rng);
      const MoveStats st = dt.move_all(now);
      expect_stats_add_up(st, n, "n = " + std::to_string(n));
      expect_as_rebuilt(dt, "n = " + std::to_string(n));
    }
  }
}

TEST(Relocation, BadArguments) {
  SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(10, 1));
  EXPECT_THROW(dt.move(0, {1, 1, 0}), Error);
  EXPECT_THROW(dt.move(10, {1, 0, 0}), Error);
  std::vector<Vec3> now(dt.sites().begin(), dt.sites().end());
  EXPECT_THROW(dt.move_all(std::span(now).first(9)), Error);
  now[3] = {0, 0, 2};
  const Vec3 before = dt.site(0);
  now[0] = {0, 0, 1};
  EXPECT_THROW(dt.move_all(now), Error);
  EXPECT_EQ(dt.site(0), before);  // checked before anything moves
  // Removed sites' entries are ignored.
  dt.remove(3);
  const MoveStats st = dt.move_all(now);
  EXPECT_EQ(st.moved + st.refused, 1u);
  expect_as_rebuilt(dt, "after remove");
}

}  // namespace
}  // namespace geovor
