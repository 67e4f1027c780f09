#include "geovor/layers/region_clip.hpp"

#include <geos_c.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <memory>
#include <string>

#include "geovor/core/coordinate_grid.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/lonlat/ellipsoid_area.hpp"

namespace geovor {
namespace {

// The region with points inserted along its straight lon/lat edges where a straight piece and
// the geodesic between its ends part by more than densify_m (as the cells' edges are densified):
// the pieces then follow the edges as drawn, and their areas (geodesics between the written
// vertices) are those of the region as drawn.
constexpr int kMaxRegionSplits = 20;  // halvings of one edge at most
constexpr int kLargeRegion = 2000;     // vertices from which a cell meets only the region near it

void densify_edge(LonLat a, LonLat b, double densify_m, int depth, Ring& out) {
  const LonLat mid{(a.lon_deg + b.lon_deg) / 2, (a.lat_deg + b.lat_deg) / 2};
  const Vec3 ua = SiteEncoder::from_lat_lon(a.lat_deg, a.lon_deg), ub = SiteEncoder::from_lat_lon(b.lat_deg, b.lon_deg);
  const Vec3 um = SiteEncoder::from_lat_lon(mid.lat_deg, mid.lon_deg);
  const Vec3 sum{ua.x + ub.x, ua.y + ub.y, ua.z + ub.z};
  const double norm = std::sqrt(dot(sum, sum));
  const double apart = norm < 1e-9 ? INFINITY  // ends opposite (or one point 360 degrees round)
                                   : std::acos(std::clamp(dot(um, sum) / norm, -1.0, 1.0)) * SiteEncoder::kEarthRadiusM;
  // Near a pole, also until the piece is within an eighth of its distance to the pole (as the
  // cells' edges there): a straight lon/lat line and the geodesic part fast near a pole, and a
  // piece measured by geodesics would fold.
  const double to_pole_m = (90 - std::abs(mid.lat_deg)) * (M_PI / 180) * SiteEncoder::kEarthRadiusM;
  if (depth < kMaxRegionSplits && apart > std::min(densify_m, to_pole_m / 8)) {
    densify_edge(a, mid, densify_m, depth + 1, out);
    densify_edge(mid, b, densify_m, depth + 1, out);
    return;
  }
  out.push_back(a);
}

Ring densified(const Ring& ring, double densify_m) {
  Ring out;
  for (std::size_t i = 0; i + 1 < ring.size(); ++i) densify_edge(ring[i], ring[i + 1], densify_m, 0, out);
  if (!ring.empty()) out.push_back(ring.back());
  return out;
}

MultiPolygon densified(const MultiPolygon& mp, double densify_m) {
  MultiPolygon out;
  for (const Polygon& p : mp) {
    Polygon d{densified(p.exterior, densify_m), {}};
    for (const Ring& h : p.holes) d.holes.push_back(densified(h, densify_m));
    out.push_back(std::move(d));
  }
  return out;
}

// One GEOS context per worker (GEOS's reentrant API), and geometries freed with it.
class Geos {
 public:
  Geos() : h_(GEOS_init_r()) {
    GEOSContext_setErrorMessageHandler_r(h_, [](const char* message, void* self) { static_cast<Geos*>(self)->error_ = message; }, this);
  }
  const std::string& last_error() const { return error_; }
  ~Geos() { GEOS_finish_r(h_); }
  Geos(const Geos&) = delete;
  Geos& operator=(const Geos&) = delete;
  GEOSContextHandle_t h() const { return h_; }

  struct Free {
    GEOSContextHandle_t h;
    void operator()(GEOSGeometry* g) const { GEOSGeom_destroy_r(h, g); }
  };
  using Ptr = std::unique_ptr<GEOSGeometry, Free>;
  Ptr own(GEOSGeometry* g) const { return Ptr(g, Free{h_}); }

  GEOSGeometry* ring(const Ring& r) const {
    GEOSCoordSequence* seq = GEOSCoordSeq_create_r(h_, static_cast<unsigned>(r.size()), 2);
    for (unsigned i = 0; i < r.size(); ++i) GEOSCoordSeq_setXY_r(h_, seq, i, r[i].lon_deg, r[i].lat_deg);
    return GEOSGeom_createLinearRing_r(h_, seq);
  }

