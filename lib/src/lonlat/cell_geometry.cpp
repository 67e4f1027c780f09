#include "geovor/lonlat/cell_geometry.hpp"

#include "geovor/kernel/predicates.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdlib>
#include <new>
#include <numeric>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>

#include "geovor/core/assert.hpp"
#include "geovor/core/compensated_sum.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/lonlat/ellipsoid_area.hpp"
#include "geovor/lonlat/polygon_validity.hpp"
#include "lonlat/boundary.hpp"
#include "lonlat/snap_rounding.hpp"
#include "lonlat/thin_triangles.hpp"

namespace geovor {
namespace {

using lonlat::Densifier;
using lonlat::make_pt;
using lonlat::normalized;
using lonlat::Pt;
static_assert(CellGeometry::kSnapRad == lonlat::kSnapRad);

// Planar area (square degrees) of the whole lon/lat rectangle.
constexpr double kWholeDeg2 = 360.0 * 180.0;

// Per-thread buffers of build(), reused (polygon() is thread-safe); Slot tells apart two of one type.
template <typename T, int Slot = 0>
std::vector<T>& scratch() {
  thread_local std::vector<T> buffer;
  return buffer;
}

// The geodesic segments of the edge a -> interior -> b as PolygonArea sees them (repeated
// positions dropped), appended to `segments`; returns the edge's prime-meridian crossings.
template <typename Interior>
int append_segments(const Pt& a, const Interior& interior, const Pt& b, std::vector<GeodesicEdge>& segments) {
  int crossings = 0;
  double lon = a.lon, lat = a.lat;
  auto segment = [&](double lon2, double lat2) {
    if (lon2 == lon && lat2 == lat) return;
    segments.push_back({lat, lon, lat2, lon2});
    crossings += prime_meridian_transit(lon, lon2);
    lon = lon2, lat = lat2;
  };
  for (const auto& q : interior) segment(q.lon, q.lat);
  segment(b.lon, b.lat);
  return crossings;
}

}  // namespace

CellGeometry::CellGeometry(const VoronoiDiagram& diagram, const CellGeometryOptions& options)
    : vd_(&diagram), options_(options) {
  lonlat::check_densify_options(options.densify_m, options.max_step_deg, options.max_depth);
  find_pole_owners();
  if (diagram.kind() != VoronoiDiagram::Kind::Cells) return;
  const unsigned threads = static_cast<unsigned>(
      std::min<std::size_t>(thread_count(options.threads), std::max<std::size_t>(1, diagram.num_vertices() / 16384)));
  const std::vector<SiteId> thin_sites = classify_triangles(threads);
  compute_vertex_lonlat(threads);
  densify_edges(threads);
  if (!thin_sites.empty()) snap_round_thin_cells(thin_sites);
}

void CellGeometry::find_pole_owners() {
  const VoronoiDiagram& diagram = *vd_;
  if (diagram.is_weighted()) return find_power_pole_owners();
  double zmax = -2, zmin = 2;
  for (SiteId s = 0; s < diagram.site_capacity(); ++s) {
    if (!diagram.has_cell(s)) continue;
    const double z = diagram.site(s).z;
    if (z > zmax) zmax = z, north_owner_ = s;
    else if (z == zmax) north_owner_ = kNoIndex;
    if (z < zmin) zmin = z, south_owner_ = s;
    else if (z == zmin) south_owner_ = kNoIndex;
  }
}

void CellGeometry::find_power_pole_owners() {
  // The site of largest power z / lift at each pole, exactly (compare_power); a tie: none.
  const VoronoiDiagram& vd = *vd_;
  for (const double pz : {1.0, -1.0}) {
    const Vec3 pole{0, 0, pz};
    SiteId best = kNoIndex;
    bool tie = false;
    for (SiteId s = 0; s < vd.site_capacity(); ++s) {
      if (!vd.has_cell(s)) continue;
      const Sign c = best == kNoIndex ? Sign::Positive
                                      : kernel::compare_power(pole, vd.site(s), vd.lift(s), vd.site(best), vd.lift(best));
      if (c == Sign::Positive) best = s, tie = false;
      else if (c == Sign::Zero) tie = true;
    }
    (pz > 0 ? north_owner_ : south_owner_) = tie ? kNoIndex : best;
  }
}

CellGeometry::EdgeSides CellGeometry::edge_sides(SiteId left, SiteId right) const {
  const VoronoiDiagram& vd = *vd_;
  const double cl = vd.lift(left), cr = vd.lift(right);
  if (cl == cr) return {vd.site(left), vd.site(right)};
  // left - right along the power bisector's normal: c_r p_l - c_l p_r.
  return {cr * vd.site(left), cl * vd.site(right)};
}

std::vector<SiteId> CellGeometry::classify_triangles(unsigned threads) {
  const VoronoiDiagram& diagram = *vd_;
  const std::size_t nv = diagram.num_vertices();
  const std::span<const SiteId> order = diagram.storage_order();
  // The edges shorter than two decimal steps (chord), which rounding alone can fold, and the
  // triangles with a side shorter than four: their cells are snap rounded (snap_round_thin_cells).
  // (The step of the grid they are snapped to: the output's, at most kThinCellDecimals, so that
  // 17 decimals and full precision write the same.)
  const lonlat::ThinThresholds th = lonlat::thin_thresholds(thin_cell_decimals(options_.precision), options_.densify_m);
  // Into the vertices (calloc: fresh pages, first touched by the threads that fill them; each
  // triangle once, by the cell of its smallest site): classify_cell.
  vertices_.reset(static_cast<Vertex*>(std::calloc(std::max<std::size_t>(nv, 1), sizeof(Vertex))));
  if (!vertices_) throw std::bad_alloc();
  std::vector<std::vector<SiteId>> thin(threads);
  std::vector<std::size_t> filled(threads, 0);
  // In chunks taken in turn: the cell layer's texts share the cores meanwhile, so equal slices
  // finished milliseconds apart.
  constexpr std::size_t kCellChunk = 1024;
  parallel_chunks(order.size(), kCellChunk, threads, [&](unsigned thread, std::size_t begin, std::size_t end) {
    std::size_t count = 0;
    for (std::size_t j = begin; j < end; ++j) {
      if (j + 8 < order.size())  // the vertices are scattered: requested some cells ahead
        for (const TriId t : diagram.cell_vertices(order[j + 8])) __builtin_prefetch(&diagram.vertex(t));
      count += classify_cell(order[j], th, thin[thread]);
    }
    filled[thread] += count;
  });
  GEOVOR_ASSERT(std::accumulate(filled.begin(), filled.end(), std::size_t{0}) == nv);  // every triangle once
  // The sites of the caps' triangles (their cells are thin near those vertices) and of the
  // small ones above: where a decimal step can be wider than a cell (snap_round_thin_cells).
  // At kSnapAllDecimals or fewer, every cell: a step of a kilometre or more reaches beyond the
  // neighbours of a thin cell, whose positions would not be hot pixels.
  std::vector<SiteId> thin_sites;
  if (options_.precision >= 0 && options_.precision <= kSnapAllDecimals) {
    for (const SiteId s : order) thin_sites.push_back(s);
  } else {
    for (const std::vector<SiteId>& list : thin) thin_sites.insert(thin_sites.end(), list.begin(), list.end());
    std::sort(thin_sites.begin(), thin_sites.end());  // whatever the threads
    thin_sites.erase(std::unique(thin_sites.begin(), thin_sites.end()), thin_sites.end());
  }
  return thin_sites;
}

std::size_t CellGeometry::classify_cell(SiteId s, const lonlat::ThinThresholds& th, std::vector<SiteId>& thin) {
  const VoronoiDiagram& diagram = *vd_;
  const std::span<const TriId> tris = diagram.cell_vertices(s);
  const std::span<const SiteId> nbrs = diagram.cell_neighbors(s);
  const std::size_t d = tris.size();
  std::size_t count = 0;
  for (std::size_t i = 0; i < d; ++i) {
    const TriId a = tris[i], b = tris[i + 1 == d ? 0 : i + 1];
    const SiteId u = nbrs[i == 0 ? d - 1 : i - 1], w = nbrs[i];
    if (a < b && norm2(diagram.vertex(a) - diagram.vertex(b)) < th.fold2)  // the sites of both vertices
      thin.insert(thin.end(), {s, u, w, nbrs[i + 1 == d ? 0 : i + 1]});
    if (s < u && s < w) {
      // Triangle t_i of cell s has the sites s, neighbour i - 1 and neighbour i: its shortest side
      // rounded down to float (the same for both cells of an edge), whether it is a cap (its
      // sites are thin cells) and whether its vertex is near a pole (its edges are guarded like
      // caps': cap angles are below 3.6 degrees; lunes 1 km from a pole crossed).
      const Vec3 &ps = diagram.site(s), &pu = diagram.site(u), &pw = diagram.site(w);
      const double su = norm2(ps - pu), sw = norm2(ps - pw), uw = norm2(pu - pw);
      Vertex& vertex = vertices_[a];
      vertex.min_side2 = lonlat::round_down_to_float(std::min({su, sw, uw}));
      const Vec3& va = diagram.vertex(a);
      const bool cap = lonlat::is_cap(ps, pu, pw, va, std::max({su, sw, uw}));
      vertex.flags = (cap ? kCap : 0) | (lonlat::near_pole_for_chords(va, th.pole_guard2) ? kNearPole : 0);
      if (cap || vertex.min_side2 < th.small2) thin.insert(thin.end(), {s, u, w});
      ++count;
    }
  }
  return count;
}

void CellGeometry::compute_vertex_lonlat(unsigned threads) {
  // The costly part of construction: a to_lat_lon per vertex.
  constexpr std::size_t kVertexChunk = 4096;
  parallel_chunks(vd_->num_vertices(), kVertexChunk, threads, [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      const Pt p = make_pt(vd_->vertex(static_cast<TriId>(t)), options_.precision);
      Vertex& vertex = vertices_[t];
      vertex.v = p.v, vertex.lon = p.lon, vertex.lat = p.lat;
    }
  });
}

