// The moving sites' filter (Algorithm 1): every site stays within its tolerance of its reference,
// its tolerance is at most that of each bi-cell containing it, through moves, insertions and
// removals; moves below the tolerances are all filtered.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "geovor/delaunay/bicell_tolerance.hpp"
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

// Algorithm 1's invariant, checked from outside: every site is within its tolerance of its
// reference position, and its tolerance is at most that of every bi-cell containing it, computed
// at the reference positions (either orientation of the bi-cell: both are certified bounds).
void expect_filter_invariant(SphericalDelaunay& dt, const std::string& what) {
  if (dt.num_sites() < 5) return;
  for (SiteId s = 0; s < dt.site_capacity(); ++s) {
    if (!dt.is_live(s)) continue;
    const double tol = dt.tolerance(s);
    const Vec3 d = dt.site(s) - dt.reference(s);
    ASSERT_TRUE(norm2(d) == 0 || std::sqrt(norm2(d)) < tol) << what << ": site " << s << " out of its tolerance";
  }
  const auto tri = dt.triangles();
  const auto twin = dt.halfedges();
  auto one = [&](HalfedgeId e) {
    const SiteId a = tri[e], b = tri[next_halfedge(e)], c = tri[prev_halfedge(e)], d = tri[prev_halfedge(twin[e])];
    return bicell_tolerance(dt.reference(a), dt.reference(b), dt.reference(c), dt.reference(d),
                                               dt.options().merge_distance);
  };
  for (HalfedgeId e = 0; e < tri.size(); ++e) {
    if (twin[e] < e) continue;
    const double tau = std::max(one(e), one(twin[e]));
    for (const SiteId w : {tri[e], tri[next_halfedge(e)], tri[prev_halfedge(e)], tri[prev_halfedge(twin[e])]})
      ASSERT_LE(dt.tolerance(w), tau) << what << ": site " << w << ", bi-cell of half-edge " << e;
  }
}

void expect_stats_add_up(const MoveStats& st, std::size_t asked, const std::string& what) {
  EXPECT_EQ(st.moved, st.filtered + st.flipped + st.reinserted + st.rebuilt) << what;
  EXPECT_EQ(st.moved + st.refused, asked) << what;
}

// Lloyd-like: every site drifts a little in its own direction at each round, so filtered moves
// pile up away from the reference positions; a tolerance too large shows up here.
TEST(MoveFilter, DriftBySmallSteps) {
  for (const auto& [pts, name] : {std::pair{testing::uniform_on_sphere(3000, 14), "uniform"},
                                  std::pair{testing::clustered(3000, 6, 0.05, 2), "clustered"},
                                  std::pair{weather_station_sites(), "weather stations"}}) {
    SphericalDelaunay dt = SphericalDelaunay::build(pts);
    std::mt19937_64 rng(6);
    std::vector<Vec3> dir(dt.site_capacity());
    for (SiteId s = 0; s < dt.site_capacity(); ++s) dir[s] = testing::normalized(cross(dt.site(s), jitter(dt.site(s), 1, rng)));
    MoveStats all;
    // Each site's step is a fraction of its shortest edge.
    std::vector<double> spacing(dt.site_capacity(), INFINITY);
    for (HalfedgeId e = 0; e < dt.halfedges().size(); ++e) {
      const SiteId a = dt.triangles()[e], b = dt.triangles()[next_halfedge(e)];
      spacing[a] = std::min(spacing[a], std::sqrt(norm2(dt.site(a) - dt.site(b))));
    }
    for (int round = 0; round < 40; ++round) {
      std::vector<Vec3> now(dt.sites().begin(), dt.sites().end());
      const double step = (round < 20 ? 3e-4 : 3e-3) * std::uniform_real_distribution<double>(0.5, 1)(rng);
      for (SiteId s = 0; s < now.size(); ++s) now[s] = testing::normalized(now[s] + step * spacing[s] * dir[s]);
      const MoveStats st = dt.move_all(now);
      expect_stats_add_up(st, now.size(), name);
      all += st;
      if (round % 4 == 3) {
        expect_as_rebuilt(dt, std::string(name) + ", round " + std::to_string(round));
        expect_filter_invariant(dt, std::string(name) + ", round " + std::to_string(round));
      }
      if (::testing::Test::HasFailure()) return;
    }
    EXPECT_GT(all.filtered, all.moved / 2) << name;
    EXPECT_GT(all.reanchored, 0u) << name;  // the second test (tolerances at the new position)
    EXPECT_GT(all.flipped, 0u) << name;
  }
}

