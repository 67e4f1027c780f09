/// \file polygon_validity_test.cpp
/// \brief polygon_problem() against GEOS (through OGR, the oracle) on rounded rings full of
/// touching, collinear and crossing cases; remove_spikes().
#include "geovor/lonlat/polygon_validity.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "geovor/lonlat/ellipsoid_area.hpp"
#include "support/lonlat_checks.hpp"

namespace geovor {
namespace {

TEST(PolygonValidity, AgainstGeosOnRoundedRings) {
  // Random lon/lat quadrilaterals and pentagons on a coarse grid (many touching, collinear and
  // crossing cases): polygon_problem() says valid exactly when GEOS does, for CCW rings.
  std::uint64_t state = 14;
  auto next = [&](int n) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<int>((state >> 33) % static_cast<std::uint64_t>(n));
  };
  int agree = 0;
  for (int iter = 0; iter < 4000; ++iter) {
    Ring r;
    const int n = 3 + next(4);
    for (int i = 0; i < n; ++i) r.push_back({static_cast<double>(next(5)), static_cast<double>(next(5))});
    r.push_back(r.front());
    if (!(planar_area_deg2(r) > 0)) continue;
    const MultiPolygon mp{Polygon{r, {}}};
    const bool ours = polygon_problem(mp).empty();
    const bool geos = testing::geos_invalid(mp).empty();
    // Repeated positions: GEOS accepts them, we refuse them (what we write never repeats one).
    bool repeats = false;
    for (std::size_t i = 0; i + 1 < r.size(); ++i) repeats |= r[i] == r[i + 1];
    if (repeats) {
      EXPECT_FALSE(ours);
      continue;
    }
    EXPECT_EQ(ours, geos) << "ring of " << n << ": " << polygon_problem(mp);
    if (ours) EXPECT_EQ(is_star_shaped_ccw(r), is_star_shaped_ccw(r));
    if (is_star_shaped_ccw(r)) EXPECT_TRUE(geos);
    ++agree;
  }
  EXPECT_GT(agree, 1000);
}

// Two parts on a coarse grid (touching at positions, along segments, crossing, nested):
// polygon_problem() accepting them means GEOS does (ours is stricter only where a position of one
// part lies inside a segment of the other), and parts meeting only at shared positions are
// accepted.
TEST(PolygonValidity, TwoPartsAgainstGeos) {
  std::uint64_t state = 21;
  auto next = [&](int n) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<int>((state >> 33) % static_cast<std::uint64_t>(n));
  };
  int touching_at_positions = 0, accepted = 0;
  for (int iter = 0; iter < 6000; ++iter) {
    MultiPolygon mp;
    for (int part = 0; part < 2; ++part) {
      Ring r;
      const int n = 3 + next(2);
      for (int i = 0; i < n; ++i) r.push_back({static_cast<double>(next(4)), static_cast<double>(next(4))});
      r.push_back(r.front());
      mp.push_back(Polygon{r, {}});
    }
    if (!polygon_problem({mp[0]}).empty() || !polygon_problem({mp[1]}).empty()) continue;  // each part valid
    const bool ours = polygon_problem(mp).empty();
    const bool geos = testing::geos_invalid(mp).empty();
    if (ours) {
      EXPECT_TRUE(geos) << "accepted, GEOS: " << testing::geos_invalid(mp);
      ++accepted;
    }
    // Parts sharing a position, GEOS valid, no position of one on a segment of the other but
    // shared ones: ours must accept.
    bool shared = false;
    for (const LonLat& a : mp[0].exterior)
      for (const LonLat& b : mp[1].exterior) shared |= a == b;
    if (geos && shared && !ours) {
      const std::string why = polygon_problem(mp);
      EXPECT_EQ(why, "two parts cross or overlap");  // only the stricter rule may refuse
    }
    touching_at_positions += geos && shared && ours;
  }
  EXPECT_GT(accepted, 50);
  EXPECT_GT(touching_at_positions, 20);
}

