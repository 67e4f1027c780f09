#include "geovor/voronoi/cell_geometry.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string>

#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor {
namespace {

constexpr double kDeg = std::numbers::pi / 180;
// WGS84 first eccentricity squared e^2 = f (2 - f): geodetic -> geocentric direction.
constexpr double kFlattening = 1 / 298.257223563;
constexpr double kE2 = kFlattening * (2 - kFlattening);
constexpr double kSnap2 = CellGeometry::kSnapRad * CellGeometry::kSnapRad;
// Planar area (square degrees) of the whole lon/lat rectangle.
constexpr double kWholeDeg2 = 360.0 * 180.0;

Vec3 normalized(const Vec3& v) { return (1 / std::sqrt(norm2(v))) * v; }

bool is_pole(double lat) { return lat == 90 || lat == -90; }

// Moves a point within kSnapRad of a pole onto it, and one within kSnapRad of the antimeridian
// onto it (y = +0: to_lat_lon then gives exactly -180), so rounding never decides a side.
Vec3 snap(Vec3 v) {
  const double h2 = v.x * v.x + v.y * v.y;
  const double r2 = h2 + v.z * v.z;
  if (h2 <= kSnap2 * r2) return {0, 0, v.z > 0 ? 1.0 : -1.0};
  if (v.x < 0 && v.y * v.y <= kSnap2 * r2) v.y = 0;
  return v;
}

// A boundary point on the sphere and in lon/lat (degrees).
struct Pt {
  Vec3 v;
  double lon, lat;
};

Pt make_pt(const Vec3& raw) {
  const Vec3 v = snap(raw);
  const LatLon ll = SiteEncoder::to_lat_lon(v);
  return {v, ll.lon_deg, ll.lat_deg};
}

// Geocentric direction (unnormalised) of a geodetic position at height 0.
Vec3 geodetic_direction(double lon_deg, double lat_deg) {
  const double phi = lat_deg * kDeg, lam = lon_deg * kDeg;
  const double cp = std::cos(phi);
  return {cp * std::cos(lam), cp * std::sin(lam), (1 - kE2) * std::sin(phi)};
}

// Adaptive bisection of great-circle arcs (gis.md section 4).
class Densifier {
 public:
  Densifier(const CellGeometryOptions& o, std::vector<Pt>& out)
      : out_(out),
        tol2_(std::pow(o.densify_m / SiteEncoder::kEarthRadiusM, 2)),
        cos_step_(std::cos(o.max_step_deg * kDeg)),
        max_depth_(o.max_depth) {}

