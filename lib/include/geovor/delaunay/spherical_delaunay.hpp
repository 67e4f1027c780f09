/// \file spherical_delaunay.hpp
/// \brief The Delaunay triangulation of sites on the sphere, exact on any input.
///
/// The sites are unit vectors stored as doubles. Rounded to doubles they lie within about 2^-52 of
/// the unit sphere, so, as in the "second approach" of de Castro's thesis (Ch. 3, Caroli et al.,
/// SEA 2010), the structure is the regular triangulation of weighted points on the sphere: the 3D
/// convex hull of the stored points. Both predicates are 3D orientations of the stored doubles,
/// decided exactly (kernel/predicates.hpp), and ties (four co-circular sites, sites on one great
/// circle) are broken by a symbolic perturbation ordered by site index, so the triangulation is a
/// function of the sites and their indices only, whatever the insertion order.
///
/// Lemma 9 of the thesis: if every point is within delta of the sphere and any two are farther
/// apart than 2 sqrt(delta), no point is hidden (every site is a vertex). Normalised doubles have
/// delta <= 2^-51, so sites are kept at least kMinSeparation = 2^-24 apart (0.38 m on the Earth):
/// a closer site is merged into its neighbour and the merge is reported, never dropped silently.
///
/// Data layout (geogram/delaunator style, all flat arrays of std::uint32_t):
///  - sites_[s]: the unit vector of site s;
///  - triangles_[3t + i]: the i-th site of triangle t, counter-clockwise seen from outside;
///  - halfedges_[e]: the twin of half-edge e (never kNoIndex: the surface is closed);
///  - site_edge_[s]: one half-edge leaving s, kNoIndex for a removed site.
/// With n >= 3 live sites there are exactly 2n - 4 triangles (Euler); with fewer, none.
/// 76 bytes per site in all.
///
/// Triangles whose circumcircle is larger than a hemisphere (possible only when all sites lie in
/// one open hemisphere) are kept, so the surface stays a closed sphere; is_ghost() flags them
/// (CGAL's "ghost faces").
///
/// One concept per source file (lib/src/delaunay/): the build, insertion, the cavity, removal,
/// validation, the bi-cell tolerance, the filter and relocation; their proofs: docs/delaunay.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/delaunay/halfedge.hpp"

