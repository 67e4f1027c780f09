#include "lonlat/boundary.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <type_traits>

#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/kernel/predicates.hpp"
#include "geovor/lonlat/cell_geometry.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace geovor::lonlat {
namespace {

constexpr double kDeg = std::numbers::pi / 180;
// WGS84 first eccentricity squared e^2 = f (2 - f): geodetic -> geocentric direction.
constexpr double kFlattening = 1 / 298.257223563;
constexpr double kE2 = kFlattening * (2 - kFlattening);
constexpr double kSnap2 = kSnapRad * kSnapRad;

// Moves a point within kSnapRad of a pole onto it, and one within kSnapRad of the antimeridian
// onto it (y = +0: to_lat_lon then gives exactly -180), so rounding never decides a side.
Vec3 snap(Vec3 v) {
  const double h2 = v.x * v.x + v.y * v.y;
  const double r2 = h2 + v.z * v.z;
  if (h2 <= kSnap2 * r2) return {0, 0, v.z > 0 ? 1.0 : -1.0};
  if (v.x < 0 && v.y * v.y <= kSnap2 * r2) v.y = 0;
  return v;
}

// Geocentric direction (unnormalised) of a geodetic position at height 0.
Vec3 geodetic_direction(double lon_deg, double lat_deg) {
  const double phi = lat_deg * kDeg, lam = lon_deg * kDeg;
  const double cp = std::cos(phi);
  return {cp * std::cos(lam), cp * std::sin(lam), (1 - kE2) * std::sin(phi)};
}

// The direction of the point halfway in longitude (the short way) and in geodetic latitude
// between a and b, as normalized(geodetic_direction(mid lon, mid lat)) but by bisecting the
// angles' (cos, sin) pairs, without trigonometry: v is proportional to (cos lat cos lon,
// cos lat sin lon, (1 - e²) sin lat). Neither a nor b is a pole.
Vec3 lonlat_midpoint(const Pt& a, const Pt& b) {
  const double ra = std::sqrt(a.v.x * a.v.x + a.v.y * a.v.y), rb = std::sqrt(b.v.x * b.v.x + b.v.y * b.v.y);
  // Longitudes: (x, y) / rho; their bisector is the short way's midpoint (up to 180 apart).
  double cl = a.v.x / ra + b.v.x / rb, sl = a.v.y / ra + b.v.y / rb;
  const double nl = std::sqrt(cl * cl + sl * sl);
  // Latitudes: ((1 - e²) rho, z) / norm, in the right half-plane, 180 degrees apart at most.
  const double ua = (1 - kE2) * ra, ub = (1 - kE2) * rb;
  const double ha = std::sqrt(ua * ua + a.v.z * a.v.z), hb = std::sqrt(ub * ub + b.v.z * b.v.z);
  double cp = ua / ha + ub / hb, sp = a.v.z / ha + b.v.z / hb;
  const double np = std::sqrt(cp * cp + sp * sp);
  if (!(nl > 1e-3) || !(np > 1e-3)) {  // about 180 degrees apart: the bisector is undefined
    double dl = b.lon - a.lon;
    if (dl > 180) dl -= 360;
    if (dl < -180) dl += 360;
    return normalized(geodetic_direction(a.lon + dl / 2, (a.lat + b.lat) / 2));
  }
  cl /= nl, sl /= nl, cp /= np, sp /= np;
  return normalized(Vec3{cp * cl, cp * sl, (1 - kE2) * sp});
}

// A ring position with its sheet: the unwrapped longitude is lon + 360 k, with lon in
// [-180, 180) as to_lat_lon gives it (on the antimeridian, lon = -180 exactly).
struct RP {
  Vec3 v;
  double lon, lat;
  int k;
  bool back = false;  // reached along a pole line the short way back (see loop_to_polygons)
  bool full = false;  // reached along a pole line after a whole turn (the owner's, see loop_to_polygons)
};

// The step of sheet from p to q, neither of them on a pole line: -1, 0 or 1 (exact).
int sheet_step(const Vec3& pv, double plon, const Vec3& qv, double qlon) {
  const double d = qlon - plon;
  if (std::fabs(d) > 90) {
    // Only near a pole (or across the antimeridian) do longitudes jump this far, and then the
    // difference is ill-conditioned near 180 degrees. Along an arc that does not pass through a
    // pole, the longitude moves monotonically, east exactly when the north pole lies on the
    // arc's left: decided exactly on the sphere points.
    const Sign side = kernel::orient(pv, qv, Vec3{0, 0, 1});
    if (side == Sign::Positive) return d < 0 ? 1 : 0;
    if (side == Sign::Negative) return d > 0 ? -1 : 0;
  }
  return d > 180 ? -1 : d < -180 ? 1 : 0;
}

// Sheet of q after p along the ring (exact: integer steps and comparisons only).
int next_sheet(const RP& p, const RP& q) {
  if (q.full) return p.lat > 0 ? p.k - 1 : p.k + 1;  // west along the north pole's line, east along the south's
  if (is_pole(p.lat) && p.lat == q.lat) {
    // Along a pole from the incoming meridian a = p.lon to the outgoing b = q.lon: the cell's
    // wedge at the pole is (a - b) mod 360 at the north pole (longitude decreases, interior on
    // the left), (b - a) mod 360 at the south pole.
    // Taken back (q.back), the run goes the other way: east at the north pole, west at the south.
    if (p.lat > 0) return q.back ? (q.lon < p.lon ? p.k + 1 : p.k) : (q.lon > p.lon ? p.k - 1 : p.k);
    return q.back ? (q.lon > p.lon ? p.k - 1 : p.k) : (q.lon < p.lon ? p.k + 1 : p.k);
  }
  if (!is_pole(p.lat) && !is_pole(q.lat)) return p.k + sheet_step(p.v, p.lon, q.v, q.lon);
  const double d = q.lon - p.lon;
  if (d > 180) return p.k - 1;
  if (d < -180) return p.k + 1;
  return p.k;
}

// Intersection of the segment p -> q with the antimeridian, as the ring position (-180, lat)
// in sheet k. The latitude is that of the great-circle arc between the two sphere points, the
// same bits whichever way the segment runs (|q.y| p + |p.y| q is symmetric and has y = 0).
RP crossing(const RP& p, const RP& q, int k, int precision) {
  if (is_pole(p.lat) && is_pole(q.lat)) return {p.v, -180, p.lat, k};
  const Vec3 c = std::fabs(q.v.y) * p.v + std::fabs(p.v.y) * q.v;
  return {c, -180, snap_to_decimals(SiteEncoder::to_lat_lon(c).lat_deg, precision), k};
}

// Sides of p (-1, 0 on the line, 1) for the strip [-180, 180] of sheet j: >= 0 east of its west
// edge (unwrapped -180 + 360 j), and >= 0 west of its east edge (180 + 360 j). Exact.
int side_of_west_edge(const RP& p, int j) {
  if (p.k != j) return p.k > j ? 1 : -1;
  return p.lon == -180 ? 0 : 1;
}
int side_of_east_edge(const RP& p, int j) {
  if (p.k <= j) return 1;
  return p.k == j + 1 && p.lon == -180 ? 0 : -1;
}

// Sutherland-Hodgman against one half-plane of the strip of sheet j (kept: side >= 0), whose
// boundary is the antimeridian in sheet `line`. The ring crosses it at most twice (cells are
// convex on the sphere), so the result is one ring.
void clip_half(const std::vector<RP>& in, std::vector<RP>& out, int (*side)(const RP&, int), int j,
               int line, int precision) {
  out.clear();
  const std::size_t n = in.size();
  for (std::size_t i = 0; i < n; ++i) {
    const RP& p = in[i == 0 ? n - 1 : i - 1];
    const RP& q = in[i];
    const int sp = side(p, j), sq = side(q, j);
    if (sq >= 0) {
      if (sp < 0 && sq > 0) out.push_back(crossing(p, q, line, precision));
      out.push_back(q);
    } else if (sp > 0) {
      out.push_back(crossing(p, q, line, precision));
    }
  }
}

struct Scratch {
  std::vector<RP> ring, tmp, piece;
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// The box of polygons: latitudes from their positions; longitudes all (a polar ring), of the
// one polygon, or of pieces cut at the antimeridian, which come west to east by sheet (the first
// ends at 180, the last starts at -180).
enum class Lons { All, One, Cut };
BBox box_of(const MultiPolygon& out, Lons lons) {
  BBox b{180, 90, -180, -90};
  for (const Polygon& poly : out)
    for (const LonLat& p : poly.exterior) {
      b.south = std::min(b.south, p.lat_deg);
      b.north = std::max(b.north, p.lat_deg);
    }
  auto lon_range = [](const Polygon& poly, double& lo, double& hi) {
    lo = 180, hi = -180;
    for (const LonLat& p : poly.exterior) {
      lo = std::min(lo, p.lon_deg);
      hi = std::max(hi, p.lon_deg);
    }
  };
  double lo, hi;
  switch (lons) {
    case Lons::All:
      b.west = -180, b.east = 180;
      break;
    case Lons::One:
      lon_range(out[0], b.west, b.east);
      break;
    case Lons::Cut:
      lon_range(out.front(), b.west, hi);
      lon_range(out.back(), lo, b.east);
      break;
  }
  return b;
}

// Closes `pts` (lon/lat, already in [-180, 180]) into a ring: no consecutive duplicates, exact
// copy of the first position at the end, counter-clockwise. Returns false if degenerate.
// distinct: no two consecutive positions are equal already, cyclically.
bool finish_ring(Ring& ring, bool distinct) {
  std::size_t w = ring.size();
  if (!distinct) {
    w = 0;
    for (std::size_t i = 0; i < ring.size(); ++i)
      if (w == 0 || !(ring[i] == ring[w - 1])) ring[w++] = ring[i];
    while (w > 1 && ring[w - 1] == ring[0]) --w;
    ring.resize(w);
  }
  if (w < 3) return false;
  ring.push_back(ring[0]);
  const double a = planar_area_deg2(ring);
  if (a == 0 || std::isnan(a)) return false;
  if (a < 0) std::reverse(ring.begin(), ring.end());
  return true;
}

// Appends the ring of `pts` written in sheet `sheet` (p.k of each point: its own sheet, 0 for
// a Pt) to out[used], the next polygon, counted when it is not degenerate (finish_ring).
template <typename P>
void append_piece(MultiPolygon& out, std::size_t& used, const std::vector<P>& pts, int sheet) {
  if (out.size() <= used) out.emplace_back();
  Polygon& poly = out[used];
  poly.holes.clear();
  Ring& r = poly.exterior;
  r.resize(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    int k = 0;
    if constexpr (std::is_same_v<P, RP>) k = pts[i].k;
    // Only the antimeridian (lon -180 one sheet up) may leave [-180, 180); clamp rounding noise.
    r[i] = {std::clamp(pts[i].lon + 360.0 * (k - sheet), -180.0, 180.0), pts[i].lat};
  }
  // A loop of Pt (polygons_of's usual cell) has no equal neighbours left, and is written as it is.
  if (finish_ring(r, std::is_same_v<P, Pt>)) ++used;
}

}  // namespace

Pt make_pt(const Vec3& raw, int precision) {
  const Vec3 v = snap(raw);
  const LatLon ll = SiteEncoder::to_lat_lon(v);
  if (precision < 0) return {v, ll.lon_deg, ll.lat_deg};
  double lon = snap_to_decimals(ll.lon_deg, precision);
  if (lon == 180) lon = -180;  // the antimeridian's canonical longitude, as to_lat_lon gives it
  return {v, lon, snap_to_decimals(ll.lat_deg, precision)};
}

void check_densify_options(double densify_m, double max_step_deg, int max_depth) {
  if (!(densify_m > 0) || !std::isfinite(densify_m))
    throw Error(ErrorCode::InvalidArgument, "densify_m must be a positive number of metres");
  if (!(max_step_deg > 0) || !(max_step_deg <= 180))
    throw Error(ErrorCode::InvalidArgument, "max_step_deg must be in (0, 180]");
  if (max_depth < 1 || max_depth > 40) throw Error(ErrorCode::InvalidArgument, "max_depth must be in [1, 40]");
}

Densifier::Densifier(double densify_m, double max_step_deg, int max_depth, std::vector<Pt>& out,
                     int precision)
    : out_(out),
      tol2_(std::pow(densify_m / SiteEncoder::kEarthRadiusM, 2)),
      cos_step_(std::cos(max_step_deg * kDeg)),
      max_depth_(max_depth),
      precision_(precision) {
  // A step of the grid a thin cell is written on (CellGeometry's snap rounding), as an angle.
  pole_row2_ = std::pow(std::pow(10.0, -CellGeometry::thin_cell_decimals(precision)) * kDeg, 2);
}

void Densifier::edge(const Pt& a, const Pt& b, const Vec3& left, const Vec3& right, double site_chord2) {
  left_ = &left;
  right_ = &right;
  have_axis_ = false;
  // Both sites, at half their distance from the arc, stay inside their written cells.
  edge_tol2_ = std::min(tol2_, site_chord2 / 16);
  if (a.v == b.v) return;
  if (!at_pole(a.v) && !at_pole(b.v)) {
    // An arc passing within kSnapRad of a pole gets the pole as a vertex, so that the
    // longitude jump of about 180 degrees is decided by the pole rule, not by rounding.
    // Most arcs are nowhere near a pole: ruled out without the square root (the margin keeps
    // every arc the exact test below could accept).
    const Vec3 c = cross(a.v, b.v);
    const bool short_arc = dot(a.v, b.v) > -0.5;
    const bool far = short_arc && c.z * c.z > 4 * kSnapRad * kSnapRad * norm2(c);
    const Vec3 n = far ? Vec3{} : short_arc ? normalized(c) : axis();
    if (!far && std::fabs(n.z) <= kSnapRad) {
      for (const double pz : {1.0, -1.0}) {
        // Closest point of the arc's great circle to the pole (0, 0, pz).
        const Vec3 q = normalized({-pz * n.z * n.x, -pz * n.z * n.y, pz * (1 - n.z * n.z)});
        if (dot(cross(a.v, q), n) >= 0 && dot(cross(q, b.v), n) >= 0) {
          const Pt p = make_pt({0, 0, pz}, precision_);
          split(a, p, 1);
          out_.push_back(p);
          split(p, b, 1);
          return;
        }
      }
    }
  }
  split(a, b, 0);
}


const Vec3& Densifier::axis() {
  if (!have_axis_) {
    axis_ = normalized(*left_ - *right_);
    have_axis_ = true;
  }
  return axis_;
}

Vec3 Densifier::midpoint(const Vec3& a, const Vec3& b) {
  return dot(a, b) > -0.5 ? normalized(a + b) : VoronoiDiagram::arc_midpoint(a, b, axis());
}

namespace {

// The squared distance to the pole axis of the nearest of a piece's ends and midpoint: the chord
// turns fastest in lon/lat at the end nearer the pole, so the midpoint alone can pass a piece whose
// chord there spans tens of degrees of longitude a few centimetres from the pole.
double to_pole2(const Vec3& a, const Vec3& b, const Vec3& m) {
  return std::min({a.x * a.x + a.y * a.y, b.x * b.x + b.y * b.y, m.x * m.x + m.y * m.y});
}

}  // namespace

bool Densifier::clear_of_pole_and_guards(const Vec3& a, const Vec3& b, const Vec3& m, double dev2) const {
  // Within a few hundred metres of a pole, within an eighth of the distance to it: there a
  // straight lon/lat segment is a circle of latitude, and one spanning 90 degrees of longitude
  // 100 m from the pole crossed its neighbours (lunes of sites near the equator, their tips
  // metres from the pole).
  if (64 * dev2 > to_pole2(a, b, m)) return false;
  for (const Vec3& g : guards_) {
    const double h = dot(m, g);
    if (64 * dev2 > h * h) return false;
  }
  return true;
}

void Densifier::split(const Pt& a, const Pt& b, int depth) {
  // Not below kMinPieceRad: the copies of one Voronoi vertex (co-circular sites) are joined by
  // edges nanometres long, which the guards below would split to max_depth (2^20 points each:
  // a 7 x 7 grid on a pole took 17 s and 1.3 GB).
  if (norm2(a.v - b.v) < kMinPieceRad * kMinPieceRad) return;
  // Past max_depth only the pole rule and the guards below split on: a side of a lune from pole
  // to pole reaches max_depth at pieces of 19 m, and a vertex centimetres from the pole is then
  // joined by a straight lon/lat segment spanning 20 degrees of longitude (a ring of sites 1.5 m
  // around the other pole: two cells unwritable). It ends by itself once a piece is within an
  // eighth of its distance to the pole, however close (an arc within kSnapRad gets the pole as a
  // vertex): points written on the pole line are runs there, which the pole rules and the pinch
  // of loop_to_polygons close. Stopping two steps short of the pole left chords spanning tens of
  // degrees of longitude there, which crossed (docs/design.md, the poles). The guards keep
  // splitting too: within the pole rule's eighth, a chord metres from the pole still bulges by
  // decimetres, and a thin cell's other side there can be centimetres away (a lune's tip 1.8 m
  // from the pole, its sides 1 cm apart at the tip: a chord past max_depth, 19 degrees of
  // longitude, crossed the other side's; fuzz_cells). They end as well: a guard's distance grows
  // linearly from a common vertex, a chord's deviation quadratically with its length.
  // kMaxPoleDepth only guards against a bug.
  const bool past = depth >= max_depth_;
  if (past && depth >= kMaxPoleDepth) return;
  // On the sphere: a point merely written at a pole (within a decimal step of it) is not one,
  // and an arc from it is no meridian.
  const bool pa = at_pole(a.v), pb = at_pole(b.v);
  Vec3 m;
  if (past) {
    if (pa || pb) return;
    m = midpoint(a.v, b.v);
    const double dev2 = norm2(m - lonlat_midpoint(a, b));
    // The guards add no point within a step of the pole (pole_row2_): it would be written on
    // the pole line or its first row, where the written path is the pole rules' (meridians to
    // the pole line, runs along it), whatever the chord. A ring of 19 sites around the south
    // pole at 7 decimals has a lune's tip 5 mm from the north pole, written on the pole line;
    // guarded, the first piece of its other side, 5 to 14 mm out, gave a point written on the
    // first row 0.014 degrees east of the meridian on which its first side reached the pole
    // line, across that side (unwritable at 7 decimals; fuzz_cells).
    if (m.x * m.x + m.y * m.y <= pole_row2_ ? 64 * dev2 <= to_pole2(a.v, b.v, m)
                                             : clear_of_pole_and_guards(a.v, b.v, m, dev2))
      return;
  } else if (pa || pb) {
    // From a pole the arc is a meridian, straight in lon/lat. Pole to pole (N to S) needs a
    // midpoint, which gives the meridian its longitude; so does an arc from a pole to a point
    // near the other pole (longer than 120 degrees), whose own longitude is ill-conditioned:
    // the arc's axis gives the midpoint.
    if (pa && pb && a.v.z == b.v.z) return;
    if (!(pa && pb) && dot(a.v, b.v) > -0.5) return;
    m = midpoint(a.v, b.v);
  } else {
    m = midpoint(a.v, b.v);
    if (dot(a.v, b.v) >= cos_step_) {
      // Great-circle midpoint against the midpoint of the straight lon/lat segment.
      const double dev2 = norm2(m - lonlat_midpoint(a, b));
      if (dev2 <= edge_tol2_ && clear_of_pole_and_guards(a.v, b.v, m, dev2)) return;
    }
  }
  const Pt mp = make_pt(m, precision_);
  split(a, mp, depth + 1);
  out_.push_back(mp);
  split(mp, b, depth + 1);
}

namespace {

void polygons_of(std::vector<Pt>& loop, std::vector<OwnLon>& own, MultiPolygon& out, BBox* bbox, int precision,
                 LoopInfo* info, PoleOwner pole_owner);

}  // namespace

void loop_to_polygons(std::vector<Pt>& loop, MultiPolygon& out, BBox* bbox, int precision, LoopInfo* info,
                      PoleOwner pole_owner, std::span<const std::uint32_t> keep_lon) {
  thread_local std::vector<OwnLon> own;
  own.clear();
  if (!keep_lon.empty()) {
    constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    own.assign(loop.size(), OwnLon{kNone, kNone});
    for (const std::uint32_t i : keep_lon) own[i] = {loop[i].lon, loop[i].lon};
  }
  polygons_of(loop, own, out, bbox, precision, info, pole_owner);
}

bool merge_repeated_positions(std::vector<Pt>& loop, std::vector<OwnLon>& own) {
  const bool has_own = !own.empty();
  bool near_pole = false;  // a point within 0.01 degree of a pole
  auto same = [](const Pt& a, const Pt& b) { return a.lat == b.lat && (a.lon == b.lon || is_pole(a.lat)); };
  // A run at a pole keeps the sphere point of one merely rounded there, if it has one: at_pole(v)
  // then says that the pole itself is a vertex of the boundary, with its true angle there.
  auto merge = [](Pt& kept, const Pt& dropped) {
    if (is_pole(kept.lat) && !at_pole(dropped.v)) kept.v = dropped.v;
  };
  // A merged run is drawn from its first point's own longitude to its last point's.
  std::size_t w = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    near_pole |= std::fabs(loop[i].lat) > 89.99;
    if (w == 0 || !same(loop[i], loop[w - 1])) {
      if (has_own) own[w] = own[i];
      loop[w++] = loop[i];
    } else {
      merge(loop[w - 1], loop[i]);
      if (has_own) own[w - 1].out = own[i].out;
    }
  }
  while (w > 1 && same(loop[w - 1], loop[0])) {
    merge(loop[0], loop[w - 1]);
    if (has_own) own[0].in = own[w - 1].in;
    --w;
  }
  loop.resize(w);
  if (has_own) own.resize(w);
  return near_pole;
}

