/// \file geometry_check_test.cpp
/// \brief geometry_problem(): what a writer refuses, and what it accepts (the extremes of the
/// ranges, a polar cap, an open ring's exact closure).
#include "geovor/io/geometry_check.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace geovor {
namespace {

Ring box(double w, double s, double e, double n) { return {{w, s}, {e, s}, {e, n}, {w, n}, {w, s}}; }

TEST(GeometryCheck, Accepts) {
  EXPECT_EQ(geometry_problem(LonLat{180, -90}), "");
  EXPECT_EQ(geometry_problem(LonLat{-180, 90}), "");
  EXPECT_EQ(geometry_problem(MultiPolygon{}), "");
  EXPECT_EQ(geometry_problem(MultiPolygon{{box(-180, -90, 180, 90), {box(1, 1, 2, 2)}}}), "");
  EXPECT_EQ(geometry_problem(MultiLineString{{{0, 0}, {1, 1}}}), "");
}

TEST(GeometryCheck, Refuses) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(geometry_problem(LonLat{nan, 0}), "a coordinate is not finite");
  EXPECT_EQ(geometry_problem(LonLat{0, std::numeric_limits<double>::infinity()}), "a coordinate is not finite");
  EXPECT_NE(geometry_problem(LonLat{std::nextafter(180.0, 200.0), 0}).find("longitude"), std::string::npos);
  EXPECT_NE(geometry_problem(LonLat{0, -90.5}).find("latitude"), std::string::npos);
  EXPECT_EQ(geometry_problem(MultiLineString{{{0, 0}}}), "a line string has 1 positions, fewer than 2");
  EXPECT_NE(geometry_problem(MultiLineString{{{0, 0}, {0, nan}}}), "");
  EXPECT_EQ(geometry_problem(MultiPolygon{{{{0, 0}, {1, 0}, {0, 0}}, {}}}), "a ring has 3 positions, fewer than 4");
  Ring open = box(0, 0, 1, 1);
  open.back().lon_deg = std::nextafter(0.0, 1.0);  // closed only up to a bit
  EXPECT_EQ(geometry_problem(MultiPolygon{{open, {}}}), "a ring is not closed (its last position differs from its first)");
  EXPECT_EQ(geometry_problem(MultiPolygon{{box(0, 0, 1, 1), {open}}}),
            "a ring is not closed (its last position differs from its first)");
  EXPECT_NE(geometry_problem(MultiPolygon{{box(0, 0, 1, 91), {}}}).find("latitude"), std::string::npos);
}

}  // namespace
}  // namespace geovor
