// Moving sites (issue 6): SphericalDelaunay::move()/move_all(), the thesis' vertex-tolerance
// filter (Ch. 5, Algorithm 1) carried to the sphere, relocation by flips or by remove + insert.
// The argument for the tolerance bound is in spherical_delaunay.hpp.
#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/spatial_sort.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/kernel/predicates.hpp"
#include "kernel/in_sphere_filter.hpp"

namespace geovor {
namespace {

double chord2(const Vec3& a, const Vec3& b) { return norm2(a - b); }

// kernel::orient(p, q, r) == Positive, with the static filter inline (the call is rare).
bool positive(const Vec3& p, const Vec3& q, const Vec3& r) {
  const int quick = kernel::detail::in_sphere_filter_only(Vec3{}, p, q, r);  // det(p, q, r)
  if (quick != 0) return quick > 0;
  return kernel::orient(p, q, r) == Sign::Positive;
}

bool is_unit(const Vec3& p) {
  const double r2 = norm2(p);
  return std::isfinite(r2) && std::fabs(r2 - 1.0) <= 0x1p-49;
}

}  // namespace

MoveStats SphericalDelaunay::move(SiteId s, const Vec3& p, const RelocationOptions& options) {
  if (!is_live(s)) throw Error(ErrorCode::InvalidArgument, "move: site " + std::to_string(s) + " is not live");
  if (!is_unit(p)) throw Error(ErrorCode::InvalidArgument, "move: site " + std::to_string(s) + ": not a unit vector");
  GEOVOR_ASSERT(priority_.empty());
  const MoveStats st = move_one(s, p, options);
  if (st.moved) touch();
  return st;
}

MoveStats SphericalDelaunay::move_all(std::span<const Vec3> positions, const RelocationOptions& options) {
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

bool SphericalDelaunay::reanchor(SiteId s, const Vec3& p) {
  // The second test (the filter failed: p is too far from s's reference f_s). Before the move the
  // sign of each bi-cell B containing s is the one at its references (Algorithm 1's invariant),
  // and also the one with s at its current position m_s instead: |m_s - f_s| < eps_s <= tau_B.
  // With tau_B' the tolerance of B recomputed with f_s := p, if |p - m_s| < tau_B', the
  // configurations (m_s, f) and (p, f) have the same sign, hence so does (p, f) and, if every
  // other site w of B is within tau_B' of f_w, the current positions: nothing changes but f_s,
  // eps_s and the eps of the other sites, each still within its new eps. The edge term of tau_B'
  // keeps every edge at s longer than the merge distance, as for the filter. A site moving
  // steadily fails the filter once its drift from f_s exceeds eps_s, while its step is far below
  // eps_s: this certifies it at the cost of a tolerance refresh, without a relocation.
  const Vec3 m = sites_[s];
  const double step2 = norm2(p - m);
  if (!(step2 < anchor_[s].eps2)) return false;  // would fail too, most likely: relocate now
  // Any unit vector f may be the new reference if |f - m_s| < tau_B' and |p - f| < tau_B' (the
  // argument above with f for p). Sites drift steadily (Lloyd's iterations), so f is p moved on
  // by the same step beta times, beta set to use about 80% of the old tolerance: the next test
  // then fails after up to 1.8 times as many steps (0.6: 17% fewer re-anchors, 0.95: more fail).
  const double beta = std::floor(0.8 * std::sqrt(anchor_[s].eps2 / step2)) - 1;
  const Vec3 f_new = beta > 0 ? (1 / std::sqrt(norm2(p + beta * (p - m)))) * (p + beta * (p - m)) : p;
  const double from_m2 = norm2(f_new - m), to_p2 = norm2(p - f_new);
  const Vec3 f_old = anchor_[s].f;
  anchor_[s].f = f_new;
  // The bi-cells of the edges at s and of the link edges opposite s, as refresh_site(), all
  // computed together (a failure is rarer than the time the batch saves).
  site_tau2(s);
  const std::size_t nb = quads_.size();
  const Anchor* f = anchor_.data();
  for (std::size_t i = 0; i < nb; ++i) {
    const double tau2 = tau2_[i];
    bool ok = from_m2 < tau2 && to_p2 < tau2;
    // Within eps_w <= tau_B' (the invariant) needs no look at the site's position.
    for (int j = 0; j < 4 && ok; ++j) {
      const SiteId w = quads_[i][j];
      ok = w == s || tau2 >= f[w].eps2 || sites_[w] == f[w].f || norm2(sites_[w] - f[w].f) < tau2;
    }
    if (!ok) {
      anchor_[s].f = f_old;
      return false;
    }
  }
  sites_[s] = p;
  anchor_[s].eps2 = std::numeric_limits<double>::infinity();
  // Every site is within each new tau (checked above): no refresh follows.
  for (std::size_t i = 0; i < nb; ++i)
    for (const SiteId w : quads_[i]) anchor_[w].eps2 = std::min(anchor_[w].eps2, tau2_[i]);
  return true;
}

void SphericalDelaunay::collect_link(SiteId s) {
  link_.clear();
  const HalfedgeId e0 = site_edge_[s];
  HalfedgeId e = e0;
  do {
    link_.push_back(triangles_[next_halfedge(e)]);
    e = next_around_site(e);
  } while (e != e0);
}

void SphericalDelaunay::update_around_link() {
  bicells_.clear();
  for (const SiteId w : link_) {
    if (!alive(w) || site_edge_[w] == kNoIndex) continue;
    const HalfedgeId e0 = site_edge_[w];
    HalfedgeId e = e0;
    do {
      bicells_.push_back(e);
      e = next_around_site(e);
    } while (e != e0);
  }
  update_bicells();
}

void SphericalDelaunay::tolerances_after_insert(SiteId s) {
  if (anchor_.empty()) return;
  if (num_live_ < 5) {
    drop_tolerances();
    return;
  }
  // Every new triangle has s as a vertex: its bi-cells are those refresh_site() computes.
  anchor_.push_back({sites_[s], std::numeric_limits<double>::infinity()});
  queue_.clear();
  refresh_site(s);
  settle_queue();
}

void SphericalDelaunay::remove_keeping_tolerances(SiteId s) {
  if (anchor_.empty() || num_live_ <= 5) {
    drop_tolerances();
    remove_site(s);
    return;
  }
  collect_link(s);
  remove_site(s);
  queue_.clear();
  update_around_link();  // every new triangle has its vertices in the link
  settle_queue();
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
    // in_conflict() is inline in spherical_delaunay.cpp: the same two stages here.
    const TriId th = tri_of(h);
    const int quick = kernel::detail::in_sphere_unit_filter(sites_[triangles_[3 * th]], sites_[triangles_[3 * th + 1]],
                                                            sites_[triangles_[3 * th + 2]], sites_[d]);
    if (quick < 0 || (quick == 0 && !in_conflict_exact(th, sites_[d], priority(d)))) continue;
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

// ---------------------------------------------------------------------------------------------
// Tolerances (Algorithm 1)

namespace {

inline double vmin(double a, double b) { return b < a ? b : a; }
inline double vmax(double a, double b) { return a < b ? b : a; }

// The square of an upper bound of the largest product |u| |v| over the seven pairs of edges
// (u, v) that bound the width of the tetrahedron: two edges of each face (the face's least
// product, as 2 x area is at most the product of any two of its edges) and the three pairs of
// opposite edges. q_k bounds the squared length of edge k, in the order 01, 02, 03, 12, 13, 23.
// Its root times (1 + 2^-44) covers the roundings (each q within a relative 2^-49 of its exact
// bound, each product and the root within 2^-52). Inlined into the lanes' loop, it vectorizes.
inline double largest_product2(double q0, double q1, double q2, double q3, double q4, double q5) {
  const double f012 = vmin(vmin(q0 * q1, q0 * q3), q1 * q3);
  const double f013 = vmin(vmin(q0 * q2, q0 * q4), q2 * q4);
  const double f023 = vmin(vmin(q1 * q2, q1 * q5), q2 * q5);
  const double f123 = vmin(vmin(q3 * q4, q3 * q5), q4 * q5);
  return vmax(vmax(vmax(f012, f013), vmax(f023, f123)), vmax(vmax(q0 * q5, q1 * q4), q2 * q3));
}

// The stretch of the map T (see spherical_delaunay.hpp): 1/4 suits the nearly co-circular
// bi-cells, which set the tolerances. kInvNorm = 1/sqrt(lambda^2 + 1), rounded down.
constexpr double kLambda = 0.25;
constexpr double kInvNorm = 0.9701425001453318;

// Up to this many bi-cells are computed together, as lanes of fixed-length loops the compiler
// vectorizes (SSE2 on x86-64: two lanes per instruction), stage by stage, so that the square
// roots and divisions of different bi-cells overlap. Lanes at n and above are padding.
constexpr std::size_t kBatch = 16;

// The four points of each lane, coordinates apart (structure of arrays, for the vector loops).
struct BicellLanes {
  double x[4][kBatch], y[4][kBatch], z[4][kBatch];
  void set(std::size_t i, int j, const Vec3& p) { x[j][i] = p.x, y[j][i] = p.y, z[j][i] = p.z; }
  // Lanes n.. up to the next multiple of 4 copy lane 0: finite numbers, so the vector loops
  // never see garbage.
  void pad(std::size_t n) {
    for (std::size_t i = n; i < ((n + 3) & ~std::size_t{3}); ++i)
      for (int j = 0; j < 4; ++j) x[j][i] = x[j][0], y[j][i] = y[j][0], z[j][i] = z[j][0];
  }
};

// x[i] = sqrt(x[i]) for the kBatch lanes, two at a time on x86-64 (std::sqrt's errno handling
// keeps the compiler from vectorizing the loops that call it).
inline void sqrt_lanes(double* x, std::size_t lanes) {
#if defined(__SSE2__)
  for (std::size_t i = 0; i < lanes; i += 2) _mm_storeu_pd(x + i, _mm_sqrt_pd(_mm_loadu_pd(x + i)));
#else
  for (std::size_t i = 0; i < lanes; ++i) x[i] = std::sqrt(x[i]);
#endif
}

// The lanes' function is also compiled for AVX2 (four lanes per instruction) and picked at run
// time where the processor has it (GCC on x86-64): about 8% of the late Lloyd iterations.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define GEOVOR_LANE_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define GEOVOR_LANE_CLONES
#endif


// tau of each lane's bi-cell (points a, b the shared edge, c, d the far sites), i < n <= kBatch:
// SphericalDelaunay::bicell_tolerance(); the argument is in spherical_delaunay.hpp. (The math
// of each lane is that of a scalar evaluation: the same roundings, so the same result.)
GEOVOR_LANE_CLONES void bicell_tolerances(const BicellLanes& in, std::size_t n, double merge_distance,
                                          double* tau) {
  constexpr std::size_t N = kBatch;
  const std::size_t L = (n + 3) & ~std::size_t{3};  // lanes computed: n, padded to the vector width
  const auto& X = in.x;
  const auto& Y = in.y;
  const auto& Z = in.z;
  double volume6[N], l2[6][N], c2[N], cmx[N], cmy[N], cmz[N];
  for (std::size_t i = 0; i < L; ++i) {
    // 6 x the volume of the tetrahedron, |det(b - a, c - a, d - a)|, minus Shewchuk's bound of
    // its rounding (kernel::detail::in_sphere_det and underflow_margin, lane by lane).
    const double bx = X[1][i] - X[0][i], by = Y[1][i] - Y[0][i], bz = Z[1][i] - Z[0][i];
    const double cx = X[2][i] - X[0][i], cy = Y[2][i] - Y[0][i], cz = Z[2][i] - Z[0][i];
    const double dx = X[3][i] - X[0][i], dy = Y[3][i] - Y[0][i], dz = Z[3][i] - Z[0][i];
    const double cydz = cy * dz, czdy = cz * dy;
    const double czdx = cz * dx, cxdz = cx * dz;
    const double cxdy = cx * dy, cydx = cy * dx;
    const double perm = (std::fabs(cydz) + std::fabs(czdy)) * std::fabs(bx) +
                        (std::fabs(czdx) + std::fabs(cxdz)) * std::fabs(by) +
                        (std::fabs(cxdy) + std::fabs(cydx)) * std::fabs(bz);
    const double det = bx * (cydz - czdy) + by * (czdx - cxdz) + bz * (cxdy - cydx);
    volume6[i] = std::fabs(det) - kernel::detail::kO3dErrBound * perm -
                 0x1p-1022 * (1 + std::fabs(bx) + std::fabs(by) + std::fabs(bz));
    // Squared edge lengths 01, 02, 03, 12, 13, 23, each within a relative 2^-50 of the exact one.
    const double ex[3] = {X[2][i] - X[1][i], X[3][i] - X[1][i], X[3][i] - X[2][i]};
    const double ey[3] = {Y[2][i] - Y[1][i], Y[3][i] - Y[1][i], Y[3][i] - Y[2][i]};
    const double ez[3] = {Z[2][i] - Z[1][i], Z[3][i] - Z[1][i], Z[3][i] - Z[2][i]};
    l2[0][i] = (bx * bx + by * by + bz * bz) * (1 + 0x1p-49);
    l2[1][i] = (cx * cx + cy * cy + cz * cz) * (1 + 0x1p-49);
    l2[2][i] = (dx * dx + dy * dy + dz * dz) * (1 + 0x1p-49);
    for (int k = 0; k < 3; ++k) l2[3 + k][i] = (ex[k] * ex[k] + ey[k] * ey[k] + ez[k] * ez[k]) * (1 + 0x1p-49);
    cmx[i] = X[0][i] + X[1][i] + X[2][i] + X[3][i];
    cmy[i] = Y[0][i] + Y[1][i] + Y[2][i] + Y[3][i];
    cmz[i] = Z[0][i] + Z[1][i] + Z[2][i] + Z[3][i];
    c2[i] = cmx[i] * cmx[i] + cmy[i] * cmy[i] + cmz[i] * cmz[i];
  }
  double s0[N], inv_smin[N], t[4][N], root[N] = {};  // (zeroed: the compiler cannot see that L lanes are set)
  // Spread over the sphere (c2 <= 1/4): the isotropic bound does as well; the stretch's numbers
  // are computed all the same (from c2 = 1/4) and left unused.
  for (std::size_t i = 0; i < L; ++i) root[i] = vmax(c2[i], 0.25);
  sqrt_lanes(root, L);
  for (std::size_t i = 0; i < L; ++i) {
    const double r = 1 / root[i];
    const double ux = r * cmx[i], uy = r * cmy[i], uz = r * cmz[i];
    // s0: the largest sine of the angle between c and a point, |c x f| / (|c| |f|), rounded up
    // (|c|^2 and |f|^2 are within 2^-48 of 1).
    double m = 0;
    for (int j = 0; j < 4; ++j) {
      const double kx = uy * Z[j][i] - uz * Y[j][i], ky = uz * X[j][i] - ux * Z[j][i], kz = ux * Y[j][i] - uy * X[j][i];
      m = vmax(m, kx * kx + ky * ky + kz * kz);
      t[j][i] = X[j][i] * ux + Y[j][i] * uy + Z[j][i] * uz;
    }
    root[i] = m;
  }
  sqrt_lanes(root, L);
  // Every S below is at least s_min, and the bound on |T u|^2 falls as S grows: the edge
  // products at s_min bound those at any S. (Rounded up. The loops with a division have no
  // select, and the other way round: the compiler vectorizes neither mix.)
  for (std::size_t i = 0; i < L; ++i) {
    s0[i] = root[i] * (1 + 0x1p-46) + 0x1p-48;
    inv_smin[i] = vmin(s0[i], 1.0);
  }
  for (std::size_t i = 0; i < L; ++i) inv_smin[i] = (1 / inv_smin[i]) * (1 + 0x1p-51);
  double q[6][N];
  for (std::size_t i = 0; i < L; ++i) {
    // u.c for the edge f_j - f_i is t_j - t_i, t_i = f_i.c; each computed t is within 2^-49 of
    // f_i.c for the exact unit c (the computed c is within 2^-50 of it), their difference
    // within a relative 2^-52 more: 2^-47 covers it.
    const double inv = inv_smin[i] * (1 / kLambda);  // a power of two: exact
    const double dt[6] = {t[1][i] - t[0][i], t[2][i] - t[0][i], t[3][i] - t[0][i],
                          t[2][i] - t[1][i], t[3][i] - t[1][i], t[3][i] - t[2][i]};
    for (int k = 0; k < 6; ++k) {
      const double uc = (std::fabs(dt[k]) + 0x1p-47) * inv;
      q[k][i] = (l2[k][i] + uc * uc) * (1 + 0x1p-50);
    }
  }
  for (std::size_t i = 0; i < L; ++i) {
    root[i] = largest_product2(q[0][i], q[1][i], q[2][i], q[3][i], q[4][i], q[5][i]);  // its root below
  }
  sqrt_lanes(root, L);
  double K[N], cap1[N], S1[N];
  for (std::size_t i = 0; i < L; ++i) {
    // A move of chord D <= cap (<= 1/2) turns a point by the angle 2 asin(D / 2) <= k D,
    // k = 1 + cap^2 / 20, so by at most A = k (cap + 2^-49) (2^-49 for sites 2^-50 off the
    // sphere), and changes its component along c by at most S D + eps, S = min(k (s0 + A), 1),
    // eps = 2^-49 (1 + S) <= 2^-48 (mean value theorem on the cosine, whose derivative, a sine,
    // stays below s0 + A on the way), and its image under T moves by at most
    // sqrt(1 + 1/lambda^2) D + eps / (lambda S). Below half of w_T >= 6 V / (lambda S M), M the
    // largest edge product, no four images, hence no four points, become coplanar:
    //   D < (6 V / (2 M) - eps) / (S sqrt(lambda^2 + 1)) = K / S.
    K[i] = (volume6[i] / (2 * (root[i] * (1 + 0x1p-44))) - 0x1p-48) * kInvNorm;
  }
  for (std::size_t i = 0; i < L; ++i) {
    // Any cap is valid; the best solves K / S(cap) = cap. cap1 = K / s0 >= K / S(0) is above
    // it, so S(cap1) >= S(cap) for cap <= cap1, and cap = min(K / S(cap1), cap1) has
    // K / S(cap) >= cap.
    cap1[i] = vmin(K[i] * inv_smin[i], 0.5);
  }
  for (std::size_t i = 0; i < L; ++i) {
    const double k = 1 + (cap1[i] * cap1[i] / 20 + 0x1p-52);  // k(cap) grows with cap: k(cap1) bounds
    S1[i] = vmin(k * (s0[i] + k * (cap1[i] + 0x1p-49)), 1.0);
  }
  for (std::size_t i = 0; i < L; ++i) S1[i] = K[i] / S1[i];
  double half_width[N];
  for (std::size_t i = 0; i < L; ++i)
    half_width[i] = ((c2[i] > 0.25) & (K[i] > 0)) ? vmin(S1[i], cap1[i]) : 0.0;
  const double md = merge_distance * (1 + 0x1p-40);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(volume6[i] > 0)) {  // coplanar (a tie), or too close to tell
      tau[i] = 0;
      continue;
    }
    double hw = half_width[i];
    // Any motion in R^3 by less than half the width keeps the sign too: the better bound for
    // bi-cells spanning a large part of the sphere.
    if (!(c2[i] > 0.25) || s0[i] > 0.2) {
      const double M = std::sqrt(largest_product2(l2[0][i], l2[1][i], l2[2][i], l2[3][i], l2[4][i], l2[5][i]));
      hw = std::max(hw, volume6[i] / (2 * (M * (1 + 0x1p-44))));
    }
    // The shared edge a-b must stay longer than the merge distance (with room for the rounding
    // of the merge test's own chord): (|a - b| - merge) / 2, whose root is needed only when the
    // edge is short.
    const double need = 2 * hw + md;
    if (!(l2[0][i] >= need * need * (1 + 0x1p-44))) {
      const double ab2 = (X[1][i] - X[0][i]) * (X[1][i] - X[0][i]) + (Y[1][i] - Y[0][i]) * (Y[1][i] - Y[0][i]) +
                         (Z[1][i] - Z[0][i]) * (Z[1][i] - Z[0][i]);
      hw = std::min(hw, (std::sqrt(ab2) - md) / 2);
    }
    // The few roundings above are each within a relative 2^-52: a 2^-46 margin covers them all.
    const double x = hw * (1 - 0x1p-46);
    tau[i] = x > 0 ? x : 0;
  }
}

}  // namespace

double SphericalDelaunay::bicell_tolerance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                           double merge_distance) {
  BicellLanes lanes;
  lanes.set(0, 0, a), lanes.set(0, 1, b), lanes.set(0, 2, c), lanes.set(0, 3, d);
  lanes.pad(1);
  double tau[kBatch];
  bicell_tolerances(lanes, 1, merge_distance, tau);
  return tau[0];
}