namespace {

// Whether loop[p], at a pole, is drawn down the meridian of loop[a] and back up it to loop[b]:
// no area and no run along the pole line. A visit drawn at a point's own longitude (keep_lon) is
// one only when that is the meridian's.
bool drawn_down_and_up(const std::vector<Pt>& loop, const std::vector<OwnLon>& own, std::size_t a, std::size_t p,
                       std::size_t b) {
  return is_pole(loop[p].lat) && !is_pole(loop[a].lat) && !is_pole(loop[b].lat) && loop[a].lon == loop[b].lon &&
         (own.empty() || ((std::isnan(own[p].in) || own[p].in == loop[a].lon) &&
                          (std::isnan(own[p].out) || own[p].out == loop[a].lon)));
}

// Which poles' spikes drop_pole_spikes drops (north, south): its own rule, applied alike to every
// point, so that the passes along the loop and across its start agree.
struct SpikeRule {
  bool drop[2];
  bool operator()(const std::vector<Pt>& loop, const std::vector<OwnLon>& own, std::size_t a, std::size_t p,
                  std::size_t b) const {
    return drawn_down_and_up(loop, own, a, p, b) && drop[loop[p].lat > 0 ? 0 : 1];
  }
};

// The pass of drop_pole_spikes along the loop, in place: ends of a dropped spike at one position
// merge, which can expose another spike.
void drop_spikes_along(std::vector<Pt>& loop, std::vector<OwnLon>& own, SpikeRule spike) {
  const bool has_own = !own.empty();
  auto copy = [&](std::size_t to, std::size_t from) {
    loop[to] = loop[from];
    if (has_own) own[to] = own[from];
  };
  std::size_t w = 0;
  for (std::size_t i = 0; i < loop.size(); ++i) {
    copy(w++, i);
    while (w >= 3 && spike(loop, own, w - 3, w - 2, w - 1)) {
      copy(w - 2, w - 1);
      --w;
      if (loop[w - 1].lon == loop[w - 2].lon && loop[w - 1].lat == loop[w - 2].lat) --w;
    }
  }
  loop.resize(w);
  if (has_own) own.resize(w);
}

// The pass of drop_pole_spikes across the loop's start (at most a few: each pass drops a point).
void drop_spikes_across_start(std::vector<Pt>& loop, std::vector<OwnLon>& own, SpikeRule spike) {
  const bool has_own = !own.empty();
  auto erase = [&](std::size_t i) {
    loop.erase(loop.begin() + static_cast<std::ptrdiff_t>(i));
    if (has_own) own.erase(own.begin() + static_cast<std::ptrdiff_t>(i));
  };
  for (bool dropped = true; dropped && loop.size() > 3;) {
    dropped = false;
    const std::size_t n = loop.size();
    for (const std::size_t i : {std::size_t{0}, n - 1}) {
      if (!spike(loop, own, (i + n - 1) % n, i, (i + 1) % n)) continue;
      erase(i);
      const std::size_t m = loop.size(), j = i % m;  // the spike's ends: j - 1 and j, cyclically
      const Pt &a = loop[(j + m - 1) % m], &b = loop[j];
      if (a.lon == b.lon && a.lat == b.lat) erase(j);
      dropped = true;
      break;
    }
  }
}

}  // namespace

