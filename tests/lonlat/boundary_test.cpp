#include "lonlat/boundary.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "geovor/geo/site_encoder.hpp"
#include "geovor/lonlat/ellipsoid_area.hpp"
#include "geovor/lonlat/polygon_validity.hpp"

namespace geovor::lonlat {
namespace {

constexpr double kDeg = std::numbers::pi / 180;
constexpr double kInf = std::numeric_limits<double>::infinity();

// The unit vector at colatitude theta (radians) and longitude lon (degrees).
Vec3 at_colatitude(double theta, double lon_deg) {
  return {std::sin(theta) * std::cos(lon_deg * kDeg), std::sin(theta) * std::sin(lon_deg * kDeg), std::cos(theta)};
}

// The arc a -> b densified with max_depth 2 (standing for a side from pole to pole, which reaches
// 20 levels at pieces of 19 m), ends included; each piece is checked with an independent
// midpoint: the straight segment's lon/lat midpoint through SiteEncoder lies within a seventh of
// its distance to the pole from the arc's great circle (an eighth of the arc midpoint's distance,
// which is farther by at most as much).
std::vector<Pt> densified_near_a_pole(const Vec3& a, const Vec3& b) {
  std::vector<Pt> out;
  Densifier dens(100, 1, 2, out);
  const Pt pa = make_pt(a), pb = make_pt(b);
  dens.edge(pa, pb, a, b, kInf);
  std::vector<Pt> chain = {pa};
  chain.insert(chain.end(), out.begin(), out.end());
  chain.push_back(pb);
  const double metre = 1 / SiteEncoder::kEarthRadiusM;
  const Vec3 n = normalized(cross(a, b));
  for (std::size_t i = 0; i + 1 < chain.size(); ++i) {
    const Pt &p = chain[i], &q = chain[i + 1];
    const Vec3 mid = SiteEncoder::from_lat_lon((p.lat + q.lat) / 2, (p.lon + q.lon) / 2);
    const double off_arc = std::fabs(dot(mid, n)), to_pole = std::hypot(mid.x, mid.y);
    EXPECT_LE(off_arc, to_pole / 7) << "piece " << i << " of " << chain.size() - 1 << " at " << to_pole / metre << " m from the pole";
  }
  return chain;
}

// The copies of one Voronoi vertex that co-circular sites give are joined by edges nanometres
// long, whose guards pass through their ends: split to max_depth, such an edge had 2^20 - 1
// points (a 7 x 7 grid on a pole: 17 s and 1.3 GB). No piece is split below kMinPieceRad.
TEST(Densifier, EdgesNanometresLongAreNotSplit) {
  const Vec3 a = at_colatitude(std::numbers::pi / 2, 88.92);
  const Vec3 b = normalized(a + Vec3{0, 0, 1e-16});
  ASSERT_NE(a, b);
  const Vec3 guards[2] = {normalized(cross(a, Vec3{0, 0, 1})), normalized(cross(b, Vec3{1, 0, 0}))};
  std::vector<Pt> out;
  Densifier dens(100, 1, 20, out);
  dens.set_guards(guards);
  dens.edge(make_pt(a), make_pt(b), a, b, kInf);
  EXPECT_EQ(out.size(), 0u);
}

// Within metres of a pole a straight lon/lat segment is a circle of latitude: each piece must stay
// within an eighth of its distance to the pole, whatever max_depth. max_depth alone left a piece
// 15 m to 0.17 m from the pole at 0.185 of it.
TEST(Densifier, PoleRuleSplitsPastMaxDepth) {
  const double metre = 1 / SiteEncoder::kEarthRadiusM;
  for (const double near_m : {0.17, 0.03, 2.0}) {
    SCOPED_TRACE(near_m);
    EXPECT_LT(densified_near_a_pole(at_colatitude(60 * metre, -50), at_colatitude(near_m * metre, -27.6)).size(), 202u);
  }
}

// However close to the pole the arc passes: points written on the pole line are runs there, which
// the pole rules and the pinch close. Stopping two steps of the 7-decimal grid (2.2 cm) short of
// the pole, as before, left chords spanning tens of degrees of longitude that crossed the other
// side of a thin cell (a lune's side passing a pole 0.8 m off at 5 decimals: fuzz_cells).
TEST(Densifier, PoleRuleSplitsAnArcPassingAPoleMillimetresOff) {
  const double metre = 1 / SiteEncoder::kEarthRadiusM;
  for (const double off_deg : {0.005, 0.05}) {  // passing the pole 1.7 mm, 1.7 cm off
    SCOPED_TRACE(off_deg);
    const std::vector<Pt> chain = densified_near_a_pole(at_colatitude(100 * metre, 0), at_colatitude(20 * metre, 180 - off_deg));
    EXPECT_LT(chain.size(), 402u);
    double closest = 1;
    for (const Pt& p : chain) closest = std::min(closest, std::hypot(p.v.x, p.v.y));
    EXPECT_LT(closest, 2 * std::sin(off_deg * kDeg) * 20 * metre);  // a point near the closest approach
  }
}

// A boundary passing within a step of a pole it does not own, drawn at the pole line once and
// back up the same meridian, is a spike there, not a second run along the pole line: the ring
// is one polygon, valid (the pinch cut it at that point into two parts sharing the meridian
// -128 from -89 to -90, an invalid MultiPolygon: a cluster 1 m from the south pole, 0 decimals,
// fuzz_cells). At 0 decimals: the pole run from -150 to -37, a block north of it to -80, and
// the side back along -89 that dips to the pole line at -128 (computed at -89.5004).
TEST(LoopToPolygons, ASpikeToAPoleLineIsNotASecondRun) {
  auto pt = [](double lat, double lon) { return make_pt(SiteEncoder::from_lat_lon(lat, lon), 0); };
  for (int start = 0; start < 9; ++start) {
    std::vector<Pt> loop = {pt(-89.9999, -150), pt(-89.9999, -37), pt(-80, -37),  pt(-80, -57), pt(-89, -57),
                            pt(-89, -128),      pt(-89.5004, -128), pt(-89, -128), pt(-89, -150)};
    ASSERT_EQ(loop[6].lat, -90);
    ASSERT_FALSE(at_pole(loop[6].v));
    std::rotate(loop.begin(), loop.begin() + start, loop.end());  // the spike at every place, across the start too
    MultiPolygon out;
    LoopInfo info;
    loop_to_polygons(loop, out, nullptr, 0, &info, PoleOwner{0, 0});
    ASSERT_EQ(out.size(), 1u) << "start " << start;
    EXPECT_EQ(polygon_problem(out), "") << "start " << start;
    EXPECT_EQ(info.winding, 0);
    // The strip from -150 to -37 between the pole line and -89, and the block: 113 + 20 * 9.
    EXPECT_EQ(std::fabs(planar_area_deg2(out[0].exterior)), 113.0 + 180.0) << "start " << start;
  }
}


// The stages of loop_to_polygons.

Pt written(double lat, double lon, int precision = 0) { return make_pt(SiteEncoder::from_lat_lon(lat, lon), precision); }
// A point written on a pole line whose sphere point is merely near the pole.
Pt on_pole_line(double lat, double lon) {
  Pt p = written(lat > 0 ? 89.9999 : -89.9999, lon, 7);
  p.lat = lat, p.lon = lon;
  return p;
}
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(MergeRepeatedPositions, DropsRepeatsAcrossTheStartToo) {
  std::vector<Pt> loop = {written(0, 0), written(0, 0), written(0, 10), written(10, 10), written(0, 0)};
  std::vector<OwnLon> own;
  EXPECT_FALSE(merge_repeated_positions(loop, own));
  ASSERT_EQ(loop.size(), 3u);
  EXPECT_EQ(loop[0].lon, 0);
  EXPECT_EQ(loop[1].lon, 10);
  EXPECT_EQ(loop[2].lat, 10);
  EXPECT_TRUE(own.empty());
}

// A run at a pole is one point of the sphere whatever its longitudes: drawn from its first
// point's own longitude to its last point's, and keeping the sphere point of one merely rounded
// there (the last such), not the pole itself.
TEST(MergeRepeatedPositions, MergesARunAtAPole) {
  const Pt first = on_pole_line(90, 10), last = on_pole_line(90, 30);
  Pt pole = on_pole_line(90, 20);
  pole.v = {0, 0, 1};
  std::vector<Pt> loop = {written(80, 0), first, pole, last, written(80, 30)};
  std::vector<OwnLon> own = {{kNaN, kNaN}, {10, 10}, {kNaN, kNaN}, {30, 30}, {kNaN, kNaN}};
  EXPECT_TRUE(merge_repeated_positions(loop, own));
  ASSERT_EQ(loop.size(), 3u);
  ASSERT_EQ(own.size(), 3u);
  EXPECT_EQ(loop[1].lon, 10);
  EXPECT_EQ(loop[1].v, last.v);
  EXPECT_EQ(own[1].in, 10);
  EXPECT_EQ(own[1].out, 30);
  EXPECT_TRUE(std::isnan(own[0].in) && std::isnan(own[2].out));

  // The same run across the loop's start: merged into the first point, its `in` the last's.
  loop = {pole, written(80, 0), written(80, 30), first};
  own = {{kNaN, 20}, {kNaN, kNaN}, {kNaN, kNaN}, {10, kNaN}};
  EXPECT_TRUE(merge_repeated_positions(loop, own));
  ASSERT_EQ(loop.size(), 3u);
  EXPECT_EQ(loop[0].v, first.v);
  EXPECT_EQ(own[0].in, 10);
  EXPECT_EQ(own[0].out, 20);
}

// The loop as the cyclic sequence of its positions from the one at (lon, lat).
std::vector<std::pair<double, double>> positions_from(const std::vector<Pt>& loop, double lon, double lat) {
  std::vector<std::pair<double, double>> out;
  std::size_t start = 0;
  while (start < loop.size() && !(loop[start].lon == lon && loop[start].lat == lat)) ++start;
  for (std::size_t i = 0; i < loop.size(); ++i) out.emplace_back(loop[(start + i) % loop.size()].lon, loop[(start + i) % loop.size()].lat);
  return out;
}

// A visit to the south pole line drawn down the meridian 20 and back up it: dropped where the
// region does not hold the pole, wherever the loop starts; its ends, at one position, merge.
TEST(DropPoleSpikes, DropsASpikeDownAMeridianAndBack) {
  using Positions = std::vector<std::pair<double, double>>;
  for (std::size_t start = 0; start < 6; ++start) {
    std::vector<Pt> loop = {written(-80, 0), written(-80, 20), written(-85, 20), on_pole_line(-90, 77),
                            written(-85, 20), written(-85, 0)};
    std::rotate(loop.begin(), loop.begin() + static_cast<std::ptrdiff_t>(start), loop.end());
    std::vector<OwnLon> own;
    drop_pole_spikes(loop, own, PoleOwner{-1, 0});
    EXPECT_EQ(positions_from(loop, 0, -80), (Positions{{0, -80}, {20, -80}, {20, -85}, {0, -85}})) << "start " << start;
  }
}

TEST(DropPoleSpikes, KeepsAnOwnersOnlyVisitAndAVisitAtItsOwnLongitude) {
  const std::vector<Pt> spiked = {written(-80, 0), written(-80, 20), written(-85, 20), on_pole_line(-90, 77),
                                  written(-88, 20), written(-88, 0)};
  std::vector<OwnLon> own;
  for (const int owns : {-1, 1}) {  // unknown, or the owner with no other visit to its pole
    std::vector<Pt> loop = spiked;
    drop_pole_spikes(loop, own, PoleOwner{-1, owns});
    EXPECT_EQ(loop.size(), 6u) << "owns " << owns;
  }
  std::vector<Pt> loop = spiked;
  drop_pole_spikes(loop, own, PoleOwner{-1, 0});
  EXPECT_EQ(loop.size(), 5u);
  // Drawn at its own longitude 77 (keep_lon), the visit is no spike down the meridian 20.
  loop = spiked;
  own.assign(loop.size(), OwnLon{kNaN, kNaN});
  own[3] = {77, 77};
  drop_pole_spikes(loop, own, PoleOwner{-1, 0});
  EXPECT_EQ(loop.size(), 6u);
  // The owner drops it when it has another visit to its pole (a run along the line).
  loop = spiked;
  loop.insert(loop.begin() + 5, {on_pole_line(-90, 20), on_pole_line(-90, 0)});
  own.clear();
  drop_pole_spikes(loop, own, PoleOwner{-1, 1});
  EXPECT_EQ(loop.size(), 7u);
  EXPECT_EQ(loop[3].lat, -88);
}

TEST(PinchLatitude, ThePoleVisitedTwice) {
  const Pt n = on_pole_line(90, 0), s = on_pole_line(-90, 0), a = written(0, 0), b = written(0, 90);
  EXPECT_EQ(pinch_latitude({a, n, b, n}), 90);
  EXPECT_EQ(pinch_latitude({a, s, n, b, s, n}), 90);
  EXPECT_EQ(pinch_latitude({a, s, n, b, s}), -90);
  EXPECT_EQ(pinch_latitude({a, s, b, n}), 0);
}

TEST(InOneSheet, TheUsualCellOnly) {
  EXPECT_TRUE(in_one_sheet({written(0, 0), written(0, 10), written(10, 10), written(10, 0)}));
  EXPECT_TRUE(in_one_sheet({written(0, -180), written(0, -170), written(10, -170), written(10, -180)}));
  // Across the antimeridian: a step of one sheet east (from 170 to -170).
  EXPECT_FALSE(in_one_sheet({written(0, 170), written(0, -170), written(10, -170), written(10, 170)}));
  // Every point on the antimeridian: written in sheet -1, at +180.
  EXPECT_FALSE(in_one_sheet({written(0, -180), written(10, -180), written(5, -180)}));
}

TEST(RunsBackAlongPoleLine, ASpanOver180DegreesAtAPoleNotHeld) {
  const Pt north = on_pole_line(90, 0), south = on_pole_line(-90, 0);
  // At the north pole the run goes west from `in` to `out`: from 10 to -100 spans 110 degrees,
  // from -100 to 10 spans 250.
  EXPECT_FALSE(runs_back_along_pole_line(north, 10, -100, 0));
  EXPECT_TRUE(runs_back_along_pole_line(north, -100, 10, 0));
  EXPECT_FALSE(runs_back_along_pole_line(north, -100, 10, 1));   // the owner keeps any span
  EXPECT_FALSE(runs_back_along_pole_line(north, -100, 10, -1));  // unknown owner
  // At the south pole it goes east.
  EXPECT_TRUE(runs_back_along_pole_line(south, 10, -100, 0));
  EXPECT_FALSE(runs_back_along_pole_line(south, -100, 10, 0));
  // The pole itself a vertex of the boundary: its angle is at most 180 degrees as computed.
  Pt pole = north;
  pole.v = {0, 0, 1};
  EXPECT_FALSE(runs_back_along_pole_line(pole, -100, 10, 0));
}

}  // namespace
}  // namespace geovor::lonlat