// The per-thread state of densify_edges: its buffers, the thread's part of points_, and the
// edges whose area terms wait for a batch (geodesic_s12 solves them in vector lanes).
struct CellGeometry::EdgeWork {
  static constexpr std::size_t kNoSlot = ~std::size_t{0};
  struct Pending {
    std::size_t slot, other, end;  // the edge's two slots, the end of its segments
  };
  std::vector<Pt> edge;
  std::vector<Vec3> guards;
  Densifier dens;
  std::vector<BoundaryPoint>& points;
  std::vector<GeodesicEdge> segments;
  std::vector<double> s12;
  std::vector<Pending> pending;

  EdgeWork(const CellGeometryOptions& o, std::vector<BoundaryPoint>& part)
      : dens(o.densify_m, o.max_step_deg, o.max_depth, edge, o.precision), points(part) {}
  // The pending edges' sums of S12 into both their slots.
  void flush(EdgeSlot* slots) {
    s12.resize(segments.size());
    geodesic_s12(segments, s12);
    std::size_t first = 0;
    for (const Pending& p : pending) {
      const double sum = sum_s12(std::span<const double>(s12).subspan(first, p.end - first));
      slots[p.slot].s12 = sum;
      if (p.other != kNoSlot) slots[p.other].s12 = sum;
      first = p.end;
    }
    segments.clear();
    pending.clear();
  }
};

