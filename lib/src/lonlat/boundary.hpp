// Private to the lonlat module: great-circle boundaries on the sphere as RFC 7946 lon/lat rings
// and lines (gis.md sections 0, 1, 4 and 5). Shared by the Voronoi cells (cell_geometry.cpp) and
// the Delaunay triangles and edges (delaunay_geometry.cpp), so both follow one set of rules:
// adaptive great-circle densification, snapping to the poles and the antimeridian, the cut at
// +-180 and the closure of a ring around a pole.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "geovor/core/coordinate_grid.hpp"
#include "geovor/core/types.hpp"
#include "geovor/lonlat/geometry.hpp"

namespace geovor::lonlat {

/// Points within this angle (radians, 1.5e-11, about 0.1 mm) of a pole or of the antimeridian
/// are moved onto it (CellGeometry::kSnapRad).
inline constexpr double kSnapRad = 0x1p-36;

inline bool is_pole(double lat) { return lat == 90 || lat == -90; }
/// A point of the sphere exactly at a pole (snapped there: see make_pt).
inline bool at_pole(const Vec3& v) { return v.x == 0 && v.y == 0; }
inline Vec3 normalized(const Vec3& v) { return (1 / std::sqrt(norm2(v))) * v; }

/// A boundary point on the sphere and in geodetic lon/lat (degrees), snapped.
struct Pt {
  Vec3 v;
  double lon, lat;
};
/// The point of direction `raw`: v snapped to a pole or the antimeridian (kSnapRad), lon/lat as
/// written with `precision` decimals (snap_to_decimals; kFullPrecision: as computed), with the
/// antimeridian at lon -180 and a latitude of +-90 meaning the pole. v is not rounded: arcs
/// between points follow the sphere, positions are what the file holds.
Pt make_pt(const Vec3& raw, int precision = kFullPrecision);

/// Checks the Densifier's options. @exception Error(InvalidArgument) naming the one out of range:
/// densify_m not a positive number, max_step_deg outside (0, 180], max_depth outside [1, 40].
void check_densify_options(double densify_m, double max_step_deg, int max_depth);

/// Adaptive bisection of great-circle arcs: see CellGeometry's file comment, step 1.
class Densifier {
 public:
  /// densify_m: largest distance (metres on the sphere of radius kEarthRadiusM) between a
  /// straight lon/lat segment's midpoint and the arc; arcs longer than max_step_deg are always
  /// split; at most max_depth levels, except within metres of a pole, where pieces are split on
  /// (up to kMaxPoleDepth levels) until each is within an eighth of the distance to the pole of
  /// the nearest of its ends and midpoint, and near guards (set_guards), which bind past
  /// max_depth too, except within a step of a pole.
  /// Points are appended to `out`.
  /// Positions are written with `precision` decimals (make_pt).
  Densifier(double densify_m, double max_step_deg, int max_depth, std::vector<Pt>& out,
            int precision = kFullPrecision);

  /// Appends the points strictly between a and b of the arc a -> b, which turns positively about
  /// the axis normalize(left - right). The axis is only used for arcs longer than 120 degrees,
  /// where a + b cannot be used. `site_chord2` bounds the tolerance: at most a quarter of its
  /// square root (pass +infinity for no bound).
  void edge(const Pt& a, const Pt& b, const Vec3& left, const Vec3& right, double site_chord2);

  /// Unit normals of great circles that the next edges' written chords must keep clear of (the
  /// other sides of a thin cell): a piece is also split while its midpoint's deviation exceeds
  /// an eighth of the midpoint's distance to any of them, so that two chords, each within a
  /// quarter of their distance, cannot cross; past max_depth too (up to kMaxPoleDepth levels),
  /// but there they add no point within a step of a pole (of the output's decimals, at most
  /// CellGeometry::kThinCellDecimals), which would be written on the pole line or its first row.
  /// `normals` must outlive the calls; empty: none.
  void set_guards(std::span<const Vec3> normals) { guards_ = normals; }

 private:
  const Vec3& axis();
  Vec3 midpoint(const Vec3& a, const Vec3& b);
  void split(const Pt& a, const Pt& b, int depth);
  /// Whether a piece a -> b with great-circle midpoint m, whose straight lon/lat midpoint lies
  /// sqrt(dev2) from m, is within an eighth of its distance to the pole (at the nearest of a, b
  /// and m) and of the midpoint's distance to every guard.
  bool clear_of_pole_and_guards(const Vec3& a, const Vec3& b, const Vec3& m, double dev2) const;

