// SphericalDelaunay::build() and the inspectors: the triangulation equals CGAL's (up to
// co-circular ties), does not depend on the insertion order, merges close points and reports
// them; arrays() and from_arrays() round-trip and reject corruption.
#include "geovor/delaunay/spherical_delaunay.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <set>

#include "geovor/core/error.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/kernel/predicates.hpp"
#include "support/cgal_oracle.hpp"
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

Tri canonical(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (b < a && b < c) return {b, c, a};
  if (c < a && c < b) return {c, a, b};
  return {a, b, c};
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

// Triangles where ours and CGAL's differ must come from co-circular ties: every one of them has
// an edge whose opposite site (in our triangulation) is exactly on its circumcircle.
void expect_equal_up_to_ties(const SphericalDelaunay& dt, const std::vector<std::uint32_t>& label,
                             const std::vector<Tri>& cgal) {
  const std::vector<Tri> ours_labelled = triangle_set(dt, label);
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
    EXPECT_EQ(triangle_set(dt), testing::cgal_triangles(pts)) << "n = " << n;
  }
}

TEST(SphericalDelaunay, EqualsCgalOnClusteredAndHemispherePoints) {
  const auto clustered = testing::clustered(20000, 20, 0.01, 5);
  SphericalDelaunay dt = build_checked(clustered);
  EXPECT_EQ(triangle_set(dt), testing::cgal_triangles(clustered));
  const auto cap = testing::in_hemisphere(3000, 8);
  dt = build_checked(cap, nullptr, true);
  EXPECT_GT(dt.num_ghost_triangles(), 0u);
  EXPECT_EQ(triangle_set(dt), testing::cgal_triangles(cap));
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
    const auto a = triangle_set(build_checked(pts, nullptr, pts.size() < 3000));
    EXPECT_EQ(a, triangle_set(build_checked(pts, nullptr, false, unsorted)));
    EXPECT_EQ(a, triangle_set(build_checked(pts, nullptr, false, other_seed)));
    // Reversed input order: site ids reverse, so map them back.
    std::vector<Vec3> rev(pts.rbegin(), pts.rend());
    const SphericalDelaunay r = build_checked(rev);
    std::vector<std::uint32_t> label(rev.size());
    for (std::uint32_t i = 0; i < rev.size(); ++i) label[i] = static_cast<std::uint32_t>(rev.size() - 1 - i);
    // With reversed priorities ties may resolve differently; the triangle count and validity hold.
    EXPECT_EQ(triangle_set(r, label).size(), a.size());
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

TEST(SphericalDelaunay, ArraysRoundTripAndCorruptionIsAnError) {
  const auto pts = testing::uniform_on_sphere(2000, 51);
  SphericalDelaunay dt = SphericalDelaunay::build(pts);
  for (SiteId s = 0; s < 100; s += 3) dt.remove(s);
  const SphericalDelaunay back = SphericalDelaunay::from_arrays(dt.arrays());
  EXPECT_EQ(triangle_set(back), triangle_set(dt));
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

// from_arrays() on several threads: the checks and validate_structure() cut into slices (each at
// least 2^16 items) report the first broken invariant in the serial order, whatever the threads.
TEST(SphericalDelaunay, FromArraysOnAnyThreadsReportsTheSameError) {
  const SphericalDelaunay dt = SphericalDelaunay::build(testing::uniform_on_sphere(150000, 52));
  auto outcome = [](SphericalDelaunay::Arrays a, unsigned threads) -> std::string {
    try {
      const SphericalDelaunay t = SphericalDelaunay::from_arrays(std::move(a), {}, threads);
      return "ok " + std::to_string(t.num_sites());
    } catch (const Error& e) {
      return e.what();
    }
  };
  EXPECT_EQ(outcome(dt.arrays(), 3), "ok 150000");
  std::mt19937_64 rng(4);
  int thrown = 0;
  for (int trial = 0; trial < 40; ++trial) {
    SphericalDelaunay::Arrays a = dt.arrays();
    // Two to four edits anywhere: the one the serial loops meet first is the error.
    for (int k = 0, edits = 2 + static_cast<int>(rng() % 3); k < edits; ++k) {
      switch (rng() % 4) {
        case 0: a.triangles[rng() % a.triangles.size()] = static_cast<SiteId>(rng() % (a.sites.size() + 5)); break;
        case 1: a.halfedges[rng() % a.halfedges.size()] = static_cast<HalfedgeId>(rng() % (a.halfedges.size() + 5)); break;
        case 2: a.site_edge[rng() % a.site_edge.size()] = static_cast<HalfedgeId>(rng() % a.halfedges.size()); break;
        default: std::swap(a.halfedges[rng() % a.halfedges.size()], a.halfedges[rng() % a.halfedges.size()]); break;
      }
    }
    const std::string serial = outcome(a, 1);
    thrown += serial.rfind("ok", 0) != 0;
    for (const unsigned threads : {2u, 3u, 0u}) EXPECT_EQ(outcome(a, threads), serial) << threads << " threads";
  }
  EXPECT_GT(thrown, 30);
}

}  // namespace
}  // namespace geovor