void CellGeometry::densify_edges(unsigned threads) {
  const VoronoiDiagram& diagram = *vd_;
  const std::span<const SiteId> order = diagram.storage_order();
  // Every edge once, in the direction of its canonical cell (the smaller site id): its densified
  // points, and its area terms in batches of segments.
  num_edge_slots_ = 3 * diagram.num_vertices();
  edge_slots_.reset(static_cast<EdgeSlot*>(std::calloc(num_edge_slots_, sizeof(EdgeSlot))));
  if (!edge_slots_) throw std::bad_alloc();
  nbr_base_ = diagram.cell_neighbors(order.front()).data();  // the lists are in storage order
  GEOVOR_ASSERT(diagram.cell_neighbors(order.back()).data() > nbr_base_);
  points_.resize(threads);
  // Chunks of cells taken in turn: the work per cell follows the densification, which varies
  // by region (large ocean cells), so equal slices of the storage order finish far apart.
  constexpr std::size_t kChunk = 1024;
  std::atomic<std::size_t> next_chunk{0};
  parallel_for(order.size(), threads, [&](unsigned thread, std::size_t, std::size_t) {
    EdgeWork work(options_, points_[thread]);
    for (;;) {
      const std::size_t begin = kChunk * next_chunk.fetch_add(1, std::memory_order_relaxed);
      if (begin >= order.size()) break;
      const std::size_t end = std::min(order.size(), begin + kChunk);
      for (std::size_t j = begin; j < end; ++j) {
        prefetch_edge_inputs(order, j);
        densify_cell_edges(order[j], thread, work);
      }
    }
    work.flush(edge_slots_.get());
  });
}

void CellGeometry::prefetch_edge_inputs(std::span<const SiteId> order, std::size_t j) const {
  const VoronoiDiagram& diagram = *vd_;
  constexpr std::size_t kWhere = 16, kLists = 8;
  if (j + kWhere < order.size()) {
    const SiteId s = order[j + kWhere];
    for (const SiteId w : diagram.cell_neighbors(s))
      if (w > s) diagram.prefetch(w, 0);
  }
  if (j + kLists < order.size()) {
    const SiteId s = order[j + kLists];
    for (const TriId t : diagram.cell_vertices(s)) __builtin_prefetch(&vertices_[t]);
    for (const SiteId w : diagram.cell_neighbors(s))
      if (w > s) {
        diagram.prefetch(w, 1);
        const std::span<const SiteId> other = diagram.cell_neighbors(w);
        __builtin_prefetch(edge_slots_.get() + (other.data() - nbr_base_));
      }
  }
}

void CellGeometry::densify_cell_edges(SiteId s, unsigned thread, EdgeWork& work) {
  const VoronoiDiagram& diagram = *vd_;
  const std::span<const TriId> tris = diagram.cell_vertices(s);
  const std::span<const SiteId> nbrs = diagram.cell_neighbors(s);
  const std::size_t d = tris.size();
  for (std::size_t i = 0; i < d; ++i) {
    const SiteId w = nbrs[i];
    const TriId ta = tris[i], tb = tris[i + 1 == d ? 0 : i + 1];
    const Vertex &va = vertices_[ta], &vb = vertices_[tb];
    if (w < s) continue;  // the other cell's
    const Pt a{va.v, va.lon, va.lat}, b{vb.v, vb.lon, vb.lat};
    // Both triangles of the edge contain its two sites: the shorter of their shortest
    // sides bounds their distance.
    work.edge.clear();
    work.guards.clear();
    if (va.flags | vb.flags) edge_guards(s, w, va, vb, work.guards);
    work.dens.set_guards(work.guards);
    const EdgeSides sides = edge_sides(s, w);
    work.dens.edge(a, b, sides.left, sides.right, std::min(va.min_side2, vb.min_side2));
    const std::size_t slot = static_cast<std::size_t>(nbrs.data() - nbr_base_) + i;
    EdgeSlot e;  // built here, then stored in both slots (s12: at the flush)
    e.s12 = 0;
    e.first = static_cast<std::uint32_t>(work.points.size());
    e.count = static_cast<std::uint32_t>(work.edge.size());
    e.part = thread + 1;  // 0: not computed (calloc)
    for (const Pt& q : work.edge) work.points.push_back({q.v, q.lon, q.lat});
    e.crossings = append_segments(a, work.edge, b, work.segments);
    edge_slots_[slot] = e;
    const std::size_t other = other_slot(s, w);
    if (other != EdgeWork::kNoSlot) edge_slots_[other] = e;
    work.pending.push_back({slot, other, work.segments.size()});
    if (work.segments.size() >= 4096) work.flush(edge_slots_.get());
  }
}

// The other cell's slot of the edge gets the same data (its sum at the flush), so that each cell
// reads only its own slots, in storage order; not when the two sites share more than this edge
// (tiny diagrams: that cell computes it in place).
std::size_t CellGeometry::other_slot(SiteId s, SiteId w) const {
  const std::span<const SiteId> other_nbrs = vd_->cell_neighbors(w);
  const auto it = std::find(other_nbrs.begin(), other_nbrs.end(), s);
  if (it == other_nbrs.end() || std::find(it + 1, other_nbrs.end(), s) != other_nbrs.end()) return EdgeWork::kNoSlot;
  return static_cast<std::size_t>(other_nbrs.data() - nbr_base_) + static_cast<std::size_t>(it - other_nbrs.begin());
}

// The working state of snap_round_thin_cells, shared by its stages: the region's cells and
// edges, the vertices it moves, and its edges as paths of snap vertices.
struct CellGeometry::SnapRegion {
  // An edge of the region, once, by the slot of its canonical cell (the smaller site id).
  struct Edge {
    std::size_t slot, other;  // the canonical cell's slot, the other cell's
    TriId a, b;               // its end vertices, in the canonical direction
    SiteId lo;                // the canonical cell; the edge is its j-th
    std::uint32_t j;
    bool rerouted;
  };
  // Per site: 0 outside, 1 a thin cell (its edges snap rounded), 2 a thin cell's neighbour (hot
  // pixels, and the rerouted edges it shares), 3 beyond those but at a moved vertex.
  std::vector<std::uint8_t> ring;
  std::vector<SiteId> cells[2];  // rings 1 and 2
  std::vector<Edge> edges;
  int decimals = 0;              // the grid's: the output's, at most kThinCellDecimals
  bool moves = false;            // the grid is coarser than the output: rerouted edges' ends move
  std::vector<TriId> moved_ids;  // those ends, sorted
  std::vector<bool> moved_set;   // per vertex, when `moves`
  std::vector<BoundaryPoint> points;                   // the paths' points, by SnapVertex::tag
  std::vector<std::vector<lonlat::SnapVertex>> paths;  // the rerouted edges, raw and written
  std::vector<lonlat::SnapVertex> extra;               // the other edges' points: hot pixels only
  std::vector<std::size_t> path_edge;                  // each path's index in `edges`

