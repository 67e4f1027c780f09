// Moving sites (issue 6): SphericalDelaunay::move()/move_all(), the thesis' vertex-tolerance
// filter (Ch. 5, Algorithm 1) carried to the sphere, relocation by flips or by remove + insert.
// The argument for the tolerance bound is in spherical_delaunay.hpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
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
  // Sites staying put (most of them, when few move) cost one comparison.
  for (SiteId s = 0; s < sites_.size(); ++s)
    if (!(positions[s] == sites_[s]) && alive(s) && !is_unit(positions[s]))
      throw Error(ErrorCode::InvalidArgument, "move_all: position of site " + std::to_string(s) + " is not a unit vector");
  GEOVOR_ASSERT(priority_.empty());
  MoveStats total;
  for (SiteId s = 0; s < sites_.size(); ++s)
    if (!(positions[s] == sites_[s]) && alive(s)) total += move_one(s, positions[s], options);
  if (total.moved) touch();
  return total;
}

MoveStats SphericalDelaunay::move_one(SiteId s, const Vec3& p, const RelocationOptions& options) {
  MoveStats st;
  if (sites_[s] == p) return st;
  const bool filter = options.filter && num_live_ >= 4;  // fewer sites: no bi-cell to certify
  if (filter) {
    if (tolerance2_.empty()) init_tolerances();
    // Algorithm 1, line 2: within the tolerance of the reference position, nothing changes.
    if (norm2(p - reference_[s]) < tolerance2_[s]) {
      sites_[s] = p;
      st.moved = st.filtered = 1;
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
  if (!filter || tolerance2_.empty()) {
    drop_tolerances();  // not kept current without the filter: rebuilt at the next filtered move
    return st;
  }
  // Algorithm 1, lines 8-20: s gets its new position as reference, and every bi-cell the
  // relocation created lowers the tolerances of its sites; those that fall below their own
  // displacement are refreshed in turn.
  queue_.clear();
  refresh_site(s);
  for (const TriId t : touched_) {
    // Triangles at s: their three bi-cells are s's, just refreshed.
    if (triangles_[3 * t] == s || triangles_[3 * t + 1] == s || triangles_[3 * t + 2] == s) continue;
    for (int j = 0; j < 3; ++j) update_bicell(3 * t + j);
  }
  update_around_link();  // the hole left by a removal was retriangulated around them
  st.refreshed = settle_queue();
  return st;
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
  for (const SiteId w : link_) {
    if (!alive(w) || site_edge_[w] == kNoIndex) continue;
    const HalfedgeId e0 = site_edge_[w];
    HalfedgeId e = e0;
    do {
      update_bicell(e);
      e = next_around_site(e);
    } while (e != e0);
  }
}

void SphericalDelaunay::tolerances_after_insert(SiteId s) {
  if (tolerance2_.empty()) return;
  if (num_live_ < 5) {
    drop_tolerances();
    return;
  }
  // Every new triangle has s as a vertex: its bi-cells are those refresh_site() computes.
  reference_.push_back(sites_[s]);
  tolerance2_.push_back(std::numeric_limits<double>::infinity());
  queue_.clear();
  refresh_site(s);
  settle_queue();
}

void SphericalDelaunay::remove_keeping_tolerances(SiteId s) {
  if (tolerance2_.empty() || num_live_ <= 5) {
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

// Lower bound of half the minimal width of the tetrahedron (a, b, c, d), up to a relative
// rounding of a few 2^-53 that the caller's margin covers; 0 when (nearly) flat.
double half_width_lower(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // 6 x volume = |det(b - a, c - a, d - a)|, minus Shewchuk's bound of its rounding.
  double permanent;
  const double det = kernel::detail::in_sphere_det(a, b, c, d, &permanent);
  const double volume6 = std::fabs(det) - kernel::detail::kO3dErrBound * permanent;
  if (!(volume6 > 0)) return 0;  // coplanar, or too close to tell
  // Each height and each distance between opposite edges' lines is 6V / |u x v| for two edges u,
  // v (of the face, or the two opposite edges); the width of a tetrahedron is the least of these
  // seven (it is attained by a face and a vertex or by two edges): 6V over the largest |u x v|.
  const Vec3 ab = b - a, ac = c - a, ad = d - a, bc = c - b, bd = d - b, cd = d - c;
  const double m2 = std::max({norm2(cross(ab, ac)), norm2(cross(ab, ad)), norm2(cross(ac, ad)),
                              norm2(cross(bc, bd)), norm2(cross(ab, cd)), norm2(cross(ac, bd)),
                              norm2(cross(ad, bc))});
  // Rounding: the edges are within 2^-53 per component, each product and difference too, so each
  // component of a cross product is within 8 2^-53 L^2 of the exact one (L the longest edge), its
  // norm within 2^-49 L^2.
  const double l2 = std::max({norm2(ab), norm2(ac), norm2(ad), norm2(bc), norm2(bd), norm2(cd)});
  return volume6 / (2 * (std::sqrt(m2) + 0x1p-48 * l2));
}

// The bound for points moving on the sphere (see spherical_delaunay.hpp): the four points seen
// through T, which stretches the component along their mean direction by 1/S. Sets S (1: no
// gain over the isotropic bound).
double spherical_half_tolerance(const Vec3 (&f)[4], double& S) {
  S = 1;
  Vec3 c = f[0] + f[1] + f[2] + f[3];
  const double c2 = norm2(c);
  if (!(c2 > 0.25)) return 0;  // spread over the sphere: the isotropic bound does as well
  c = (1 / std::sqrt(c2)) * c;
  // s0: the largest sine of the angle between c and a point, |c x f| / (|c| |f|), rounded up
  // (|c|^2 and |f|^2 are within 2^-48 of 1).
  double s2 = 0;
  for (const Vec3& p : f) s2 = std::max(s2, norm2(cross(c, p)));
  const double s0 = std::sqrt(s2) * (1 + 0x1p-46) + 0x1p-48;
  // Moves up to tau_cap turn a point by at most A; a move of chord D then changes its component
  // along c by at most S D + eps. (The tolerance is far below s0 but for ties of huge bi-cells.)
  const double tau_cap = std::min(s0 / 16, 0.5);
  const double A = 1.05 * (tau_cap + 0x1p-49);
  S = std::min(1.05 * (s0 + A), 1.0);
  const double eps = 0x1p-49 * (1 + S);
  // y_i = T (f_i - f_0), T = I + (1/S - 1) c c^T / |c|^2; each within e of the exact image.
  const double k = (1 / S - 1) / norm2(c) * (1 - 0x1p-50);
  Vec3 y[4];
  double d2max = 0;
  for (int i = 0; i < 4; ++i) {
    const Vec3 d = f[i] - f[0];
    d2max = std::max(d2max, norm2(d));
    y[i] = d + (k * dot(d, c)) * c;
  }
  const double e = 0x1p-48 * (1 + 1 / S) * std::sqrt(d2max);
  // Each moved point's image moves by at most sqrt(2) D + eps / S: below half the width, no four
  // images, hence no four points, become coplanar.
  const double half = (half_width_lower(y[0], y[1], y[2], y[3]) - e - eps / S) * 0x1.6a09e667f3bcdp-1;
  return std::min(half, tau_cap);
}

}  // namespace

double SphericalDelaunay::bicell_tolerance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                           double merge_distance) {
  const Vec3 f[4] = {a, b, c, d};
  // Motions on the sphere: a bi-cell's tetrahedron is flat (height ~ edge^2), but its points are
  // not near one circle; any motion in R^3 by less than half its width keeps the sign too, the
  // better bound for bi-cells spanning a large part of the sphere.
  double S;
  double half_width = spherical_half_tolerance(f, S);
  if (S > 0.25) half_width = std::max(half_width, half_width_lower(a, b, c, d));
  // The shared edge a-b must stay longer than the merge distance (with room for the rounding of
  // the merge test's own chord).
  const double edge = (std::sqrt(norm2(b - a)) - merge_distance * (1 + 0x1p-40)) / 2;
  // The few roundings above are each within a relative 2^-52: a 2^-46 margin covers them all.
  const double tau = std::min(half_width, edge) * (1 - 0x1p-46);
  return tau > 0 ? tau : 0;
}

void SphericalDelaunay::init_tolerances() {
  reference_.assign(sites_.begin(), sites_.end());
  tolerance2_.assign(sites_.size(), std::numeric_limits<double>::infinity());
  queue_.clear();
  for (HalfedgeId e = 0; e < halfedges_.size(); ++e)
    if (halfedges_[e] > e) update_bicell(e);  // each edge (bi-cell) once
  queue_.clear();  // every site is at its reference: nothing to refresh
}

bool SphericalDelaunay::within_tolerance(SiteId s) const {
  return sites_[s] == reference_[s] || norm2(sites_[s] - reference_[s]) < tolerance2_[s];
}

void SphericalDelaunay::update_bicell(HalfedgeId e) {
  const SiteId q[4] = {triangles_[e], triangles_[next_halfedge(e)], triangles_[prev_halfedge(e)],
                       triangles_[prev_halfedge(halfedges_[e])]};
  const Vec3* f = reference_.data();
  // Squared with a relative 2^-48 to spare, so that the filter's squared chord in doubles
  // (within 2^-50 of the exact one) below it certifies a chord below the tolerance.
  const double tau = bicell_tolerance(f[q[0]], f[q[1]], f[q[2]], f[q[3]], options_.merge_distance) * (1 - 0x1p-48);
  const double tau2 = tau * tau;
  for (const SiteId w : q) {
    if (tau2 >= tolerance2_[w]) continue;
    tolerance2_[w] = tau2;
    if (!within_tolerance(w)) queue_.push_back(w);
  }
}

void SphericalDelaunay::refresh_site(SiteId s) {
  reference_[s] = sites_[s];
  tolerance2_[s] = std::numeric_limits<double>::infinity();
  const HalfedgeId e0 = site_edge_[s];
  HalfedgeId e = e0;
  do {  // the bi-cells of the edges at s and of the link edges opposite s
    update_bicell(e);
    update_bicell(next_halfedge(e));
    e = next_around_site(e);
  } while (e != e0);
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
  if (tolerance2_.empty()) init_tolerances();
  return std::sqrt(tolerance2_[s]);
}

}  // namespace geovor
