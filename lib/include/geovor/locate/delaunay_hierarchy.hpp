/// \file delaunay_hierarchy.hpp
/// \brief The Delaunay hierarchy on the sphere (Devillers 2002; thesis §7.3.3): nested random
/// samples of the sites, each triangulated, with links between a site's copies on adjacent levels.
///
/// Level 0 holds every site; a site of level l is also on level l+1 with probability 1/ratio
/// (drawn from a hash of its id and the seed, so the levels do not depend on insertion order).
/// Each level is a SphericalDelaunay whose priorities follow the level-0 ids. Walks at level l+1
/// are O(ratio) steps from the answer at level l, so descending costs O(log n).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"

namespace geovor {

class WalkGraph;  // walk_graph.hpp

/// Options of DelaunayHierarchy; every default is documented.
struct HierarchyOptions {
  /// A site of level l is also on level l+1 with probability 1 / ratio. DEFAULT: 30 (CGAL's).
  /// REQUIRES: ratio >= 2.
  std::uint32_t ratio = 30;
  /// At most this many levels, the base included. DEFAULT: 5 (CGAL's), enough for 30^4 = 810,000
  /// sites per top-level site... of which there are then few. REQUIRES: 1 <= max_levels <= 16.
  std::uint32_t max_levels = 5;
  /// Seed of the level draw. DEFAULT: 1.
  std::uint64_t seed = 1;
};

class DelaunayHierarchy {
 public:
  DelaunayHierarchy() = default;

  /// Builds level 0 from `points` (see SphericalDelaunay::build) and the levels above it.
  /// @exception Error(InvalidArgument) as SphericalDelaunay::build, or for invalid options.
  static DelaunayHierarchy build(std::span<const Vec3> points, const DelaunayOptions& options = {},
                                 const HierarchyOptions& hierarchy = {}, BuildReport* report = nullptr);

  /// The hierarchy of weighted sites: level 0 is SphericalDelaunay::build(points, lifts) (its
  /// hidden sites are on no level above), each level above the regular triangulation of its
  /// sample with the same lifts (a level whose sample has equal lifts is unweighted). Vertices
  /// closer than the merge distance (with different radii) merge in a sample: the merged one
  /// goes no higher than the level below it.
  /// @exception Error(InvalidArgument) as SphericalDelaunay::build, or for invalid options.
  static DelaunayHierarchy build(std::span<const Vec3> points, std::span<const double> lifts,
                                 const DelaunayOptions& options = {}, const HierarchyOptions& hierarchy = {},
                                 BuildReport* report = nullptr);

  /// Reassembles a hierarchy from saved parts (locate/index_file.hpp): the levels, up[l] (one
  /// link per site of level l, kNoIndex for none; the last level's all kNoIndex) and down[l]
  /// (one per site of level l; down[0] empty). Checks in O(n), so that a corrupted input is an
  /// error and never a crash: the options, every level but the base has a live site, the links
  /// are in range, up and down are inverse on live sites, every copy is the same point (with the
  /// same lift; a level above without weights has copies of equal lifts), every
  /// live site above the base has a copy below, and every live base site is on the levels its
  /// draw gives (weighted: at most those). The levels' own structure is from_arrays()'s to check.
  /// @exception Error(BadData) naming the first broken invariant.
  static DelaunayHierarchy from_parts(const HierarchyOptions& options, std::vector<SphericalDelaunay> levels,
                                      std::vector<std::vector<SiteId>> up, std::vector<std::vector<SiteId>> down);

  /// Inserts a site at level 0 and at the levels its draw gives; see SphericalDelaunay::insert.
  InsertResult insert(const Vec3& p);
  /// Removes a live level-0 site from every level it is on.
  void remove(SiteId s);