  bool moved(TriId r) const { return moves && moved_set[r]; }
  std::size_t moved_index(TriId r) const {
    const auto it = std::lower_bound(moved_ids.begin(), moved_ids.end(), r);
    return it != moved_ids.end() && *it == r ? static_cast<std::size_t>(it - moved_ids.begin()) : moved_ids.size();
  }
};

namespace {

// Where a snap vertex is written: the antimeridian at -180, as everywhere else in a file.
std::pair<double, double> written_position(const lonlat::SnapVertex& q) {
  return {q.lon == 180 ? -180.0 : q.lon, q.lat};
}

}  // namespace

void CellGeometry::snap_round_thin_cells(std::span<const SiteId> thin_sites) {
  SnapRegion region;
  mark_thin_region(thin_sites, region);
  collect_region_edges(region);
  find_moved_vertices(region);
  build_snap_paths(region);
  // Crossings of the antimeridian on the great-circle arc, as loop_to_polygons takes them (the
  // same bits whichever way the segment runs).
  const std::vector<BoundaryPoint>& points = region.points;
  auto crossing_lat = [&points](const lonlat::SnapVertex& p, const lonlat::SnapVertex& q) {
    const Vec3 &a = points[p.tag].v, &b = points[q.tag].v;
    return SiteEncoder::to_lat_lon(std::fabs(b.y) * a + std::fabs(a.y) * b).lat_deg;
  };
  lonlat::snap_round(region.paths, region.extra, region.decimals, crossing_lat);
  const std::vector<SiteId> touched = move_vertices(region);
  store_rerouted_points(region);
  mark_keep_lon(region);
  snapped_part_ = static_cast<std::uint32_t>(points_.size());
  add_touched_edges(touched, region);
  recompute_area_terms(region);
}

void CellGeometry::mark_thin_region(std::span<const SiteId> thin_sites, SnapRegion& region) const {
  const VoronoiDiagram& vd = *vd_;
  // The thin cells (ring 1) have their edges snap rounded; their neighbours (ring 2) give hot
  // pixels (every position of their edges) and take the rerouted edges they share.
  std::vector<std::uint8_t>& ring = region.ring;
  ring.assign(vd.site_capacity(), 0);
  for (const SiteId s : thin_sites)
    if (ring[s] == 0) ring[s] = 1, region.cells[0].push_back(s);
  for (const SiteId s : region.cells[0])
    for (const SiteId w : vd.cell_neighbors(s))
      if (ring[w] == 0) ring[w] = 2, region.cells[1].push_back(w);
}

void CellGeometry::add_region_edge(SiteId s, std::size_t i, bool rerouted, SnapRegion& region) const {
  const VoronoiDiagram& vd = *vd_;
  const SiteId w = vd.cell_neighbors(s)[i];
  const SiteId lo = std::min(s, w), hi = std::max(s, w);
  const std::span<const SiteId> lo_nbrs = vd.cell_neighbors(lo), hi_nbrs = vd.cell_neighbors(hi);
  const std::span<const TriId> lo_tris = vd.cell_vertices(lo);
  if (std::count(lo_nbrs.begin(), lo_nbrs.end(), hi) != 1 || std::count(hi_nbrs.begin(), hi_nbrs.end(), lo) != 1)
    return;
  const std::size_t j = lo == s ? i : static_cast<std::size_t>(std::find(lo_nbrs.begin(), lo_nbrs.end(), hi) - lo_nbrs.begin());
  const std::size_t k = static_cast<std::size_t>(std::find(hi_nbrs.begin(), hi_nbrs.end(), lo) - hi_nbrs.begin());
  const std::size_t slot = static_cast<std::size_t>(lo_nbrs.data() - nbr_base_) + j;
  const TriId a = lo_tris[j], b = lo_tris[j + 1 == lo_tris.size() ? 0 : j + 1];
  if (edge_slots_[slot].part == 0) return;
  region.edges.push_back({slot, static_cast<std::size_t>(hi_nbrs.data() - nbr_base_) + k, a, b, lo,
                          static_cast<std::uint32_t>(j), rerouted});
}

void CellGeometry::collect_region_edges(SnapRegion& region) const {
  for (int r = 0; r < 2; ++r)
    for (const SiteId s : region.cells[r]) {
      const std::span<const SiteId> nbrs = vd_->cell_neighbors(s);
      for (std::size_t i = 0; i < nbrs.size(); ++i) {
        const SiteId w = nbrs[i];
        if (w < s && region.ring[w] != 0) continue;  // found from w
        add_region_edge(s, i, region.ring[s] == 1 || region.ring[w] == 1, region);
      }
    }
}

void CellGeometry::find_moved_vertices(SnapRegion& region) const {
  // The grid: the output's decimals, at most kThinCellDecimals (the sides of a thin cell cross
  // at that scale).
  region.decimals = thin_cell_decimals(options_.precision);
  // The ends of the rerouted edges are then written on the grid: they move
  // only when the grid is coarser than the output's decimals.
  region.moves = region.decimals != options_.precision;
  std::vector<TriId>& moved_ids = region.moved_ids;
  if (region.moves)
    for (const SnapRegion::Edge& edge : region.edges)
      if (edge.rerouted) moved_ids.insert(moved_ids.end(), {edge.a, edge.b});
  std::sort(moved_ids.begin(), moved_ids.end());
  moved_ids.erase(std::unique(moved_ids.begin(), moved_ids.end()), moved_ids.end());
  region.moved_set.assign(region.moves ? vd_->num_vertices() : 0, false);
  for (const TriId r : moved_ids) region.moved_set[r] = true;
}

