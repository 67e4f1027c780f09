/// \file polygon_validity_test.cpp
/// \brief polygon_problem() against GEOS (through OGR, the oracle) on rounded rings full of
/// touching, collinear and crossing cases; remove_spikes().
#include "geovor/lonlat/polygon_validity.hpp"

#include <gtest/gtest.h>

#include <cstdint>

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