namespace geovor {

/// Options of SphericalDelaunay; every default is documented.
struct DelaunayOptions {
  /// Sites whose chord distance on the unit sphere is below this are merged into one site.
  /// DEFAULT: SphericalDelaunay::kMinSeparation (2^-24, 0.38 m on the Earth).
  /// REQUIRES: merge_distance >= kMinSeparation (below it, Lemma 9 no longer holds).
  double merge_distance = 0x1p-24;
  /// Insert in a spatially coherent order: along a Hilbert curve drawn on the faces of the cube.
  /// From 1024 points on, a few sparse random rounds go first (each point independently in round
  /// j with probability about 32^-j, each round along the curve): they keep the cavities ahead of
  /// the curve small (4.5 triangles instead of 5.9 at 2^20 uniform points, 12 conflict tests per
  /// site instead of 15) while 97% of the points are in the last round, one Hilbert pass.
  /// DEFAULT: true. Disabling it (input order) only costs time.
  bool spatial_sort = true;
  /// Sort in BRIO rounds instead (random rounds doubling in size, each along the Hilbert curve),
  /// which bounds the expected cost on any input; the default order is faster on real and uniform
  /// data (the previous site is then a neighbour of the next 92% of the time, against 62%).
  /// DEFAULT: false.
  bool brio = false;
  /// Seed of the random rounds (BRIO or sparse). DEFAULT: 1. The triangulation does not depend on
  /// it (unique perturbed triangulation); the running time does, and so does which of two points
  /// closer than merge_distance is kept (the first inserted).
  std::uint64_t seed = 1;
};

/// Why an input point did not become a site of its own.
struct Merge {
  std::uint32_t input = 0;  ///< index of the input point in the span given to build()
  SiteId site = kNoIndex;   ///< the site it went into
  double chord = 0;         ///< chord distance to that site on the unit sphere (0: exact duplicate);
                            ///< weighted: to the site it went into, possibly through a chain of
                            ///< merges each closer than the merge distance
  bool hidden = false;      ///< true if the exact hull test found it hidden (never expected)
};

/// A weighted site that is no vertex of the triangulation: its power cell is empty.
struct Hidden {
  SiteId site = kNoIndex;  ///< the hidden site (it keeps its id)
  SiteId by = kNoIndex;    ///< a live site whose cell holds the hidden site's position
};

/// What build() did with each input point.
struct BuildReport {
  std::vector<SiteId> site_of_input;  ///< the site of every input point (kNoIndex: none)
  std::vector<Merge> merges;          ///< every input point merged into another site
  std::vector<Hidden> hidden;         ///< weighted builds: the hidden sites, by id
  double sort_seconds = 0, insert_seconds = 0;
  std::size_t peak_bytes = 0;         ///< the structure's largest footprint during the build
};

/// Result of a single insertion.
struct InsertResult {
  SiteId site = kNoIndex;  ///< the new site, or the site the point was merged into
  bool merged = false;
  double chord = 0;        ///< when merged: the distance to that site on the unit sphere
  bool hidden = false;     ///< merged: the exact hull test found the point hidden; not merged
                           ///< (weighted): the site is hidden, no vertex
};

/// Options of move_all() (and move()); every default is documented.
struct RelocationOptions {
  /// Skip the moves within the site's certified tolerance (thesis Algorithm 1): the site's
  /// coordinates change, the triangles do not. DEFAULT: true.
  bool filter = true;
  /// Relocate by flips when the move inverts no incident triangle (thesis §5.2.1); otherwise, and
  /// when this is false, by remove + insert keeping the id. DEFAULT: true.
  bool flips = true;
  /// move_all() only, with the filter, from kRebuildMinSites (16384) live sites and none removed:
  /// when the tolerances are not current or the last batch relocated more than 12% of the sites,
  /// estimate (from about 512 sites) the share of live sites whose move tolerances computed afresh
  /// would miss; above 2%, rebuild the triangulation from the new positions in place (same ids, same
  /// triangles: MoveStats::rebuilt) and drop the tolerances, since relocating a site costs about
  /// eight times its share of a rebuild and computing all tolerances about one rebuild.
  /// DEFAULT: true. The result does not depend on it.
  bool rebuild_when_faster = true;
};

/// What move()/move_all() did (counts of sites). moved = filtered + flipped + reinserted + rebuilt.
struct MoveStats {
  std::size_t moved = 0;       ///< sites whose position changed
  std::size_t filtered = 0;    ///< moves certified by the tolerance filter (no combinatorial change)
  std::size_t flipped = 0;     ///< relocated by flips
  std::size_t reinserted = 0;  ///< relocated by remove + insert
  std::size_t rebuilt = 0;     ///< moved by a rebuild in place (RelocationOptions::rebuild_when_faster)
  std::size_t reanchored = 0;  ///< of the filtered moves, those certified by the second test (tolerances recomputed at the new position)
  std::size_t refused = 0;     ///< moves refused (new position within merge distance of another site); site left where it was
  std::size_t refreshed = 0;   ///< tolerance refreshes of sites that did not move (Algorithm 1's queue)
  MoveStats& operator+=(const MoveStats& o) {
    moved += o.moved, filtered += o.filtered, flipped += o.flipped, reinserted += o.reinserted, rebuilt += o.rebuilt;
    reanchored += o.reanchored, refused += o.refused, refreshed += o.refreshed;
    return *this;
  }
};

/// Result of validate(): ok() or a list of violated invariants.
struct Validation {
  std::vector<std::string> errors;
  bool ok() const { return errors.empty(); }
};

class SphericalDelaunay {
 public:
  /// Smallest allowed separation between sites (chord on the unit sphere): 2 sqrt(2^-50).
  static constexpr double kMinSeparation = 0x1p-24;