// A point at a pole the site does not own, between two points off the poles on one meridian,
// is a spike to the pole line and back up that meridian (a boundary passing within a step of
// the pole, drawn at it): no area and no run along the pole line, so it is dropped, as
// remove_spikes would drop it. Left in, it was a second visit to the pole, and the pinch
// (write_pinched) cut the ring there into two parts sharing that meridian (0 decimals,
// fuzz_cells). A visit drawn at a point's own longitude (keep_lon) is a spike only when that is
// the meridian's.
void drop_pole_spikes(std::vector<Pt>& loop, std::vector<OwnLon>& own, PoleOwner pole_owner) {
  // The owner's too, when it has another visit to that pole (a run along the line): its region
  // lies on both sides of the spike, a neighbour's tip collapsed onto that meridian. Pinched
  // there, the two parts shared the meridian's segment (clusters a metre from the south pole,
  // 0 decimals: fuzz_cells).
  bool other_visit[2] = {false, false};  // north, south
  for (std::size_t i = 0, n = loop.size(); i < n; ++i)
    if (is_pole(loop[i].lat) && !drawn_down_and_up(loop, own, (i + n - 1) % n, i, (i + 1) % n))
      other_visit[loop[i].lat > 0 ? 0 : 1] = true;
  SpikeRule spike;
  spike.drop[0] = pole_owner.north == 0 || (pole_owner.north == 1 && other_visit[0]);
  spike.drop[1] = pole_owner.south == 0 || (pole_owner.south == 1 && other_visit[1]);
  drop_spikes_along(loop, own, spike);
  drop_spikes_across_start(loop, own, spike);
}