// Up to six parts on a coarse grid: polygon_problem() accepting them means GEOS does (the
// bounding-box sweep for nested parts must not miss a pair), and nested parts are found.
TEST(PolygonValidity, SeveralPartsAgainstGeos) {
  std::uint64_t state = 33;
  auto next = [&](int n) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<int>((state >> 33) % static_cast<std::uint64_t>(n));
  };
  int accepted = 0, nested = 0;
  for (int iter = 0; iter < 4000; ++iter) {
    MultiPolygon mp;
    const int parts = 2 + next(5);
    for (int part = 0; part < parts; ++part) {
      // Mostly small triangles (quarter steps); one part in three a large one, so that parts nest.
      const bool large = next(3) == 0;
      const double step = large ? 1 : 0.25;
      const int x0 = next(7), y0 = next(7);
      Ring r;
      for (int i = 0; i < 3; ++i)
        r.push_back({x0 + step * next(large ? 7 : 4), y0 + step * next(large ? 7 : 4)});
      r.push_back(r.front());
      if (polygon_problem({Polygon{r, {}}}).empty()) mp.push_back(Polygon{r, {}});
    }
    if (mp.size() < 2) continue;
    const std::string ours = polygon_problem(mp);
    const std::string geos = testing::geos_invalid(mp);
    if (ours.empty()) {
      EXPECT_EQ(geos, "") << "accepted";
      ++accepted;
    }
    if (ours == "a part lies inside another") {
      EXPECT_NE(geos, "");
      ++nested;
    }
  }
  EXPECT_GT(accepted, 100);
  EXPECT_GT(nested, 20);
}

// Thousands of parts side by side (snap rounding pinches a thin lune into as many): the part
// inside another is found wherever it is, including inside a long part that began far before.
TEST(PolygonValidity, ThousandsOfParts) {
  MultiPolygon chain;
  for (int i = 0; i < 4000; ++i) {  // diamonds touching at their corners along y = 1
    const double x = 2.0 * i;
    chain.push_back(Polygon{{{x, 1}, {x + 1, 0.5}, {x + 2, 1}, {x + 1, 1.5}, {x, 1}}, {}});
  }
  // A long thin part below them, starting before the first and ending inside the diamond at 4998.
  chain.push_back(Polygon{{{-1, -2}, {4999, -2}, {4999, 0}, {-1, 0}, {-1, -2}}, {}});
  EXPECT_EQ(polygon_problem(chain), "");
  EXPECT_EQ(testing::geos_invalid(chain), "");
  MultiPolygon inner = chain;
  // Inside the long part, after that diamond began (which the sweep must not take as its end).
  inner.push_back(Polygon{{{4998.2, -1.5}, {4998.8, -1.5}, {4998.5, -1}, {4998.2, -1.5}}, {}});
  EXPECT_EQ(polygon_problem(inner), "a part lies inside another");
  EXPECT_NE(testing::geos_invalid(inner), "");
  MultiPolygon twice = chain;
  twice.push_back(chain[1234]);
  EXPECT_NE(polygon_problem(twice), "");
}