  SphericalDelaunay() = default;
  explicit SphericalDelaunay(const DelaunayOptions& options);

  /// Builds the triangulation of `points` (unit vectors, |p|^2 within 2^-49 of 1).
  /// Site ids are assigned in input order to the points that are not merged.
  /// @exception Error(InvalidArgument) if a point is not finite or not of unit length, or the
  ///   options are invalid.
  static SphericalDelaunay build(std::span<const Vec3> points, const DelaunayOptions& options = {},
                                 BuildReport* report = nullptr);

  /// The regular triangulation of weighted sites (docs/weighted.md): point i is the circle of
  /// centre points[i] and radius r_i, given by its lift lifts[i] = cos(r_i / R) in (0, 1] (see
  /// site_lift(), geo/site_weights.hpp); the triangulation is the convex hull of the lifted points
  /// points[i] / lifts[i], decided exactly with the lifts taken as the doubles they are.
  ///  - A site whose lifted point is inside the hull is hidden: it keeps its id but is no vertex
  ///    (is_hidden(), BuildReport::hidden with a site whose cell holds its position).
  ///  - Points at one position (bit-identical vectors) merge into the one with the smallest lift
  ///    (the largest circle; ties: the first in input order). Points closer than merge_distance
  ///    merge as they are inserted: a vertex that the new site hides is merged into it, otherwise
  ///    the new point into the vertex (the first inserted is kept); a point hidden at its
  ///    insertion is merged only into a vertex it finds within that distance.
  ///  - Equal lifts give the triangulation of build(points) (the lifts are then dropped:
  ///    is_weighted() is false).
  /// Sites of a weighted triangulation cannot be inserted, removed or moved (InvalidArgument).
  /// @exception Error(InvalidArgument) as build(), or if the sizes differ or a lift is not in
  ///   (0, 1].
  static SphericalDelaunay build(std::span<const Vec3> points, std::span<const double> lifts,
                                 const DelaunayOptions& options = {}, BuildReport* report = nullptr);

  /// The raw arrays of a triangulation, as saved in an index file.
  struct Arrays {
    std::vector<Vec3> sites;
    std::vector<SiteId> triangles;
    std::vector<HalfedgeId> halfedges;
    std::vector<HalfedgeId> site_edge;  ///< kNoIndex - 1 marks a removed (or hidden) site
    std::vector<double> lifts;          ///< weighted: each site's lift; empty when unweighted
    std::vector<SiteId> hidden_by;      ///< weighted: who hides each site (kNoIndex: none; empty: no site hidden)
  };
  /// A copy of the arrays (site_edge with removed sites marked).
  Arrays arrays() const;
  /// Rebuilds a triangulation from arrays() output. Checks every index and the structure
  /// (everything validate() checks but the geometric predicates, in O(n)), and for weighted arrays
  /// each lift in (0, 1], not all equal, and each hidden site no vertex and hidden by a live one,
  /// so a corrupted input is an error and never a crash.
  /// The checks run on `threads` threads (0: one per core); the result and the error do not
  /// depend on it.
  /// @exception Error(BadData) naming the first broken invariant.
  static SphericalDelaunay from_arrays(Arrays arrays, const DelaunayOptions& options = {}, unsigned threads = 1);

  /// Inserts one site (stations going online). A point closer than merge_distance to a site is
  /// merged into it instead. New sites get the next id, so existing ids never change.
  InsertResult insert(const Vec3& p);

  /// Removes a live site (stations going offline); other ids do not change.
  void remove(SiteId s);

