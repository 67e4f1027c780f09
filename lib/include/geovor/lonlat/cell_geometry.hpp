/// \file cell_geometry.hpp
/// \brief Voronoi cells as RFC 7946 polygons in longitude/latitude (degrees), and their area on
/// the WGS84 ellipsoid.
///
/// The pipeline (../shared/research/gis.md, sections 0, 1, 4 and 5):
///  1. Every edge is densified along its great circle by adaptive bisection on the sphere: an
///     arc is split while the great-circle midpoint is farther than densify_m from the midpoint
///     of the straight lon/lat segment, or while it is longer than max_step_deg, down to
///     max_depth levels. Near sites closer than 4 densify_m the tolerance of an edge drops to a
///     quarter of the shortest side of its two Delaunay triangles (at most a quarter of the
///     distance between its two sites), so every site stays inside its written cell. Near the
///     vertex of a cap (a cell angle below 3.6 degrees: thin lunes), and at vertices near a pole
///     (where the plate carree can turn a chord by a degree: above 84 degrees of latitude for
///     densify_m 100), a piece is also split until it deviates by at most an eighth of its
///     distance to the other sides of both cells, so that no two chords cross
///     (lonlat::Densifier::set_guards).
///     180-degree edges (lunes, three sites) are split by rotating in their bisector plane; an
///     arc with a pole as an end point is a meridian and is not split (except pole to pole); an
///     arc passing within kSnapRad of a pole is split at the pole. An edge is always densified in one canonical direction, from the cell of
///     the smaller site id, and reversed for the other cell, so both cells carry bit-identical
///     vertices and the tiling has neither gaps nor overlaps.
///  2. Points on the sphere become geodetic longitude/latitude with SiteEncoder::to_lat_lon
///     (geocentric direction -> geodetic latitude). Points within kSnapRad of a pole become the
///     pole, and points within kSnapRad of the antimeridian land exactly on it, so rounding
///     noise never decides a side.
///  3. A vertex at a pole is replaced by two pole positions carrying the longitudes of the
///     incoming and outgoing edges (a point merely written on the pole line, all of whose
///     edges are snap rounded, below, keeps its own longitude in every cell through it).
///     Longitudes are unwrapped: the winding is 0, or +-360 for a
///     cell holding a pole.
///  4. A cell crossing +-180 is cut there into a MultiPolygon; the crossing latitude is the
///     intersection of the (densified) great-circle arc with the antimeridian, identical for
///     both parts and both cells. A cell holding a pole runs from -180 to 180 along its boundary
///     and is closed through (180, +-90) and (-180, +-90).
///  Where a decimal step can be wider than a cell (near the vertex of a cap, or sites a few steps
///  apart), the edges of those cells are snap rounded at construction (kThinCellDecimals,
///  lonlat/snap_rounding.hpp): routed through every written position within a step, so that
///  rounding merges their thin parts instead of folding them; at kSnapAllDecimals or fewer, the
///  edges of every cell.
///  5. Rings are closed by an exact copy of the first position, exterior rings counter-clockwise
///     in (lon, lat) (planar signed area > 0), without consecutive duplicates, longitudes within
///     [-180, 180] and latitudes within [-90, 90].
/// One site gives the whole sphere [-180, 180] x [-90, 90]; two sites give two hemispheres.
///
/// Voronoi vertices are written where they are computed, never merged: co-circular sites give
/// several triangles with one circumcentre, computed as copies millimetres apart, and their
/// short edges are snap rounded (above); merging them had moved a vertex across a neighbouring
/// lune's side. Every cell contains a disk of radius 0.19 m around its site (sites are at least
/// 0.38 m apart), so no cell vanishes.
#pragma once

#include <algorithm>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <span>
#include <vector>

#include "geovor/core/coordinate_grid.hpp"
#include "geovor/core/types.hpp"
#include "geovor/lonlat/ellipsoid_area.hpp"
#include "geovor/lonlat/geometry.hpp"
#include "geovor/lonlat/polygon_validity.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace geovor {

namespace lonlat {
struct LoopInfo;        // lib/src/lonlat/boundary.hpp (private)
struct ThinThresholds;  // lib/src/lonlat/thin_triangles.hpp (private)
}

