#include "geovor/lonlat/delaunay_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/kernel/predicates.hpp"
#include "geovor/lonlat/cell_geometry.hpp"
#include "geovor/lonlat/ellipsoid_area.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"
#include "lonlat/boundary.hpp"

namespace geovor {
namespace {

using lonlat::Pt;
constexpr double kPi = std::numbers::pi;


// Scratch of one geometry, reused (the class is used from several threads).
struct Scratch {
  std::vector<Pt> loop, arc;
};
Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

}  // namespace

const char* to_string(FaceKind kind) {
  switch (kind) {
    case FaceKind::Proper: return "proper";
    case FaceKind::GreatCircle: return "great_circle";
    case FaceKind::Ghost: return "ghost";
  }
  return "?";
}

DelaunayGeometry::DelaunayGeometry(const SphericalDelaunay& dt, const DelaunayGeometryOptions& options)
    : dt_(&dt), options_(options) {
  lonlat::check_densify_options(options.densify_m, options.max_step_deg, options.max_depth);
  sites_.resize(dt.site_capacity());
  // A site this close to a pole (chord, unit sphere) is drawn at the pole: straight lon/lat sides
  // to a vertex a metre from the pole at another longitude can cross each other (GEOS-invalid).
  const double pole_snap = std::min(kPoleSnapM, options.densify_m) / SiteEncoder::kEarthRadiusM;
  for (SiteId s = 0; s < dt.site_capacity(); ++s) {
    if (!dt.is_live(s)) continue;
    Vec3 v = dt.site(s);
    if (v.x * v.x + v.y * v.y <= pole_snap * pole_snap) v = {0, 0, v.z > 0 ? 1.0 : -1.0};
    const Pt p = lonlat::make_pt(v, options.precision);
    sites_[s] = {p.v, p.lon, p.lat};
  }
  kinds_.resize(dt.num_triangles());
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    switch (kernel::orient(dt.site(dt.tri_site(t, 0)), dt.site(dt.tri_site(t, 1)), dt.site(dt.tri_site(t, 2)))) {
      case Sign::Positive: kinds_[t] = FaceKind::Proper; break;
      case Sign::Zero: kinds_[t] = FaceKind::GreatCircle; break;
      case Sign::Negative: kinds_[t] = FaceKind::Ghost; break;
    }
    has_proper_ = has_proper_ || kinds_[t] == FaceKind::Proper;
  }
  thickness2_.resize(dt.num_triangles());
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    double h2 = std::numeric_limits<double>::infinity();  // a GreatCircle face is a hemisphere
    if (kinds_[t] != FaceKind::GreatCircle) {
      for (int i = 0; i < 3; ++i) {
        const Vec3 &p = sites_[dt.tri_site(t, i)].v, &q = sites_[dt.tri_site(t, (i + 1) % 3)].v,
                   &r = sites_[dt.tri_site(t, (i + 2) % 3)].v;
        // Distance from p to the great circle of q and r: det(p, q, r) / |q x r|, both from the
        // small differences of the sites (exact for close sites), not from their cross products
        // (errors of 1e-16, far above the height of a thin triangle).
        const double d = dot(p, cross(q - p, r - p));
        h2 = std::min(h2, d * d / norm2(cross(q, r - q)));
      }
      h2 = std::max(h2, kMinThickness * kMinThickness);
    }
    thickness2_[t] = h2;
  }
}

double DelaunayGeometry::edge_bound2(HalfedgeId e) const {
  const SphericalDelaunay& dt = *dt_;
  const Vec3& u = dt.site(dt.tri_site(e / 3, static_cast<int>(e % 3)));
  const Vec3& v = dt.site(dt.tri_site(e / 3, static_cast<int>((e + 1) % 3)));
  return std::max(std::min(thickness2_[e / 3], thickness2_[dt.halfedges()[e] / 3]), 0x1p-60 * norm2(u - v));
}

bool DelaunayGeometry::is_hull_edge(HalfedgeId e) const {
  return is_outer(e / 3) != is_outer(dt_->halfedges()[e] / 3);
}

bool DelaunayGeometry::is_outer_edge(HalfedgeId e) const {
  return is_outer(e / 3) && is_outer(dt_->halfedges()[e] / 3);
}