  /// \name Moving sites (relocation.cpp, the filter in move_filter.cpp; docs/delaunay.md)
  /// Moves keep the site's id, and the result is the triangulation a fresh build of the new
  /// positions gives (same triangles: the perturbation follows the ids).
  ///
  /// The filter (thesis Ch. 5, Algorithm 1): every site s keeps a reference position f_s and a
  /// tolerance eps_s, a lower bound of bicell_tolerance() over the bi-cells containing s; a move
  /// to p with chord |p - f_s| < eps_s changes no Delaunay certificate, so only the coordinates
  /// change (O(1), no allocation). A move failing it may still pass the second test
  /// (MoveStats::reanchored): the tolerances recomputed with a new reference near p. Otherwise
  /// the site is relocated: by flips when every triangle of its star stays positively oriented
  /// around the new position, else by remove + insert keeping the id; the bi-cells it changed
  /// lower their sites' eps, and a site whose eps falls below its own displacement is refreshed
  /// (MoveStats::refreshed). A position within the merge distance of another site (chord in
  /// doubles, as insert()) is refused: the site stays where it was (MoveStats::refused).
  /// Memory: 32 bytes per site (f_s and eps_s^2), allocated at the first filtered move, kept
  /// current by insert() and remove(), and rebuilt in O(n) after an unfiltered move.
  ///@{
  /// Moves live site s to unit vector p (|p|^2 within 2^-49 of 1); keeps its id.
  /// @exception Error(InvalidArgument) if s is not live or p is not a unit vector.
  MoveStats move(SiteId s, const Vec3& p, const RelocationOptions& options = {});
  /// Moves every live site s to positions[s], one after the other: first, in id order, the moves
  /// the filter certifies, then the others in the Hilbert-curve order of their targets (ties by
  /// id), which keeps consecutive relocations in cache; so when two targets are within the merge
  /// distance, which one is refused depends on that order. With
  /// RelocationOptions::rebuild_when_faster, may rebuild the triangulation in place instead (same
  /// ids and triangles; never when a move would be refused).
  /// positions.size() == site_capacity(); removed sites' entries are ignored.
  /// @exception Error(InvalidArgument) for a wrong size or a live site's non-unit position
  ///   (checked before anything moves).
  MoveStats move_all(std::span<const Vec3> positions, const RelocationOptions& options = {});
  /// The certified tolerance of live site s (chord on the unit sphere), computing the tolerances
  /// if they are not current; for tests and statistics.
  double tolerance(SiteId s);
  /// The filter's reference position of live site s (where its tolerance was computed from);
  /// call tolerance() first. For tests.
  const Vec3& reference(SiteId s) const { return anchor_[s].f; }
  ///@}

  /// \name Inspectors
  ///@{
  std::size_t num_sites() const { return num_live_; }
  /// One past the largest site id ever used (removed sites keep their id).
  std::size_t site_capacity() const { return sites_.size(); }
  bool is_live(SiteId s) const { return s < sites_.size() && alive(s); }
  /// True iff the triangulation has weights (lifts not all equal).
  bool is_weighted() const { return !lifts_.empty(); }
  /// The lift of site s: 1 for an unweighted triangulation.
  double lift(SiteId s) const { return lifts_.empty() ? 1.0 : lifts_[s]; }
  std::span<const double> lifts() const { return lifts_; }
  /// True iff s is a hidden site of a weighted triangulation (an id without a vertex).
  bool is_hidden(SiteId s) const { return s < hidden_by_.size() && hidden_by_[s] != kNoIndex; }
  /// For a hidden site: a live site whose power cell holds its position; kNoIndex otherwise.
  SiteId hidden_by(SiteId s) const { return is_hidden(s) ? hidden_by_[s] : kNoIndex; }
  std::size_t num_hidden() const;
  const Vec3& site(SiteId s) const { return sites_[s]; }
  /// The lifted point site(s) / lift(s), each coordinate rounded once (site(s) when unweighted):
  /// a site's power at a unit vector q is dot(q, lifted_site(s)) up to that rounding.
  Vec3 lifted_site(SiteId s) const {
    if (lifts_.empty()) return sites_[s];
    const double c = lifts_[s];
    return {sites_[s].x / c, sites_[s].y / c, sites_[s].z / c};
  }
  std::span<const Vec3> sites() const { return sites_; }
  std::size_t num_triangles() const { return triangles_.size() / 3; }
  std::span<const SiteId> triangles() const { return triangles_; }
  std::span<const HalfedgeId> halfedges() const { return halfedges_; }
  SiteId tri_site(TriId t, int i) const { return triangles_[3 * t + i]; }
  /// A half-edge leaving s, or kNoIndex if s has no triangle (removed, or fewer than 3 sites).
  HalfedgeId site_edge(SiteId s) const { return alive(s) ? site_edge_[s] : kNoIndex; }
  /// Next half-edge leaving the same site, counter-clockwise seen from outside.
  HalfedgeId next_around_site(HalfedgeId e) const { return halfedges_[prev_halfedge(e)]; }
  /// Exact: true iff the triangle's circumcircle is larger than a hemisphere (orient < 0).
  bool is_ghost(TriId t) const;
  std::size_t num_ghost_triangles() const;
  const DelaunayOptions& options() const { return options_; }
  /// Bytes held by the arrays (capacity), for the memory benchmark.
  std::size_t memory_bytes() const;
  /// A stamp of the structure, drawn from a process-wide counter when the triangulation is made
  /// and at every change (insert, remove, ...: every mutator calls touch()); copies keep it, so
  /// equal stamps mean equal structures. Caches of a triangulation (the Locator's WalkGraph)
  /// compare it to know they are stale.
  std::uint64_t revision() const { return revision_; }
  ///@}