void CellGeometry::build_snap_paths(SnapRegion& region) const {
  const int decimals = region.decimals;
  auto on_grid = [decimals](double x) { return snap_to_decimals(x, decimals); };
  std::vector<BoundaryPoint>& points = region.points;
  // A vertex of a rerouted edge is taken as computed (its written position is then on the
  // grid); one of an edge left as it is, which only gives a hot pixel, as written.
  auto vertex = [&](const BoundaryPoint& q, bool grid, bool rerouted) {
    const Pt raw = rerouted ? make_pt(q.v, kFullPrecision) : Pt{q.v, q.lon, q.lat};
    double lon = grid ? on_grid(raw.lon) : q.lon, lat = grid ? on_grid(raw.lat) : q.lat;
    // The antimeridian is written at -180: here on the side of the raw position.
    if (lon == -180 && raw.lon > 0) lon = 180;
    points.push_back(q);
    return lonlat::SnapVertex{raw.lon, raw.lat, lon, lat, static_cast<std::uint32_t>(points.size() - 1)};
  };
  {  // every cell at coarse precisions: reserved, not grown
    std::size_t total = 0, rerouted = 0;
    for (const SnapRegion::Edge& edge : region.edges)
      total += edge_slots_[edge.slot].count + 2, rerouted += edge.rerouted;
    points.reserve(total);
    region.paths.reserve(rerouted);
    region.path_edge.reserve(rerouted);
  }
  for (std::size_t k = 0; k < region.edges.size(); ++k) {
    const SnapRegion::Edge& edge = region.edges[k];
    const EdgeSlot& e = edge_slots_[edge.slot];
    const Vertex &va = vertices_[edge.a], &vb = vertices_[edge.b];
    std::vector<lonlat::SnapVertex> path;
    path.reserve(e.count + 2);
    path.push_back(vertex({va.v, va.lon, va.lat}, region.moved(edge.a), edge.rerouted || region.moved(edge.a)));
    const BoundaryPoint* p = points_[e.part - 1].data() + e.first;
    for (std::uint32_t i = 0; i < e.count; ++i) path.push_back(vertex(p[i], edge.rerouted, edge.rerouted));
    path.push_back(vertex({vb.v, vb.lon, vb.lat}, region.moved(edge.b), edge.rerouted || region.moved(edge.b)));
    if (edge.rerouted) {
      region.paths.push_back(std::move(path));
      region.path_edge.push_back(k);
    } else {
      region.extra.insert(region.extra.end(), path.begin(), path.end());
    }
  }
}

std::vector<SiteId> CellGeometry::move_vertices(SnapRegion& region) {
  const VoronoiDiagram& vd = *vd_;
  std::vector<std::pair<double, double>> moved_to(region.moved_ids.size());
  std::vector<std::array<SiteId, 3>> moved_sites(region.moved_ids.size());  // each one's triangle's sites
  for (std::size_t k = 0; k < region.paths.size() && region.moves; ++k) {
    const SnapRegion::Edge& edge = region.edges[region.path_edge[k]];
    moved_to[region.moved_index(edge.a)] = written_position(region.paths[k].front());
    moved_to[region.moved_index(edge.b)] = written_position(region.paths[k].back());
    // Vertex j of cell lo (the edge's start) has the sites lo, neighbours j - 1 and j; vertex
    // j + 1 (its end) lo, neighbours j and j + 1.
    const std::span<const SiteId> nbrs = vd.cell_neighbors(edge.lo);
    const std::size_t d = nbrs.size(), j = edge.j;
    moved_sites[region.moved_index(edge.a)] = {edge.lo, nbrs[(j + d - 1) % d], nbrs[j]};
    moved_sites[region.moved_index(edge.b)] = {edge.lo, nbrs[j], nbrs[(j + 1) % d]};
  }
  // The cells around a moved vertex beyond the region need their edges' area terms again.
  std::vector<SiteId> touched;
  for (std::size_t k = 0; k < region.moved_ids.size(); ++k) {
    const TriId t = region.moved_ids[k];
    std::tie(vertices_[t].lon, vertices_[t].lat) = moved_to[k];
    for (const SiteId s : moved_sites[k])
      if (region.ring[s] == 0) region.ring[s] = 3, touched.push_back(s);
  }
  return touched;
}

void CellGeometry::store_rerouted_points(const SnapRegion& region) {
  std::vector<BoundaryPoint>& part = points_.emplace_back();
  for (std::size_t k = 0; k < region.paths.size(); ++k) {
    const std::vector<lonlat::SnapVertex>& path = region.paths[k];
    EdgeSlot& e = edge_slots_[region.edges[region.path_edge[k]].slot];
    e.first = static_cast<std::uint32_t>(part.size());
    e.count = static_cast<std::uint32_t>(path.size() - 2);
    e.part = static_cast<std::uint32_t>(points_.size());
    for (std::size_t i = 1; i + 1 < path.size(); ++i) {
      const lonlat::SnapVertex& v = path[i];
      BoundaryPoint q;
      if (v.tag == lonlat::kNewVertex) {  // a crossing of the antimeridian: on it, exactly
        q.v = SiteEncoder::from_lat_lon(v.lat, -180);
        q.v.y = 0;
      } else {
        q = region.points[v.tag];
      }
      std::tie(q.lon, q.lat) = written_position(v);
      part.push_back(q);
    }
  }
}

// A point written on a pole line but not at the pole, where every edge through it is snap
// rounded, is drawn there at its own longitude (loop_to_polygons' keep_lon) by every cell
// through it: the snap rounded picture around it is valid as it is. Drawn by the rules of a
// vertex at the pole (meridians down from its neighbours, a run along the line between them),
// a lune's tip 5 mm from the south pole ran back west along the line and rose through its own
// incoming side one row up (a ring of 40 sites around the north pole, 7 decimals: fuzz_cells).
// The pole's owner too (loop_to_polygons then runs it a whole turn along the line from the
// point when that is its only visit there). The edges' points: in build().
void CellGeometry::mark_keep_lon(const SnapRegion& region) {
  std::vector<TriId> ends;  // vertices on a pole line, once per snap rounded edge
  for (std::size_t k = 0; k < region.paths.size(); ++k) {
    const SnapRegion::Edge& edge = region.edges[region.path_edge[k]];
    for (const bool front : {true, false}) {
      const lonlat::SnapVertex& end = front ? region.paths[k].front() : region.paths[k].back();
      if (lonlat::is_pole(written_position(end).second) && !lonlat::at_pole(region.points[end.tag].v))
        ends.push_back(front ? edge.a : edge.b);
    }
  }
  std::sort(ends.begin(), ends.end());
  for (std::size_t i = 0; i < ends.size();) {
    std::size_t j = i;
    while (j < ends.size() && ends[j] == ends[i]) ++j;
    if (j - i == 3) vertices_[ends[i]].flags |= kKeepLon;  // its three edges
    i = j;
  }
}

