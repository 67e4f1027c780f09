// Moving sites (issue 6): move()/move_all(), the filter first (move_filter.cpp), then relocation
// by flips (thesis §5.2.1) or by remove + insert, and move_all()'s rebuild when faster.
// docs/delaunay.md, "Moving sites".
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "delaunay/conflict.hpp"
#include "delaunay/unit_vector.hpp"
#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/bicell_tolerance.hpp"
#include "geovor/delaunay/spatial_sort.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/kernel/predicates.hpp"
#include "kernel/in_sphere_filter.hpp"

namespace geovor {
namespace {

// kernel::orient(p, q, r) == Positive, with the static filter inline (the call is rare).
bool positive(const Vec3& p, const Vec3& q, const Vec3& r) {
  const int quick = kernel::detail::in_sphere_filter_only(Vec3{}, p, q, r);  // det(p, q, r)
  if (quick != 0) return quick > 0;
  return kernel::orient(p, q, r) == Sign::Positive;
}

}  // namespace

MoveStats SphericalDelaunay::move(SiteId s, const Vec3& p, const RelocationOptions& options) {
  require_unweighted("move");
  if (!is_live(s)) throw Error(ErrorCode::InvalidArgument, "move: site " + std::to_string(s) + " is not live");
  if (!is_unit(p)) throw Error(ErrorCode::InvalidArgument, "move: site " + std::to_string(s) + ": not a unit vector");
  GEOVOR_ASSERT(priority_.empty());
  const MoveStats st = move_one(s, p, options);
  if (st.moved) touch();
  return st;
}

MoveStats SphericalDelaunay::move_all(std::span<const Vec3> positions, const RelocationOptions& options) {
  require_unweighted("move_all");
  if (positions.size() != sites_.size())
    throw Error(ErrorCode::InvalidArgument, "move_all: " + std::to_string(positions.size()) +
                                                " positions for " + std::to_string(sites_.size()) + " site ids");
  // Every position is checked before anything moves (a site staying put is a unit vector: only
  // moves can fail); this reads only the positions, and the liveness when sites were removed.
  const bool all_live = num_live_ == sites_.size();
  for (SiteId s = 0; s < sites_.size(); ++s)
    if (!is_unit(positions[s]) && (all_live || alive(s)))
      throw Error(ErrorCode::InvalidArgument, "move_all: position of site " + std::to_string(s) + " is not a unit vector");
  GEOVOR_ASSERT(priority_.empty());
  MoveStats total;
  if (!options.filter || num_live_ < 4) {
    for (SiteId s = 0; s < sites_.size(); ++s)
      if (!(positions[s] == sites_[s]) && alive(s)) total += move_one(s, positions[s], options);
    if (total.moved) touch();
    return total;
  }
  if (options.rebuild_when_faster && num_live_ >= kRebuildMinSites && num_live_ == sites_.size() &&
      priority_.empty() && (anchor_.empty() || relocated_share_ > kRelocatedShareToRebuild)) {
    // Relocating most sites costs several times a rebuild: estimate the share of sites whose move
    // the filter would miss with tolerances computed afresh, and rebuild if it is large.
    if (fresh_failure_share(positions) > kFreshFailureShareToFilter) {
      if (rebuild_in_place(positions, total)) {
        touch();
        return total;
      }
    } else {
      drop_tolerances();  // recomputed afresh below: their drift made the last batch slow
    }
  }
  // The same moves one at a time (move_one() in some order is exact in any order), ordered for
  // speed: first every move the filter certifies, then the others along the Hilbert curve of their
  // targets, so that consecutive relocations work in the same neighbourhood (site ids are in no
  // spatial order, and a relocation's cost is mostly its cache misses).
  if (anchor_.empty()) init_tolerances();
  std::vector<SiteId> unsorted;
  std::vector<Vec3> targets;
  for (SiteId s = 0; s < sites_.size(); ++s) {
    if ((s & 7) == 0 && s + 128 < sites_.size()) {
      __builtin_prefetch(&positions[s + 128]);
      __builtin_prefetch(&positions[s + 128 + 4]);
      __builtin_prefetch(&sites_[s + 128], 1);
      __builtin_prefetch(&sites_[s + 128 + 4], 1);
      __builtin_prefetch(&anchor_[s + 128]);
      __builtin_prefetch(&anchor_[s + 128 + 2]);
      __builtin_prefetch(&anchor_[s + 128 + 4]);
      __builtin_prefetch(&anchor_[s + 128 + 6]);
    }
    if (positions[s] == sites_[s] || !alive(s)) continue;
    if (norm2(positions[s] - anchor_[s].f) < anchor_[s].eps2) {  // move_one()'s filter, inline
      sites_[s] = positions[s];
      ++total.moved;
      ++total.filtered;
    } else {
      unsorted.push_back(s);
      targets.push_back(positions[s]);
    }
  }
  // Hilbert order of the targets (ties by id), as fine as their number asks.
  std::vector<SiteId> pending(unsorted.size());
  {
    const std::vector<std::uint32_t> order = hilbert_order(targets);
    for (std::size_t i = 0; i < order.size(); ++i) pending[i] = unsorted[order[i]];
  }
  // Consecutive pending sites are still a few sites apart, so each move would start with cache
  // misses on its star, a chain of them (each triangle names the next). Walk the stars of the
  // next few pending sites ahead of time, one hop per move for each, prefetching the next
  // triangle, the link sites' data and the triangles across the link: the walks' misses overlap
  // one another and the moves, and each hop reads only what an earlier hop fetched.
  struct StarWalk {
    HalfedgeId first = kNoIndex, at = kNoIndex, across = kNoIndex;
  };
  constexpr std::size_t kWalks = 16, kAhead = 10;
  StarWalk walks[kWalks];
  const std::size_t np = pending.size();
  for (std::size_t i = 0; i < np; ++i) {
    if (i + kAhead + 2 < np) {
      const SiteId a = pending[i + kAhead + 2];
      __builtin_prefetch(&site_edge_[a]);
      __builtin_prefetch(&positions[a]);
      __builtin_prefetch(&anchor_[a]);
      __builtin_prefetch(&sites_[a]);
    }
    if (i + kAhead < np) {  // its site_edge_ was fetched two moves ago
      const HalfedgeId e = site_edge_[pending[i + kAhead]];
      walks[(i + kAhead) % kWalks] = {e, e, kNoIndex};
      __builtin_prefetch(&triangles_[e]);
      __builtin_prefetch(&halfedges_[e]);
    }
    for (std::size_t j = i + 1; j < i + kAhead && j < np; ++j) {
      StarWalk& w = walks[j % kWalks];
      if (w.across != kNoIndex) {  // the far site of the last link edge's bi-cell
        const SiteId x = triangles_[prev_halfedge(w.across)];
        __builtin_prefetch(&anchor_[x]);
        __builtin_prefetch(&sites_[x]);
        w.across = kNoIndex;
      }
      if (w.at == kNoIndex) continue;
      const HalfedgeId e = w.at, en = next_halfedge(e);
      const SiteId v = triangles_[en];
      __builtin_prefetch(&anchor_[v]);
      __builtin_prefetch(&sites_[v]);
      w.across = halfedges_[en];  // the triangle across the link edge
      __builtin_prefetch(&triangles_[w.across]);
      const HalfedgeId next = next_around_site(e);
      if (next == w.first) {
        w.at = kNoIndex;
      } else {
        w.at = next;
        __builtin_prefetch(&triangles_[next]);
        __builtin_prefetch(&halfedges_[next]);
      }
    }
    const SiteId s = pending[i];
    total += move_one(s, positions[s], options);
  }
  relocated_share_ = static_cast<double>(total.flipped + total.reinserted) / static_cast<double>(num_live_);
  if (total.moved) touch();
  return total;
}

double SphericalDelaunay::fresh_failure_share(std::span<const Vec3> positions) const {
  // About 512 sites spread over the ids; each one's tolerance at the current positions, stopping
  // at the first bi-cell whose tolerance is below its move. (Only a policy: nothing depends on it
  // being right.)
  const std::size_t stride = std::max<std::size_t>(1, sites_.size() / 512);
  std::size_t tested = 0, failed = 0;
  const Vec3* f = sites_.data();
  for (SiteId s = 0; s < sites_.size(); s += static_cast<SiteId>(stride)) {
    if (!alive(s)) continue;
    ++tested;
    if (positions[s] == sites_[s]) continue;
    const double d2 = norm2(positions[s] - sites_[s]);
    const HalfedgeId e0 = site_edge_[s];
    HalfedgeId e = e0;
    bool fails = false;
    do {
      for (const HalfedgeId h : {e, next_halfedge(e)}) {
        const double tau = bicell_tolerance(f[triangles_[h]], f[triangles_[next_halfedge(h)]],
                                            f[triangles_[prev_halfedge(h)]],
                                            f[triangles_[prev_halfedge(halfedges_[h])]], options_.merge_distance);
        fails = fails || !(d2 < tau * tau);
      }
      e = next_around_site(e);
    } while (!fails && e != e0);
    failed += fails;
  }
  return tested ? static_cast<double>(failed) / static_cast<double>(tested) : 0;
}

bool SphericalDelaunay::rebuild_in_place(std::span<const Vec3> positions, MoveStats& stats) {
  // Ids are input indices (no site is removed) and the perturbed triangulation is unique: the
  // same triangles as relocating every site. A merge means some move must be refused, which the
  // one-by-one moves decide: give up then.
  BuildReport report;
  SphericalDelaunay next = build(positions, options_, &report);
  if (!report.merges.empty()) return false;
  std::size_t moved = 0;
  for (SiteId s = 0; s < sites_.size(); ++s) moved += !(positions[s] == sites_[s]);
  *this = std::move(next);  // no tolerances: the next batch estimates again
  stats.moved += moved;
  stats.rebuilt += moved;
  return true;
}

MoveStats SphericalDelaunay::move_one(SiteId s, const Vec3& p, const RelocationOptions& options) {
  MoveStats st;
  if (sites_[s] == p) return st;
  const bool filter = options.filter && num_live_ >= 4;  // fewer sites: no bi-cell to certify
  if (filter) {
    if (anchor_.empty()) init_tolerances();
    // Algorithm 1, line 2: within the tolerance of the reference position, nothing changes.
    if (norm2(p - anchor_[s].f) < anchor_[s].eps2) {
      sites_[s] = p;
      st.moved = st.filtered = 1;
      return st;
    }
    if (reanchor(s, p)) {
      st.moved = st.filtered = st.reanchored = 1;
      return st;
    }
  }
  if (refuse_move(s, p)) {
    st.refused = 1;
    return st;
  }
  touched_.clear();
  link_.clear();
  bool by_flips = options.flips && relocate_by_flips(s, p);
  if (!by_flips && !reinsert(s, p)) {
    st.refused = 1;
    return st;
  }
  st.moved = 1;
  (by_flips ? st.flipped : st.reinserted) = 1;
  if (!filter || anchor_.empty()) {
    drop_tolerances();  // not kept current without the filter: rebuilt at the next filtered move
    return st;
  }
  // Algorithm 1, lines 8-20: s gets its new position as reference, and every bi-cell the
  // relocation created lowers the tolerances of its sites; those that fall below their own
  // displacement are refreshed in turn.
  queue_.clear();
  refresh_site(s);
  bicells_.clear();
  for (const TriId t : touched_) {
    // Triangles at s: their three bi-cells are s's, just refreshed.
    if (triangles_[3 * t] == s || triangles_[3 * t + 1] == s || triangles_[3 * t + 2] == s) continue;
    for (int j = 0; j < 3; ++j) bicells_.push_back(3 * t + j);
  }
  update_bicells();
  update_around_link();  // the hole left by a removal was retriangulated around them
  st.refreshed = settle_queue();
  return st;
}

bool SphericalDelaunay::refuse_move(SiteId s, const Vec3& p) const {
  const double md2 = options_.merge_distance * options_.merge_distance;
  if (num_live_ <= 3) {
    for (SiteId t = 0; t < sites_.size(); ++t)
      if (t != s && alive(t) && chord2(p, sites_[t]) < md2) return true;
    return false;
  }
  // The nearest site to p is found by the greedy walk; if it is s itself (p is in s's Voronoi
  // cell), the nearest other site is a Delaunay neighbour of s (they share s's cell when s goes).
  // Neighbours of the walk's end cover its rounding.
  const SiteId v = walk_to_nearest(p, s);
  if (v != s && chord2(p, sites_[v]) < md2) return true;
  const HalfedgeId e0 = site_edge_[v];
  HalfedgeId e = e0;
  do {
    const SiteId w = triangles_[next_halfedge(e)];
    if (w != s && chord2(p, sites_[w]) < md2) return true;
    e = next_around_site(e);
  } while (e != e0);
  return false;
}

bool SphericalDelaunay::reinsert(SiteId s, const Vec3& p) {
  const Vec3 old = sites_[s];
  if (num_live_ > 3) collect_link(s);  // the sites around the hole, whose bi-cells change
  remove_site(s);
  sites_[s] = p;
  const SiteId hint = last_site_;
  const InsertResult r = insert_site(s, hint);
  if (!r.merged) return true;
  // refuse_move() saw no site within the merge distance, so this is never expected; the site
  // goes back where it was all the same.
  sites_[s] = old;
  const InsertResult back = insert_site(s, hint);
  GEOVOR_ASSERT(!back.merged);
  return false;
}

// ---------------------------------------------------------------------------------------------
// Relocation by flips (thesis §5.2.1)

bool SphericalDelaunay::adjacent(SiteId a, SiteId b) const {
  const HalfedgeId e0 = site_edge_[a];
  HalfedgeId e = e0;
  do {
    if (triangles_[next_halfedge(e)] == b) return true;
    e = next_around_site(e);
  } while (e != e0);
  return false;
}

void SphericalDelaunay::flip(HalfedgeId e) {
  // Triangles (a, b, c) at e = a->b and (b, a, d) at its twin become (c, a, d) and (d, b, c),
  // in the same two slots; the new diagonal is d->c at 3 t0 + 2.
  const HalfedgeId e1 = next_halfedge(e), e2 = prev_halfedge(e);
  const HalfedgeId f = halfedges_[e], f1 = next_halfedge(f), f2 = prev_halfedge(f);
  const SiteId a = triangles_[e], b = triangles_[e1], c = triangles_[e2], d = triangles_[f2];
  const HalfedgeId o_bc = halfedges_[e1], o_ca = halfedges_[e2], o_ad = halfedges_[f1], o_db = halfedges_[f2];
  const TriId t0 = tri_of(e), t1 = tri_of(f);
  auto set = [this](HalfedgeId h, SiteId from, HalfedgeId twin) {
    triangles_[h] = from;
    halfedges_[h] = twin;
    halfedges_[twin] = h;
  };
  set(3 * t0, c, o_ca);
  set(3 * t0 + 1, a, o_ad);
  set(3 * t1, d, o_db);
  set(3 * t1 + 1, b, o_bc);
  set(3 * t0 + 2, d, 3 * t1 + 2);
  triangles_[3 * t1 + 2] = c;
  site_edge_[a] = 3 * t0 + 1;
  site_edge_[b] = 3 * t1 + 1;
  site_edge_[c] = 3 * t0;
  site_edge_[d] = 3 * t1;
}

bool SphericalDelaunay::relocate_by_flips(SiteId s, const Vec3& p) {
  if (num_live_ < 5) return false;  // a few sites: remove + insert is as cheap and has no corner case
  const Vec3 old = sites_[s];
  // Every triangle of the star, before (no ghost) and after the move, is positively oriented:
  // the star stays a fan around s inside the same link, so the surface stays a sphere.
  const HalfedgeId e0 = site_edge_[s];
  HalfedgeId e = e0;
  do {
    const Vec3& w1 = sites_[triangles_[next_halfedge(e)]];
    const Vec3& w2 = sites_[triangles_[prev_halfedge(e)]];
    if (!positive(old, w1, w2) || !positive(p, w1, w2)) return false;
    e = next_around_site(e);
  } while (e != e0);

  sites_[s] = p;
  stack_.clear();
  flipped_.clear();
  do {  // the edges at s and the link edges: the bi-cells containing s
    stack_.push_back(e);
    stack_.push_back(next_halfedge(e));
    e = next_around_site(e);
  } while (e != e0);
  // Lawson's flips with the perturbed test: each flip adds a tetrahedron to the hull's volume,
  // so they end, at the only surface whose every edge is locally Delaunay.
  const std::size_t max_flips = 64 + 4 * num_live_;
  bool ok = true;
  while (!stack_.empty()) {
    const HalfedgeId h = stack_.back();
    stack_.pop_back();
    const HalfedgeId tw = halfedges_[h];
    const SiteId d = triangles_[prev_halfedge(tw)];
    // in_conflict()'s two stages (conflict.hpp), on the site d.
    const TriId th = tri_of(h);
    const int quick = kernel::detail::in_sphere_unit_filter(sites_[triangles_[3 * th]], sites_[triangles_[3 * th + 1]],
                                                            sites_[triangles_[3 * th + 2]], sites_[d]);
    if (quick < 0 || (quick == 0 && !in_conflict_exact(th, sites_[d], 1.0, priority(d)))) continue;
    const SiteId a = triangles_[h], b = triangles_[next_halfedge(h)], c = triangles_[prev_halfedge(h)];
    // The flip must keep the surface a sphere seen from the centre: both new triangles positively
    // oriented and the new edge not already there. Otherwise undo and reinsert.
    if (flipped_.size() >= max_flips || c == d ||
        !positive(sites_[c], sites_[a], sites_[d]) || !positive(sites_[d], sites_[b], sites_[c]) ||
        adjacent(c, d)) {
      ok = false;
      break;
    }
    const TriId t0 = tri_of(h), t1 = tri_of(tw);
    flip(h);
    flipped_.push_back(c);  // the new edge c-d, by its sites: flips move half-edges between slots
    flipped_.push_back(d);
    touched_.push_back(t0);
    touched_.push_back(t1);
    stack_.push_back(3 * t0);
    stack_.push_back(3 * t0 + 1);
    stack_.push_back(3 * t1);
    stack_.push_back(3 * t1 + 1);
  }
  if (ok) return true;
  // Undo in reverse order: flipping the new edge c-d back gives the old edge again.
  for (std::size_t i = flipped_.size(); i > 0; i -= 2) {
    const SiteId c = flipped_[i - 2], d = flipped_[i - 1];
    HalfedgeId h = site_edge_[c];
    while (triangles_[next_halfedge(h)] != d) h = next_around_site(h);
    flip(h);
  }
  sites_[s] = old;
  touched_.clear();
  return false;
}

}  // namespace geovor
