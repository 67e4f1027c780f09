// The moving sites' filter (thesis Ch. 5, Algorithm 1): each site's reference position and
// certified tolerance, kept current through relocations, insertions and removals. Why a move
// within the tolerance changes no triangle: docs/delaunay.md, "The filter".
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "delaunay/bicell_lanes.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"

namespace geovor {

bool SphericalDelaunay::reanchor(SiteId s, const Vec3& p) {
  // The second test: the filter failed, s's tolerances recomputed at a new reference near p may
  // certify the move without a relocation (docs/delaunay.md, "The second test").
  const Vec3 m = sites_[s];
  const double step2 = norm2(p - m);
  if (!(step2 < anchor_[s].eps2)) return false;  // would fail too, most likely: relocate now
  // f: p moved on along the step to use about 80% of the old tolerance (0.6: 17% fewer
  // re-anchors, 0.95: more fail).
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
