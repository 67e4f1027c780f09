// Which degenerate case the sites of a triangulation are.
#include "geovor/delaunay/degenerate_case.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "support/generators.hpp"

namespace geovor {
namespace {

std::string case_of(const std::vector<Vec3>& points) {
  return degenerate_case(SphericalDelaunay::build(points));
}

TEST(DegenerateCase, NamesEachCase) {
  EXPECT_EQ(case_of({}), "no sites");
  EXPECT_EQ(case_of({{1, 0, 0}}), "one site");
  EXPECT_EQ(case_of({{1, 0, 0}, {-1, 0, 0}}), "two sites");
  EXPECT_EQ(case_of({{1, 0, 0}, {1, 0, 0}, {-1, 0, 0}}), "two sites");  // a duplicate merges
  EXPECT_EQ(case_of(testing::on_great_circle(12, 1)), "all sites on one great circle");
  EXPECT_EQ(case_of(testing::in_hemisphere(50, 2)), "all sites in one open hemisphere");
  EXPECT_EQ(case_of(testing::on_small_circle(12, 30, 3)), "all sites in one open hemisphere");
  EXPECT_EQ(case_of(testing::uniform_on_sphere(100, 4)), "none");
  EXPECT_EQ(case_of(testing::cube_corners()), "none");
}

}  // namespace
}  // namespace geovor