  // Appends the points strictly between a and b of the arc a -> b, which turns positively about
  // the axis normalize(left - right) (the bisector normal of the sites on its left and right).
  // The axis is only computed for arcs longer than 120 degrees, where a + b cannot be used.
  // `site_chord2` is a lower bound of |left - right|^2: a quarter of it bounds the tolerance.
  void edge(const Pt& a, const Pt& b, const Vec3& left, const Vec3& right, double site_chord2) {
    left_ = &left;
    right_ = &right;
    have_axis_ = false;
    // Both sites, at half their distance from the arc, stay inside their written cells.
    edge_tol2_ = std::min(tol2_, site_chord2 / 16);
    if (a.v == b.v) return;
    if (!is_pole(a.lat) && !is_pole(b.lat)) {
      // An arc passing within kSnapRad of a pole gets the pole as a vertex, so that the
      // longitude jump of about 180 degrees is decided by the pole rule, not by rounding.
      const Vec3 n = dot(a.v, b.v) > -0.5 ? normalized(cross(a.v, b.v)) : axis();
      if (std::fabs(n.z) <= CellGeometry::kSnapRad) {
        for (const double pz : {1.0, -1.0}) {
          // Closest point of the arc's great circle to the pole (0, 0, pz).
          const Vec3 q = normalized({-pz * n.z * n.x, -pz * n.z * n.y, pz * (1 - n.z * n.z)});
          if (dot(cross(a.v, q), n) >= 0 && dot(cross(q, b.v), n) >= 0) {
            const Pt p = make_pt({0, 0, pz});
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

 private:
  const Vec3& axis() {
    if (!have_axis_) {
      axis_ = normalized(*left_ - *right_);
      have_axis_ = true;
    }
    return axis_;
  }

  Vec3 midpoint(const Vec3& a, const Vec3& b) {
    return dot(a, b) > -0.5 ? normalized(a + b) : VoronoiDiagram::arc_midpoint(a, b, axis());
  }

  void split(const Pt& a, const Pt& b, int depth) {
    if (depth >= max_depth_ || a.v == b.v) return;
    const bool pa = is_pole(a.lat), pb = is_pole(b.lat);
    Vec3 m;
    if (pa || pb) {
      // From a pole the arc is a meridian, straight in lon/lat: only pole to pole (N to S) needs
      // a midpoint, which gives the meridian its longitude.
      if (!(pa && pb)) return;
      m = midpoint(a.v, b.v);
    } else {
      m = midpoint(a.v, b.v);
      if (dot(a.v, b.v) >= cos_step_) {
        // Great-circle midpoint against the midpoint of the straight lon/lat segment.
        double dl = b.lon - a.lon;
        if (dl > 180) dl -= 360;
        if (dl < -180) dl += 360;
        const Vec3 q = normalized(geodetic_direction(a.lon + dl / 2, (a.lat + b.lat) / 2));
        if (norm2(m - q) <= edge_tol2_) return;
      }
    }
    const Pt mp = make_pt(m);
    split(a, mp, depth + 1);
    out_.push_back(mp);
    split(mp, b, depth + 1);
  }

  std::vector<Pt>& out_;
  double tol2_, cos_step_;
  int max_depth_;
  const Vec3* left_ = nullptr;
  const Vec3* right_ = nullptr;
  bool have_axis_ = false;
  Vec3 axis_;
  double edge_tol2_ = 0;
};

// A ring position with its sheet: the unwrapped longitude is lon + 360 k, with lon in
// [-180, 180) as to_lat_lon gives it (on the antimeridian, lon = -180 exactly).
struct RP {
  Vec3 v;
  double lon, lat;
  int k;
};

// Sheet of q after p along the ring (exact: integer steps and comparisons only).
int next_sheet(const RP& p, const RP& q) {
  if (is_pole(p.lat) && p.lat == q.lat) {
    // Along a pole from the incoming meridian a = p.lon to the outgoing b = q.lon: the cell's
    // wedge at the pole is (a - b) mod 360 at the north pole (longitude decreases, interior on
    // the left), (b - a) mod 360 at the south pole.
    if (p.lat > 0) return q.lon > p.lon ? p.k - 1 : p.k;
    return q.lon < p.lon ? p.k + 1 : p.k;
  }
  const double d = q.lon - p.lon;
  if (d > 180) return p.k - 1;
  if (d < -180) return p.k + 1;
  return p.k;
}

// Intersection of the segment p -> q with the antimeridian, as the ring position (-180, lat)
// in sheet k. The latitude is that of the great-circle arc between the two sphere points, the
// same bits whichever way the segment runs (|q.y| p + |p.y| q is symmetric and has y = 0).
RP crossing(const RP& p, const RP& q, int k) {
  if (is_pole(p.lat) && is_pole(q.lat)) return {p.v, -180, p.lat, k};
  const Vec3 c = std::fabs(q.v.y) * p.v + std::fabs(p.v.y) * q.v;
  return {c, -180, SiteEncoder::to_lat_lon(c).lat_deg, k};
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
               int line) {
  out.clear();
  const std::size_t n = in.size();
  for (std::size_t i = 0; i < n; ++i) {
    const RP& p = in[i == 0 ? n - 1 : i - 1];
    const RP& q = in[i];
    const int sp = side(p, j), sq = side(q, j);
    if (sq >= 0) {
      if (sp < 0 && sq > 0) out.push_back(crossing(p, q, line));
      out.push_back(q);
    } else if (sp > 0) {
      out.push_back(crossing(p, q, line));
    }
  }
}

struct Scratch {
  std::vector<Pt> loop, edge;
  std::vector<RP> ring, tmp, piece;
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// Closes `pts` (lon/lat, already in [-180, 180]) into a ring: no consecutive duplicates, exact
// copy of the first position at the end, counter-clockwise. Returns false if degenerate.
bool finish_ring(Ring& ring) {
  std::size_t w = 0;
  for (std::size_t i = 0; i < ring.size(); ++i)
    if (w == 0 || !(ring[i] == ring[w - 1])) ring[w++] = ring[i];
  while (w > 1 && ring[w - 1] == ring[0]) --w;
  ring.resize(w);
  if (w < 3) return false;
  ring.push_back(ring[0]);
  const double a = planar_area_deg2(ring);
  if (a == 0 || std::isnan(a)) return false;
  if (a < 0) std::reverse(ring.begin(), ring.end());
  return true;
}

void append_piece(MultiPolygon& out, std::size_t& used, const std::vector<RP>& pts, int sheet) {
  if (out.size() <= used) out.emplace_back();
  Polygon& poly = out[used];
  poly.holes.clear();
  Ring& r = poly.exterior;
  r.clear();
  for (const RP& p : pts) {
    double lon = p.lon + 360.0 * (p.k - sheet);
    // Only the antimeridian (lon -180 one sheet up) may leave [-180, 180); clamp rounding noise.
    lon = std::clamp(lon, -180.0, 180.0);
    r.push_back({lon, p.lat});
  }
  if (finish_ring(r)) ++used;
}

}  // namespace

double planar_area_deg2(const Ring& ring) {
  if (ring.size() < 4) return 0;
  const double x0 = ring[0].lon_deg, y0 = ring[0].lat_deg;
  double twice = 0;
  for (std::size_t i = 1; i + 1 < ring.size(); ++i) {
    const double x1 = ring[i].lon_deg - x0, y1 = ring[i].lat_deg - y0;
    const double x2 = ring[i + 1].lon_deg - x0, y2 = ring[i + 1].lat_deg - y0;
    twice += x1 * y2 - x2 * y1;
  }
  return twice / 2;
}

CellGeometry::CellGeometry(const VoronoiDiagram& diagram, const CellGeometryOptions& options)
    : vd_(&diagram), options_(options) {
  if (!(options.densify_m > 0) || !std::isfinite(options.densify_m))
    throw Error(ErrorCode::InvalidArgument, "densify_m must be a positive number of metres");
  if (!(options.max_step_deg > 0) || !(options.max_step_deg <= 180))
    throw Error(ErrorCode::InvalidArgument, "max_step_deg must be in (0, 180]");
  if (options.max_depth < 1 || options.max_depth > 40)
    throw Error(ErrorCode::InvalidArgument, "max_depth must be in [1, 40]");
  if (!(options.collapse_m >= 0) || !(options.collapse_m < 0.1))
    throw Error(ErrorCode::InvalidArgument, "collapse_m must be in [0, 0.1) metres");
  if (diagram.kind() != VoronoiDiagram::Kind::Cells) return;

  // Union-find over the Voronoi vertices joined by a short edge; the root is the smallest id.
  const std::size_t nv = diagram.num_vertices();
  std::vector<TriId> rep(nv);
  for (TriId t = 0; t < nv; ++t) rep[t] = t;
  auto find = [&rep](TriId t) {
    while (rep[t] != t) t = rep[t] = rep[rep[t]];
    return t;
  };
  const double collapse2 = std::pow(options.collapse_m / SiteEncoder::kEarthRadiusM, 2);
  for (const SiteId s : diagram.storage_order()) {
    const std::span<const TriId> tris = diagram.cell_vertices(s);
    for (std::size_t i = 0; i < tris.size(); ++i) {
      const TriId a = tris[i], b = tris[i + 1 == tris.size() ? 0 : i + 1];
      if (a < b && norm2(diagram.vertex(a) - diagram.vertex(b)) < collapse2) {
        const TriId ra = find(a), rb = find(b);
        if (ra < rb) rep[rb] = ra;
        if (rb < ra) rep[ra] = rb;
      }
    }
  }
  vertices_.resize(nv);
  for (TriId t = 0; t < nv; ++t) {
    const TriId r = find(t);
    if (r == t) {
      const Pt p = make_pt(diagram.vertex(t));
      vertices_[t] = {p.v, p.lon, p.lat, t, std::numeric_limits<float>::infinity()};
    } else {
      vertices_[t] = vertices_[r];  // r < t: already computed
      vertices_[t].min_side2 = std::numeric_limits<float>::infinity();
    }
  }
  // Shortest side of each triangle: the triangles t_i and t_i+1 of cell s both have the side
  // (s, neighbour i). Rounded down to float, the same for both cells of an edge.
  for (const SiteId s : diagram.storage_order()) {
    const std::span<const TriId> tris = diagram.cell_vertices(s);
    const std::span<const SiteId> nbrs = diagram.cell_neighbors(s);
    for (std::size_t i = 0; i < tris.size(); ++i) {
      const double d2 = norm2(diagram.site(s) - diagram.site(nbrs[i]));
      float f = static_cast<float>(d2);
      if (f > d2) f = std::nextafter(f, 0.0f);
      for (const TriId t : {tris[i], tris[i + 1 == tris.size() ? 0 : i + 1]})
        vertices_[t].min_side2 = std::min(vertices_[t].min_side2, f);
    }
  }
}

MultiPolygon CellGeometry::polygon(SiteId s, BBox* bbox) const {
  MultiPolygon out;
  polygon(s, out, bbox);
  return out;
}

void CellGeometry::polygon(SiteId s, MultiPolygon& out, BBox* bbox) const {
  const VoronoiDiagram& vd = *vd_;
  std::size_t used = 0;
  if (bbox) *bbox = BBox{};
  if (!vd.has_cell(s)) {
    out.clear();
    return;
  }
  if (vd.kind() == VoronoiDiagram::Kind::WholeSphere) {
    out.resize(1);
    out[0].holes.clear();
    out[0].exterior.assign({{-180, -90}, {180, -90}, {180, 90}, {-180, 90}, {-180, -90}});
    if (bbox) *bbox = {-180, -90, 180, 90};
    return;
  }

  Scratch& sc = scratch();
  std::vector<Pt>& loop = sc.loop;
  std::vector<Pt>& edge = sc.edge;
  loop.clear();
  Densifier dens(options_, edge);

  if (vd.kind() == VoronoiDiagram::Kind::Hemispheres) {
    // The bisector circle as four quarter arcs, computed for the smaller site id and reversed
    // for the other one, so both hemispheres share every vertex.
    const SiteId other = vd.cell_neighbors(s)[0];
    const SiteId lo = std::min(s, other);
    const Vec3 n = vd.hemisphere_normal(lo);
    // e1 on the equator (z x n), e2 = n x e1 the top of the circle: a pole if n is horizontal.
    // For a bisector near the equator (n near a pole), e1 is x made orthogonal to n instead.
    const Vec3 e1 = std::hypot(n.x, n.y) > 0x1p-26 ? normalized({-n.y, n.x, 0})
                                                   : normalized(Vec3{1, 0, 0} - n.x * n);
    const Vec3 e2 = normalized(cross(n, e1));
    const Vec3 q[4] = {e1, e2, -1.0 * e1, -1.0 * e2};
    const Vec3& left = vd.site(lo);
    const Vec3& right = vd.site(std::max(s, other));
    for (int i = 0; i < 4; ++i) {
      const Pt a = make_pt(q[i]), b = make_pt(q[(i + 1) % 4]);
      loop.push_back(a);
      edge.clear();
      dens.edge(a, b, left, right, norm2(left - right));
      loop.insert(loop.end(), edge.begin(), edge.end());
    }
    if (s != lo) std::reverse(loop.begin(), loop.end());
  } else {
    const std::span<const TriId> tris = vd.cell_vertices(s);
    const std::span<const SiteId> nbrs = vd.cell_neighbors(s);
    const std::size_t d = tris.size();
    for (std::size_t i = 0; i < d; ++i) {
      const Vertex& va = vertices_[tris[i]];
      const Vertex& vb = vertices_[tris[i + 1 == d ? 0 : i + 1]];
      if (va.rep == vb.rep) continue;  // collapsed edge
      const Pt a{va.v, va.lon, va.lat}, b{vb.v, vb.lon, vb.lat};
      loop.push_back(a);
      // Canonical direction: as the cell of the smaller site id runs it. Both triangles of the
      // edge contain its two sites: the shorter of their shortest sides bounds their distance.
      const SiteId w = nbrs[i];
      const double chord2 = std::min(va.min_side2, vb.min_side2);
      edge.clear();
      if (s < w) {
        dens.edge(a, b, vd.site(s), vd.site(w), chord2);
        loop.insert(loop.end(), edge.begin(), edge.end());
      } else {
        dens.edge(b, a, vd.site(w), vd.site(s), chord2);
        loop.insert(loop.end(), edge.rbegin(), edge.rend());
      }
    }
  }

  // Drop consecutive duplicates in lon/lat (cyclically).
  {
    std::size_t w = 0;
    for (std::size_t i = 0; i < loop.size(); ++i)
      if (w == 0 || loop[i].lon != loop[w - 1].lon || loop[i].lat != loop[w - 1].lat)
        loop[w++] = loop[i];
    while (w > 1 && loop[w - 1].lon == loop[0].lon && loop[w - 1].lat == loop[0].lat) --w;
    loop.resize(w);
  }
  if (loop.size() < 3) {
    out.clear();
    return;
  }

  // A vertex at a pole becomes two pole positions with the incoming and outgoing longitudes.
  std::vector<RP>& ring = sc.ring;
  ring.clear();
  const std::size_t n = loop.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Pt& p = loop[i];
    if (!is_pole(p.lat)) {
      ring.push_back({p.v, p.lon, p.lat, 0});
      continue;
    }
    const double in = loop[i == 0 ? n - 1 : i - 1].lon, outl = loop[i + 1 == n ? 0 : i + 1].lon;
    ring.push_back({p.v, in, p.lat, 0});
    if (outl != in) ring.push_back({p.v, outl, p.lat, 0});
  }

  // Unwrap: sheets along the ring, and the winding (in turns) after closing it.
  const std::size_t m = ring.size();
  for (std::size_t i = 1; i < m; ++i) ring[i].k = next_sheet(ring[i - 1], ring[i]);
  const int winding = next_sheet(ring[m - 1], ring[0]) - ring[0].k;
  GEOVOR_ASSERT(winding >= -1 && winding <= 1);

  std::vector<RP>& piece = sc.piece;
  bool polar = winding != 0;
  if (winding == 0) {
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
    } else {
      // Cut at the antimeridian: clip to the strip [-180, 180] of every sheet touched.
      for (int j = kmin; j <= kmax; ++j) {
        clip_half(ring, sc.tmp, side_of_west_edge, j, j);
        clip_half(sc.tmp, piece, side_of_east_edge, j, j + 1);
        if (piece.size() >= 3) append_piece(out, used, piece, j);
      }
    }
  } else {
    // A pole inside: start where the boundary meets the antimeridian (180 for the north pole,
    // where longitudes increase; -180 for the south pole), run one turn, close through the pole.
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
      const RP x = crossing(at(i - 1), at(i), line);
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
  out.resize(used);

  if (bbox && used > 0) {
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
    if (polar) {
      b.west = -180, b.east = 180;
    } else if (used == 1) {
      lon_range(out[0], b.west, b.east);
    } else {
      // Pieces come west to east by sheet: the first ends at 180, the last starts at -180.
      double lo, hi;
      lon_range(out.front(), b.west, hi);
      lon_range(out.back(), lo, b.east);
    }
    *bbox = b;
  }
}

MultiPolygon cell_polygon(const VoronoiDiagram& diagram, SiteId s,
                          const CellGeometryOptions& options, BBox* bbox) {
  return CellGeometry(diagram, options).polygon(s, bbox);
}

double ellipsoid_area_m2(const MultiPolygon& polygons) {
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  const double whole = geod.EllipsoidArea();
  // Signed area on the left of a ring, in (-whole/2, whole/2] from GeographicLib; a ring whose
  // lon/lat area is large is a polygon larger than half the ellipsoid, not a negative sliver.
  auto ring_area = [&](const Ring& ring, bool reverse) {
    const double planar = std::fabs(planar_area_deg2(ring));
    if (planar >= kWholeDeg2 * (1 - 1e-12)) return whole;
    GeographicLib::PolygonArea pa(geod);
    for (std::size_t i = 0; i + 1 < ring.size(); ++i) pa.AddPoint(ring[i].lat_deg, ring[i].lon_deg);
    double perimeter = 0, area = 0;
    pa.Compute(reverse, true, perimeter, area);
    // A polygon of more than half the ellipsoid has more than 2 pi rad^2 = 20626 deg^2 in lon/lat.
    if (area < 0 && planar > 10000) area += whole;
    return area;
  };
  double total = 0;
  for (const Polygon& poly : polygons) {
    total += ring_area(poly.exterior, false);
    for (const Ring& h : poly.holes) total -= ring_area(h, true);
  }
  return total;
}

}  // namespace geovor
