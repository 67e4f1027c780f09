#include "geovor/delaunay/site_rows.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "geovor/delaunay/spherical_delaunay.hpp"

namespace geovor {
namespace {

std::vector<std::uint32_t> as_vector(std::span<const std::uint32_t> s) { return {s.begin(), s.end()}; }

TEST(SiteRows, BuiltFromFirstThenMergedInInputOrder) {
  // Input 2 built site 0; inputs 0 and 4 merged into it (a built-from input need not be the lowest).
  BuildReport report;
  report.site_of_input = {0, 1, 0, 2, 0, kNoIndex};
  report.merges = {{0, 0, 0.0, false}, {4, 0, 1e-9, false}};
  const SiteRows rows = rows_of_sites(report, 3);
  ASSERT_EQ(rows.num_sites(), 3u);
  EXPECT_EQ(as_vector(rows.of(0)), (std::vector<std::uint32_t>{2, 0, 4}));
  EXPECT_EQ(as_vector(rows.of(1)), (std::vector<std::uint32_t>{1}));
  EXPECT_EQ(as_vector(rows.of(2)), (std::vector<std::uint32_t>{3}));
  EXPECT_EQ(rows.first(0), 2u);
  EXPECT_EQ(rows.begin, (std::vector<std::uint32_t>{0, 3, 4, 5}));  // input 5 has no site
}

TEST(SiteRows, SitesBeyondTheCapacityAndEmptySites) {
  BuildReport report;
  report.site_of_input = {3, 0, 7};
  report.merges = {{9, 0, 0.0, false}};  // out of range: ignored
  const SiteRows rows = rows_of_sites(report, 4);
  EXPECT_EQ(as_vector(rows.of(0)), (std::vector<std::uint32_t>{1}));
  EXPECT_TRUE(rows.of(1).empty());
  EXPECT_EQ(rows.first(1), kNoIndex);
  EXPECT_EQ(as_vector(rows.of(3)), (std::vector<std::uint32_t>{0}));
  EXPECT_EQ(rows.inputs.size(), 2u);  // input 2's site 7 is not below the capacity
}

TEST(SiteRows, FromARealBuildWithDuplicates) {
  const Vec3 a{1, 0, 0}, b{0, 1, 0}, c{0, 0, 1}, d{-1, 0, 0}, e{0, 0, -1};
  const std::vector<Vec3> points = {a, b, a, c, d, e, b, a};
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(points, {}, &report);
  ASSERT_EQ(dt.num_sites(), 5u);
  const SiteRows rows = rows_of_sites(report, dt.site_capacity());
  const SiteId sa = report.site_of_input[0], sb = report.site_of_input[1];
  // Each site holds the inputs at its position; the one not merged comes first.
  std::vector<std::uint32_t> of_a = as_vector(rows.of(sa)), of_b = as_vector(rows.of(sb));
  ASSERT_EQ(of_a.size(), 3u);
  ASSERT_EQ(of_b.size(), 2u);
  for (const Merge& m : report.merges) EXPECT_NE(rows.first(m.site), m.input);
  std::sort(of_a.begin(), of_a.end());
  std::sort(of_b.begin(), of_b.end());
  EXPECT_EQ(of_a, (std::vector<std::uint32_t>{0, 2, 7}));
  EXPECT_EQ(of_b, (std::vector<std::uint32_t>{1, 6}));
  EXPECT_EQ(rows.inputs.size(), points.size());
}

}  // namespace
}  // namespace geovor