void SphericalDelaunay::init_tolerances() {
  anchor_.resize(sites_.size());
  for (SiteId s = 0; s < sites_.size(); ++s) anchor_[s] = {sites_[s], std::numeric_limits<double>::infinity()};
  queue_.clear();
  bicells_.clear();
  for (HalfedgeId e = 0; e < halfedges_.size(); ++e)
    if (halfedges_[e] > e) bicells_.push_back(e);  // each edge (bi-cell) once
  update_bicells();
  queue_.clear();  // every site is at its reference: nothing to refresh
}

bool SphericalDelaunay::within_tolerance(SiteId s) const {
  return sites_[s] == anchor_[s].f || norm2(sites_[s] - anchor_[s].f) < anchor_[s].eps2;
}

void SphericalDelaunay::bicell_sites(HalfedgeId e, Quad& q) const {
  q[0] = triangles_[e];
  q[1] = triangles_[next_halfedge(e)];
  q[2] = triangles_[prev_halfedge(e)];
  q[3] = triangles_[prev_halfedge(halfedges_[e])];
}

void SphericalDelaunay::bicell_tau2(const Quad* q, std::size_t n, double* tau2) const {
  const Anchor* f = anchor_.data();
  BicellLanes lanes;
  double tau[kBatch];
  for (std::size_t done = 0; done < n; done += kBatch) {
    const std::size_t m = std::min(kBatch, n - done);
    for (std::size_t i = 0; i < m; ++i)
      for (int j = 0; j < 4; ++j) lanes.set(i, j, f[q[done + i][j]].f);
    lanes.pad(m);
    bicell_tolerances(lanes, m, options_.merge_distance, tau);
    // Squared with a relative 2^-48 to spare, so that the filter's squared chord in doubles
    // (within 2^-50 of the exact one) below it certifies a chord below the tolerance.
    for (std::size_t i = 0; i < m; ++i) {
      const double x = tau[i] * (1 - 0x1p-48);
      tau2[done + i] = x * x;
    }
  }
}