  static constexpr int kMaxPoleDepth = 64;
  static constexpr double kMinPieceRad = 0x1p-40;  // 6 micrometres: no piece is split below
  std::vector<Pt>& out_;
  double tol2_, cos_step_;
  int max_depth_;
  int precision_;
  const Vec3* left_ = nullptr;
  const Vec3* right_ = nullptr;
  bool have_axis_ = false;
  Vec3 axis_;
  double edge_tol2_ = 0;
  double pole_row2_;  // squared step of the thin cells' grid (radians): within it of a pole, its first row
  std::span<const Vec3> guards_;
};

/// The closed boundary `loop` (densified, without repeating its first point) of a region on the
/// sphere that lies on its left (counter-clockwise seen from outside) and is convex, or holds
/// exactly one pole, as a MultiPolygon: cut at the antimeridian, closed through (+-180, +-90)
/// around a pole, rings counter-clockwise and closed by an exact copy. `loop` is modified
/// (consecutive duplicates dropped). An empty result means a degenerate loop. The points' lon/lat
/// must already be written with `precision` decimals; the antimeridian crossings are too.
/// `info`, if given, gets the ring's winding: +1 when it encloses the north pole, -1 the south
/// pole, 0 when it encloses neither (a pole on the ring is not enclosed; for a loop pinched at a
/// pole, below, the sum over its parts, of which one at most may enclose a pole); and whether a point of
/// the loop lies within 0.01 degree of a pole, where longitudes are ill-conditioned.
/// `pole_owner` says, when known, whether the region holds each pole in its interior (1), not
/// (0), or unknown (-1): a region that does not hold the pole and spans more than 180 degrees
/// of longitude at a point of the loop drawn at it runs the short way back along the pole line
/// there (a spike on the line, cancelled by its other run, or removed when cleaning). When it is
/// known, a loop drawn at one pole more than once is pinched there: the parts between its runs
/// at that pole become rings of their own, each closed by one run along the pole line.
/// `keep_lon`: the indices in `loop` of points written on a pole line but not at the pole that
/// are drawn at their own longitudes, the ends of a run there that starts or ends at one of them
/// too (CellGeometry sets them only where every ring through the point does); a region holding
/// that pole whose only visit there is such a point (not a spike down a meridian and back) runs
/// a whole turn along the line from it when its ring would otherwise wind around the pole.
struct PoleOwner {
  int north = -1, south = -1;
};
struct LoopInfo {
  int winding = 0;
  bool near_pole = false;
  /// The rounded loop winds around a pole more than once: no ring, nothing was written.
  bool tangled = false;
};
void loop_to_polygons(std::vector<Pt>& loop, MultiPolygon& out, BBox* bbox = nullptr,
                      int precision = kFullPrecision, LoopInfo* info = nullptr, PoleOwner pole_owner = {},
                      std::span<const std::uint32_t> keep_lon = {});

/// The stages of loop_to_polygons that are pure functions of the loop, here for their tests.
/// The longitudes at which a visit to a pole line (a run of points there, merged into one) is
/// drawn when its first or last point is in keep_lon: that point's own (NaN: the neighbour's
/// meridian, the rule of a vertex at the pole). An empty list of them: no keep_lon in the loop.
struct OwnLon {
  double in, out;
};
/// Drops consecutive duplicates in lon/lat (cyclically), and consecutive points at one pole
/// whatever their longitudes (one point of the sphere: rounding puts runs of points there); `own`
/// (empty, or one per point) follows. Returns whether a point was within 0.01 degree of a pole.
bool merge_repeated_positions(std::vector<Pt>& loop, std::vector<OwnLon>& own);
/// Drops the points at a pole drawn down a meridian and back up it (no area, no run along the
/// pole line: a boundary passing within a step of the pole), where the region does not hold the
/// pole, or holds it with another visit there; left in, such a spike was a second visit, and the
/// loop was pinched there into parts sharing the meridian (fuzz_cells). REQUIRES: loop.size() > 3.
void drop_pole_spikes(std::vector<Pt>& loop, std::vector<OwnLon>& own, PoleOwner pole_owner);
/// The pole (latitude 90 or -90; 0: none) the loop visits more than once, the north pole first:
/// there the region is pinched into parts, each closed by one run along the pole line.
double pinch_latitude(const std::vector<Pt>& loop);
/// Whether every step of the loop stays within one sheet of longitudes and not every point is
/// on the antimeridian: the usual cell, whose ring is the loop itself.
bool in_one_sheet(const std::vector<Pt>& loop);
/// Whether a vertex p at a pole, drawn from longitude `in` to `out` there, runs the short way
/// back along the pole line: the region does not hold the pole (owns == 0; -1: unknown, 1: it
/// does) and its span there exceeds 180 degrees, which is then rounding, and p is not the pole
/// itself (whose angle is at most 180 degrees). See loop_to_polygons' pole_owner.
bool runs_back_along_pole_line(const Pt& p, double in, double out, int owns);

/// An open path (densified) as lines: cut at the antimeridian (both parts end on it at the same
/// latitude, at +180 and -180) and at a pole it passes through; parts of fewer than two distinct
/// positions are dropped. Crossing latitudes are written with `precision` decimals.
void path_to_lines(const std::vector<Pt>& path, MultiLineString& out, int precision = kFullPrecision);

}  // namespace geovor::lonlat