void CellGeometry::add_touched_edges(std::span<const SiteId> touched, SnapRegion& region) const {
  const std::vector<std::uint8_t>& ring = region.ring;
  for (const SiteId s : touched) {
    const std::span<const SiteId> nbrs = vd_->cell_neighbors(s);
    for (std::size_t i = 0; i < nbrs.size(); ++i) {
      const SiteId w = nbrs[i];
      if ((w < s && ring[w] == 3) || ring[w] == 1 || ring[w] == 2) continue;  // found from w, or in `edges`
      add_region_edge(s, i, false, region);
    }
  }
}

void CellGeometry::recompute_area_terms(const SnapRegion& region) {
  std::vector<Pt> interior;
  std::vector<GeodesicEdge> segments;
  std::vector<double> s12;
  for (const SnapRegion::Edge& edge : region.edges) {
    EdgeSlot& e = edge_slots_[edge.slot];
    const Vertex &va = vertices_[edge.a], &vb = vertices_[edge.b];
    if (!edge.rerouted && !region.moved(edge.a) && !region.moved(edge.b)) continue;
    interior.clear();
    const BoundaryPoint* p = points_[e.part - 1].data() + e.first;
    for (std::uint32_t i = 0; i < e.count; ++i) interior.push_back({p[i].v, p[i].lon, p[i].lat});
    segments.clear();
    e.crossings = append_segments(Pt{va.v, va.lon, va.lat}, interior, Pt{vb.v, vb.lon, vb.lat}, segments);
    s12.resize(segments.size());
    geodesic_s12(segments, s12);
    e.s12 = sum_s12(s12);
    edge_slots_[edge.other] = e;
  }
}

void CellGeometry::edge_guards(SiteId lo, SiteId hi, const Vertex& a, const Vertex& b, std::vector<Vec3>& guards) const {
  guards.clear();
  const VoronoiDiagram& vd = *vd_;
  const double far = 8 * options_.densify_m / SiteEncoder::kEarthRadiusM;
  for (const SiteId c : {lo, hi}) {
    const SiteId across = c == lo ? hi : lo;
    const std::span<const TriId> tris = vd.cell_vertices(c);
    const std::span<const SiteId> nbrs = vd.cell_neighbors(c);
    const std::size_t d = tris.size();
    for (std::size_t i = 0; i < d; ++i) {
      if (nbrs[i] == across) continue;
      const Vertex& f0 = vertices_[tris[i]];
      const Vertex& f1 = vertices_[tris[i + 1 == d ? 0 : i + 1]];
      const bool at_a = &f0 == &a || &f1 == &a, at_b = &f0 == &b || &f1 == &b;  // vertices_ entries
      const Vec3 n = vd.is_weighted() ? vd.bisector_normal(c, nbrs[i]) : lonlat::normalized(vd.site(c) - vd.site(nbrs[i]));
      if (at_a && at_b) {
        // The other side of a lune (its ends ours): the side it must keep clear
        // of most. Its chords had crossed a lune 0.39 m wide (relax of a column).
      } else if (at_a || at_b) {
        // A side at a common vertex comes close only where the angle between them is acute.
        const Vec3& v = at_a ? a.v : b.v;
        const Vec3& e_far = at_a ? b.v : a.v;
        const Vec3& f_far = (&f0 == (at_a ? &a : &b)) ? f1.v : f0.v;
        if (dot(e_far - dot(v, e_far) * v, f_far - dot(v, f_far) * v) <= 0) continue;
      } else if (std::min(std::fabs(dot(a.v, n)), std::fabs(dot(b.v, n))) >= far) {
        continue;  // the distance along the edge is least at an end (concave): never binding
      }
      guards.push_back(n);
    }
  }
}

void CellGeometry::prefetch(SiteId s, int stage) const {
  const VoronoiDiagram& vd = *vd_;
  if (!edge_slots_ || !vd.has_cell(s)) return;
  const std::span<const TriId> tris = vd.cell_vertices(s);
  const std::span<const SiteId> nbrs = vd.cell_neighbors(s);
  const EdgeSlot* own = edge_slots_.get() + (nbrs.data() - nbr_base_);
  // Every cache line of [p, p + bytes).
  auto lines = [](const void* p, std::size_t bytes) {
    const char* c = static_cast<const char*>(p);
    for (std::size_t k = 0; k < bytes; k += 64) __builtin_prefetch(c + k);
    if (bytes > 0) __builtin_prefetch(c + bytes - 1);
  };
  switch (stage) {
    case 0:
      vd.prefetch(s, 1);  // the cell's lists
      lines(own, tris.size() * sizeof(EdgeSlot));
      break;
    case 1:
      for (const TriId t : tris) {
        lines(&vertices_[t], sizeof(Vertex));
        lines(&vd.vertex(t), sizeof(Vec3));
      }
      break;
    default:
      for (std::size_t i = 0; i < tris.size(); ++i)
        if (own[i].part != 0 && own[i].count != 0)
          lines(points_[own[i].part - 1].data() + own[i].first, std::min<std::size_t>(own[i].count, 8) * sizeof(BoundaryPoint));
      break;
  }
}

MultiPolygon CellGeometry::polygon(SiteId s, BBox* bbox) const {
  MultiPolygon out;
  polygon(s, out, bbox);
  return out;
}

void CellGeometry::polygon(SiteId s, MultiPolygon& out, BBox* bbox) const { build(s, out, bbox, nullptr); }

CellStatus CellGeometry::polygon(SiteId s, MultiPolygon& out, double& area_m2, BBox* bbox) const {
  return build(s, out, bbox, &area_m2);
}