  Ptr multipolygon(const MultiPolygon& mp) const {
    std::vector<GEOSGeometry*> polygons;
    for (const Polygon& p : mp) {
      std::vector<GEOSGeometry*> holes;
      for (const Ring& h : p.holes) holes.push_back(ring(h));
      polygons.push_back(GEOSGeom_createPolygon_r(h_, ring(p.exterior), holes.data(), static_cast<unsigned>(holes.size())));
    }
    return own(GEOSGeom_createCollection_r(h_, GEOS_MULTIPOLYGON, polygons.data(), static_cast<unsigned>(polygons.size())));
  }

  // The polygons of g (lines and points of a touching intersection left out), exteriors
  // counter-clockwise and holes clockwise in (lon, lat), as RFC 7946 wants them.
  MultiPolygon polygons(const GEOSGeometry* g) const {
    MultiPolygon out;
    add_polygons(g, out);
    return out;
  }

 private:
  Ring ring_of(const GEOSGeometry* r, bool counter_clockwise) const {
    const GEOSCoordSequence* seq = GEOSGeom_getCoordSeq_r(h_, r);
    unsigned n = 0;
    GEOSCoordSeq_getSize_r(h_, seq, &n);
    Ring out(n);
    for (unsigned i = 0; i < n; ++i) GEOSCoordSeq_getXY_r(h_, seq, i, &out[i].lon_deg, &out[i].lat_deg);
    if ((planar_area_deg2(out) > 0) != counter_clockwise) std::reverse(out.begin(), out.end());
    return out;
  }

  void add_polygons(const GEOSGeometry* g, MultiPolygon& out) const {
    const int type = GEOSGeomTypeId_r(h_, g);
    if (type == GEOS_POLYGON) {
      if (GEOSisEmpty_r(h_, g)) return;
      Polygon p;
      p.exterior = ring_of(GEOSGetExteriorRing_r(h_, g), true);
      for (int i = 0; i < GEOSGetNumInteriorRings_r(h_, g); ++i) p.holes.push_back(ring_of(GEOSGetInteriorRingN_r(h_, g, i), false));
      out.push_back(std::move(p));
    } else if (type == GEOS_MULTIPOLYGON || type == GEOS_GEOMETRYCOLLECTION) {
      for (int i = 0; i < GEOSGetNumGeometries_r(h_, g); ++i) add_polygons(GEOSGetGeometryN_r(h_, g, i), out);
    }
  }

  GEOSContextHandle_t h_;
  std::string error_;
};

// The grid of the written coordinates (GEOS's grid size), 0 for doubles.
double grid_size(int precision) { return precision < 0 ? 0.0 : std::pow(10.0, -precision); }

// The site whose cell holds q, by a greedy walk over the cells' neighbours from `start` (exact
// for unweighted cells up to ties; a caller checks the cell, as a weighted diagram may stop short).
SiteId walk_to_cell(const VoronoiDiagram& d, const Vec3& q, SiteId start) {
  SiteId s = start;
  for (;;) {
    SiteId best = s;
    double best_dot = dot(d.site(s), q);
    for (const SiteId n : d.cell_neighbors(s))
      if (const double v = dot(d.site(n), q); v > best_dot) best = n, best_dot = v;
    if (best == s) return s;
    s = best;
  }
}

// The clip of one region: its pieces, its area, its problems.
struct RegionWork {
  const VoronoiDiagram& diagram;
  const CellGeometry& cells;
  const Geos& geos;
  double grid;
  std::vector<std::uint32_t>& stamp;  // the region a cell was last queued for, + 1
  std::size_t tested = 0;

  // A cell's written polygon as GEOS geometry; null when it was not written (collapsed).
  Geos::Ptr cell(SiteId s) const {
    MultiPolygon mp;
    double area = 0;
    if (cells.polygon(s, mp, area) != CellStatus::Written || mp.empty()) return geos.own(nullptr);
    return geos.multipolygon(mp);
  }