TEST(MoveFilter, SingleMovesInterleavedWithInsertAndRemove) {
  const auto pts = testing::uniform_on_sphere(1500, 4);
  SphericalDelaunay dt = SphericalDelaunay::build(std::span(pts).first(1000));
  std::mt19937_64 rng(9);
  std::size_t next = 1000;
  for (int i = 0; i < 3000; ++i) {
    const SiteId s = static_cast<SiteId>(rng() % dt.site_capacity());
    if (i % 100 == 50 && next < pts.size()) {
      dt.insert(pts[next++]);
      expect_filter_invariant(dt, "insert at " + std::to_string(i));
    }
    if (!dt.is_live(s)) continue;
    if (i % 100 == 99) {
      dt.remove(s);
      expect_filter_invariant(dt, "remove at " + std::to_string(i));
      continue;
    }
    const double step = std::pow(10.0, -1.0 - 4.0 * std::uniform_real_distribution<double>(0, 1)(rng));
    const Vec3 p = jitter(dt.site(s), step, rng);
    const MoveStats st = dt.move(s, p);
    expect_stats_add_up(st, 1, "move " + std::to_string(i));
    if (st.moved) {
      ASSERT_EQ(dt.site(s), p);
    }
    if (i % 500 == 0) {
      expect_as_rebuilt(dt, "after move " + std::to_string(i));
      expect_filter_invariant(dt, "after move " + std::to_string(i));
    }
  }
  expect_as_rebuilt(dt, "end");
}

// A site's tolerance is the minimum over the bi-cells containing it (computed here from the star),
// and moves below every site's tolerance are all filtered and keep the triangulation right.
TEST(MoveFilter, SiteToleranceIsTheMinimumOverItsBicells) {
  SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(2000, 31));
  const auto tri = dt.triangles();
  const auto twin = dt.halfedges();
  // Both orientations of the bi-cell give certified bounds, differing in the last bits.
  auto one = [&](HalfedgeId e) {
    const SiteId a = tri[e], b = tri[next_halfedge(e)], c = tri[prev_halfedge(e)], d = tri[prev_halfedge(twin[e])];
    return bicell_tolerance(dt.site(a), dt.site(b), dt.site(c), dt.site(d), dt.options().merge_distance);
  };
  std::vector<double> tol(dt.site_capacity());
  for (SiteId s = 0; s < dt.site_capacity(); ++s) {
    double lo = INFINITY, hi = INFINITY;
    const HalfedgeId e0 = dt.site_edge(s);
    HalfedgeId e = e0;
    do {
      for (const HalfedgeId h : {e, next_halfedge(e)}) {
        lo = std::min({lo, one(h), one(twin[h])});
        hi = std::min(hi, std::max(one(h), one(twin[h])));
      }
      e = dt.next_around_site(e);
    } while (e != e0);
    tol[s] = dt.tolerance(s);
    EXPECT_LE(tol[s], hi);
    EXPECT_GE(tol[s], lo * (1 - 1e-12));
    EXPECT_GT(tol[s], 0);
  }
  std::mt19937_64 rng(3);
  std::vector<Vec3> now(dt.sites().begin(), dt.sites().end());
  for (SiteId s = 0; s < now.size(); ++s) {
    const Vec3 d = testing::normalized(cross(now[s], {0.6, -0.3, 0.2}));
    now[s] = testing::normalized(now[s] + 0.9 * tol[s] * d);
  }
  const MoveStats st = dt.move_all(now);
  EXPECT_EQ(st.filtered, now.size());
  expect_as_rebuilt(dt, "all within tolerance");
}

}  // namespace
}  // namespace geovor