// What snap rounding leaves: a ring through one position twice is split into parts touching
// there (GEOS: valid MultiPolygon); a fold-back on a line (a, b, c with c back towards a) loses
// its tip; a ring left on one line has collapsed, a fold has not.
TEST(PolygonValidity, CertifySplitsPinchesAndDropsFolds) {
  // Two squares meeting at (1, 1), as one ring.
  MultiPolygon pinched{Polygon{{{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {1, 2}, {1, 1}, {0, 1}, {0, 0}}, {}}};
  EXPECT_NE(polygon_problem(pinched), "");
  EXPECT_NE(testing::geos_invalid(pinched), "");  // GEOS: ring self-intersection
  bool cleaned = false;
  EXPECT_EQ(certify_written(pinched, &cleaned), WrittenStatus::Written);
  EXPECT_TRUE(cleaned);
  EXPECT_EQ(pinched.size(), 2u);
  EXPECT_EQ(testing::geos_invalid(pinched), "");
  double area = 0;
  for (const Polygon& poly : pinched) area += planar_area_deg2(poly.exterior);
  EXPECT_EQ(area, 2);

  // A fold-back: the tip goes; the path keeps the same segments, with one collinear position.
  Ring fold = {{0, 0}, {3, 0}, {3, 1}, {1, 1}, {2, 1}, {0, 1}, {0, 0}};  // 1 -> 2 -> 0 along y = 1
  remove_spikes(fold);
  EXPECT_EQ(fold, (Ring{{0, 0}, {3, 0}, {3, 1}, {2, 1}, {0, 1}, {0, 0}}));
  EXPECT_EQ(testing::geos_invalid({Polygon{fold, {}}}), "");
  Ring past = {{0, 0}, {3, 0}, {3, 1}, {2, 1}, {4, 1}, {1, 1}, {0, 1}, {0, 0}};  // past its start, twice
  remove_spikes(past);
  EXPECT_EQ(past, (Ring{{0, 0}, {3, 0}, {3, 1}, {1, 1}, {0, 1}, {0, 0}}));
  EXPECT_EQ(testing::geos_invalid({Polygon{past, {}}}), "");

  MultiPolygon line{Polygon{{{0, 0}, {1, 1}, {3, 3}, {2, 2}, {0, 0}}, {}}};  // no a, b, a spike
  EXPECT_EQ(certify_written(line), WrittenStatus::Collapsed);
  EXPECT_TRUE(line.empty());
  MultiPolygon bowtie{Polygon{{{0, 0}, {2, 2}, {2, 0}, {0, 2}, {0, 0}}, {}}};  // area 0, but a fold
  EXPECT_EQ(certify_written(bowtie), WrittenStatus::Unwritable);
}

// A path routed once more around three pixels (A B C A B, the tips of 19 cells of a co-circular
// ring at 7 decimals, fuzz_cells' regression cocircular_ring_p7_tip_loop_winds_back): the loop
// split off there is clockwise and smaller than a square of 1e-6 degree, so it has collapsed;
// the same loop a thousand times larger is no rounding, and the ring is unwritable.
TEST(PolygonValidity, CertifyDropsTinyLoopsWoundBack) {
  for (const double scale : {1e-7, 1e-4}) {
    SCOPED_TRACE(scale);
    const double x0 = -166.47013, y0 = 16.5882352;
    const LonLat a{x0, y0 + scale}, b{x0, y0}, c{x0 - 10 * scale, y0};
    // From c: a, b, then a large part to the east and back to a, b, c.
    MultiPolygon mp{Polygon{{c, a, b, {x0 + 5, y0 - 1}, {x0 + 5, y0 + 1}, a, b, c}, {}}};
    EXPECT_NE(testing::geos_invalid(mp), "");
    const WrittenStatus status = certify_written(mp);
    if (scale < 1e-6) {
      ASSERT_EQ(status, WrittenStatus::Written);
      ASSERT_EQ(mp.size(), 1u);
      EXPECT_EQ(testing::geos_invalid(mp), "");
      EXPECT_EQ(mp[0].exterior.size(), 5u);  // a, b and the two eastern corners
    } else {
      EXPECT_EQ(status, WrittenStatus::Unwritable);
    }
  }
}

TEST(PolygonValidity, RemoveSpikes) {
  Ring r = {{0, 0}, {1, 0}, {2, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
  remove_spikes(r);
  EXPECT_EQ(r, (Ring{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}}));
  Ring seam = {{5, 5}, {0, 0}, {1, 0}, {1, 1}, {0, 0}, {5, 5}};
  remove_spikes(seam);
  EXPECT_EQ(seam, (Ring{{0, 0}, {1, 0}, {1, 1}, {0, 0}}));
  Ring flat = {{0, 0}, {1, 0}, {0, 0}};
  remove_spikes(flat);
  EXPECT_LT(flat.size(), 4u);
}

}  // namespace
}  // namespace geovor
