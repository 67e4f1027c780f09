// SphericalDelaunay against independent oracles: CGAL's Delaunay_triangulation_on_sphere_2,
// brute force (no site in any circumcircle), and its own invariants on the hard sets.
#include "geovor/delaunay/spherical_delaunay.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "geovor/core/error.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/kernel/predicates.hpp"
#include "support/cgal_oracle.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

using testing::Tri;

Tri canonical(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
}

// Our triangles in terms of `label[site]` (e.g. the input index of each site), sorted.
std::vector<Tri> our_triangles(const SphericalDelaunay& dt, const std::vector<std::uint32_t>& label = {}) {
  std::vector<Tri> out;
  auto L = [&](SiteId s) { return label.empty() ? s : label[s]; };
  for (TriId t = 0; t < dt.num_triangles(); ++t)
    out.push_back(canonical(L(dt.tri_site(t, 0)), L(dt.tri_site(t, 1)), L(dt.tri_site(t, 2))));
  std::sort(out.begin(), out.end());
  return out;
}

// For each site, the input index CGAL kept among the inputs merged into it (CGAL keeps the
// first one it inserts, in its own order), so both triangle lists speak of the same points.
std::vector<std::uint32_t> cgal_labels(const SphericalDelaunay& dt, const BuildReport& rep,
                                       const std::vector<std::uint32_t>& cgal_rejected) {
  std::vector<std::uint32_t> label(dt.site_capacity(), kNoIndex);
  std::vector<char> lost(rep.site_of_input.size(), 0);
  for (const std::uint32_t i : cgal_rejected) lost[i] = 1;
  for (std::uint32_t i = 0; i < rep.site_of_input.size(); ++i) {
    std::uint32_t& l = label[rep.site_of_input[i]];
    if (l == kNoIndex || (lost[l] && !lost[i])) l = i;
  }
  return label;
}

SphericalDelaunay build_checked(const std::vector<Vec3>& pts, BuildReport* rep = nullptr,
                                bool global = false, const DelaunayOptions& opt = {}) {
  BuildReport local;
  BuildReport* r = rep ? rep : &local;
  SphericalDelaunay dt = SphericalDelaunay::build(pts, opt, r);
  const Validation v = dt.validate(r, global);
  EXPECT_TRUE(v.ok()) << (v.errors.empty() ? "" : v.errors.front());
  return dt;
}

// Triangles where ours and CGAL's differ must come from co-circular ties: every one of them has
// an edge whose opposite site (in our triangulation) is exactly on its circumcircle.
void expect_equal_up_to_ties(const SphericalDelaunay& dt, const std::vector<std::uint32_t>& label,
                             const std::vector<Tri>& cgal) {
  const std::vector<Tri> ours_labelled = our_triangles(dt, label);
  ASSERT_EQ(ours_labelled.size(), cgal.size());
  std::vector<Tri> only_ours;
  std::set_difference(ours_labelled.begin(), ours_labelled.end(), cgal.begin(), cgal.end(),
                      std::back_inserter(only_ours));
  if (only_ours.empty()) return;
  // Check the tie property on our own triangulation, in site ids.
  std::set<Tri> diff(only_ours.begin(), only_ours.end());
  std::size_t tied = 0, differing = 0;
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    bool has_tie = false;
    for (int j = 0; j < 3; ++j) {
      const HalfedgeId tw = dt.halfedges()[3 * t + j];
      const SiteId d = dt.triangles()[prev_halfedge(tw)];
      has_tie |= kernel::in_sphere_sign(dt.site(dt.tri_site(t, 0)), dt.site(dt.tri_site(t, 1)),
                                        dt.site(dt.tri_site(t, 2)), dt.site(d)) == Sign::Zero;
    }
    tied += has_tie;
  }
  differing = only_ours.size();
  EXPECT_GT(tied, 0u) << differing << " triangles differ from CGAL without any co-circular tie";
  // Every differing triangle must be one with a tie.
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    const SiteId a = dt.tri_site(t, 0), b = dt.tri_site(t, 1), c = dt.tri_site(t, 2);
    const Tri tri = canonical(label[a], label[b], label[c]);
    if (!diff.count(tri)) continue;
    bool has_tie = false;
    for (int j = 0; j < 3; ++j) {
      const SiteId d = dt.triangles()[prev_halfedge(dt.halfedges()[3 * t + j])];
      has_tie |= kernel::in_sphere_sign(dt.site(a), dt.site(b), dt.site(c), dt.site(d)) == Sign::Zero;
    }
    EXPECT_TRUE(has_tie) << "triangle " << tri[0] << "," << tri[1] << "," << tri[2] << " differs without a tie";
  }
}