double pinch_latitude(const std::vector<Pt>& loop) {
  std::size_t runs[2] = {0, 0};  // north, south
  for (const Pt& p : loop)
    if (is_pole(p.lat)) ++runs[p.lat > 0 ? 0 : 1];
  return runs[0] >= 2 ? 90 : runs[1] >= 2 ? -90 : 0;
}

bool in_one_sheet(const std::vector<Pt>& loop) {
  bool one_sheet = true, off_antimeridian = false;
  for (std::size_t i = 0, n = loop.size(); one_sheet && i < n; ++i) {
    const Pt &p = loop[i], &q = loop[i + 1 == n ? 0 : i + 1];
    one_sheet = sheet_step(p.v, p.lon, q.v, q.lon) == 0;
    off_antimeridian |= p.lon != -180;
  }
  return one_sheet && off_antimeridian;  // else the sheet of the whole ring is -1
}

// The ring runs west along the north pole's line (east along the south's) from the incoming
// meridian to the outgoing one: that span is the region's angle at the pole. When the caller
// knows that the region does not hold the pole, a span over 180 degrees is rounding (a
// boundary passing within a decimal step of the pole, drawn at it, with the region on the
// side away from the pole): the ring then runs the short way back along the pole line, the
// reverse of its neighbour's run there, and cancels against its own run along the pole line
// on the side nearer the pole (lunes passing the pole within a step: both runs are spikes
// on the line, removed alike on both sides). Only touching the pole there had drawn a chord
// where the neighbour ran along the pole line. The owner keeps any span: its cell may hold
// the pole by an ulp, with a vertex of its neighbours at the pole within rounding, each
// taking its own wedge (sites on one latitude, one of them an ulp higher: dropping its wedge
// left a gap). So does a cell whose boundary has the pole itself as a vertex: its angle there
// is at most 180 degrees, one over it is the rounding of its neighbours' longitudes (two
// sites of equal z, the pole on their bisector: each cell's wedge is 180 degrees, one of them
// just over it as written), and taken back it had wound around the pole (fuzz_cells).
bool runs_back_along_pole_line(const Pt& p, double in, double out, int owns) {
  const double span = std::fmod((p.lat > 0 ? in - out : out - in) + 720.0, 360.0);
  return owns == 0 && span > 180 && !at_pole(p.v);
}