CellStatus CellGeometry::check_near_pole(SiteId s, bool near_pole, MultiPolygon& out, BBox* bbox,
                                         double& area_m2) const {
  // Within a few decimal steps of a pole, longitudes are ill-conditioned: a computed vertex a
  // nanodegree from the pole, on its far side, can turn a thin lune into a cell around the Earth
  // (fuzz_cells). Cells reaching that close, or cut at +-180, are rare: their area is checked
  // against the cell's on the sphere, and one that disagrees is reported, not written wrong.
  if (!(near_pole || out.size() > 1) ||
      cell_areas_agree(area_m2, vd_->cell_area_sr(s), out, options_.densify_m, options_.precision))
    return CellStatus::Written;
  out.clear();
  area_m2 = 0;
  if (bbox) *bbox = BBox{};
  return CellStatus::Unwritable;
}

CellStatus CellGeometry::finish(SiteId s, const lonlat::LoopInfo& info, MultiPolygon& out, BBox* bbox) const {
  const int winding = info.winding;
  if (info.tangled) {
    out.clear();
    if (bbox) *bbox = BBox{};
    return CellStatus::Unwritable;
  }
  if (out.empty()) return CellStatus::Collapsed;
  if (winding != 0 || s == north_owner_ || s == south_owner_) {
    auto unwritable = [&] {
      // A ring with no area left collapsed, though rounding made it wind around a pole it does
      // not own: its spikes removed, it lies on a line, or (winding around a pole) on the pole
      // lines only, its sides rounded onto meridians and the rest onto the pole line.
      MultiPolygon cleaned = out;
      bool on_poles = winding != 0;
      for (Polygon& poly : cleaned) {
        remove_spikes(poly.exterior);
        for (const LonLat& p : poly.exterior) on_poles &= std::fabs(p.lat_deg) == 90;
      }
      const bool collapsed = on_poles || certify_written(cleaned) == CellStatus::Collapsed;
      out.clear();
      if (bbox) *bbox = BBox{};
      return collapsed ? CellStatus::Collapsed : CellStatus::Unwritable;
    };
    // The poles, decided exactly: a ring may enclose a pole only if its site owns it; the
    // owner's ring must enclose it or pass through it (rounding can put the pole on its
    // boundary). A rounded wedge at a pole turned the wrong way otherwise gives a cell around
    // the whole Earth.
    bool at_north = false, at_south = false;
    for (const Polygon& poly : out)
      for (const LonLat& p : poly.exterior) {
        at_north |= p.lat_deg == 90;
        at_south |= p.lat_deg == -90;
      }
    if ((winding > 0 && s != north_owner_) || (winding < 0 && s != south_owner_) ||
        (s == north_owner_ && winding <= 0 && !at_north) || (s == south_owner_ && winding >= 0 && !at_south))
      return unwritable();
    for (const Polygon& poly : out)
      if (std::fabs(planar_area_deg2(poly.exterior)) >= kWholeDeg2 * (1 - 1e-12)) return unwritable();
  }
  bool cleaned = false;
  const CellStatus status = certify_written(out, &cleaned);
  if (status != CellStatus::Written) {
    if (bbox) *bbox = BBox{};
    return status;
  }
  if (cleaned && bbox) {
    // The removed spikes may have held an extreme: the box of what is left (the rules of
    // loop_to_polygons: polar or cut boxes keep their longitudes, a ring cannot lose a pole).
    BBox b = *bbox;
    b.south = 90, b.north = -90;
    for (const Polygon& poly : out)
      for (const LonLat& p : poly.exterior) b.south = std::min(b.south, p.lat_deg), b.north = std::max(b.north, p.lat_deg);
    if (out.size() == 1 && !(b.west == -180 && b.east == 180)) {
      b.west = 180, b.east = -180;
      for (const LonLat& p : out[0].exterior) b.west = std::min(b.west, p.lon_deg), b.east = std::max(b.east, p.lon_deg);
    }
    *bbox = b;
  }
  return CellStatus::Written;
}