  /// Checks every invariant exactly: twin symmetry, consistent orientation, no repeated site in a
  /// triangle, every vertex star a single cycle, Euler characteristic (2n - 4 triangles), local
  /// Delaunay of every edge under the perturbation, and that every live site is a vertex.
  /// With a report, also checks that every input point of build() is accounted for: it is a live
  /// site or merged into one, and every merge is listed. With `global`, also checks each triangle
  /// against every site (O(n^2): small inputs only). The checks of the structure, of every edge
  /// and of every triangle run on `threads` threads (0: one per core; core/parallel.hpp); the
  /// result does not depend on it.
  Validation validate(const BuildReport* report = nullptr, bool global = false, unsigned threads = 1) const;
  /// The combinatorial part of validate() only (no predicate): O(n), for loading files, on
  /// `threads` threads (0: one per core; core/parallel.hpp); the result does not depend on it.
  Validation validate_structure(unsigned threads = 1) const;

 private:
  static constexpr HalfedgeId kRemoved = kNoIndex - 1;  // site_edge_ of a removed site
  static constexpr std::size_t kMaxSites = 700'000'000;  // 6n half-edges must fit in 32 bits
  bool alive(SiteId s) const { return site_edge_[s] != kRemoved; }
  std::uint32_t priority(SiteId s) const { return priority_.empty() ? s : priority_[s]; }
  static std::uint64_t next_revision();
  void touch() { revision_ = next_revision(); }  // every change of sites or triangles calls it
  static void check_weights(const Arrays& arrays);  // from_arrays' checks of the weights
  // build() of either kind: lifts empty for unweighted sites; forced[i], if not empty and not
  // kNoIndex, is an input point that point i merges into (weighted only: same positions);
  // hilbert, if not empty, is hilbert_order(points), already computed.
  static SphericalDelaunay build_sites(std::span<const Vec3> points, std::span<const double> lifts,
                                       std::span<const std::uint32_t> forced, const DelaunayOptions& options,
                                       BuildReport* report, std::vector<std::uint32_t> hilbert = {});
  void lift_sites();  // weighted build: lifted_ and lifted_bound_ of the slots
  // Weighted build: hidden_by_ from slots to final ids (lifts_ are already by id, copied from the
  // input); who hides each hidden site.
  void renumber_weights(std::span<const SiteId> new_id, std::size_t num_ids);