namespace {

// The points strictly between sites a and b of the arc a -> b turning positively about the unit
// axis n, appended to `out`: cut into pieces of at most 90 degrees by rotation about n (so that
// arcs of any length, up to a full turn but one point, are handled), each densified.
// `bound2` bounds the densification tolerance to a quarter of its square root (see
// DelaunayGeometry::thickness2).
void arc_points(const Pt& a, const Pt& b, const Vec3& n, const DelaunayGeometryOptions& o, double bound2,
                std::vector<Pt>& out) {
  double theta = std::atan2(dot(cross(a.v, b.v), n), dot(a.v, b.v));
  if (theta <= 0) theta += 2 * kPi;
  const int pieces = std::max(1, static_cast<int>(std::ceil(theta / (kPi / 2))));
  const Vec3 quarter = cross(n, a.v);  // a turned by 90 degrees about n
  lonlat::Densifier dens(o.densify_m, o.max_step_deg, o.max_depth, out, o.precision);
  const Vec3 origin{0, 0, 0};
  Pt prev = a;
  for (int k = 1; k <= pieces; ++k) {
    const double phi = theta * k / pieces;
    const Pt next = k == pieces ? b : lonlat::make_pt(std::cos(phi) * a.v + std::sin(phi) * quarter, o.precision);
    // left - right = n: the Densifier's axis for arcs beyond 120 degrees (never reached here).
    dens.edge(prev, next, n, origin, bound2);
    if (k < pieces) out.push_back(next);
    prev = next;
  }
}

// Appends to `loop` the arc from u to v about axis n (both ends excluded), computed from the
// smaller site id to the larger so that every user of the edge gets the same bits.
void append_canonical_arc(const Pt& pu, const Pt& pv, SiteId u, SiteId v, const Vec3& n,
                          const DelaunayGeometryOptions& o, double bound2, std::vector<Pt>& loop,
                          std::vector<Pt>& arc) {
  arc.clear();
  if (u < v) {
    arc_points(pu, pv, n, o, bound2, arc);
    loop.insert(loop.end(), arc.begin(), arc.end());
  } else {
    arc_points(pv, pu, -1.0 * n, o, bound2, arc);
    loop.insert(loop.end(), arc.rbegin(), arc.rend());
  }
}

}  // namespace

WrittenStatus DelaunayGeometry::triangle_polygon(TriId t, MultiPolygon& out) const {
  const SphericalDelaunay& dt = *dt_;
  Scratch& sc = scratch();
  sc.loop.clear();
  const FaceKind k = kind(t);
  SiteId s[3] = {dt.tri_site(t, 0), dt.tri_site(t, 1), dt.tri_site(t, 2)};
  if (k == FaceKind::Ghost) std::swap(s[1], s[2]);  // the small triangle, counter-clockwise
  const Vec3 axis = VoronoiDiagram::circumcenter(dt, s[0], s[1], s[2]);
  for (int i = 0; i < 3; ++i) {
    const SiteId u = s[i], v = s[(i + 1) % 3];
    const Pt pu{sites_[u].v, sites_[u].lon, sites_[u].lat}, pv{sites_[v].v, sites_[v].lon, sites_[v].lat};
    sc.loop.push_back(pu);
    // Minor arcs, except on a great circle, where the face turns about the circle's axis.
    Vec3 n = axis;
    if (k != FaceKind::GreatCircle) {
      const Vec3 c = cross(dt.site(u), dt.site(v));
      if (norm2(c) > 0) n = lonlat::normalized(c);
    }
    // The half-edge of t from u to v, or from v to u in a Ghost's swapped order.
    int j = 0;
    while (j < 2 && !(dt.tri_site(t, j) == u && dt.tri_site(t, (j + 1) % 3) == v) &&
           !(dt.tri_site(t, j) == v && dt.tri_site(t, (j + 1) % 3) == u))
      ++j;
    append_canonical_arc(pu, pv, u, v, n, options_, edge_bound2(3 * t + j), sc.loop, sc.arc);
  }
  lonlat::loop_to_polygons(sc.loop, out, nullptr, options_.precision);
  const WrittenStatus status = certify_written(out, nullptr);
  if (status != WrittenStatus::Written) return status;
  // A corner thinner than a decimal step folds onto one point and its spike is removed (by the
  // certification, or by the cut at +-180 when the corner pokes across it by less than a step):
  // what is left is valid but is no triangle of its three sites, so it is reported instead.
  for (const SiteId site : s) {
    const SitePt& p = sites_[site];
    bool found = false;
    for (const Polygon& poly : out)
      for (const LonLat& q : poly.exterior)
        found |= q.lat_deg == p.lat && (q.lon_deg == p.lon || lonlat::is_pole(p.lat) ||
                                        (std::fabs(p.lon) == 180 && q.lon_deg == -p.lon));
    if (!found) {
      out.clear();
      return WrittenStatus::Unwritable;
    }
  }
  // Near a pole longitudes are ill-conditioned, and a sliver with a corner there, cut at +-180,
  // was closed along the antimeridian through the other pole: the whole Earth. As for cells
  // (CellGeometry::check_near_pole), such a triangle's area is checked against its area on the
  // sphere, and one that disagrees is reported, not written wrong.
  bool near_pole_or_cut = out.size() > 1;
  for (const Polygon& poly : out)
    for (const LonLat& q : poly.exterior) near_pole_or_cut |= std::fabs(q.lat_deg) >= 89 || std::fabs(q.lon_deg) == 180;
  if (near_pole_or_cut &&
      !cell_areas_agree(ellipsoid_area_m2(out), triangle_area_sr(t), out, options_.densify_m, options_.precision)) {
    out.clear();
    return WrittenStatus::Unwritable;
  }
  return WrittenStatus::Written;
}