  /// Moves live level-0 site s to unit vector p on every level it is on (SphericalDelaunay::move
  /// on each, each level with its own tolerances); ids and links do not change. Returns level 0's
  /// stats; a refused move (p within the merge distance of another site) changes no level.
  /// @exception Error(InvalidArgument) as SphericalDelaunay::move.
  MoveStats move(SiteId s, const Vec3& p, const RelocationOptions& options = {});
  /// Moves every live level-0 site s to positions[s] (size base().site_capacity(); removed
  /// sites' entries ignored): level 0 first, then each level above to where its copies below went,
  /// so a move refused at level 0 is refused everywhere. Returns level 0's stats.
  /// @exception Error(InvalidArgument) as SphericalDelaunay::move_all.
  MoveStats move_all(std::span<const Vec3> positions, const RelocationOptions& options = {});

  /// \name Inspectors
  ///@{
  int num_levels() const { return static_cast<int>(levels_.size()); }
  const SphericalDelaunay& level(int l) const { return levels_[static_cast<std::size_t>(l)]; }
  const SphericalDelaunay& base() const { return levels_.front(); }
  /// The copy of level-l site s on level l+1, or kNoIndex.
  SiteId up(int l, SiteId s) const { return up_[static_cast<std::size_t>(l)][s]; }
  /// The copy of level-l site s (l >= 1) on level l-1.
  SiteId down(int l, SiteId s) const { return down_[static_cast<std::size_t>(l)][s]; }
  /// Every up (resp. down) link of level l, indexed by the level-l site (for saving).
  std::span<const SiteId> up_links(int l) const { return up_[static_cast<std::size_t>(l)]; }
  std::span<const SiteId> down_links(int l) const { return down_[static_cast<std::size_t>(l)]; }
  /// The highest level of a level-0 site with this id, from its draw.
  int drawn_level(SiteId s) const;
  const HierarchyOptions& options() const { return options_; }
  /// True iff the sites are weighted (base().is_weighted()).
  bool is_weighted() const { return !levels_.empty() && base().is_weighted(); }
  /// The largest 1 / lift of the base's sites, rounded up (1 for unweighted sites): |p / lift| of
  /// every lifted point is at most this (the Locator's rounding bound).
  double lifted_norm_bound() const { return lifted_norm_bound_; }
  /// Bytes held by the levels and links (not the walk graph: see walk_graph()).
  std::size_t memory_bytes() const;
  /// The packed copy of the hierarchy as it is now, for the Locators' walks: built at the first
  /// call after a change (O(n log n), about one build; the caller waits, so does a concurrent
  /// one), then shared by every caller until the next change, which drops the hierarchy's hold
  /// (a Locator keeps its copy until it sees the change). Thread-safe among const callers. A
  /// build runs on `threads` threads (0: one per core); the graph does not depend on it.
  std::shared_ptr<const WalkGraph> walk_graph(unsigned threads = 1) const;
  ///@}

  /// validate() of every level, plus the links: up and down are inverse, every copy is the same
  /// point, and every level-0 site of drawn level l has copies on levels 1..l.
  Validation validate() const;

 private:
  // Levels 1.. above a built base, each the sample of the one below (lifts: by base id, or empty).
  void build_levels(std::span<const double> lifts, const DelaunayOptions& options);
  void set_lifted_norm_bound();

  HierarchyOptions options_;
  double lifted_norm_bound_ = 1;
  std::vector<SphericalDelaunay> levels_;
  std::vector<std::vector<SiteId>> up_;    // up_[l][s]: level l -> level l+1 (last level: none)
  std::vector<std::vector<SiteId>> down_;  // down_[l][s]: level l -> level l-1 (down_[0] empty)

  // walk_graph()'s copy; a copied or moved hierarchy starts without one (a graph names its source).
  struct WalkGraphCache {
    std::mutex mutex;
    std::shared_ptr<const WalkGraph> graph;
    WalkGraphCache() = default;
    WalkGraphCache(const WalkGraphCache&) {}
    WalkGraphCache& operator=(const WalkGraphCache&) {
      graph.reset();
      return *this;
    }
  };
  mutable WalkGraphCache walk_graph_;
};

}  // namespace geovor
