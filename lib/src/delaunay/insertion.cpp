// Inserting a site: where the point goes (a walk to its nearest site, a triangle in conflict or a
// merge), then its cavity (cavity.cpp) replaced by a fan. docs/delaunay.md, "Insertion".
#include <cmath>
#include <string>

#include "delaunay/cavity.hpp"
#include "delaunay/conflict.hpp"
#include "delaunay/unit_vector.hpp"
#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/kernel/predicates.hpp"

namespace geovor {

bool SphericalDelaunay::in_conflict_exact(TriId t, const Vec3& p, double c, std::uint32_t prio) const {
  const SiteId a = triangles_[3 * t], b = triangles_[3 * t + 1], d = triangles_[3 * t + 2];
  // Ties get the perturbation; only now are the priorities needed.
  if (lifts_.empty())
    return kernel::perturbed_in_sphere(sites_[a], priority(a), sites_[b], priority(b), sites_[d],
                                       priority(d), p, prio) == Sign::Positive;
  return kernel::perturbed_in_sphere_weighted(sites_[a], lifts_[a], priority(a), sites_[b], lifts_[b], priority(b),
                                              sites_[d], lifts_[d], priority(d), p, c, prio) == Sign::Positive;
}

void SphericalDelaunay::require_unweighted(const char* what) const {
  if (!lifts_.empty())
    throw Error(ErrorCode::InvalidArgument, std::string(what) + ": not supported on a triangulation of weighted sites");
}

InsertResult SphericalDelaunay::insert(const Vec3& p) {
  require_unweighted("insert");
  touch();
  const double r2 = norm2(p);
  if (!std::isfinite(r2) || std::fabs(r2 - 1.0) > 0x1p-49)
    throw Error(ErrorCode::InvalidArgument, "insert: not a unit vector (|p|^2 = " + format_number(r2) + ")");
  if (sites_.size() >= kMaxSites) throw Error(ErrorCode::InvalidArgument, "too many sites");
  GEOVOR_ASSERT(priority_.empty());
  const SiteId s = static_cast<SiteId>(sites_.size());
  sites_.push_back(p);
  site_edge_.push_back(kRemoved);
  const InsertResult r = insert_site(s, last_site_);
  if (r.merged) {  // the point never became a site: give its id back
    sites_.pop_back();
    site_edge_.pop_back();
  } else {
    tolerances_after_insert(s);  // the relocation filter's new bi-cells
  }
  return r;
}

InsertResult SphericalDelaunay::insert_site(SiteId s, SiteId hint) {
  const Vec3& p = sites_[s];
  const double lift_p = lift(s);
  const std::uint32_t prio = priority(s);
  const double md2 = options_.merge_distance * options_.merge_distance;
  if (num_live_ < 3) {
    // No triangle yet: compare with the (at most two) live sites directly.
    SiteId live[2];
    std::size_t k = 0;
    for (SiteId t = 0; t < sites_.size() && k < num_live_; ++t)
      if (t != s && alive(t)) live[k++] = t;
    for (std::size_t i = 0; i < k; ++i) {
      const double d2 = chord2(p, sites_[live[i]]);
      if (d2 < md2) return {live[i], true, std::sqrt(d2), false};
    }
    site_edge_[s] = kNoIndex;
    ++num_live_;
    last_site_ = s;
    if (num_live_ == 3) make_first_triangles(live[0], live[1], s);
    return {s, false, 0, false};
  }
  if (hint == kNoIndex || !alive(hint) || site_edge_[hint] == kNoIndex) hint = any_live_site();
  const Placement where = place(p, lift_p, prio, hint);
  if (where.merged_into != kNoIndex) return {where.merged_into, true, where.chord, where.hidden};
  if (where.conflict == kNoIndex) {  // weighted: p's lifted point is inside the hull
    hidden_by_[s] = where.hidden_by;
    return {s, false, 0, true};
  }
  find_cavity(p, lift_p, prio, where.conflict);
  if (num_boundary_ != num_cavity_ + 2 && lifts_.empty()) {
    abandon_cavity();
    // Not a disk: a site is inside the cavity, which only a point on (or extremely near) a site
    // not met so far can cause.
    const Placement near = nearest_site(p, triangles_[3 * where.conflict]);
    GEOVOR_ASSERT(near.merged_into != kNoIndex);
    return {near.merged_into, true, near.chord, false};
  }
  // The nearest site of p becomes its Delaunay neighbour, so it is on the cavity's boundary
  // (every vertex of a disk-shaped cavity is): the merge test needs no search of its own.
  SiteId closest = kNoIndex;
  double best = md2;
  const Vec3* const S = sites_.data();
  const CavityEdge* const bnd = boundary_.data();
  for (std::size_t k = 0; k < num_boundary_; ++k) {
    const double d2 = chord2(p, S[bnd[k].a]);
    if (d2 < best) [[unlikely]]
      best = d2, closest = bnd[k].a;
  }
  if (closest != kNoIndex) {
    abandon_cavity();
    return {closest, true, std::sqrt(best), false};
  }
  // A weighted point can hide vertices: they lie inside its cavity, a disk.
  if (num_boundary_ != num_cavity_ + 2) hide_cavity_interior(s);
  fill_cavity(s);
  ++num_live_;
  last_site_ = s;
  return {s, false, 0, false};
}

SiteId SphericalDelaunay::any_live_site() const {
  if (last_site_ != kNoIndex && last_site_ < sites_.size() && alive(last_site_) &&
      (num_live_ < 3 || site_edge_[last_site_] != kNoIndex))
    return last_site_;
  for (SiteId s = 0; s < sites_.size(); ++s)
    if (alive(s) && (num_live_ < 3 || site_edge_[s] != kNoIndex)) return s;
  return kNoIndex;
}


// Greedy walk on the Delaunay graph towards the site maximising dot(p, site): the simplex method
// on the hull's vertex graph, so a local maximum is the global one. Plain doubles are enough:
// the result only seeds the exact conflict search. Weighted: the same for dot(p, site / lift).
SiteId SphericalDelaunay::walk_to_nearest(const Vec3& p, SiteId v) const {
  return lifts_.empty() ? walk_to_largest<false>(p, v) : walk_to_largest<true>(p, v);
}

template <bool kWeighted>
SiteId SphericalDelaunay::walk_to_largest(const Vec3& p, SiteId v) const {
  // Weighted: d / c > best_d / best_c, both lifts positive, without a division.
  double best_d = dot(p, sites_[v]), best_c = kWeighted ? lifts_[v] : 1.0;
  for (;;) {
    const HalfedgeId e0 = site_edge_[v];
    HalfedgeId e = e0;
    SiteId next = v;
    do {
      const SiteId w = triangles_[next_halfedge(e)];
      const double d = dot(p, sites_[w]);
      if constexpr (kWeighted) {
        const double c = lifts_[w];
        if (d * best_c > best_d * c) best_d = d, best_c = c, next = w;
      } else if (d > best_d) {
        best_d = d, next = w;
      }
      e = next_around_site(e);
    } while (e != e0);
    if (next == v) return v;
    v = next;
  }
}

TriId SphericalDelaunay::find_conflict(const Vec3& p, double c, std::uint32_t prio, SiteId near) const {
  // The new site's nearest neighbour becomes its Delaunay neighbour, so some triangle around it
  // is in conflict; the exhaustive search below is only a safety net. Weighted: so does the site
  // of largest power when the new site's cell holds its own position, and otherwise a search.
  const HalfedgeId e0 = site_edge_[near];
  HalfedgeId e = e0;
  do {
    if (in_conflict(tri_of(e), p, c, prio)) return tri_of(e);
    e = next_around_site(e);
  } while (e != e0);
  if (!lifts_.empty()) return search_conflict(p, c, prio, near);
  for (TriId t = 0; t < num_triangles(); ++t)
    if (in_conflict(t, p, c, prio)) return t;
  return kNoIndex;
}

bool SphericalDelaunay::origin_inside() const {
  // Once inside the hull of the lifted points, the centre stays inside: the hull only grows.
  if (origin_inside_ || num_live_ < 2 * origin_checked_at_) return origin_inside_;
  origin_checked_at_ = std::max<std::size_t>(num_live_, 4);
  for (TriId t = 0; t < num_triangles(); ++t)
    if (kernel::orient(sites_[triangles_[3 * t]], sites_[triangles_[3 * t + 1]], sites_[triangles_[3 * t + 2]]) !=
        Sign::Positive)
      return false;
  return origin_inside_ = true;
}

TriId SphericalDelaunay::radial_triangle(const Vec3& p, TriId t) const {
  // A visibility walk: across an edge whose great circle has p on its outer side.
  for (std::size_t step = 0; step <= num_triangles(); ++step) {
    int out = -1;
    for (int j = 0; j < 3 && out < 0; ++j)
      if (kernel::orient(sites_[triangles_[3 * t + j]], sites_[triangles_[3 * t + (j == 2 ? 0 : j + 1)]], p) ==
          Sign::Negative)
        out = j;
    if (out < 0) return t;
    t = tri_of(halfedges_[3 * t + static_cast<unsigned>(out)]);
  }
  return kNoIndex;
}

TriId SphericalDelaunay::search_conflict(const Vec3& p, double c, std::uint32_t prio, SiteId near) const {
  // With the centre inside the hull, the ray from it toward p leaves the hull through the face
  // whose cone holds p: p's lifted point is outside the hull (not hidden) iff beyond that face.
  // Ties (p on an edge or at a vertex of it) are decided among the faces around its corners.
  if (origin_inside()) {
    const TriId t = radial_triangle(p, tri_of(site_edge_[near]));
    if (t != kNoIndex) {
      if (in_conflict(t, p, c, prio)) return t;
      for (int j = 0; j < 3; ++j) {
        const HalfedgeId e0 = site_edge_[triangles_[3 * t + j]];
        HalfedgeId e = e0;
        do {
          if (in_conflict(tri_of(e), p, c, prio)) return tri_of(e);
          e = next_around_site(e);
        } while (e != e0);
      }
      return kNoIndex;
    }
  }
  // Otherwise: the triangles in conflict are connected (the faces visible from a point outside a
  // convex polytope), but need not touch the star of `near`: breadth first from it.
  std::vector<char> seen(num_triangles(), 0);
  std::vector<TriId> queue;
  const HalfedgeId e0 = site_edge_[near];
  HalfedgeId e = e0;
  do {
    seen[tri_of(e)] = 1;
    queue.push_back(tri_of(e));
    e = next_around_site(e);
  } while (e != e0);
  for (std::size_t k = 0; k < queue.size(); ++k) {
    const TriId t = queue[k];
    if (k >= 1 && in_conflict(t, p, c, prio)) return t;
    for (int j = 0; j < 3; ++j) {
      const TriId u = tri_of(halfedges_[3 * t + j]);
      if (!seen[u]) seen[u] = 1, queue.push_back(u);
    }
  }
  return kNoIndex;
}

void SphericalDelaunay::hide_cavity_interior(SiteId s) {
  // Interior vertices are those of cavity triangles that start no boundary edge. One closer to s
  // than the merge distance is merged into s (the larger circle), not hidden.
  const double md2 = options_.merge_distance * options_.merge_distance;
  for (std::size_t k = 0; k < num_boundary_; ++k) site_edge_[boundary_[k].a] = kNoIndex - 2;
  for (std::size_t k = 0; k < num_cavity_; ++k) {
    const TriId t = cavity_[k];
    for (int j = 0; j < 3; ++j) {
      const SiteId v = triangles_[3 * t + j] & ~kMark;
      if (site_edge_[v] == kNoIndex - 2 || site_edge_[v] == kRemoved) continue;
      site_edge_[v] = kRemoved;
      --num_live_;
      const double d2 = chord2(sites_[v], sites_[s]);
      if (d2 < md2)
        absorbed_.push_back({v, s, std::sqrt(d2), false});
      else
        hidden_by_[v] = s;
    }
  }
  // fill_cavity() sets the boundary vertices' edges again.
}

SphericalDelaunay::Placement SphericalDelaunay::place(const Vec3& p, double c, std::uint32_t prio,
                                                      SiteId hint) {
  Placement where;
  // Fast path: consecutive sites in a spatial order are near, so the triangles around the last
  // site are often in conflict already. Those found not in conflict stay marked as tested, so
  // the cavity search does not test them again.
  const HalfedgeId e0 = site_edge_[hint];
  HalfedgeId e = e0;
  TriId* tested = tested_.data();
  std::size_t nt = 0;
  do {
    const TriId t = tri_of(e);
    if (in_conflict(t, p, c, prio)) {
      where.conflict = t;
      num_tested_ = nt;
      return where;
    }
    triangles_[3 * t + 1] |= kMark;
    if (nt == tested_.size()) tested = grow(tested_);
    tested[nt++] = t;
    e = next_around_site(e);
  } while (e != e0);
  for (std::size_t k = 0; k < nt; ++k) triangles_[3 * tested[k] + 1] &= ~kMark;
  num_tested_ = 0;
  // Slow path: walk to the nearest site; a point on or next to it merges before any exhaustive
  // search (a duplicate can be hidden inside the hull).
  const SiteId v = walk_to_nearest(p, hint);
  const Placement near = nearest_site(p, v);  // its walk starts at the end: no step
  if (near.merged_into != kNoIndex) return near;
  where.conflict = find_conflict(p, c, prio, v);
  if (where.conflict == kNoIndex && !lifts_.empty()) {
    where.hidden_by = v;  // a weighted site hidden: v's cell holds p (largest power there)
  } else if (where.conflict == kNoIndex) {
    // No triangle in conflict: p lies inside the hull, which the minimum separation excludes;
    // it goes into the nearest site all the same, and the report says so.
    where.merged_into = v;
    where.chord = std::sqrt(chord2(p, sites_[v]));
    where.hidden = true;
  }
  return where;
}

SphericalDelaunay::Placement SphericalDelaunay::nearest_site(const Vec3& p, SiteId hint) const {
  // The walk is in doubles; the nearest site is then v or one of its neighbours.
  const SiteId v = walk_to_nearest(p, hint);
  SiteId closest = v;
  double best = chord2(p, sites_[v]);
  const HalfedgeId e0 = site_edge_[v];
  HalfedgeId e = e0;
  do {
    const SiteId w = triangles_[next_halfedge(e)];
    const double d2 = chord2(p, sites_[w]);
    if (d2 < best) best = d2, closest = w;
    e = next_around_site(e);
  } while (e != e0);
  Placement where;
  if (best < options_.merge_distance * options_.merge_distance) {
    where.merged_into = closest;
    where.chord = std::sqrt(best);
  }
  return where;
}

void SphericalDelaunay::make_first_triangles(SiteId a, SiteId b, SiteId c) {
  // Two triangles glued along their three edges: the (flat) hull of three points.
  triangles_.assign({a, b, c, a, c, b});
  halfedges_.assign({5, 4, 3, 2, 1, 0});
  site_edge_[a] = 0;
  site_edge_[b] = 1;
  site_edge_[c] = 2;
}


}  // namespace geovor