namespace {

// A boundary drawn at one pole more than once (a region passing within a step of the pole on
// several sides, or holding it with its boundary there on several sides): its runs along the
// pole line would overlap (one turn each way, or a second turn for the owner). The pole is one
// point of the sphere, so the region is pinched there.
// The parts of a loop pinched at the pole of latitude split_lat (pinch_latitude), each between
// consecutive runs there and closed by one run along the pole line, into `out` (polygons_of's
// results, with its info and bbox for the whole).
void write_pinched(const std::vector<Pt>& loop, const std::vector<OwnLon>& own, double split_lat, bool near_pole,
                   MultiPolygon& out, BBox* bbox, int precision, LoopInfo* info, PoleOwner pole_owner) {
  const bool has_own = !own.empty();
  const std::size_t n = loop.size();
  std::size_t first = 0;
  while (loop[first].lat != split_lat) ++first;
  LoopInfo whole;
  whole.near_pole = near_pole;
  int enclosing = 0;  // parts around a pole: one at most (the other pole's), else rounding
  MultiPolygon parts_out;
  std::vector<Pt> part;
  std::vector<OwnLon> part_own;
  out.clear();
  for (std::size_t a = first;;) {
    std::size_t b = (a + 1) % n;
    while (loop[b].lat != split_lat) b = (b + 1) % n;
    part.clear();
    part_own.clear();
    for (std::size_t i = (a + 1) % n; i != b; i = (i + 1) % n) {
      part.push_back(loop[i]);
      if (has_own) part_own.push_back(own[i]);
    }
    // Closed at the pole from b's run to a's: in where b's starts, out where a's ends.
    part.push_back(loop[b]);
    if (has_own) part_own.push_back({own[b].in, own[a].out});
    LoopInfo part_info;
    polygons_of(part, part_own, parts_out, nullptr, precision, &part_info, pole_owner);
    whole.winding += part_info.winding;
    whole.tangled |= part_info.tangled;
    enclosing += part_info.winding != 0;
    for (Polygon& poly : parts_out) out.push_back(std::move(poly));
    a = b;
    if (a == first) break;
  }
  if (enclosing > 1) whole.tangled = true;
  if (info) *info = whole;
  if (whole.tangled) out.clear();
  // Parts may wrap around the antimeridian each: all longitudes unless there is one.
  if (bbox && !out.empty()) *bbox = box_of(out, out.size() > 1 || whole.winding != 0 ? Lons::All : Lons::One);
}

constexpr std::size_t kNoTouch = ~std::size_t{0};

// The loop as ring positions, a vertex at a pole as two with the incoming and outgoing
// longitudes (a point in keep_lon: its own; one position when they are the same), into `ring`.
// Returns the owner's one visit to its pole drawn as one position at its own longitude, if any
// (kNoTouch): its ring may need a whole turn there (add_whole_turn).
std::size_t ring_with_pole_runs(const std::vector<Pt>& loop, const std::vector<OwnLon>& own, PoleOwner pole_owner,
                                std::vector<RP>& ring) {
  const bool has_own = !own.empty();
  ring.clear();
  std::size_t touch = kNoTouch;
  const std::size_t n = loop.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Pt& p = loop[i];
    if (!is_pole(p.lat)) {
      ring.push_back({p.v, p.lon, p.lat, 0});
      continue;
    }
    const std::size_t prev = i == 0 ? n - 1 : i - 1, next = i + 1 == n ? 0 : i + 1;
    double in = loop[prev].lon, outl = loop[next].lon;
    // Where the run's first or last point is in keep_lon, its own longitude: the snap rounded
    // segment from the neighbour, as every other ring through that point draws it.
    if (has_own && !std::isnan(own[i].in)) in = own[i].in;
    if (has_own && !std::isnan(own[i].out)) outl = own[i].out;
    ring.push_back({p.v, in, p.lat, 0});
    const int owns = p.lat > 0 ? pole_owner.north : pole_owner.south;
    const bool back = runs_back_along_pole_line(p, in, outl, owns);
    if (outl != in) ring.push_back({p.v, outl, p.lat, 0, back});
    else if (owns == 1 && has_own && !std::isnan(own[i].in) && !std::isnan(own[i].out) && touch == kNoTouch &&
             !drawn_down_and_up(loop, own, prev, i, next))
      touch = ring.size() - 1;  // not a spike down a meridian and back, which cleaning removes
  }
  return touch;
}