void DelaunayGeometry::edge_line(HalfedgeId e, MultiLineString& out) const {
  const SphericalDelaunay& dt = *dt_;
  Scratch& sc = scratch();
  sc.loop.clear();
  const TriId t = e / 3;
  const SiteId u = dt.tri_site(t, static_cast<int>(e % 3)), v = dt.tri_site(t, static_cast<int>((e + 1) % 3));
  const Pt pu{sites_[u].v, sites_[u].lon, sites_[u].lat}, pv{sites_[v].v, sites_[v].lon, sites_[v].lat};
  // The minor arc; for antipodal sites (no minor arc), the one bounding the edge's smaller-id face.
  const SiteId lo = std::min(u, v), hi = std::max(u, v);
  Vec3 n;
  const Vec3 c = cross(dt.site(lo), dt.site(hi));
  if (norm2(c) > 0) {
    n = lonlat::normalized(c);
  } else {
    const HalfedgeId f = std::min(e, dt.halfedges()[e]);
    const TriId tf = f / 3;
    n = VoronoiDiagram::circumcenter(dt, dt.tri_site(tf, 0), dt.tri_site(tf, 1), dt.tri_site(tf, 2));
    if (dt.tri_site(tf, static_cast<int>(f % 3)) != lo) n = -1.0 * n;
  }
  sc.loop.push_back(u < v ? pu : pv);
  sc.arc.clear();
  arc_points(u < v ? pu : pv, u < v ? pv : pu, n, options_, edge_bound2(e), sc.arc);
  sc.loop.insert(sc.loop.end(), sc.arc.begin(), sc.arc.end());
  sc.loop.push_back(u < v ? pv : pu);
  if (u > v) std::reverse(sc.loop.begin(), sc.loop.end());
  lonlat::path_to_lines(sc.loop, out, options_.precision);
}

double DelaunayGeometry::triangle_area_sr(TriId t) const {
  const SphericalDelaunay& dt = *dt_;
  const Vec3 &a = dt.site(dt.tri_site(t, 0)), &b = dt.site(dt.tri_site(t, 1)), &c = dt.site(dt.tri_site(t, 2));
  switch (kind(t)) {
    case FaceKind::GreatCircle: return 2 * kPi;
    case FaceKind::Ghost: return VoronoiDiagram::triangle_area_sr(a, c, b);
    case FaceKind::Proper: break;
  }
  return VoronoiDiagram::triangle_area_sr(a, b, c);
}

double DelaunayGeometry::edge_length_m(HalfedgeId e) const {
  const SphericalDelaunay& dt = *dt_;
  const TriId t = e / 3;
  const Vec3& a = dt.site(dt.tri_site(t, static_cast<int>(e % 3)));
  const Vec3& b = dt.site(dt.tri_site(t, static_cast<int>((e + 1) % 3)));
  return SiteEncoder::kEarthRadiusM * std::atan2(std::sqrt(norm2(cross(a, b))), dot(a, b));
}

double DelaunayGeometry::circumradius_m(TriId t) const {
  const SphericalDelaunay& dt = *dt_;
  const Vec3& a = dt.site(dt.tri_site(t, 0));
  const Vec3 n = VoronoiDiagram::circumcenter(dt, dt.tri_site(t, 0), dt.tri_site(t, 1), dt.tri_site(t, 2));
  return SiteEncoder::kEarthRadiusM * std::atan2(std::sqrt(norm2(cross(n, a))), dot(n, a));
}

}  // namespace geovor