  // Insertion (insertion.cpp). Where a new point goes: merged into a site, or a triangle in
  // conflict with it.
  struct Placement {
    SiteId merged_into = kNoIndex;
    double chord = 0;
    bool hidden = false;
    TriId conflict = kNoIndex;
    SiteId hidden_by = kNoIndex;  // weighted: no conflict, the site of largest power at p
  };
  // p's lift c is read only when the triangulation is weighted.
  bool in_conflict(TriId t, const Vec3& p, double c, std::uint32_t prio) const;  // inline: conflict.hpp
  bool in_conflict_exact(TriId t, const Vec3& p, double c, std::uint32_t prio) const;
  // Unweighted: the site nearest p (largest dot); weighted: of largest power dot(p, site) / lift.
  SiteId walk_to_nearest(const Vec3& p, SiteId start) const;
  template <bool kWeighted>
  SiteId walk_to_largest(const Vec3& p, SiteId start) const;  // walk_to_nearest's two loops
  TriId find_conflict(const Vec3& p, double c, std::uint32_t prio, SiteId near) const;
  // Weighted: a triangle in conflict with p, kNoIndex when p is hidden: the face of the hull
  // whose cone holds p when the centre is inside the hull, else breadth first from `near`.
  TriId search_conflict(const Vec3& p, double c, std::uint32_t prio, SiteId near) const;
  // Whether the centre is strictly inside the hull (no triangle with orient <= 0), checked again
  // each time the number of sites has doubled until it is.
  bool origin_inside() const;
  // The triangle whose cone from the centre holds p, by a visibility walk from t; kNoIndex if the
  // walk does not end.
  TriId radial_triangle(const Vec3& p, TriId t) const;
  // Leaves the triangles it found not in conflict marked in tested_ for find_cavity().
  Placement place(const Vec3& p, double c, std::uint32_t prio, SiteId hint);
  // Weighted: the vertices inside the cavity found last (none on its boundary) become hidden by s.
  void hide_cavity_interior(SiteId s);
  void require_unweighted(const char* what) const;
  // The site p merges into (merged_into set) if any lies within the merge distance.
  Placement nearest_site(const Vec3& p, SiteId hint) const;
  void make_first_triangles(SiteId a, SiteId b, SiteId c);
  SiteId any_live_site() const;
  // Inserts site s, already stored in sites_ with site_edge_[s] == kRemoved (not inserted yet);
  // on a merge s stays so and the result names the site it went into.
  InsertResult insert_site(SiteId s, SiteId hint);

  // The cavity (cavity.cpp): the triangles in conflict with p, grown from seed, and the
  // half-edges bounding them.
  void find_cavity(const Vec3& p, double c, std::uint32_t prio, TriId seed);
  // find_cavity() by the filter alone and without a call; false (its marks undone) when a test
  // needs the exact stage or a scratch buffer is full.
  template <bool kWeighted>
  bool find_cavity_filtered(const Vec3& p, double c, TriId seed);
  // Replaces the cavity found last by the fan of triangles joining its boundary to site s.
  void fill_cavity(SiteId s);
  // Frees triangle slots (a removal's star, a weighted cavity that hid vertices): the last
  // triangles of the arrays move into them.
  void free_triangle_slots(std::vector<TriId> spare);
  // Gives up the cavity found last (p merges instead): clears its marks.
  void abandon_cavity();

  // Removal (removal.cpp): remove() without dropping the tolerances.
  void remove_site(SiteId s);
  void move_triangle(TriId from, TriId to);

  // Relocation (relocation.cpp).
  MoveStats move_one(SiteId s, const Vec3& p, const RelocationOptions& options);
  // move_all()'s policy (RelocationOptions::rebuild_when_faster).
  static constexpr std::size_t kRebuildMinSites = 16384;
  static constexpr double kRelocatedShareToRebuild = 0.12, kFreshFailureShareToFilter = 0.02;
  double fresh_failure_share(std::span<const Vec3> positions) const;
  bool rebuild_in_place(std::span<const Vec3> positions, MoveStats& stats);  // false: a merge
  bool refuse_move(SiteId s, const Vec3& p) const;  // p within merge distance of another site
  bool relocate_by_flips(SiteId s, const Vec3& p);  // false: nothing changed, reinsert instead
  void flip(HalfedgeId e);                           // the diagonal of the two triangles at e
  bool adjacent(SiteId a, SiteId b) const;
  bool reinsert(SiteId s, const Vec3& p);            // false: merged, put back (never expected)

