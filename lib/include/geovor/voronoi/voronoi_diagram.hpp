/// \file voronoi_diagram.hpp
/// \brief VoronoiDiagram: the Voronoi cells on the unit sphere dual to a SphericalDelaunay.
///
/// The Voronoi vertex of triangle t = (a, b, c) (counter-clockwise seen from outside, as stored)
/// is the centre of its empty cap, normalize((b - a) x (c - a)). The formula needs no special
/// case: for a ghost triangle (empty cap larger than a hemisphere) it gives the centre of that
/// larger cap, and for a flat triangle through the centre of the sphere (all sites on one great
/// circle) the pole of that circle on the triangle's side. Since the sites are the stored doubles,
/// which lie within 2^-51 of the sphere, this is the exact dual of the triangulation (the power
/// diagram of the hull, de Castro's thesis Ch. 3) up to the rounding of one cross product.
///
/// Cells are stored in CSR form. For a live site s with triangles t_0 ... t_{d-1} around it,
/// counter-clockwise seen from outside (SphericalDelaunay::next_around_site):
///  - cell_vertices(s)[i] = t_i: the cell boundary is vertex(t_0), vertex(t_1), ... in that order,
///    counter-clockwise around s (the cell is on the left of every edge);
///  - the cycle starts with t_0 such that cell_neighbors(s)[0] is the smallest neighbour, so the
///    lists do not depend on how the triangulation stores its triangles;
///  - cell_neighbors(s)[i] = the site across the edge from vertex(t_i) to vertex(t_{i+1}); that
///    edge is an arc of the bisector great circle of s and the neighbour, at most 180 degrees long
///    (exactly 180 degrees in the lunes of sites on one great circle and with three sites).
/// Consecutive vertices can coincide (co-circular sites give several triangles with one
/// circumcentre); the zero-length edges are kept so that the lists mirror the triangulation.
///
/// Without triangles (fewer than three sites) the cells are described by kind():
///  - Kind::Empty: no site;
///  - Kind::WholeSphere: one site, whose cell is the whole sphere (4 pi sr);
///  - Kind::Hemispheres: two sites, whose cells are the two hemispheres bounded by their bisector
///    great circle; hemisphere_normal(s) is the pole of the cell of s, cell_neighbors(s) the
///    other site, and cell_vertices(s) is empty.
///
/// Weighted sites (docs/weighted.md): the cells are the power cells, the vertex of a triangle of
/// sites with different lifts is power_vertex(), an edge lies on the power bisector
/// (bisector_normal()), a hidden site has no cell, and a site may lie outside its own cell.
///
/// A VoronoiDiagram is a snapshot: it copies what it needs and does not change when the
/// triangulation does (insertions and removals need a new diagram).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "geovor/core/default_init.hpp"
#include "geovor/core/types.hpp"

namespace geovor {

class SphericalDelaunay;

class VoronoiDiagram {
 public:
  /// What the cells are; see the file comment.
  enum class Kind : std::uint8_t { Empty, WholeSphere, Hemispheres, Cells };

  VoronoiDiagram() = default;
  /// Builds the diagram of the live sites of `dt` in O(number of triangles), the vertices and
  /// the cells' lists split over `threads` threads (0: one per core); the result does not
  /// depend on it.
  explicit VoronoiDiagram(const SphericalDelaunay& dt, unsigned threads = 1);
  /// The same as `*this = VoronoiDiagram(dt, threads)`, reusing this diagram's storage: for a
  /// diagram rebuilt at every step (Lloyd's iterations), no fresh memory to fault in each time.
  void assign(const SphericalDelaunay& dt, unsigned threads = 1);