// Unwraps the ring: the sheets along it (from ring[0]'s); returns its winding (turns) once closed.
int unwrap(std::vector<RP>& ring) {
  for (std::size_t i = 1; i < ring.size(); ++i) ring[i].k = next_sheet(ring[i - 1], ring[i]);
  return next_sheet(ring.back(), ring[0]) - ring[0].k;
}

// The owner's boundary through a point of its pole line drawn at its own longitude, and
// nowhere else along that line: the owner lies on both sides of it, so its ring, which winds
// around the pole, would touch its own closure along the line there. It runs a whole turn
// along the line from that point instead (the reverse of its boundary's turn), and is cut
// at the antimeridian like any ring: two parts meeting at the point (a ring of sites 35 m
// around the north pole whose lunes' tips meet millimetres from the south pole, one of them
// on the south pole's owner: unwritable, fuzz_cells' ring less the site that owned it).
void add_whole_turn(std::vector<RP>& ring, std::size_t touch) {
  if (touch == kNoTouch || unwrap(ring) != (ring[touch].lat > 0 ? 1 : -1)) return;
  RP turn = ring[touch];
  turn.full = true;
  ring.insert(ring.begin() + static_cast<std::ptrdiff_t>(touch) + 1, turn);
}

// An unwrapped ring that winds around no pole, appended to out from out[used] (used counts the
// pieces): in one sheet if every point can be written there, else cut at the antimeridian.
void write_unwound(const std::vector<RP>& ring, MultiPolygon& out, std::size_t& used, int precision) {
  Scratch& sc = scratch();
  // Sheets every point can be written in: [k - 1, k] on the antimeridian, else {k}.
  int common_lo = std::numeric_limits<int>::min(), common_hi = std::numeric_limits<int>::max();
  int kmin = common_hi, kmax = common_lo;
  for (const RP& p : ring) {
    const int lo = p.lon == -180 ? p.k - 1 : p.k;
    common_lo = std::max(common_lo, lo);
    common_hi = std::min(common_hi, p.k);
    kmin = std::min(kmin, lo);
    kmax = std::max(kmax, p.k);
  }
  if (common_lo <= common_hi) {
    append_piece(out, used, ring, common_lo);
    return;
  }
  // Cut at the antimeridian: clip to the strip [-180, 180] of every sheet touched.
  for (int j = kmin; j <= kmax; ++j) {
    clip_half(ring, sc.tmp, side_of_west_edge, j, j, precision);
    clip_half(sc.tmp, sc.piece, side_of_east_edge, j, j + 1, precision);
    if (sc.piece.size() >= 3) append_piece(out, used, sc.piece, j);
  }
}