  void clip(std::uint32_t r, const Region& region, std::vector<ClipPiece>& pieces, double& area_m2,
            std::vector<RegionProblem>& problems) {
    const GEOSContextHandle_t h = geos.h();
    Geos::Ptr shape = geos.multipolygon(densified(region.geometry, cells.options().densify_m));
    if (!GEOSisValid_r(h, shape.get())) {
      char* why = GEOSisValidReason_r(h, shape.get());
      problems.push_back({r, std::string("invalid polygon (") + (why ? why : "?") + "), repaired with GEOS MakeValid"});
      GEOSFree_r(h, why);
      shape = geos.own(GEOSMakeValid_r(h, shape.get()));
    }
    if (grid > 0 && shape) shape = geos.own(GEOSGeom_setPrecision_r(h, shape.get(), grid, 0));
    // Only the polygons: MakeValid leaves the lines of a collapsed part beside them.
    const MultiPolygon snapped = shape ? geos.polygons(shape.get()) : MultiPolygon{};
    if (snapped.empty()) {
      problems.push_back({r, "no area at the output's precision"});
      return;
    }
    shape = geos.multipolygon(snapped);
    const GEOSPreparedGeometry* prepared = GEOSPrepare_r(h, shape.get());
    const bool large = GEOSGetNumCoordinates_r(h, shape.get()) > kLargeRegion;
    std::deque<SiteId> queue;
    auto enqueue = [&](SiteId s) {
      if (stamp[s] == r + 1) return;
      stamp[s] = r + 1;
      queue.push_back(s);
    };
    SiteId start = first_live_site();
    for (const Polygon& part : snapped) {
      const LonLat v = part.exterior.front();
      start = walk_to_cell(diagram, SiteEncoder::from_lat_lon(v.lat_deg, v.lon_deg), start);
      Geos::Ptr c = cell(start);
      ++tested;
      if (c && GEOSPreparedIntersects_r(h, prepared, c.get())) enqueue(start);
      else seed_by_scan(prepared, r, enqueue);  // the walk stopped short (weighted cells, ties)
    }
    while (!queue.empty()) {
      const SiteId s = queue.front();
      queue.pop_front();
      Geos::Ptr c = cell(s);
      ++tested;
      if (c) {
        if (!GEOSPreparedIntersects_r(h, prepared, c.get())) continue;
        // A cell inside the region is its own piece (its vertices are on the grid already).
        MultiPolygon mp;
        if (GEOSPreparedContains_r(h, prepared, c.get())) {
          mp = geos.polygons(c.get());
        } else {
          // A large region near the cell first (a rectangle a degree wider than the cell's box, cut
          // by GEOS's rectangle clipper: linear in the region's size), then the overlay.
          Geos::Ptr piece = large ? intersection_near(shape.get(), c.get()) : intersection(shape.get(), c.get());
          if (!piece) {
            problems.push_back({r, "GEOS could not overlay the cell of site " + std::to_string(s) + ": " + geos.last_error()});
            continue;
          }
          mp = geos.polygons(piece.get());
        }
        if (!mp.empty()) {
          on_grid(mp);
          const double a = ellipsoid_area_m2(mp);
          if (!(a > 0))  // its geodesics between the written vertices fold (an edge meeting a pole askew)
            problems.push_back({r, "the piece of site " + std::to_string(s) + " measures " + std::to_string(a) +
                                       " m^2 as written: the region's edges meet at a pole off its meridians"});
          area_m2 += a;
          pieces.push_back({s, r, std::move(mp), a, 0.0});
        }
      }
      for (const SiteId n : diagram.cell_neighbors(s)) enqueue(n);  // an unwritten cell passes the walk on
    }
    GEOSPreparedGeom_destroy_r(h, prepared);
    if (!pieces.empty() && !(area_m2 > 0)) problems.push_back({r, "its pieces measure no area as written: shares 0"});
    for (ClipPiece& p : pieces) p.region_share = area_m2 > 0 ? p.area_m2 / area_m2 : 0.0;
  }

  // The overlay on the output's grid; null when GEOS throws (its message in last_error()).
  Geos::Ptr intersection(const GEOSGeometry* region, const GEOSGeometry* cell) const {
    return geos.own(grid > 0 ? GEOSIntersectionPrec_r(geos.h(), region, cell, grid) : GEOSIntersection_r(geos.h(), region, cell));
  }

  // Every coordinate as a reader of the file gets it back (GEOS's grid arithmetic can be an ulp
  // off the nearest double of the decimal: 30.410160000000005 for 30.41016).
  void on_grid(MultiPolygon& mp) const {
    if (grid <= 0) return;
    const int precision = cells.options().precision;
    for (Polygon& p : mp)
      for (Ring* ring : rings(p))
        for (LonLat& v : *ring) v = {snap_to_decimals(v.lon_deg, precision), snap_to_decimals(v.lat_deg, precision)};
  }