void SphericalDelaunay::update_bicells() {
  // Each bi-cell lowers the tolerances of its four sites; a site pushed below its own
  // displacement goes to the queue.
  const std::size_t n = bicells_.size();
  for (std::size_t done = 0; done < n; done += kBatch) {
    const std::size_t m = std::min(kBatch, n - done);
    Quad q[kBatch];
    double tau2[kBatch];
    for (std::size_t i = 0; i < m; ++i) bicell_sites(bicells_[done + i], q[i]);
    bicell_tau2(q, m, tau2);
    for (std::size_t i = 0; i < m; ++i)
      for (const SiteId w : q[i]) {
        if (tau2[i] >= anchor_[w].eps2) continue;
        anchor_[w].eps2 = tau2[i];
        if (!within_tolerance(w)) queue_.push_back(w);
      }
  }
  bicells_.clear();
}

void SphericalDelaunay::site_tau2(SiteId s) {
  // One walk around the star gives every bi-cell containing s: around s the triangles are
  // (s, w_i, w_i+1), so the bi-cell of the edge s-w_i is (s, w_i, w_i+1, w_i-1) and that of the
  // link edge w_i-w_i+1 is (w_i, w_i+1, s, x_i), x_i across it, in that order.
  // Each site's reference is read once.
  link_w_.clear();
  link_x_.clear();
  const HalfedgeId e0 = site_edge_[s];
  HalfedgeId e = e0;
  do {
    const HalfedgeId en = next_halfedge(e);
    link_w_.push_back(triangles_[en]);
    link_x_.push_back(triangles_[prev_halfedge(halfedges_[en])]);
    e = next_around_site(e);
  } while (e != e0);
  const std::size_t k = link_w_.size();
  quads_.resize(2 * k);
  tau2_.resize(2 * k);
  for (std::size_t i = 0; i < k; ++i) {
    const SiteId w = link_w_[i], w_next = link_w_[i + 1 == k ? 0 : i + 1], w_prev = link_w_[i == 0 ? k - 1 : i - 1];
    quads_[2 * i] = {s, w, w_next, w_prev};
    quads_[2 * i + 1] = {w, w_next, s, link_x_[i]};
  }
  const Anchor* f = anchor_.data();
  const Vec3 fs = f[s].f;
  BicellLanes lanes;
  double tau[kBatch];
  constexpr std::size_t kPairs = kBatch / 2;  // the two bi-cells of each link site per lane pair
  for (std::size_t done = 0; done < k; done += kPairs) {
    const std::size_t m = std::min(kPairs, k - done);
    for (std::size_t j = 0; j < m; ++j) {
      const std::size_t i = done + j;
      const Vec3 &fw = f[link_w_[i]].f, &fn = f[link_w_[i + 1 == k ? 0 : i + 1]].f, &fp = f[link_w_[i == 0 ? k - 1 : i - 1]].f;
      lanes.set(2 * j, 0, fs), lanes.set(2 * j, 1, fw), lanes.set(2 * j, 2, fn), lanes.set(2 * j, 3, fp);
      lanes.set(2 * j + 1, 0, fw), lanes.set(2 * j + 1, 1, fn), lanes.set(2 * j + 1, 2, fs);
      lanes.set(2 * j + 1, 3, f[link_x_[i]].f);
    }
    lanes.pad(2 * m);
    bicell_tolerances(lanes, 2 * m, options_.merge_distance, tau);
    for (std::size_t j = 0; j < 2 * m; ++j) {  // squared with the margin, as bicell_tau2()
      const double x = tau[j] * (1 - 0x1p-48);
      tau2_[2 * done + j] = x * x;
    }
  }
}