CellStatus CellGeometry::build(SiteId s, MultiPolygon& out, BBox* bbox, double* area_m2) const {
  const VoronoiDiagram& vd = *vd_;
  // Whether s holds each pole in its interior (0 when nobody does: a tie puts it on a boundary).
  auto pole_owner = [this](SiteId site) {
    return lonlat::PoleOwner{site == north_owner_, site == south_owner_};
  };
  if (area_m2) *area_m2 = 0;
  if (bbox) *bbox = BBox{};
  if (!vd.has_cell(s)) {
    out.clear();
    return CellStatus::Collapsed;
  }
  if (vd.kind() == VoronoiDiagram::Kind::WholeSphere) {
    out.resize(1);
    out[0].holes.clear();
    out[0].exterior.assign({{-180, -90}, {180, -90}, {180, 90}, {-180, 90}, {-180, -90}});
    if (bbox) *bbox = {-180, -90, 180, 90};
    if (area_m2) *area_m2 = ellipsoid_area_m2(out);
    return CellStatus::Written;
  }

  std::vector<Pt>& loop = scratch<Pt, 0>();
  std::vector<Pt>& edge = scratch<Pt, 1>();
  std::vector<std::uint32_t>& keep_lon = scratch<std::uint32_t>();  // loop_to_polygons' keep_lon
  loop.clear();
  keep_lon.clear();
  // Made when an edge is densified here (its constructor's powers cost more than a cell's
  // usual work: the edges were densified at construction).
  std::optional<Densifier> densifier;
  auto dens = [&]() -> Densifier& {
    if (!densifier) densifier.emplace(options_.densify_m, options_.max_step_deg, options_.max_depth, edge, options_.precision);
    return *densifier;
  };

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
    const EdgeSides sides = edge_sides(lo, std::max(s, other));
    const Vec3& left = sides.left;
    const Vec3& right = sides.right;
    for (int i = 0; i < 4; ++i) {
      const Pt a = make_pt(q[i], options_.precision), b = make_pt(q[(i + 1) % 4], options_.precision);
      loop.push_back(a);
      edge.clear();
      dens().edge(a, b, left, right, norm2(left - right));
      loop.insert(loop.end(), edge.begin(), edge.end());
    }
    if (s != lo) std::reverse(loop.begin(), loop.end());
  } else {
    const std::span<const TriId> tris = vd.cell_vertices(s);
    const std::span<const SiteId> nbrs = vd.cell_neighbors(s);
    const std::size_t d = tris.size();
    CompensatedSum area_sum;
    int area_crossings = 0;
    std::vector<GeodesicEdge>& segments = scratch<GeodesicEdge>();
    std::vector<double>& s12 = scratch<double>();
    const EdgeSlot* own = edge_slots_.get() + (nbrs.data() - nbr_base_);  // this cell's slots
    for (std::size_t i = 0; i < d; ++i) {
      const TriId ta = tris[i], tb = tris[i + 1 == d ? 0 : i + 1];
      const Vertex &va = vertices_[ta], &vb = vertices_[tb];
      const Pt a{va.v, va.lon, va.lat}, b{vb.v, vb.lon, vb.lat};
      if (va.flags & kKeepLon) keep_lon.push_back(static_cast<std::uint32_t>(loop.size()));
      loop.push_back(a);
      const SiteId w = nbrs[i];
      const EdgeSlot& e = own[i];
      double sum = 0;
      int crossings = 0;
      if (e.part != 0) {  // computed at construction, in the canonical direction
        if (e.count != 0) {
          const std::size_t first = loop.size();
          const BoundaryPoint* p = points_[e.part - 1].data() + e.first;
          if (s < w) {
            for (std::uint32_t k = 0; k < e.count; ++k) loop.push_back({p[k].v, p[k].lon, p[k].lat});
          } else {
            for (std::uint32_t k = e.count; k-- > 0;) loop.push_back({p[k].v, p[k].lon, p[k].lat});
          }
          if (e.part == snapped_part_) {  // snap rounded: its points on a pole line keep their longitudes
            for (std::size_t k = first; k < loop.size(); ++k)
              if (lonlat::is_pole(loop[k].lat) && !lonlat::at_pole(loop[k].v))
                keep_lon.push_back(static_cast<std::uint32_t>(k));
          }
        }
        sum = e.s12;
        crossings = e.crossings;
      } else {  // the same, in place: canonical direction from the smaller site id
        const bool forward = s < w;
        const Pt& from = forward ? a : b;
        const Pt& to = forward ? b : a;
        edge.clear();
        std::vector<Vec3>& guards = scratch<Vec3>();
        guards.clear();
        if ((va.flags | vb.flags) & (kCap | kNearPole))
          edge_guards(std::min(s, w), std::max(s, w), forward ? va : vb, forward ? vb : va, guards);
        dens().set_guards(guards);
        const EdgeSides sides = edge_sides(std::min(s, w), std::max(s, w));
        dens().edge(from, to, sides.left, sides.right, std::min(va.min_side2, vb.min_side2));
        if (forward)
          loop.insert(loop.end(), edge.begin(), edge.end());
        else
          loop.insert(loop.end(), edge.rbegin(), edge.rend());
        if (area_m2) {
          segments.clear();
          crossings = append_segments(from, edge, to, segments);
          s12.resize(segments.size());
          geodesic_s12(segments, s12);
          sum = sum_s12(s12);
        }
      }
      area_sum += s < w ? sum : -sum;
      area_crossings += s < w ? crossings : -crossings;
    }
    lonlat::LoopInfo info;
    lonlat::loop_to_polygons(loop, out, bbox, options_.precision, &info, pole_owner(s), keep_lon);
    const CellStatus status = finish(s, info, out, bbox);
    if (area_m2 && status == CellStatus::Written) {
      // The edges' sums are the ring's when the ring is the loop itself (same positions, same
      // order): not cut, no pole. Otherwise GeographicLib on the written rings.
      bool same = out.size() == 1 && out[0].holes.empty() && out[0].exterior.size() == loop.size() + 1;
      for (std::size_t j = 0; same && j < loop.size(); ++j)
        same = out[0].exterior[j].lon_deg == loop[j].lon && out[0].exterior[j].lat_deg == loop[j].lat;
      *area_m2 = same ? ring_area_m2(area_sum, area_crossings, out[0].exterior)
                      : ellipsoid_area_m2(out);
      return check_near_pole(s, info.near_pole, out, bbox, *area_m2);
    }
    return status;
  }

  lonlat::LoopInfo info;
  lonlat::loop_to_polygons(loop, out, bbox, options_.precision, &info, pole_owner(s));
  const CellStatus status = finish(s, info, out, bbox);
  if (!area_m2 || status != CellStatus::Written) return status;
  *area_m2 = ellipsoid_area_m2(out);
  return check_near_pole(s, info.near_pole, out, bbox, *area_m2);
}

MultiPolygon cell_polygon(const VoronoiDiagram& diagram, SiteId s,
                          const CellGeometryOptions& options, BBox* bbox) {
  return CellGeometry(diagram, options).polygon(s, bbox);
}

bool cell_areas_agree(double area_m2, double area_sr, const MultiPolygon& written, double densify_m,
                      int precision) {
  // The authalic radius of WGS84: the sphere with the ellipsoid's area.
  static const double authalic2 = wgs84_area_m2() / (4 * std::numbers::pi);
  const double sphere_m2 = area_sr * authalic2;
  const double diff = std::fabs(area_m2 - sphere_m2);
  if (diff <= 0.005 * sphere_m2) return true;
  // Slack along the boundary: the perimeter of what is written (metres, on the sphere; a
  // longitude step counts as a latitude step, an overestimate).
  constexpr double kMetresPerDeg = SiteEncoder::kEarthRadiusM * std::numbers::pi / 180;
  double perimeter_m = 0;
  for (const Polygon& poly : written)
    for (std::size_t i = 0; i + 1 < poly.exterior.size(); ++i)
      perimeter_m += kMetresPerDeg * std::hypot(poly.exterior[i + 1].lon_deg - poly.exterior[i].lon_deg,
                                                poly.exterior[i + 1].lat_deg - poly.exterior[i].lat_deg);
  const double step_m = precision >= 0 ? kMetresPerDeg * std::pow(10.0, -precision) : 0;
  const double slack = 0.005 * sphere_m2 + (500 + densify_m + step_m) * perimeter_m;
  // Below a metre's step, a written cell is its cell within the slack. Coarser, parts of a cell
  // thinner than a step collapse (they are not written), so only a written cell too large is
  // wrong.
  if (step_m >= 1 && area_m2 < sphere_m2) return true;
  return diff <= slack;
}

}  // namespace geovor