/// Options of the lon/lat cell geometry; every default is documented.
struct CellGeometryOptions {
  /// Largest distance (metres, on the sphere of radius SiteEncoder::kEarthRadiusM) between a
  /// written straight lon/lat segment's midpoint and the true great-circle arc. DEFAULT: 100 m.
  /// Edges near sites closer than 4 densify_m get a finer tolerance (see the file comment).
  /// REQUIRES: > 0.
  double densify_m = 100;
  /// Arcs longer than this (degrees) are always split, so the midpoint test is meaningful.
  /// DEFAULT: 1 degree. REQUIRES: > 0.
  double max_step_deg = 1;
  /// Recursion depth cap of the bisection of one edge, except within metres of a pole, where a
  /// piece is split on until it is within an eighth of its distance to the pole (a side from
  /// pole to pole reaches 20 levels at pieces of 19 m), and near the other sides of a thin cell,
  /// until it is within an eighth of its distance to them (lonlat::Densifier::set_guards).
  /// DEFAULT: 20. REQUIRES: in [1, 40].
  int max_depth = 20;
  /// Threads computing the vertices' lon/lat and the edges at construction (0: one per core).
  /// DEFAULT: 1.
  /// The result does not depend on it.
  unsigned threads = 1;
  /// Decimals of the written coordinates (0..17), or kFullPrecision for formats that store
  /// doubles. Every position is computed as a reader of the file gets it back
  /// (snap_to_decimals), so that the polygons are checked, and area_m2 measured, as written.
  /// DEFAULT: kFullPrecision.
  int precision = kFullPrecision;
};

/// What became of a cell when built at its precision (see CellGeometry::polygon): Written,
/// Collapsed or Unwritable (polygon_validity.hpp).
using CellStatus = WrittenStatus;

/// Builds the lon/lat polygons of the cells of one VoronoiDiagram. Construction precomputes, for
/// every Voronoi vertex, its snapped position and its lon/lat, and
/// for every Voronoi edge, once, its densified points and its geodesic area terms, in one slot
/// per edge and cell (24 bytes, about 144 bytes per site, plus 40 bytes per densified point);
/// O(size of the diagram and of the densified edges), on options.threads threads. Each cell is
/// then built in O(its output size). The diagram must outlive this object. polygon() is
/// thread-safe (scratch buffers are thread-local). Building the cells in
/// VoronoiDiagram::storage_order() is faster than by id when ids are spatially random.
class CellGeometry {
 public:
  /// Points within this angle (radians on the unit sphere, 1.5e-11, about 0.1 mm) of a pole or
  /// of the antimeridian are moved onto it.
  static constexpr double kSnapRad = 0x1p-36;
  /// Near the vertex of a cap (three sites nearly on one great circle: the tips of the lunes of
  /// sites on one meridian), cells are narrower than a decimal step over kilometres and their
  /// sides are snap rounded (Hobby) to the grid of options().precision decimals, or of this many
  /// (1.1 cm) at a finer or full precision: the sides of a lune whose angle is a microradian
  /// crossed at that scale even in doubles.
  static constexpr int kThinCellDecimals = 7;
  /// The decimals of the grid thin cells are snap rounded to at output `precision` (kFullPrecision
  /// or < 0: full): the output's, at most kThinCellDecimals.
  static constexpr int thin_cell_decimals(int precision) {
    return precision < 0 ? kThinCellDecimals : std::min(precision, kThinCellDecimals);
  }
  /// At this many decimals or fewer (a step of a kilometre or more) every cell is snap rounded,
  /// not only the thin ones and their neighbours: a step can reach cells beyond those, whose
  /// positions would not be hot pixels (a band of cells fell onto one row of steps).
  static constexpr int kSnapAllDecimals = 2;

  /// @exception Error(InvalidArgument) if an option is out of range.
  explicit CellGeometry(const VoronoiDiagram& diagram, const CellGeometryOptions& options = {});

  /// The cell of site s as a MultiPolygon (empty if s has no cell), following the file comment.
  /// \param[out] bbox if not null, the RFC 7946 bounding box [west, south, east, north]
  ///   (degrees): west > east for a cell cut at the antimeridian, west = -180 and east = 180
  ///   for a cell holding a pole (or spanning all longitudes).
  MultiPolygon polygon(SiteId s, BBox* bbox = nullptr) const;
  /// Same, reusing the storage of `out` (no allocation once its capacity suffices).
  void polygon(SiteId s, MultiPolygon& out, BBox* bbox = nullptr) const;
  /// Same, with the cell's area on the WGS84 ellipsoid, ellipsoid_area_m2(out) (0 when the
  /// status is not Written, as `out` is then empty): the area of the rings as written, computed
  /// faster: the geodesic area terms S12 (geodesic_s12(), which reproduces GeographicLib's
  /// Geodesic::GenInverse) of each densified Voronoi edge are summed once, at construction, in
  /// its canonical direction, and shared by its two cells (negated for the second); cells cut
  /// at the antimeridian or holding a pole use ellipsoid_area_m2(out) itself. The two agree
  /// within rounding: 1e-9 relative, or 4 ulps of the ellipsoid's area (0.25 m^2) for
  /// tiny cells. Thread-safe; the result does not depend on threads.
  /// Positions are written with options().precision decimals; a spike left by an edge that
  /// collapsed is removed (the same on both sides of the edge), a ring passing twice through a
  /// position (thin cells snap rounded) is split there into parts; the result is then checked
  /// exactly (polygon_problem() in polygon_validity.hpp). Returns the cell's status: when it is
  /// not Written, `out` is empty and the caller reports the cell.
  CellStatus polygon(SiteId s, MultiPolygon& out, double& area_m2, BBox* bbox = nullptr) const;