// An unwrapped ring that winds once around a pole (winding +1: north, -1: south), appended to
// out[used]: from where the boundary meets the antimeridian (180 for the north pole, where
// longitudes increase; -180 for the south pole), one turn, closed through the pole.
void write_around_pole(const std::vector<RP>& ring, int winding, MultiPolygon& out, std::size_t& used,
                       int precision) {
  std::vector<RP>& piece = scratch().piece;
  const std::size_t m = ring.size();
  const int line = winding > 0 ? 1 : 0;  // the antimeridian at lon -180 of this sheet
  auto side = [&](const RP& p) {         // >= 0: the line is reached or passed
    const int s0 = side_of_west_edge(p, line);
    return winding > 0 ? s0 : -s0;
  };
  auto at = [&](std::size_t j) {  // the ring unrolled: position j of the doubled path
    RP p = ring[j % m];
    p.k += winding * static_cast<int>(j / m);
    return p;
  };
  std::size_t i = 0;
  while (side(at(i)) < 0) ++i;
  GEOVOR_ASSERT(i <= m);
  piece.clear();
  if (side(at(i)) == 0) {
    for (std::size_t j = i; j <= i + m; ++j) piece.push_back(at(j));
  } else {
    const RP x = crossing(at(i - 1), at(i), line, precision);
    piece.push_back(x);
    for (std::size_t j = i; j < i + m; ++j) piece.push_back(at(j));
    RP x2 = x;
    x2.k += winding;
    piece.push_back(x2);
  }
  // Written in the sheet where the first position is -180 (north) or 180 (south); then
  // through the pole: (180, 90), (-180, 90) for the north, (-180, -90), (180, -90) for the south.
  const int sheet = winding > 0 ? line : line - 1;
  const double pole = winding > 0 ? 90 : -90, east_first = winding > 0 ? 180 : -180;
  const Vec3 pole_v{0, 0, winding > 0 ? 1.0 : -1.0};
  piece.push_back({pole_v, east_first, pole, sheet});
  piece.push_back({pole_v, -east_first, pole, sheet});
  append_piece(out, used, piece, sheet);
}

