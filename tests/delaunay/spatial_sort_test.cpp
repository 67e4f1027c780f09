#include "geovor/delaunay/spatial_sort.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/generators.hpp"

namespace geovor {
namespace {

std::vector<std::uint32_t> sorted(std::vector<std::uint32_t> v) {
  std::sort(v.begin(), v.end());
  return v;
}

TEST(SpatialSort, OrdersArePermutations) {
  const auto pts = testing::uniform_on_sphere(10000, 1);
  std::vector<std::uint32_t> ids(pts.size());
  for (std::uint32_t i = 0; i < ids.size(); ++i) ids[i] = i;
  EXPECT_EQ(sorted(hilbert_order(pts)), ids);
  EXPECT_EQ(sorted(brio_order(pts, 5)), ids);
  EXPECT_EQ(brio_order(pts, 5), brio_order(pts, 5));  // deterministic
  EXPECT_NE(brio_order(pts, 5), brio_order(pts, 6));
}

TEST(SpatialSort, HilbertOrderIsSpatiallyCoherent) {
  // Consecutive points along the curve are much closer than in input (random) order.
  const auto pts = testing::uniform_on_sphere(20000, 2);
  auto mean_step = [&](const std::vector<std::uint32_t>& order) {
    double sum = 0;
    for (std::size_t i = 1; i < order.size(); ++i) sum += std::sqrt(norm2(pts[order[i]] - pts[order[i - 1]]));
    return sum / static_cast<double>(order.size() - 1);
  };
  std::vector<std::uint32_t> input(pts.size());
  for (std::uint32_t i = 0; i < input.size(); ++i) input[i] = i;
  const double random_step = mean_step(input), hilbert_step = mean_step(hilbert_order(pts));
  EXPECT_GT(random_step, 1.0);            // about 4/3 for uniform points
  EXPECT_LT(hilbert_step, random_step / 30);
}

TEST(SpatialSort, KeysFollowAHilbertCurve) {
  // On each face, sorting the centres of a 16 x 16 grid of cells by key must visit every cell
  // once, each next to the previous one: the defining property of a Hilbert curve.
  constexpr int kGrid = 16;
  for (int face = 0; face < 6; ++face) {
    std::vector<std::pair<std::uint64_t, std::pair<int, int>>> cells;
    for (int i = 0; i < kGrid; ++i)
      for (int j = 0; j < kGrid; ++j) {
        const double u = -1 + (2 * i + 1.0) / kGrid, v = -1 + (2 * j + 1.0) / kGrid;
        Vec3 p;
        switch (face) {
          case 0: p = {u, v, 1}; break;
          case 5: p = {u, v, -1}; break;
          case 1: p = {1, u, v}; break;
          case 3: p = {-1, u, v}; break;
          case 2: p = {v, 1, u}; break;
          default: p = {v, -1, u}; break;
        }
        cells.push_back({hilbert_key(p), {i, j}});
      }
    std::sort(cells.begin(), cells.end());
    for (std::size_t k = 1; k < cells.size(); ++k) {
      EXPECT_NE(cells[k].first, cells[k - 1].first);
      const int di = std::abs(cells[k].second.first - cells[k - 1].second.first);
      const int dj = std::abs(cells[k].second.second - cells[k - 1].second.second);
      EXPECT_EQ(di + dj, 1) << "face " << face << " step " << k;
      EXPECT_EQ(cells[k].first >> 32, static_cast<std::uint64_t>(face));
    }
  }
}

TEST(SpatialSort, KeysSeparateTheCubeFaces) {
  EXPECT_LT(hilbert_key({0, 0, 1}), hilbert_key({1, 0, 0}));
  EXPECT_LT(hilbert_key({1, 0, 0}), hilbert_key({0, 0, -1}));
  EXPECT_EQ(hilbert_key({0, 0, 1}) >> 32, 0u);
  EXPECT_EQ(hilbert_key({0, 0, -1}) >> 32, 5u);
}

}  // namespace
}  // namespace geovor