  /// A memory hint for callers that build many cells in an order other than storage_order()
  /// (input order, say): the cells' data is then scattered and polygon() waits on memory. Call
  /// prefetch(s, 0) some cells before polygon(s) (the cell's lists and edge slots), prefetch(s,
  /// 1) a few cells later (its vertices, here and in the diagram, which cell_area_sr() reads),
  /// then prefetch(s, 2) (its densified points). Changes no result; thread-safe.
  void prefetch(SiteId s, int stage) const;

  const VoronoiDiagram& diagram() const { return *vd_; }
  const CellGeometryOptions& options() const { return options_; }

 private:
  const VoronoiDiagram* vd_;
  CellGeometryOptions options_;
  // Arrays from calloc: fresh zero pages, first touched by the threads that fill them.
  struct Free {
    void operator()(void* p) const { std::free(p); }
  };
  // Per Voronoi vertex, in 48 bytes: its snapped position and longitude/latitude (degrees), the
  // squared chord of the shortest side of its triangle (a lower bound of the distance between
  // the sites of an edge), and flags: its triangle is a cap (kCap), it lies near a pole
  // (kNearPole); the edges at such a vertex are guarded (edge_guards). See the constructor.
  // kKeepLon: written on a pole line, drawn there at its own longitude (snap_round_thin_cells).
  struct Vertex {
    Vec3 v;
    double lon, lat;
    float min_side2;
    std::uint8_t flags;
  };
  static_assert(sizeof(Vertex) == 48);
  std::unique_ptr<Vertex[], Free> vertices_;
  static constexpr std::uint8_t kCap = 1, kNearPole = 2, kKeepLon = 4;
  // Per Voronoi edge and each of its two cells, in that cell's slot (slot = index in the
  // diagram's neighbour lists), computed at construction in the direction of the canonical cell
  // (the smaller site id): its densified points strictly between its end vertices
  // (points_[part - 1][first .. first + count)), the sum of S12 over its segments, and its
  // prime-meridian crossings (PolygonArea's transit); part 0: not computed, when the two sites
  // share more than this one edge (tiny diagrams), and the larger site's cell computes it in place.
  struct EdgeSlot {
    double s12;
    std::uint32_t first, count;
    std::int32_t crossings;
    std::uint32_t part;
  };
  std::unique_ptr<EdgeSlot[], Free> edge_slots_;
  std::size_t num_edge_slots_ = 0;
  const SiteId* nbr_base_ = nullptr;  // cell_neighbors() of the first cell in storage
  struct BoundaryPoint {
    Vec3 v;
    double lon, lat;
  };
  std::vector<std::vector<BoundaryPoint>> points_;  // one part per construction thread
  // The part (EdgeSlot::part) of the snap rounded edges' points (0: none): those written on a
  // pole line but not at the pole are drawn at their own longitudes, as vertices with kKeepLon.
  std::uint32_t snapped_part_ = 0;
  CellStatus build(SiteId s, MultiPolygon& out, BBox* bbox, double* area_m2) const;
  // The stages of construction, in order (cell_geometry.cpp).
  // north_owner_ and south_owner_.
  void find_pole_owners();
  // vertices_' min_side2 and flags, each triangle once; returns the sites whose cells are snap
  // rounded (snap_round_thin_cells): near a cap's vertex or a short side, or every cell at
  // kSnapAllDecimals or fewer.
  std::vector<SiteId> classify_triangles(unsigned threads);
  // classify_triangles for the triangles of cell s it owns (s their smallest site), appending
  // the sites of thin ones to `thin`; returns how many.
  std::size_t classify_cell(SiteId s, const lonlat::ThinThresholds& th, std::vector<SiteId>& thin);
  // vertices_' snapped positions and lon/lat.
  void compute_vertex_lonlat(unsigned threads);
  // edge_slots_ and points_: every edge densified once, with its area terms.
  struct EdgeWork;
  void densify_edges(unsigned threads);
  // Memory hints for densify_cell_edges some cells ahead of order[j].
  void prefetch_edge_inputs(std::span<const SiteId> order, std::size_t j) const;
  // The edges of cell s it is canonical for (the smaller site id), into both their slots.
  void densify_cell_edges(SiteId s, unsigned thread, EdgeWork& work);
  // The slot of cell w for its edge with s, or ~0 when they share more than that edge.
  std::size_t other_slot(SiteId s, SiteId w) const;
  // The great circles the edge between sites lo < hi, from vertex a to vertex b (entries of
  // vertices_, told apart by address), must keep clear of when one of its cells is thin
  // (Densifier::set_guards), into `guards`. Called only
  // for an edge at a cap's vertex or one near a pole (Vertex::flags): cells are thin only at caps, and
  // only near a pole can the plate carree turn chords by more than a cap's angle.
  void edge_guards(SiteId lo, SiteId hi, const Vertex& a, const Vertex& b, std::vector<Vec3>& guards) const;
  // Snap rounds (lonlat/snap_rounding.hpp) the edges of the cells of `thin_sites` and of their
  // neighbours, at a decimal precision: near a cap's vertex a cell can be narrower than a step
  // over kilometres, and its rounded sides crossed. Called at the end of construction.
  void snap_round_thin_cells(std::span<const SiteId> thin_sites);
  // The stages of snap_round_thin_cells, in order, on its working state (cell_geometry.cpp).
  struct SnapRegion;
  // The thin cells (ring 1) and their neighbours (ring 2).
  void mark_thin_region(std::span<const SiteId> thin_sites, SnapRegion& region) const;
  // Every edge of those cells once, rerouted when one of its cells is thin.
  void collect_region_edges(SnapRegion& region) const;
  // The edge between s and its neighbour i, from its canonical cell, unless computed in place.
  void add_region_edge(SiteId s, std::size_t i, bool rerouted, SnapRegion& region) const;
  // The grid, and the rerouted edges' ends it moves (a grid coarser than the output's).
  void find_moved_vertices(SnapRegion& region) const;
  // The edges as paths of snap vertices: rerouted ones to snap_round, the others' hot pixels.
  void build_snap_paths(SnapRegion& region) const;
  // Writes the moved vertices where snap_round put them; returns the cells beyond the region
  // around them (ring 3), whose edges' area terms change.
  std::vector<SiteId> move_vertices(SnapRegion& region);
  // The rerouted edges' points, in a part of points_ of their own (snapped_part_).
  void store_rerouted_points(const SnapRegion& region);
  // kKeepLon on the vertices written on a pole line whose three edges are all snap rounded.
  void mark_keep_lon(const SnapRegion& region);
  // The edges of the touched cells (ring 3) not yet in the region's.
  void add_touched_edges(std::span<const SiteId> touched, SnapRegion& region) const;
  // The area terms of every rerouted edge or edge at a moved vertex, in both its slots.
  void recompute_area_terms(const SnapRegion& region);
  // Cleans and checks `out` as built for site s, whose ring encloses the pole info.winding says
  // (loop_to_polygons, lonlat/boundary.hpp); empties it unless valid.
  CellStatus finish(SiteId s, const lonlat::LoopInfo& info, MultiPolygon& out, BBox* bbox) const;
  // The area check of a written cell reaching within 0.01 degree of a pole or cut at +-180
  // (see polygon()): Unwritable, `out` emptied and `area_m2` 0, if it fails.
  CellStatus check_near_pole(SiteId s, bool near_pole, MultiPolygon& out, BBox* bbox, double& area_m2) const;
  // The site whose cell holds each pole in its interior (the site of largest, smallest z:
  // the hull's extreme point in that direction, an exact comparison), or kNoIndex when two
  // sites tie (the pole is on the boundary of their cells).
  SiteId north_owner_ = kNoIndex, south_owner_ = kNoIndex;
  // The owners of the poles of power cells: largest power, not largest z.
  void find_power_pole_owners();
  // What the densifier takes as an edge's two sites: left - right is along the (power) bisector's
  // normal, toward the left cell (the sites themselves without weights).
  struct EdgeSides {
    Vec3 left, right;
  };
  EdgeSides edge_sides(SiteId left, SiteId right) const;
};

/// One cell, building a CellGeometry first (O(size of the diagram)): for one-off use only; use
/// CellGeometry to build many cells.
MultiPolygon cell_polygon(const VoronoiDiagram& diagram, SiteId s,
                          const CellGeometryOptions& options = {}, BBox* bbox = nullptr);

/// A cheap invariant of a written cell (a violation is a bug): its area on the ellipsoid, area_m2,
/// agrees with its area on the unit sphere, area_sr, scaled by the authalic radius, within the
/// ellipsoid's flattening (0.5 %) plus what the written boundary may differ from the cell's by
/// (densification, rounding to `precision` decimals, ellipsoidal against great-circle edges:
/// 500 m + densify_m + a decimal step, times the perimeter of `written`). At a precision coarser
/// than a metre, parts of a cell thinner than a step collapse, so only a written area too large
/// is checked there.
bool cell_areas_agree(double area_m2, double area_sr, const MultiPolygon& written, double densify_m,
                      int precision);

}  // namespace geovor