TEST(SphericalDelaunay, EqualsCgalOnUniformPoints) {
  for (const std::size_t n : {4u, 10u, 100u, 5000u, 40000u}) {
    const auto pts = testing::uniform_on_sphere(n, 100 + n);
    const SphericalDelaunay dt = build_checked(pts, nullptr, n <= 5000);
    EXPECT_EQ(dt.num_triangles(), 2 * n - 4);
    EXPECT_EQ(our_triangles(dt), testing::cgal_triangles(pts)) << "n = " << n;
  }
}

TEST(SphericalDelaunay, EqualsCgalOnClusteredAndHemispherePoints) {
  const auto clustered = testing::clustered(20000, 20, 0.01, 5);
  SphericalDelaunay dt = build_checked(clustered);
  EXPECT_EQ(our_triangles(dt), testing::cgal_triangles(clustered));
  const auto cap = testing::in_hemisphere(3000, 8);
  dt = build_checked(cap, nullptr, true);
  EXPECT_GT(dt.num_ghost_triangles(), 0u);
  EXPECT_EQ(our_triangles(dt), testing::cgal_triangles(cap));
}

TEST(SphericalDelaunay, WeatherStationsEqualCgalUpToTies) {
  const std::string path = std::string(GEOVOR_SOURCE_DIR) + "/datasets/weather_stations.csv";
  const SiteTable table = read_sites_csv_file(path);
  ASSERT_EQ(table.rows_read, 5634u);
  std::vector<Vec3> pts;
  for (const auto& s : table.sites) pts.push_back(s.unit);
  BuildReport rep;
  const SphericalDelaunay dt = build_checked(pts, &rep, true);
  EXPECT_EQ(dt.num_sites() + rep.merges.size(), pts.size());
  for (const Merge& m : rep.merges) EXPECT_EQ(m.chord, 0.0);  // the data has only exact duplicates
  std::vector<std::uint32_t> rejected;
  const auto cgal = testing::cgal_triangles(pts, &rejected);
  EXPECT_EQ(rejected.size(), rep.merges.size());
  expect_equal_up_to_ties(dt, cgal_labels(dt, rep, rejected), cgal);
}

TEST(SphericalDelaunay, BruteForceNoSiteInAnyCircumcircle) {
  // validate(global) tests every triangle against every site, exactly.
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const auto pts = testing::uniform_on_sphere(300, seed);
    build_checked(pts, nullptr, true);
  }
}

TEST(SphericalDelaunay, ResultDoesNotDependOnInsertionOrder) {
  // The perturbation makes the triangulation unique, even on grids full of co-circular sites.
  for (const auto& pts : {testing::lat_lon_grid(10), testing::cube_corners(),
                          testing::on_great_circle(50, 3), testing::on_small_circle(40, 30, 2),
                          testing::uniform_on_sphere(2000, 4)}) {
    DelaunayOptions unsorted;
    unsorted.spatial_sort = false;
    DelaunayOptions other_seed;
    other_seed.brio = true;
    other_seed.seed = 12345;
    const auto a = our_triangles(build_checked(pts, nullptr, pts.size() < 3000));
    EXPECT_EQ(a, our_triangles(build_checked(pts, nullptr, false, unsorted)));
    EXPECT_EQ(a, our_triangles(build_checked(pts, nullptr, false, other_seed)));
    // Reversed input order: site ids reverse, so map them back.
    std::vector<Vec3> rev(pts.rbegin(), pts.rend());
    const SphericalDelaunay r = build_checked(rev);
    std::vector<std::uint32_t> label(rev.size());
    for (std::uint32_t i = 0; i < rev.size(); ++i) label[i] = static_cast<std::uint32_t>(rev.size() - 1 - i);
    // With reversed priorities ties may resolve differently; the triangle count and validity hold.
    EXPECT_EQ(our_triangles(r, label).size(), a.size());
  }
}

