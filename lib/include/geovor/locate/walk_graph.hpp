/// \file walk_graph.hpp
/// \brief A packed, read-only copy of a DelaunayHierarchy laid out for the Locator's walks.
///
/// A walk reads a site's neighbours, then their coordinates. In the triangulation that is three
/// dependent loads per neighbour (half-edge, twin, site) into arrays indexed by site ids in input
/// order, so at 2^20 random sites nearly every one is a cache miss. Here, on every level, the live
/// sites are renumbered along the Hilbert curve (spatial_sort.hpp; the base by hilbert_key(), with
/// one node in 16 kept with its key for curve_start()), so that neighbours are mostly
/// close in memory, and each site is one record holding everything a walk reads of it:
///   coordinates (3 doubles) | node above | site id (base) or node below | degree | neighbours,
/// 36 + 4 * degree bytes rounded up to 8. A walk step needs the records of the current site's
/// neighbours; the one it moves to already holds its own neighbour list, so each step waits for
/// one memory access, not two. A node is its record's offset in 8-byte words on its level.
///
/// Memory: about 64 bytes per site on the base (degree 6 on average), + 4 per site id (node of
/// each site), + 0.75 for the curve sample; the levels above add about 1/29 of that (68 bytes
/// per site measured at 2^20 uniform sites). The coordinates are copies of the
/// triangulation's doubles (bit for bit), so any comparison made on them is the one the
/// triangulation would make; on a level of weighted sites they are the lifted points
/// SphericalDelaunay::lifted_site() (site / lift, rounded once), whose dot product with q orders
/// the sites by power.
///
/// A WalkGraph is immutable; when the hierarchy changes (any level's revision() changes) it is
/// stale, and matches() says so. The hierarchy owns the graph of its current state
/// (DelaunayHierarchy::walk_graph()), built once and shared by every Locator asking.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "geovor/core/default_init.hpp"
#include "geovor/core/types.hpp"
#include "geovor/locate/delaunay_hierarchy.hpp"

namespace geovor {

class WalkGraph {
 public:
  /// Builds the packed copy of every level of `h`: O(n log n) (one Hilbert sort per level), on
  /// `threads` threads (0: one per core); the graph does not depend on it.
  explicit WalkGraph(const DelaunayHierarchy& h, unsigned threads = 1);

  /// True iff the graph is a copy of `h` as it is now: the same object with the same revision()
  /// on every level. O(levels).
  bool matches(const DelaunayHierarchy& h) const {
    if (source_ != &h || static_cast<std::size_t>(h.num_levels()) != revisions_.size()) return false;
    for (std::size_t l = 0; l < revisions_.size(); ++l)
      if (h.level(static_cast<int>(l)).revision() != revisions_[l]) return false;
    return true;
  }

  int num_levels() const { return static_cast<int>(levels_.size()); }
  std::uint32_t num_nodes(int l) const { return level_(l).num_nodes; }
  /// A node of level l (REQUIRES: num_nodes(l) > 0).
  static constexpr std::uint32_t any_node() { return 0; }
  /// The site's unit vector, or its lifted point on a weighted level.
  Vec3 point(int l, std::uint32_t v) const { return point_at(level_(l).words.data() + v); }
  /// The node of the same site on level l + 1, or kNoIndex (always on the top level).
  std::uint32_t up(int l, std::uint32_t v) const { return field(level_(l).words.data() + v, 0); }
  /// The node of the same site on level l - 1 (REQUIRES: l >= 1).
  std::uint32_t down(int l, std::uint32_t v) const { return field(level_(l).words.data() + v, 1); }
  std::uint32_t degree(int l, std::uint32_t v) const { return field(level_(l).words.data() + v, 2); }
  /// The site id of base node v, and the base node of live site s.
  SiteId site_of(std::uint32_t v) const { return field(level_(0).words.data() + v, 1); }
  std::uint32_t node_of(SiteId s) const { return node_of_[s]; }
  /// A base node near q found through the Hilbert curve: the base nodes are in the order of
  /// their hilbert_key(), and one in kCurveSample is kept with its key; of the two kept nodes
  /// around q's key, the nearer to q (kNoIndex if there is no site). Curve neighbours are
  /// usually, not always, near (the curve jumps at some cell borders): a start, no answer.
  std::uint32_t curve_start(const Vec3& q) const;
  static constexpr std::uint32_t kCurveSample = 16;
  /// f(w, point of w) for every neighbour w of node v of level l, counter-clockwise.
  template <class F>
  void for_each_neighbour(int l, std::uint32_t v, F&& f) const {
    const std::uint64_t* words = level_(l).words.data();
    const std::uint64_t* rec = words + v;
    const std::uint32_t deg = field(rec, 2);
    for (std::uint32_t k = 0; k < deg; ++k) {
      const std::uint32_t w = field(rec, 3 + k);
      f(w, point_at(words + w));
    }
  }
  /// Bytes held (capacity), all levels.
  std::size_t memory_bytes() const;

  /// Arrays of 32-bit words not zero-filled by resize() (core/default_init.hpp).
  using U32s = std::vector<std::uint32_t, DefaultInitAllocator<std::uint32_t>>;

 private:
  // Large levels in transparent huge pages (where the system allows them on request): a walk
  // touches records all over the level, and with 4 KiB pages most of its misses also miss the TLB.
  template <class T>
  struct HugePageAllocator {
    using value_type = T;
    HugePageAllocator() = default;
    template <class U>
    HugePageAllocator(const HugePageAllocator<U>&) {}
    T* allocate(std::size_t n);
    void deallocate(T* p, std::size_t) { std::free(p); }
    // resize() leaves the words unwritten: the thread that writes a record touches its pages first.
    template <class U>
    void construct(U* p) noexcept {
      ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
    friend bool operator==(const HugePageAllocator&, const HugePageAllocator&) { return true; }
  };
  struct Level {
    std::vector<std::uint64_t, HugePageAllocator<std::uint64_t>> words;  // the records, back to back
    std::uint32_t num_nodes = 0;
  };
  // Records are read and written with memcpy: the words hold doubles and 32-bit fields.
  static Vec3 point_at(const std::uint64_t* rec) {
    Vec3 p;
    std::memcpy(&p.x, rec, 8);
    std::memcpy(&p.y, rec + 1, 8);
    std::memcpy(&p.z, rec + 2, 8);
    return p;
  }
  static std::uint32_t field(const std::uint64_t* rec, std::uint32_t k) {  // k-th 32-bit field after p
    std::uint32_t x;
    std::memcpy(&x, reinterpret_cast<const unsigned char*>(rec + 3) + 4 * k, 4);
    return x;
  }
  const Level& level_(int l) const { return levels_[static_cast<std::size_t>(l)]; }

  const DelaunayHierarchy* source_ = nullptr;
  std::vector<std::uint64_t> revisions_;
  std::vector<Level> levels_;
  U32s node_of_;
  std::vector<std::uint64_t> curve_keys_;   // hilbert_key() of every kCurveSample-th base node
  std::vector<std::uint32_t> curve_nodes_;  // and that node
};

}  // namespace geovor