  // The filter (move_filter.cpp, Algorithm 1).
  bool reanchor(SiteId s, const Vec3& p);           // the second test: f_s := p, no relocation
  void tolerances_after_insert(SiteId s);            // insert() keeps the tolerances current
  void remove_keeping_tolerances(SiteId s);          // so does remove()
  void collect_link(SiteId s);                       // link_ = the neighbours of s
  void update_around_link();                         // the bi-cells at the sites of link_
  void init_tolerances();
  void drop_tolerances() { anchor_.clear(); }
  bool within_tolerance(SiteId s) const;             // m_s == f_s or |m_s - f_s| < eps_s
  using Quad = std::array<SiteId, 4>;               // a bi-cell's sites: a, b (the edge), c, d
  void bicell_sites(HalfedgeId e, Quad& q) const;
  // Squared tolerances (with the filter's margin) of n bi-cells at the reference positions.
  void bicell_tau2(const Quad* q, std::size_t n, double* tau2) const;
  void update_bicells();                             // bicells_ lower eps of their sites; cleared
  void site_tau2(SiteId s);                          // quads_, tau2_: the bi-cells containing s
  void refresh_site(SiteId s);                       // f_s = m_s, eps_s recomputed
  std::size_t settle_queue();                        // refreshes the sites that left their tolerance

  DelaunayOptions options_;
  std::uint64_t revision_ = next_revision();
  std::vector<Vec3> sites_;
  std::vector<SiteId> triangles_;
  std::vector<HalfedgeId> halfedges_;
  std::vector<HalfedgeId> site_edge_;
  std::vector<std::uint32_t> priority_;  // empty: priority = site id (a link hull uses global ids)
  std::vector<double> lifts_;            // weighted only: cos(r / R) of each site (by id)
  std::vector<SiteId> hidden_by_;        // weighted only: kNoIndex, or who hides the site
  // Weighted build only (freed after it): each slot's lifted point fl(site / lift), and the
  // static bound of the filter on them (kernel/in_sphere_filter.hpp, in_sphere_lifted_static).
  std::vector<Vec3> lifted_;
  double lifted_bound_ = 0;
  std::vector<Merge> absorbed_;          // weighted build: vertices merged into the site that hid them
  mutable bool origin_inside_ = false;   // origin_inside()'s cache
  mutable std::size_t origin_checked_at_ = 2;
  std::size_t num_live_ = 0;
  SiteId last_site_ = kNoIndex;           // hint for the next walk

  // Scratch of one insertion, kept to avoid allocations.
  struct CavityEdge {
    SiteId a, b;       // the boundary edge a -> b of the cavity
    HalfedgeId outer;  // its twin, in the triangle outside
  };
  // Their sizes are capacities (grown by doubling, never shrunk): the counts below are the data.
  std::vector<TriId> cavity_, tested_;
  std::vector<CavityEdge> boundary_;
  std::size_t num_cavity_ = 0, num_tested_ = 0, num_boundary_ = 0;

  // Relocation (Algorithm 1): reference positions and squared tolerances, empty when not current.
  // f_s and eps_s^2 side by side: the filter and a relocation read both (one cache line).
  struct Anchor {
    Vec3 f;
    double eps2;
  };
  std::vector<Anchor> anchor_;
  // Scratch of one relocation, kept to avoid allocations.
  std::vector<SiteId> queue_, link_;
  std::vector<HalfedgeId> stack_, flipped_;
  std::vector<TriId> touched_;
  std::vector<double> tau2_;  // reanchor()'s bi-cell tolerances, squared
  std::vector<HalfedgeId> bicells_;  // the bi-cells update_bicells() computes next
  std::vector<Quad> quads_;          // site_tau2()'s bi-cells' sites
  std::vector<SiteId> link_w_, link_x_;  // site_tau2()'s link and the sites across it
  double relocated_share_ = 0;  // of the last filtered move_all(): (flipped + reinserted) / live sites
};

}  // namespace geovor
