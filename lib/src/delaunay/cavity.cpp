// The cavity of a new point: the triangles in conflict with it, grown from one, and its
// retriangulation as the fan joining its boundary to the point. Why it is a disk (star-shaped
// from the point): docs/delaunay.md, "The cavity".
#include "delaunay/cavity.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

#include "delaunay/conflict.hpp"
#include "geovor/core/assert.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "kernel/in_sphere_filter.hpp"

namespace geovor {

// The common case, with no call in the loop so that its state stays in registers: every test
// decided by the filter, every buffer large enough.
template <bool kWeighted>
bool SphericalDelaunay::find_cavity_filtered(const Vec3& p, double c_p, TriId seed) {
  TriId* const cavity = cavity_.data();
  TriId* const tested = tested_.data();
  CavityEdge* const boundary = boundary_.data();
  const std::size_t cap_c = cavity_.size(), cap_t = tested_.size(), cap_b = boundary_.size();
  SiteId* const tri = triangles_.data();
  const HalfedgeId* const twin = halfedges_.data();
  const Vec3* const site = sites_.data();
  const double* const lift = lifts_.data();
  const Vec3* const lifted = lifted_.data();  // the build's lifted points (empty otherwise)
  const Vec3 lp{p.x / c_p, p.y / c_p, p.z / c_p};
  const double lifted_bound = lifted_.empty() ? INFINITY : lifted_bound_;
  const std::size_t nt0 = num_tested_;
  std::size_t nc = 0, nt = nt0, nb = 0;
  if (cap_c == 0) return false;
  cavity[nc++] = 3 * seed;  // cavity[k] is the half-edge by which the k-th triangle was entered
  tri[3 * seed] |= kMark;
  // The neighbour across edge a -> b of a cavity triangle: false if the filter cannot decide.
  auto visit = [&](HalfedgeId o, SiteId a, SiteId b) __attribute__((always_inline)) {
    const TriId u = tri_of(o);
    const SiteId u0 = tri[3 * u], u1 = tri[3 * u + 1];
    if (u0 & kMark) return true;  // in the cavity: an inner edge
    if (!(u1 & kMark)) {          // not tested before
      const SiteId u2 = tri[3 * u + 2];
      int c;
      if constexpr (kWeighted) {
        c = lifted ? kernel::detail::in_sphere_lifted_static(lifted[u0], lifted[u1], lifted[u2], lp, lifted_bound) : 0;
        if (c == 0)
          c = kernel::detail::in_sphere_weighted_filter(site[u0], lift[u0], site[u1], lift[u1], site[u2], lift[u2], p, c_p);
      } else
        c = kernel::detail::in_sphere_unit_filter(site[u0], site[u1], site[u2], p);
      if (c == 0) return false;
      if (c > 0) {
        tri[3 * u] = u0 | kMark;
        cavity[nc++] = o;
        return true;
      }
      tri[3 * u + 1] = u1 | kMark;
      tested[nt++] = u;
    }
    boundary[nb++] = {a, b, o};
    return true;
  };
  // A triangle adds at most 3 entries to each buffer: one bound covers all three.
  const std::size_t cap = std::min({cap_c, cap_t, cap_b});
  bool ok = cap >= nt + 4;
  if (ok) {
    const SiteId v0 = tri[3 * seed] & ~kMark, v1 = tri[3 * seed + 1], v2 = tri[3 * seed + 2];
    ok = visit(twin[3 * seed], v0, v1) && visit(twin[3 * seed + 1], v1, v2) && visit(twin[3 * seed + 2], v2, v0);
  }
  // The other triangles were entered across an edge: only their two other edges need a visit
  // (the edges inside a disk-shaped cavity are those it was grown by; the marks catch the rest).
  for (std::size_t next = 1; ok && next < nc; ++next) {
    if (nc + nt + nb + 3 > cap) {
      ok = false;
      break;
    }
    const HalfedgeId in = cavity[next];
    const HalfedgeId e1 = next_halfedge(in), e2 = next_halfedge(e1);
    const SiteId a = tri[in] & ~kMark, b = tri[e1] & ~kMark, c = tri[e2] & ~kMark;  // one is marked
    ok = visit(twin[e1], b, c) && visit(twin[e2], c, a);
  }
  if (!ok) {  // undo this search's marks; place()'s stay for find_cavity()
    for (std::size_t k = 0; k < nc; ++k) tri[3 * tri_of(cavity[k])] &= ~kMark;
    for (std::size_t k = nt0; k < nt; ++k) tri[3 * tested[k] + 1] &= ~kMark;
    return false;
  }
  for (std::size_t k = 0; k < nt; ++k) tri[3 * tested[k] + 1] &= ~kMark;
  for (std::size_t k = 0; k < nc; ++k) cavity[k] = tri_of(cavity[k]);
  num_cavity_ = nc;
  num_boundary_ = nb;
  num_tested_ = 0;
  return true;
}

void SphericalDelaunay::find_cavity(const Vec3& p, double c, std::uint32_t prio, TriId seed) {
  if (lifts_.empty() ? find_cavity_filtered<false>(p, c, seed) : find_cavity_filtered<true>(p, c, seed)) return;
  // tested_ holds the triangles place() found not in conflict; they are still marked.
  // Grow the set of triangles in conflict with p (connected: the faces of the hull visible from
  // p), breadth first with cavity_ as the queue, marking faces so each is tested once.
  TriId* cavity = cavity_.data();
  TriId* tested = tested_.data();
  CavityEdge* boundary = boundary_.data();
  std::size_t nc = 0, nt = num_tested_, nb = 0;
  if (cavity_.empty()) cavity = grow(cavity_);
  std::size_t cap_c = cavity_.size(), cap_t = tested_.size(), cap_b = boundary_.size();
  cavity[nc++] = seed;
  SiteId* const tri = triangles_.data();  // no reallocation below
  const HalfedgeId* const twin = halfedges_.data();
  tri[3 * seed] |= kMark;
  for (std::size_t next = 0; next < nc; ++next) {
    const TriId t = cavity[next];
    // Entry 0 of t carries the cavity mark: the boundary records strip it.
    const SiteId v[3] = {tri[3 * t] & ~kMark, tri[3 * t + 1], tri[3 * t + 2]};
    for (int j = 0; j < 3; ++j) {
      const HalfedgeId o = twin[3 * t + j];
      const TriId u = tri_of(o);
      const SiteId u0 = tri[3 * u], u1 = tri[3 * u + 1];
      if (u0 & kMark) continue;  // in the cavity: an inner edge
      if (!(u1 & kMark)) {       // not tested before
        if (in_conflict(u, p, c, prio)) {
          tri[3 * u] = u0 | kMark;
          if (nc == cap_c) cavity = grow(cavity_), cap_c = cavity_.size();
          cavity[nc++] = u;
          continue;
        }
        tri[3 * u + 1] = u1 | kMark;
        if (nt == cap_t) tested = grow(tested_), cap_t = tested_.size();
        tested[nt++] = u;
      }
      if (nb == cap_b) boundary = grow(boundary_), cap_b = boundary_.size();
      boundary[nb++] = {v[j], v[j == 2 ? 0 : j + 1], o};
    }
  }
  for (std::size_t k = 0; k < nt; ++k) tri[3 * tested[k] + 1] &= ~kMark;
  num_cavity_ = nc;
  num_boundary_ = nb;
  num_tested_ = 0;
  // The cavity's marks stay: fill_cavity() overwrites those triangles, abandon_cavity() clears.
}

void SphericalDelaunay::abandon_cavity() {
  for (std::size_t k = 0; k < num_cavity_; ++k) triangles_[3 * cavity_[k]] &= ~kMark;
}

void SphericalDelaunay::fill_cavity(SiteId s) {
  // A disk of nc triangles with h vertices inside has nb = nc + 2 - 2h boundary edges (Euler);
  // h > 0 only for weighted sites, whose inner vertices hide_cavity_interior() has hidden.
  const std::size_t nb = num_boundary_, nc = num_cavity_;
  GEOVOR_ASSERT(nb <= nc + 2 && (nc + 2 - nb) % 2 == 0 && (nb == nc + 2 || !lifts_.empty()));
  // Replace the cavity by the fan of triangles (a, b, s), one per boundary edge a -> b, reusing
  // the cavity's slots and adding two (fewer when vertices were hidden).
  const TriId first_new = static_cast<TriId>(num_triangles());
  const std::size_t added = nb > nc ? nb - nc : 0;
  triangles_.resize(triangles_.size() + 3 * added);
  halfedges_.resize(halfedges_.size() + 3 * added);
  if (nb > cavity_.size()) grow(cavity_);
  TriId* const slot = cavity_.data();  // slot[k]: the triangle of the k-th fan triangle
  for (std::size_t k = 0; k < added; ++k) slot[nc + k] = first_new + static_cast<TriId>(k);
  const CavityEdge* const bnd = boundary_.data();
  SiteId* const tri = triangles_.data();
  HalfedgeId* const twin = halfedges_.data();
  HalfedgeId* const site_edge = site_edge_.data();
  for (std::size_t k = 0; k < nb; ++k) {
    const HalfedgeId e = 3 * slot[k];
    const CavityEdge& b = bnd[k];
    tri[e] = b.a;  // also clears the cavity mark
    tri[e + 1] = b.b;
    tri[e + 2] = s;
    twin[e] = b.outer;
    twin[b.outer] = e;
    site_edge[b.a] = e;  // every boundary vertex starts exactly one boundary edge
  }
  for (std::size_t k = 0; k < nb; ++k) {
    const HalfedgeId e = 3 * slot[k];
    const HalfedgeId f = site_edge[bnd[k].b];  // the fan triangle whose boundary edge leaves b
    twin[e + 1] = f + 2;
    twin[f + 2] = e + 1;
  }
  // The last boundary edges found lie farthest from the seed, which faces the previous site: the
  // next site, further along the curve, is most often in conflict with the fan triangles there.
  site_edge[s] = 3 * slot[nb - 1] + 2;
  if (nc > nb)  // the cavity's slots past the fan
    free_triangle_slots({cavity_.begin() + static_cast<std::ptrdiff_t>(nb), cavity_.begin() + static_cast<std::ptrdiff_t>(nc)});
}

void SphericalDelaunay::free_triangle_slots(std::vector<TriId> spare) {
  // The last triangles of the arrays move into the freed slots, the highest slot first.
  std::sort(spare.begin(), spare.end(), std::greater<>());
  for (const TriId t : spare) {
    const TriId last = static_cast<TriId>(num_triangles() - 1);
    if (t != last) move_triangle(last, t);
    triangles_.resize(triangles_.size() - 3);
    halfedges_.resize(halfedges_.size() - 3);
  }
}

}  // namespace geovor