TEST(SphericalDelaunay, SmallInputs) {
  EXPECT_EQ(build_checked({}).num_triangles(), 0u);
  const auto pts = testing::uniform_on_sphere(4, 1);
  EXPECT_EQ(build_checked({pts[0]}).num_triangles(), 0u);
  EXPECT_EQ(build_checked({pts[0], pts[1]}).num_triangles(), 0u);
  const SphericalDelaunay three = build_checked({pts[0], pts[1], pts[2]}, nullptr, true);
  EXPECT_EQ(three.num_triangles(), 2u);
  EXPECT_EQ(three.num_ghost_triangles(), 1u);  // the back of the triangle covers more than half
  EXPECT_EQ(build_checked(pts, nullptr, true).num_triangles(), 4u);
  const SphericalDelaunay cube = build_checked(testing::cube_corners(), nullptr, true);
  EXPECT_EQ(cube.num_triangles(), 12u);
  EXPECT_EQ(cube.num_ghost_triangles(), 0u);
}

TEST(SphericalDelaunay, DegenerateCircles) {
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

TEST(SphericalDelaunay, HardSets) {
  for (const std::size_t n : {100u, 250u, 1000u, 2000u}) {
    const auto s = testing::skinny_set(n);
    BuildReport rep;
    const SphericalDelaunay dt = build_checked(s, &rep, n <= 250);
    EXPECT_EQ(dt.num_sites() + rep.merges.size(), s.size());
    // CGAL may reject the near-duplicate (1, 0, 6e-17) of (1, 0, 0) too; compare when it agrees.
    std::vector<std::uint32_t> rejected;
    const auto cgal = testing::cgal_triangles(s, &rejected);
    if (rejected.size() == rep.merges.size()) expect_equal_up_to_ties(dt, cgal_labels(dt, rep, rejected), cgal);
  }
  const auto global_grid = testing::lat_lon_grid(1.0);
  BuildReport rep;
  const SphericalDelaunay g = build_checked(global_grid, &rep);
  EXPECT_EQ(g.num_sites(), 179u * 360u + 2u);
  const auto region = testing::lat_lon_grid(0.1, 40, 50, 0, 10);
  const SphericalDelaunay r = build_checked(region);
  EXPECT_EQ(r.num_sites(), 101u * 101u);
  EXPECT_GT(r.num_ghost_triangles(), 0u);
  const auto poles = testing::poles_with_longitudes(50);
  BuildReport prep;
  const SphericalDelaunay p = build_checked(poles, &prep, true);
  EXPECT_EQ(p.num_sites(), 2u + 100u);  // each pole given 50 times is one site
  EXPECT_EQ(prep.merges.size(), 98u);
}

TEST(SphericalDelaunay, NearDuplicatesAroundTheSeparationBound) {
  const auto base = testing::uniform_on_sphere(500, 21);
  for (const double factor : {0.0, 0.5, 2.0}) {
    std::vector<Vec3> pts = base;
    for (std::size_t i = 0; i < 100; ++i) {
      // A point at chord distance factor * 2^-24 from site i, along a tangent direction.
      const Vec3 p = base[i];
      Vec3 t = cross(p, Vec3{0.3, 0.5, 0.8});
      t = (1.0 / std::sqrt(norm2(t))) * t;
      const Vec3 q = p + (factor * SphericalDelaunay::kMinSeparation) * t;
      pts.push_back((1.0 / std::sqrt(norm2(q))) * q);
    }
    BuildReport rep;
    const SphericalDelaunay dt = build_checked(pts, &rep, true);
    if (factor < 1.0) {
      EXPECT_EQ(dt.num_sites(), base.size());
      ASSERT_EQ(rep.merges.size(), 100u);
      for (const Merge& m : rep.merges) EXPECT_LT(m.chord, SphericalDelaunay::kMinSeparation);
    } else {
      EXPECT_EQ(dt.num_sites(), pts.size());
      EXPECT_TRUE(rep.merges.empty());
    }
  }
}

TEST(SphericalDelaunay, DynamicInsertAndRemoveEqualAFreshBuild) {
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
    EXPECT_EQ(our_triangles(dt), our_triangles(build_checked(rest), label));
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

TEST(SphericalDelaunay, RemoveDownToNothing) {
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

TEST(SphericalDelaunay, RejectsBadInputAndOptions) {
  EXPECT_THROW(SphericalDelaunay::build(std::vector<Vec3>{{1, 1, 0}}), Error);
  EXPECT_THROW(SphericalDelaunay::build(std::vector<Vec3>{{NAN, 0, 0}}), Error);
  DelaunayOptions tight;
  tight.merge_distance = SphericalDelaunay::kMinSeparation / 2;
  EXPECT_THROW(SphericalDelaunay{tight}, Error);
}

TEST(SphericalDelaunay, MemoryPerSite) {
  const auto pts = testing::uniform_on_sphere(1 << 16, 77);
  const SphericalDelaunay dt = SphericalDelaunay::build(pts);
  EXPECT_LE(static_cast<double>(dt.memory_bytes()) / dt.num_sites(), 80.0);
}

TEST(SphericalDelaunay, ValidateCatchesCorruption) {
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

}  // namespace
}  // namespace geovor

namespace geovor {
namespace {

TEST(SphericalDelaunay, LongitudesAtTheAntimeridianAndPoles) {
  // 180 and -180 are one point (an exact duplicate); 179.9999999 is 1.1 cm away at the equator,
  // closer than the separation, so it merges too, with its distance reported.
  std::vector<Vec3> pts;
  for (const double lat : {-60.0, 0.0, 45.0}) {
    for (double lon : {180.0, -180.0, 179.9999999, 540.0}) {
      double la = lat;
      ASSERT_EQ(normalize_lat_lon(la, lon), "");
      pts.push_back(SiteEncoder::from_lat_lon(la, lon));
    }
  }
  for (double lon : {0.0, 17.0, -123.0}) {  // any longitude at a pole is the pole
    double lat = 90;
    ASSERT_EQ(normalize_lat_lon(lat, lon), "");
    pts.push_back(SiteEncoder::from_lat_lon(lat, lon));
  }
  pts.push_back(SiteEncoder::from_lat_lon(-10, 90));
  BuildReport rep;
  const SphericalDelaunay dt = build_checked(pts, &rep, true);
  EXPECT_EQ(dt.num_sites(), 3u + 1u + 1u);
  ASSERT_EQ(rep.merges.size(), pts.size() - dt.num_sites());
  int exact = 0, near = 0;
  for (const Merge& m : rep.merges) {
    if (m.chord == 0) {
      ++exact;
    } else {
      ++near;
      EXPECT_LT(m.chord * SiteEncoder::kEarthRadiusM, 0.02);
    }
  }
  EXPECT_EQ(exact, 3 * 2 + 2);  // -180 and 540 equal 180 bit for bit; the pole thrice
  EXPECT_EQ(near, 3);           // 179.9999999 at each latitude
}

}  // namespace
}  // namespace geovor

namespace geovor {
namespace {

TEST(SphericalDelaunay, ArraysRoundTripAndCorruptionIsAnError) {
  const auto pts = testing::uniform_on_sphere(2000, 51);
  SphericalDelaunay dt = SphericalDelaunay::build(pts);
  for (SiteId s = 0; s < 100; s += 3) dt.remove(s);
  const SphericalDelaunay back = SphericalDelaunay::from_arrays(dt.arrays());
  EXPECT_EQ(our_triangles(back), our_triangles(dt));
  EXPECT_EQ(back.num_sites(), dt.num_sites());
  EXPECT_TRUE(back.validate().ok());
  // Corrupt one entry at a time: from_arrays throws Error, or (harmless change) gives a structure
  // whose validate() is decided without crashing. Never a crash.
  std::mt19937_64 rng(3);
  int thrown = 0;
  for (int trial = 0; trial < 300; ++trial) {
    SphericalDelaunay::Arrays a = dt.arrays();
    switch (trial % 4) {
      case 0: a.triangles[rng() % a.triangles.size()] = static_cast<SiteId>(rng() % (a.sites.size() + 5)); break;
      case 1: a.halfedges[rng() % a.halfedges.size()] = static_cast<HalfedgeId>(rng() % (a.halfedges.size() + 5)); break;
      case 2: a.site_edge[rng() % a.site_edge.size()] = static_cast<HalfedgeId>(rng()); break;
      default: a.sites[rng() % a.sites.size()].x += 1e-3; break;
    }
    try {
      const SphericalDelaunay t = SphericalDelaunay::from_arrays(std::move(a));
      (void)t.validate();
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::BadData);
      ++thrown;
    }
  }
  EXPECT_GT(thrown, 250);
  SphericalDelaunay::Arrays truncated = dt.arrays();
  truncated.halfedges.pop_back();
  EXPECT_THROW(SphericalDelaunay::from_arrays(std::move(truncated)), Error);
}

}  // namespace
}  // namespace geovor