  /// \name Inspectors
  ///@{
  Kind kind() const { return kind_; }
  /// Number of cells = number of live sites.
  std::size_t num_cells() const { return num_cells_; }
  /// One past the largest site id (removed sites keep their id and have no cell).
  std::size_t site_capacity() const { return sites_.size(); }
  /// True iff s is a live site, i.e. has a cell.
  bool has_cell(SiteId s) const { return s < live_.size() && live_[s] != 0; }
  /// The unit vector of site s.
  const Vec3& site(SiteId s) const { return sites_[s]; }
  /// Number of Voronoi vertices = number of triangles (0 unless kind() == Kind::Cells).
  std::size_t num_vertices() const { return vertices_.size(); }
  /// The Voronoi vertex of triangle t: a unit vector (|v|^2 within a few ulps of 1).
  const Vec3& vertex(TriId t) const { return vertices_[t]; }
  std::span<const Vec3> vertices() const { return vertices_; }
  /// Moves the vertices out, for a binding that hands them to numpy without a copy; the diagram
  /// then has no vertices (vertex(), the geometry and the areas need them) until assign().
  std::vector<Vec3> release_vertices() { return std::move(vertices_); }
  /// The triangles around s, counter-clockwise: the ids of the vertices of its cell, in order.
  /// Empty unless kind() == Kind::Cells and has_cell(s).
  std::span<const TriId> cell_vertices(SiteId s) const {
    if (kind_ != Kind::Cells || !has_cell(s)) return {};
    return {cell_tris_.data() + cells_[s].begin, cell_tris_.data() + cells_[s].end};
  }
  /// The neighbour across each edge (vertex i to vertex i + 1, cyclically); with two sites, the
  /// other site. Same length as cell_vertices(s) when kind() == Kind::Cells.
  std::span<const SiteId> cell_neighbors(SiteId s) const {
    if (!has_cell(s)) return {};
    if (kind_ == Kind::Cells) return {cell_nbrs_.data() + cells_[s].begin, cell_nbrs_.data() + cells_[s].end};
    if (kind_ == Kind::Hemispheres) return {s == pair_[0] ? &pair_[1] : &pair_[0], 1};
    return {};
  }
  /// Kind::Hemispheres only: the unit normal of the bisector plane pointing into the cell of s,
  /// bisector_normal(s, other); the cell is {p : dot(p, n) >= 0}.
  Vec3 hemisphere_normal(SiteId s) const;
  /// The unit normal of the (power) bisector plane of s and other, pointing to the side of s:
  /// normalize(site(s) - site(other)), or with lifts normalize(c_o site(s) - c_s site(other)).
  Vec3 bisector_normal(SiteId s, SiteId other) const;
  /// The lift of site s (1 without weights).
  double lift(SiteId s) const { return lifts_.empty() ? 1.0 : lifts_[s]; }
  bool is_weighted() const { return !lifts_.empty(); }
  /// Spherical area of the cell of s (steradians): 4 pi for the whole sphere, 2 pi for a
  /// hemisphere, 0 for a site without a cell. Computed on demand in O(degree): the fan of the
  /// spherical triangles (site, v_i, v_i+1), each by the Van Oosterom-Strackee formula, an edge
  /// longer than 90 degrees split at its midpoint first (right for cells larger than a
  /// hemisphere and for 180-degree edges); when a vertex lies more than 120 degrees from the
  /// site (lunes of co-circular sites), the fan's apex is the direction of the edges' midpoints
  /// summed by length instead, since a fan triangle with two nearly antipodal corners is
  /// ill-conditioned. The areas of all cells sum to 4 pi up to rounding.
  double cell_area_sr(SiteId s) const;
  /// The live sites in the order their cells are stored: the order in which they first appear in
  /// the triangulation's triangle array, which is spatially coherent. Visiting cells in this
  /// order is several times faster than by id when ids are in random spatial order.
  std::span<const SiteId> storage_order() const { return order_; }
  /// A memory hint for visits to cells in scattered order: prefetch(s, 0) brings in where the
  /// lists of cell s are, prefetch(s, 1), some work later, the lists themselves. Changes nothing;
  /// any id is accepted.
  void prefetch(SiteId s, int stage) const;
  /// Bytes held by the arrays (capacity).
  std::size_t memory_bytes() const;
  ///@}

  /// \name Spherical helpers (also used by the cell geometry)
  ///@{
  /// normalize((b - a) x (c - a)): the centre of the cap through a, b, c on the side where
  /// a, b, c turn counter-clockwise. Computed at the corner opposite the longest side, whose
  /// two sides are the shortest (exact differences for nearby sites): within about 2^-53
  /// radians over the sine of the triangle's largest angle of the exact normal of the three
  /// doubles (two close sites and one at an angle theta on their great circle: 1e-16 /
  /// sin(theta / 2)). The same bits for every rotation of a, b, c but on ties of side lengths.
  static Vec3 circumcenter(const Vec3& a, const Vec3& b, const Vec3& c);
  /// The same for the sites u, v, w of `dt`, in that cyclic order, started at the smallest id:
  /// the same bits whichever way the triangle is stored (the diagram's vertices).
  static Vec3 circumcenter(const SphericalDelaunay& dt, SiteId u, SiteId v, SiteId w);
  /// The power vertex of weighted sites a, b, c (lifts ca, cb, cc): the direction of the normal
  /// of the plane through a / ca, b / cb, c / cc, on the side where they turn counter-clockwise;
  /// circumcenter(a, b, c) for equal lifts (not the same bits: callers with equal lifts call that).
  static Vec3 power_vertex(const Vec3& a, double ca, const Vec3& b, double cb, const Vec3& c, double cc);
  /// Midpoint of the arc from a to b that turns positively (counter-clockwise seen from outside
  /// at the tip of `axis`) about the unit vector `axis`, of which a and b are (nearly)
  /// perpendicular. Robust up to and including 180-degree arcs (b = -a), where the axis alone
  /// decides the arc. Arcs shorter than 120 degrees use normalize(a + b) and ignore `axis`.
  static Vec3 arc_midpoint(const Vec3& a, const Vec3& b, const Vec3& axis);
  /// Signed solid angle of the spherical triangle a, b, c (unit vectors, minor arcs) in
  /// steradians, positive when counter-clockwise (Van Oosterom and Strackee, 1983).
  static double triangle_area_sr(const Vec3& a, const Vec3& b, const Vec3& c);
  ///@}

 private:
  Kind kind_ = Kind::Empty;
  std::size_t num_cells_ = 0;
  std::vector<Vec3> sites_;         // copy of the triangulation's sites (by id)
  std::vector<double> lifts_;       // copy of its lifts; empty without weights
  std::vector<std::uint8_t> live_;  // 1 iff the site has a cell
  std::vector<Vec3> vertices_;      // circumcentre of each triangle
  struct Range {
    std::uint32_t begin = 0, end = 0;
  };
  std::vector<Range> cells_;   // CSR: cell s is [cells_[s].begin, cells_[s].end)
  std::vector<SiteId> order_;  // live sites in storage order
  // Filled by the parallel walks of the stars (every entry written), not zeroed first.
  std::vector<TriId, DefaultInitAllocator<TriId>> cell_tris_;
  std::vector<SiteId, DefaultInitAllocator<SiteId>> cell_nbrs_;
  SiteId pair_[2] = {kNoIndex, kNoIndex};  // the two sites of Kind::Hemispheres
  std::vector<std::uint32_t> degree_;       // scratch of assign()
};

}  // namespace geovor