  static std::vector<Ring*> rings(Polygon& p) {
    std::vector<Ring*> all{&p.exterior};
    for (Ring& h : p.holes) all.push_back(&h);
    return all;
  }

  // The overlay with the part of the region near the cell (GEOS's rectangle clipper), or with the
  // whole region when that part is invalid (the clipper's ring can touch itself) or will not overlay.
  Geos::Ptr intersection_near(const GEOSGeometry* region, const GEOSGeometry* cell) const {
    const GEOSContextHandle_t h = geos.h();
    double w = 0, s = 0, e = 0, n = 0;
    GEOSGeom_getXMin_r(h, cell, &w);
    GEOSGeom_getYMin_r(h, cell, &s);
    GEOSGeom_getXMax_r(h, cell, &e);
    GEOSGeom_getYMax_r(h, cell, &n);
    Geos::Ptr near = geos.own(GEOSClipByRect_r(h, region, std::floor(w) - 1, std::floor(s) - 1, std::ceil(e) + 1, std::ceil(n) + 1));
    if (near && GEOSisValid_r(h, near.get()) == 1)
      if (Geos::Ptr piece = intersection(near.get(), cell)) return piece;
    return intersection(region, cell);
  }

  SiteId first_live_site() const {
    SiteId s = 0;
    while (!diagram.has_cell(s)) ++s;
    return s;
  }

  template <class Enqueue>
  void seed_by_scan(const GEOSPreparedGeometry* prepared, std::uint32_t, Enqueue& enqueue) {
    for (SiteId s = 0; s < diagram.site_capacity(); ++s) {
      if (!diagram.has_cell(s)) continue;
      Geos::Ptr c = cell(s);
      ++tested;
      if (c && GEOSPreparedIntersects_r(geos.h(), prepared, c.get())) {
        enqueue(s);
        return;
      }
    }
  }
};

}  // namespace

std::vector<ClipPiece> clip_cells_to_regions(const VoronoiDiagram& diagram, const CellGeometry& cells,
                                             const RegionTable& regions, const RegionClipOptions& options,
                                             RegionClipReport& report) {
  const std::size_t n = regions.regions.size();
  report = {};
  report.region_area_m2.assign(n, 0.0);
  std::vector<std::vector<ClipPiece>> by_region(n);
  std::vector<std::vector<RegionProblem>> problems(n);
  std::vector<std::size_t> tested(n, 0);
  const double grid = grid_size(cells.options().precision);
  if (diagram.num_cells() > 0) {
    std::vector<std::vector<std::uint32_t>> stamps(thread_count(options.threads));  // per worker
    // The largest regions first, so that no core is left with one at the end.
    std::vector<std::size_t> order(n), size(n, 0);
    for (std::size_t r = 0; r < n; ++r) {
      order[r] = r;
      for (const Polygon& p : regions.regions[r].geometry) size[r] += p.exterior.size();
    }
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return size[a] > size[b]; });
    parallel_chunks(n, 1, options.threads, [&](unsigned worker, std::size_t begin, std::size_t end) {
      const Geos geos;
      std::vector<std::uint32_t>& stamp = stamps[worker];
      if (stamp.empty()) stamp.assign(diagram.site_capacity(), 0);
      for (std::size_t i = begin; i < end; ++i) {
        const std::size_t r = order[i];
        RegionWork work{diagram, cells, geos, grid, stamp};
        work.clip(static_cast<std::uint32_t>(r), regions.regions[r], by_region[r], report.region_area_m2[r], problems[r]);
        tested[r] = work.tested;
      }
    });
  }
  std::vector<ClipPiece> pieces;
  for (std::size_t r = 0; r < n; ++r) {
    for (ClipPiece& p : by_region[r]) pieces.push_back(std::move(p));
    for (RegionProblem& p : problems[r]) report.problems.push_back(std::move(p));
    report.cells_tested += tested[r];
  }
  std::stable_sort(pieces.begin(), pieces.end(), [](const ClipPiece& a, const ClipPiece& b) { return a.site < b.site; });
  std::vector<bool> met(diagram.site_capacity(), false);
  for (const ClipPiece& p : pieces) met[p.site] = true;
  for (SiteId s = 0; s < diagram.site_capacity(); ++s)
    if (diagram.has_cell(s) && !met[s]) report.sites_outside.push_back(s);
  return pieces;
}

}  // namespace geovor
