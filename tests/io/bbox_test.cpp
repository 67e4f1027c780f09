/// \file bbox_test.cpp
/// \brief RFC 7946 boxes: parts across the antimeridian, polar caps, ties, and BBoxUnion against
/// geojson_bbox() of all the boxes at once.
#include "geovor/io/bbox.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace geovor {
namespace {

// Counter-clockwise rectangle.
Ring box(double w, double s, double e, double n) { return {{w, s}, {e, s}, {e, n}, {w, n}, {w, s}}; }

TEST(BBox, Rules) {
  auto bb = [](const Geometry& g) {
    const auto b = geojson_bbox(g);
    return b ? std::vector<double>{b->west, b->south, b->east, b->north} : std::vector<double>{};
  };
  EXPECT_EQ(bb(LonLat{3, 4}), (std::vector<double>{3, 4, 3, 4}));
  EXPECT_EQ(bb(MultiPolygon{}), std::vector<double>{});
  // A square with a hole; a cell cut at the antimeridian; the north and south polar caps.
  EXPECT_EQ(bb(MultiPolygon{{box(0.12345678912, 0, 10, 10), {{{2, 2}, {2, 4}, {4, 4}, {4, 2}, {2, 2}}}}}),
            (std::vector<double>{0.12345678912, 0, 10, 10}));
  EXPECT_EQ(bb(MultiPolygon{{box(170, -10, 180, 10), {}}, {box(-180, -10, -170, 10), {}}}),
            (std::vector<double>{170, -10, -170, 10}));
  EXPECT_EQ(bb(MultiPolygon{{{{-180, 70}, {-90, 72.25}, {0, 70.5}, {90, 71}, {180, 70}, {180, 90}, {-180, 90}, {-180, 70}},
                             {}}}),
            (std::vector<double>{-180, 70, 180, 90}));
  EXPECT_EQ(bb(MultiPolygon{{{{180, -75}, {90, -76}, {0, -75}, {-90, -74}, {-180, -75}, {-180, -90}, {180, -90}, {180, -75}},
                             {}}}),
            (std::vector<double>{-180, -90, 180, -74}));
  // Line parts on both sides of the antimeridian.
  EXPECT_EQ(bb(MultiLineString{{{170, 1}, {180, 2}}, {{-180, 2}, {-170, 3}, {-160, 3.5}}}), (std::vector<double>{170, 1, -160, 3.5}));
  // Parts far apart on the same side: no crossing.
  EXPECT_EQ(bb(MultiLineString{{{-10, 0}, {-5, 1}}, {{20, 0}, {30, 1}}}),
            (std::vector<double>{-10, 0, 30, 1}));
  // Parts at -180..-10 and 10..180 (touching at the antimeridian): the arc 10 -> -10 eastwards.
  EXPECT_EQ(bb(MultiPolygon{{box(-180, 0, -10, 1), {}}, {box(10, 0, 180, 1), {}}}),
            (std::vector<double>{10, 0, -10, 1}));

  BBoxUnion u;
  EXPECT_FALSE(u.result());
  u.add({170, -10, -170, 10});
  u.add({0, 20, 10, 30});
  auto r = u.result();
  ASSERT_TRUE(r);
  EXPECT_EQ((std::vector<double>{r->west, r->south, r->east, r->north}),
            (std::vector<double>{0, -10, -170, 30}));
  u.add({-180, 80, 180, 90});
  r = u.result();
  EXPECT_EQ((std::vector<double>{r->west, r->south, r->east, r->north}),
            (std::vector<double>{-180, -10, 180, 90}));
  // Many small boxes (compaction) covering -100..100 in steps.
  BBoxUnion many;
  for (int i = 0; i < 200000; ++i) {
    const double w = -100 + (i % 2000) * 0.1;
    many.add({w, 0, w + 0.1, 1});
  }
  r = many.result();
  ASSERT_TRUE(r);
  EXPECT_NEAR(r->west, -100, 1e-9);
  EXPECT_NEAR(r->east, 100, 1e-9);
  // Staircases of overlapping boxes, each reaching a little farther east than the union so
  // far, of every length around the compactions (after 4,097 pending, then every 4,097): the
  // east edge is the last box's.
  for (const int from : {4090, 8185, 65530})
    for (int length = from; length < from + 16; ++length) {
      BBoxUnion stairs;
      for (int i = 0; i < length; ++i) stairs.add({-170 + i * 0.001, 0, -170 + i * 0.001 + 0.0015, 1});
      r = stairs.result();
      ASSERT_TRUE(r);
      EXPECT_EQ(r->west, -170);
      EXPECT_EQ(r->east, -170 + (length - 1) * 0.001 + 0.0015) << length;
    }
  // Random boxes (some across the antimeridian, one whole-circle late), enough to compact
  // several times, against geojson_bbox() of all of them at once as the parts of one geometry;
  // also the results along the way.
  std::mt19937_64 rng(77);
  for (const double span : {0.5, 20.0, 300.0}) {
    BBoxUnion incremental;
    MultiLineString parts;
    std::uniform_real_distribution<double> lon(-180, 180), width(0, span);
    for (int i = 0; i < 150000; ++i) {
      double west = lon(rng), east = west + width(rng);
      if (i == 140000) west = -180, east = 180;
      if (east > 180) east -= 360;  // crosses the antimeridian
      incremental.add({west, 0, east, 1});
      if (west <= east) {
        parts.push_back({{west, 0}, {east, 1}});
      } else {
        parts.push_back({{west, 0}, {180, 1}});
        parts.push_back({{-180, 0}, {east, 1}});
      }
      if (i < 50 || i == 1000 || i == 70000 || i == 139999 || i == 149999) {
        const auto got = incremental.result();
        const auto want = geojson_bbox(parts);
        ASSERT_TRUE(got && want);
        ASSERT_EQ(got->west, want->west) << "span " << span << " box " << i;
        ASSERT_EQ(got->east, want->east) << "span " << span << " box " << i;
      }
    }
  }
}

}  // namespace
}  // namespace geovor