// loop_to_polygons, with the own longitudes of its keep_lon points (empty: none), in stages.
void polygons_of(std::vector<Pt>& loop, std::vector<OwnLon>& own, MultiPolygon& out, BBox* bbox, int precision,
                 LoopInfo* info, PoleOwner pole_owner) {
  if (info) *info = LoopInfo{};
  if (bbox) *bbox = BBox{};
  const bool has_own = !own.empty();
  const bool near_pole = merge_repeated_positions(loop, own);
  if (info) info->near_pole = near_pole;
  if (near_pole && loop.size() > 3) drop_pole_spikes(loop, own, pole_owner);
  // Two points may still be three positions: a visit to a pole drawn at its own longitudes (a
  // part of a pinched loop: the point where it left the line, and its run there).
  if (loop.size() < 2 || (loop.size() < 3 && !has_own)) {
    out.clear();
    return;
  }
  if (near_pole && (pole_owner.north >= 0 || pole_owner.south >= 0)) {
    const double split_lat = pinch_latitude(loop);
    if (split_lat != 0) {
      write_pinched(loop, own, split_lat, near_pole, out, bbox, precision, info, pole_owner);
      return;
    }
  }
  std::size_t used = 0;
  // The usual cell: the ring written is the loop itself in sheet 0, as the general way writes it.
  if (!near_pole && loop.size() >= 3 && in_one_sheet(loop)) {
    append_piece(out, used, loop, 0);
    out.resize(used);
    if (bbox && used > 0) *bbox = box_of(out, Lons::One);
    return;
  }
  std::vector<RP>& ring = scratch().ring;
  const std::size_t touch = ring_with_pole_runs(loop, own, pole_owner, ring);
  if (ring.size() < 3) {
    out.clear();
    return;
  }
  add_whole_turn(ring, touch);
  const int winding = unwrap(ring);
  if (winding < -1 || winding > 1) {  // rounded positions wound it twice around a pole (fuzz_cells)
    if (info) info->winding = winding, info->tangled = true;
    return;
  }
  if (info) info->winding = winding;
  if (winding == 0)
    write_unwound(ring, out, used, precision);
  else
    write_around_pole(ring, winding, out, used, precision);
  out.resize(used);
  if (bbox && used > 0) *bbox = box_of(out, winding != 0 ? Lons::All : used == 1 ? Lons::One : Lons::Cut);
}

}  // namespace

void path_to_lines(const std::vector<Pt>& path, MultiLineString& out, int precision) {
  out.clear();
  LineString part;
  auto flush = [&] {
    std::size_t w = 0;  // drop consecutive duplicates
    for (std::size_t i = 0; i < part.size(); ++i)
      if (w == 0 || !(part[i] == part[w - 1])) part[w++] = part[i];
    part.resize(w);
    if (part.size() >= 2) out.push_back(part);
    part.clear();
  };
  // The current position is at unwrapped longitude lon + 360 k; the current part is written in
  // sheet `sheet` (k - sheet is 0, or 1 on its east edge, where lon is -180 and written 180), so
  // written longitudes are the converted ones bit for bit.
  int k = 0, sheet = 0;
  auto written = [&](double lon, int at) { return lon == -180 && at == sheet + 1 ? 180.0 : lon; };
  const std::size_t n = path.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Pt& p = path[i];
    if (is_pole(p.lat)) {
      // A meridian reaches the pole: the part ends there with the incoming longitude and the
      // next starts there with the outgoing one (a pole has every longitude).
      if (i > 0) part.push_back({written(path[i - 1].lon, k), p.lat});
      flush();
      if (i + 1 < n) {
        const Pt& q = path[i + 1];
        // On the antimeridian, start on the side the path goes to.
        const bool east = q.lon == -180 && i + 2 < n && path[i + 2].lon > 0;
        k = east ? 1 : 0, sheet = 0;
        part.push_back({written(q.lon, k), p.lat});
      }
      continue;
    }
    if (part.empty()) {
      const bool east = p.lon == -180 && i + 1 < n && path[i + 1].lon > 0 && !is_pole(path[i + 1].lat);
      k = east ? 1 : 0, sheet = 0;
      part.push_back({written(p.lon, k), p.lat});
      continue;
    }
    const Pt& a = path[i - 1];
    const double d = p.lon - a.lon;
    const int kp = d > 180 ? k - 1 : d < -180 ? k + 1 : k;
    // Unwrapped, relative to the current sheet: west edge -180, east edge 180 (lon -180, k = sheet + 1).
    const bool beyond_east = kp > sheet + 1 || (kp == sheet + 1 && p.lon > -180);
    const bool beyond_west = kp < sheet;
    if (beyond_east || beyond_west) {
      double lat;
      const bool a_on_edge = a.lon == -180 && (k == sheet + 1 || k == sheet);
      if (a_on_edge) {
        lat = a.lat;  // the previous position is on the antimeridian itself
      } else {
        const Vec3 c = std::fabs(p.v.y) * a.v + std::fabs(a.v.y) * p.v;
        lat = snap_to_decimals(SiteEncoder::to_lat_lon(c).lat_deg, precision);
        part.push_back({beyond_east ? 180.0 : -180.0, lat});
      }
      flush();
      sheet += beyond_east ? 1 : -1;
      part.push_back({beyond_east ? -180.0 : 180.0, lat});
    }
    k = kp;
    part.push_back({written(p.lon, k), p.lat});
  }
  flush();
}

}  // namespace geovor::lonlat