void SphericalDelaunay::refresh_site(SiteId s) {
  anchor_[s].f = sites_[s];
  anchor_[s].eps2 = std::numeric_limits<double>::infinity();
  site_tau2(s);
  // Each bi-cell lowers the tolerances of its four sites; a site pushed below its own
  // displacement goes to the queue.
  for (std::size_t i = 0; i < quads_.size(); ++i)
    for (const SiteId w : quads_[i]) {
      if (tau2_[i] >= anchor_[w].eps2) continue;
      anchor_[w].eps2 = tau2_[i];
      if (!within_tolerance(w)) queue_.push_back(w);
    }
}

std::size_t SphericalDelaunay::settle_queue() {
  std::size_t refreshed = 0;
  while (!queue_.empty()) {
    const SiteId w = queue_.back();
    queue_.pop_back();
    if (!alive(w) || within_tolerance(w)) continue;  // already refreshed
    refresh_site(w);
    ++refreshed;
  }
  return refreshed;
}

double SphericalDelaunay::tolerance(SiteId s) {
  if (!is_live(s)) throw Error(ErrorCode::InvalidArgument, "tolerance: site " + std::to_string(s) + " is not live");
  if (num_live_ < 4) return 0;
  if (anchor_.empty()) init_tolerances();
  return std::sqrt(anchor_[s].eps2);
}

}  // namespace geovor
