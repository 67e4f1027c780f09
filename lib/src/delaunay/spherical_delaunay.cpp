#include "geovor/delaunay/spherical_delaunay.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>

#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/spatial_sort.hpp"
#include "geovor/kernel/predicates.hpp"
#include "kernel/in_sphere_filter.hpp"

namespace geovor {
namespace {

// A face is marked during a cavity search by the high bit of one of its site entries:
// entry 0 for "in the cavity", entry 1 for "tested, not in conflict". Site ids stay below 2^31.
constexpr SiteId kMark = 0x80000000u;
constexpr std::size_t kMaxSites = 700'000'000;  // 6n half-edges must fit in 32 bits

double chord2(const Vec3& a, const Vec3& b) { return norm2(a - b); }

template <class T>
std::size_t bytes_of(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

// Scratch buffers are vectors whose size is their capacity: grows one, returns its new data.
template <class T>
[[gnu::noinline]] T* grow(std::vector<T>& v) {
  v.resize(2 * v.size() + 64);
  return v.data();
}

// Sparse rounds first: a point joins round j with probability about 32^-j (independently, from a
// hash of its position and the seed, so that exact duplicates share a round and the first of them
// in input order is kept); the rounds go from the sparsest and each keeps the Hilbert order. The
// sparse sites bound the triangles ahead of the curve, so cavities stay small (10% fewer
// instructions per site than one Hilbert pass) while 97% of the sites are in the last round.
std::vector<std::uint32_t> sparse_rounds_first(const std::vector<std::uint32_t>& order,
                                               std::span<const Vec3> points, std::uint64_t seed) {
  constexpr int kLogRatio = 5, kRounds = 8;
  std::vector<std::uint8_t> round(points.size());  // 0: the last, densest round
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint64_t bits[3];
    const double c[3] = {points[i].x + 0.0, points[i].y + 0.0, points[i].z + 0.0};  // -0 is 0
    std::memcpy(bits, c, sizeof bits);
    std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL + (bits[0] ^ std::rotl(bits[1], 21) ^ std::rotl(bits[2], 42));
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;  // splitmix64's finaliser
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    round[i] = static_cast<std::uint8_t>(std::min(z == 0 ? 63 : __builtin_ctzll(z) / kLogRatio, kRounds - 1));
  }
  std::size_t start[kRounds + 1] = {};
  for (const std::uint32_t i : order) ++start[kRounds - round[i]];
  for (int r = 1; r <= kRounds; ++r) start[r] += start[r - 1];
  std::vector<std::uint32_t> out(order.size());
  for (const std::uint32_t i : order) out[start[kRounds - 1 - round[i]]++] = i;
  return out;
}

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

}  // namespace

SphericalDelaunay::SphericalDelaunay(const DelaunayOptions& options) : options_(options) {
  if (!(options.merge_distance >= kMinSeparation) || !std::isfinite(options.merge_distance))
    throw Error(ErrorCode::InvalidArgument,
                "merge distance " + num(options.merge_distance) +
                    " is below the minimum separation 2^-24 of sites on the unit sphere");
}

// The hot path is inline and makes no call, so it needs no register spills; the exact and
// perturbed stages are out of line.
inline bool SphericalDelaunay::in_conflict(TriId t, const Vec3& p, std::uint32_t prio) const {
  const SiteId* tri = triangles_.data() + 3 * t;
  const Vec3* s = sites_.data();
  // Sites and inserted points are unit vectors (checked on input): the static filter applies.
  const int filtered = kernel::detail::in_sphere_unit_filter(s[tri[0]], s[tri[1]], s[tri[2]], p);
  if (filtered != 0) [[likely]]
    return filtered > 0;
  return in_conflict_exact(t, p, prio);
}

bool SphericalDelaunay::in_conflict_exact(TriId t, const Vec3& p, std::uint32_t prio) const {
  const SiteId a = triangles_[3 * t], b = triangles_[3 * t + 1], c = triangles_[3 * t + 2];
  // Ties get the perturbation; only now are the priorities needed.
  return kernel::perturbed_in_sphere(sites_[a], priority(a), sites_[b], priority(b), sites_[c],
                                     priority(c), p, prio) == Sign::Positive;
}

// ---------------------------------------------------------------------------------------------
// Build

SphericalDelaunay SphericalDelaunay::build(std::span<const Vec3> points,
                                           const DelaunayOptions& options, BuildReport* report) {
  using Clock = std::chrono::steady_clock;
  const std::size_t n = points.size();
  if (n > kMaxSites)
    throw Error(ErrorCode::InvalidArgument, "too many sites: " + std::to_string(n));
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = points[i];
    const double r2 = norm2(p);
    if (!std::isfinite(r2) || std::fabs(r2 - 1.0) > 0x1p-49)
      throw Error(ErrorCode::InvalidArgument,
                  "point " + std::to_string(i) + " is not a unit vector (|p|^2 = " + num(r2) + ")");
  }
  SphericalDelaunay dt(options);

  const auto t0 = Clock::now();
  std::vector<std::uint32_t> order;
  if (options.spatial_sort) {
    order = options.brio ? brio_order(points, options.seed) : hilbert_order(points);
    // Below a thousand points the sparse rounds would hold a handful: one Hilbert pass.
    if (!options.brio && n >= 1024) order = sparse_rounds_first(order, points, options.seed);
  } else {
    order.resize(n);
    std::iota(order.begin(), order.end(), 0u);
  }
  const auto t1 = Clock::now();

  // During the build, slot k holds the k-th point inserted, so that sites inserted together sit
  // together in memory; its priority is its input index, and the final ids follow input order.
  dt.sites_.resize(n);
  dt.priority_ = order;
  constexpr std::size_t kAhead = 16;  // the reads are random: prefetch them
  for (std::size_t k = 0; k < n; ++k) {
    if (k + kAhead < n) __builtin_prefetch(&points[order[k + kAhead]]);
    dt.sites_[k] = points[order[k]];
  }
  dt.site_edge_.assign(n, kRemoved);  // not inserted yet
  const std::size_t max_tris = n >= 3 ? 2 * n - 4 : 0;
  dt.triangles_.reserve(3 * max_tris);
  dt.halfedges_.reserve(3 * max_tris);
  std::vector<std::uint32_t>().swap(order);  // priority_ holds it from here on
  std::size_t peak = dt.memory_bytes();

  std::vector<Merge> merges;  // input = slot and site = slot until renumbered below
  SiteId hint = kNoIndex;
  for (std::size_t k = 0; k < n; ++k) {
    const InsertResult r = dt.insert_site(static_cast<SiteId>(k), hint);
    if (r.merged) {
      merges.push_back({static_cast<std::uint32_t>(k), r.site, r.chord, r.hidden});
    } else {
      hint = static_cast<SiteId>(k);
    }
  }

  // Final ids: the live sites in input order. The map from priority to id is monotone, so the
  // perturbation, and with it the triangulation, is the same. Without merges it is the order.
  std::vector<SiteId> id_of_input;
  std::vector<SiteId> new_id;  // slot -> final id
  SiteId next = static_cast<SiteId>(n);
  std::vector<std::uint32_t> input_of_slot = std::move(dt.priority_);
  dt.priority_ = std::vector<std::uint32_t>();
  if (merges.empty()) {
    new_id = std::move(input_of_slot);
  } else {
    id_of_input.assign(n, kNoIndex);
    for (std::size_t k = 0; k < n; ++k)
      if (dt.alive(static_cast<SiteId>(k))) id_of_input[input_of_slot[k]] = 0;
    next = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (id_of_input[i] != kNoIndex) id_of_input[i] = next++;
    new_id.resize(n);
    for (std::size_t k = 0; k < n; ++k) new_id[k] = id_of_input[input_of_slot[k]];
  }
  {
    // The final sites are the live input points in input order: a sequential copy instead of a
    // scatter, after freeing the build's copy so that the two never coexist.
    std::vector<Vec3>().swap(dt.sites_);
    if (merges.empty()) {
      dt.sites_.assign(points.begin(), points.end());
    } else {
      dt.sites_.reserve(next);
      for (std::size_t i = 0; i < n; ++i)
        if (id_of_input[i] != kNoIndex) dt.sites_.push_back(points[i]);
    }
    std::vector<HalfedgeId> site_edge(next);
    for (std::size_t k = 0; k < n; ++k) {
      if (k + kAhead < n && new_id[k + kAhead] != kNoIndex) __builtin_prefetch(&site_edge[new_id[k + kAhead]], 1);
      if (new_id[k] != kNoIndex) site_edge[new_id[k]] = dt.site_edge_[k];
    }
    peak = std::max(peak, dt.memory_bytes() + site_edge.capacity() * sizeof(HalfedgeId));
    dt.site_edge_ = std::move(site_edge);
  }
  for (SiteId& s : dt.triangles_) s = new_id[s];
  if (dt.last_site_ != kNoIndex) dt.last_site_ = new_id[dt.last_site_];
  peak = std::max(peak, dt.memory_bytes() + 2 * n * sizeof(SiteId));
  const auto t2 = Clock::now();

  if (report) {
    if (merges.empty()) {
      report->site_of_input.resize(n);
      std::iota(report->site_of_input.begin(), report->site_of_input.end(), SiteId{0});
    } else {
      report->site_of_input = std::move(id_of_input);
    }
    for (Merge& m : merges) {
      // A merge target is never itself merged later: it stays live during the build.
      m.input = input_of_slot[m.input];
      m.site = new_id[m.site];
      report->site_of_input[m.input] = m.site;
    }
    std::sort(merges.begin(), merges.end(),
              [](const Merge& a, const Merge& b) { return a.input < b.input; });
    report->merges = std::move(merges);
    report->sort_seconds = std::chrono::duration<double>(t1 - t0).count();
    report->insert_seconds = std::chrono::duration<double>(t2 - t1).count();
    report->peak_bytes = peak;
  }
  return dt;
}

// ---------------------------------------------------------------------------------------------
// Insertion

std::uint64_t SphericalDelaunay::next_revision() {
  static std::atomic<std::uint64_t> counter{0};
  return counter.fetch_add(1, std::memory_order_relaxed) + 1;
}

InsertResult SphericalDelaunay::insert(const Vec3& p) {
  touch();
  const double r2 = norm2(p);
  if (!std::isfinite(r2) || std::fabs(r2 - 1.0) > 0x1p-49)
    throw Error(ErrorCode::InvalidArgument, "insert: not a unit vector (|p|^2 = " + num(r2) + ")");
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
  const Placement where = place(p, prio, hint);
  if (where.merged_into != kNoIndex) return {where.merged_into, true, where.chord, where.hidden};
  find_cavity(p, prio, where.conflict);
  if (num_boundary_ != num_cavity_ + 2) {
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
// the result only seeds the exact conflict search.
SiteId SphericalDelaunay::walk_to_nearest(const Vec3& p, SiteId v) const {
  double best = dot(p, sites_[v]);
  for (;;) {
    const HalfedgeId e0 = site_edge_[v];
    HalfedgeId e = e0;
    SiteId next = v;
    do {
      const SiteId w = triangles_[next_halfedge(e)];
      const double d = dot(p, sites_[w]);
      if (d > best) best = d, next = w;
      e = next_around_site(e);
    } while (e != e0);
    if (next == v) return v;
    v = next;
  }
}

TriId SphericalDelaunay::find_conflict(const Vec3& p, std::uint32_t prio, SiteId near) const {
  // The new site's nearest neighbour becomes its Delaunay neighbour, so some triangle around it
  // is in conflict; the exhaustive search below is only a safety net.
  const HalfedgeId e0 = site_edge_[near];
  HalfedgeId e = e0;
  do {
    if (in_conflict(tri_of(e), p, prio)) return tri_of(e);
    e = next_around_site(e);
  } while (e != e0);
  for (TriId t = 0; t < num_triangles(); ++t)
    if (in_conflict(t, p, prio)) return t;
  return kNoIndex;
}

SphericalDelaunay::Placement SphericalDelaunay::place(const Vec3& p, std::uint32_t prio,
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
    if (in_conflict(t, p, prio)) {
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
  where.conflict = find_conflict(p, prio, v);
  if (where.conflict == kNoIndex) {
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

// The common case, with no call in the loop so that its state stays in registers: every test
// decided by the filter, every buffer large enough.
bool SphericalDelaunay::find_cavity_filtered(const Vec3& p, TriId seed) {
  TriId* const cavity = cavity_.data();
  TriId* const tested = tested_.data();
  CavityEdge* const boundary = boundary_.data();
  const std::size_t cap_c = cavity_.size(), cap_t = tested_.size(), cap_b = boundary_.size();
  SiteId* const tri = triangles_.data();
  const HalfedgeId* const twin = halfedges_.data();
  const Vec3* const site = sites_.data();
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
      const int c = kernel::detail::in_sphere_unit_filter(site[u0], site[u1], site[tri[3 * u + 2]], p);
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

void SphericalDelaunay::find_cavity(const Vec3& p, std::uint32_t prio, TriId seed) {
  if (find_cavity_filtered(p, seed)) return;
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
        if (in_conflict(u, p, prio)) {
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
  GEOVOR_ASSERT(num_boundary_ == num_cavity_ + 2);
  // Replace the cavity by the fan of triangles (a, b, s), one per boundary edge a -> b, reusing
  // the cavity's slots and adding two.
  const TriId first_new = static_cast<TriId>(num_triangles());
  triangles_.resize(triangles_.size() + 6);
  halfedges_.resize(halfedges_.size() + 6);
  const std::size_t nb = num_boundary_;
  if (nb > cavity_.size()) grow(cavity_);
  TriId* const slot = cavity_.data();  // slot[k]: the triangle of the k-th fan triangle
  slot[num_cavity_] = first_new;
  slot[num_cavity_ + 1] = first_new + 1;
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
}

// ---------------------------------------------------------------------------------------------
// Removal

void SphericalDelaunay::remove(SiteId s) {
  if (!is_live(s)) throw Error(ErrorCode::InvalidArgument, "remove: site " + std::to_string(s) + " is not live");
  touch();
  remove_keeping_tolerances(s);
}

void SphericalDelaunay::remove_site(SiteId s) {
  GEOVOR_ASSERT(priority_.empty());
  if (num_live_ <= 3) {
    // Fewer than three sites remain: no triangle.
    triangles_.clear();
    halfedges_.clear();
    for (SiteId t = 0; t < sites_.size(); ++t)
      if (alive(t)) site_edge_[t] = kNoIndex;
    site_edge_[s] = kRemoved;
    --num_live_;
    last_site_ = any_live_site();
    return;
  }

  // The star of s: link vertices w_i counter-clockwise, the star triangles (s, w_i, w_i+1), and
  // the outer half-edges w_i+1 -> w_i across the link.
  std::vector<SiteId> link;
  std::vector<TriId> star;
  std::vector<HalfedgeId> outer;
  const HalfedgeId e0 = site_edge_[s];
  HalfedgeId e = e0;
  do {
    link.push_back(triangles_[next_halfedge(e)]);
    star.push_back(tri_of(e));
    outer.push_back(halfedges_[next_halfedge(e)]);
    e = next_around_site(e);
  } while (e != e0);
  const std::size_t k = link.size();

  // The hole is filled by the faces of the hull of the link that s sees (they are exactly the
  // faces of the hull of the other sites in the hole; see docs/design.md). That hull is built by
  // the same exact code, with the global ids as perturbation priorities.
  SphericalDelaunay hull(options_);
  hull.sites_.reserve(k);
  hull.priority_ = link;
  for (std::size_t i = 0; i < k; ++i) {
    hull.sites_.push_back(sites_[link[i]]);
    hull.site_edge_.push_back(kRemoved);
    const InsertResult r = hull.insert_site(static_cast<SiteId>(i), hull.last_site_);
    GEOVOR_ASSERT(!r.merged);
  }
  std::vector<TriId> fill;
  std::vector<TriId> slot_of(hull.num_triangles(), kNoIndex);
  for (TriId t = 0; t < hull.num_triangles(); ++t) {
    const SiteId a = link[hull.triangles_[3 * t]], b = link[hull.triangles_[3 * t + 1]],
                 c = link[hull.triangles_[3 * t + 2]];
    if (kernel::perturbed_in_sphere(sites_[a], priority(a), sites_[b], priority(b), sites_[c],
                                    priority(c), sites_[s], priority(s)) == Sign::Positive) {
      slot_of[t] = star[fill.size()];
      fill.push_back(t);
    }
  }
  GEOVOR_ASSERT(fill.size() == k - 2);

  for (const TriId ht : fill) {
    const TriId t = slot_of[ht];
    for (int j = 0; j < 3; ++j) {
      const HalfedgeId he = 3 * ht + j;
      const std::uint32_t la = hull.triangles_[he];
      triangles_[3 * t + j] = link[la];
      const HalfedgeId htw = hull.halfedges_[he];
      if (slot_of[tri_of(htw)] != kNoIndex) {
        halfedges_[3 * t + j] = 3 * slot_of[tri_of(htw)] + htw % 3;
      } else {
        // A boundary edge of the hole: w_la -> w_la+1, glued to the outer half-edge.
        GEOVOR_ASSERT(hull.triangles_[next_halfedge(he)] == (la + 1) % k);
        halfedges_[3 * t + j] = outer[la];
        halfedges_[outer[la]] = 3 * t + j;
      }
    }
  }
  for (std::size_t i = 0; i < k; ++i) site_edge_[link[(i + 1) % k]] = outer[i];
  site_edge_[s] = kRemoved;
  --num_live_;
  last_site_ = link[0];

  // Two star slots are left over: fill them with the last triangles of the arrays.
  std::vector<TriId> spare(star.begin() + static_cast<std::ptrdiff_t>(k - 2), star.end());
  std::sort(spare.begin(), spare.end(), std::greater<>());
  for (const TriId t : spare) {
    const TriId last = static_cast<TriId>(num_triangles() - 1);
    if (t != last) move_triangle(last, t);
    triangles_.resize(triangles_.size() - 3);
    halfedges_.resize(halfedges_.size() - 3);
  }
}

void SphericalDelaunay::move_triangle(TriId from, TriId to) {
  for (int j = 0; j < 3; ++j) {
    const HalfedgeId ef = 3 * from + j, et = 3 * to + j;
    triangles_[et] = triangles_[ef];
    halfedges_[et] = halfedges_[ef];
    halfedges_[halfedges_[et]] = et;
    if (site_edge_[triangles_[et]] == ef) site_edge_[triangles_[et]] = et;
  }
}

// ---------------------------------------------------------------------------------------------
// Inspectors and validation

bool SphericalDelaunay::is_ghost(TriId t) const {
  return kernel::orient(sites_[triangles_[3 * t]], sites_[triangles_[3 * t + 1]],
                        sites_[triangles_[3 * t + 2]]) == Sign::Negative;
}

std::size_t SphericalDelaunay::num_ghost_triangles() const {
  std::size_t count = 0;
  for (TriId t = 0; t < num_triangles(); ++t) count += is_ghost(t);
  return count;
}

std::size_t SphericalDelaunay::memory_bytes() const {
  return bytes_of(sites_) + bytes_of(triangles_) + bytes_of(halfedges_) + bytes_of(site_edge_) +
         bytes_of(priority_) + bytes_of(cavity_) + bytes_of(tested_) +
         bytes_of(boundary_) + bytes_of(anchor_) + bytes_of(queue_) +
         bytes_of(link_) + bytes_of(stack_) + bytes_of(flipped_) + bytes_of(touched_);
}

SphericalDelaunay::Arrays SphericalDelaunay::arrays() const {
  return {sites_, triangles_, halfedges_, site_edge_};
}

SphericalDelaunay SphericalDelaunay::from_arrays(Arrays arrays, const DelaunayOptions& options) {
  SphericalDelaunay dt(options);
  auto fail = [](const std::string& why) { throw Error(ErrorCode::BadData, "triangulation: " + why); };
  if (arrays.site_edge.size() != arrays.sites.size()) fail("site arrays differ in size");
  if (arrays.triangles.size() != arrays.halfedges.size() || arrays.triangles.size() % 3 != 0)
    fail("triangle arrays differ in size");
  if (arrays.sites.size() >= kMaxSites) fail("too many sites");
  for (std::size_t i = 0; i < arrays.sites.size(); ++i) {
    const double r2 = norm2(arrays.sites[i]);
    if (!std::isfinite(r2) || std::fabs(r2 - 1.0) > 0x1p-49) fail("site " + std::to_string(i) + " is not a unit vector");
  }
  for (const SiteId s : arrays.triangles)
    if (s >= arrays.sites.size()) fail("a triangle names an unknown site");
  for (const HalfedgeId e : arrays.halfedges)
    if (e >= arrays.halfedges.size()) fail("a half-edge's twin is out of range");
  std::size_t live = 0;
  for (const HalfedgeId e : arrays.site_edge) {
    if (e == kRemoved) continue;
    ++live;
    if (e != kNoIndex && e >= arrays.halfedges.size()) fail("a site's half-edge is out of range");
  }
  dt.sites_ = std::move(arrays.sites);
  dt.triangles_ = std::move(arrays.triangles);
  dt.halfedges_ = std::move(arrays.halfedges);
  dt.site_edge_ = std::move(arrays.site_edge);
  dt.num_live_ = live;
  const Validation v = dt.validate_structure();
  if (!v.ok()) fail(v.errors.front());
  dt.last_site_ = dt.any_live_site();
  return dt;
}

Validation SphericalDelaunay::validate_structure() const {
  Validation v;
  auto fail = [&v](std::string msg) {
    if (v.errors.size() < 50) v.errors.push_back(std::move(msg));
  };
  const std::size_t nh = halfedges_.size(), nt = num_triangles();
  std::size_t live = 0;
  for (SiteId s = 0; s < sites_.size(); ++s) live += alive(s);
  if (live != num_live_) fail("live site count " + std::to_string(live) + " != " + std::to_string(num_live_));
  if (triangles_.size() != nh) fail("triangles and halfedges differ in size");
  // Euler: a triangulated sphere with n vertices has 2n - 4 triangles.
  const std::size_t expect = live >= 3 ? 2 * live - 4 : 0;
  if (nt != expect)
    fail("Euler: " + std::to_string(nt) + " triangles for " + std::to_string(live) + " sites");
  if (!v.ok()) return v;

  for (HalfedgeId e = 0; e < nh; ++e) {
    const HalfedgeId tw = halfedges_[e];
    if (tw >= nh || tw == e || halfedges_[tw] != e) {
      fail("half-edge " + std::to_string(e) + ": twin not symmetric");
      continue;
    }
    // Orientation: a twin runs the other way, so neighbouring triangles are oriented alike.
    if (triangles_[tw] != triangles_[next_halfedge(e)] || triangles_[next_halfedge(tw)] != triangles_[e])
      fail("half-edge " + std::to_string(e) + ": twin does not run the other way");
  }
  for (TriId t = 0; t < nt; ++t) {
    const SiteId a = triangles_[3 * t], b = triangles_[3 * t + 1], c = triangles_[3 * t + 2];
    if (a >= sites_.size() || b >= sites_.size() || c >= sites_.size() || !alive(a) || !alive(b) || !alive(c))
      fail("triangle " + std::to_string(t) + " uses a removed or unknown site");
    else if (a == b || b == c || c == a)
      fail("triangle " + std::to_string(t) + " repeats a site");
  }
  if (!v.ok()) return v;

  // Every live site is a vertex whose star is one cycle: the walks around all sites together
  // meet every half-edge exactly once.
  std::size_t visited = 0;
  for (SiteId s = 0; s < sites_.size(); ++s) {
    if (!alive(s)) continue;
    const HalfedgeId e0 = site_edge_[s];
    if (live < 3) {
      if (e0 != kNoIndex) fail("site " + std::to_string(s) + " has an edge with fewer than 3 sites");
      continue;
    }
    if (e0 >= nh || triangles_[e0] != s) {
      fail("site " + std::to_string(s) + " is not a vertex");
      continue;
    }
    HalfedgeId e = e0;
    std::size_t degree = 0;
    do {
      ++degree;
      e = next_around_site(e);
    } while (e != e0 && degree <= nh);
    if (e != e0) fail("site " + std::to_string(s) + ": star is not a cycle");
    visited += degree;
  }
  if (live >= 3 && visited != nh) fail("vertex stars do not cover every half-edge once");
  return v;
}

Validation SphericalDelaunay::validate(const BuildReport* report, bool global) const {
  Validation v = validate_structure();
  if (!v.ok()) return v;
  auto fail = [&v](std::string msg) {
    if (v.errors.size() < 50) v.errors.push_back(std::move(msg));
  };
  const std::size_t nh = halfedges_.size(), nt = num_triangles();
  const std::size_t live = num_live_;

  // Local Delaunay under the perturbation: across every edge, the opposite site is outside the
  // circumcircle. (The test is the same from both sides: an even permutation.)
  for (HalfedgeId e = 0; e < nh; ++e) {
    const HalfedgeId tw = halfedges_[e];
    if (tw < e) continue;
    const SiteId d = triangles_[prev_halfedge(tw)];
    if (live == 3) continue;  // the two triangles of three sites share all their vertices
    if (in_conflict(tri_of(e), sites_[d], priority(d)))
      fail("edge " + std::to_string(e) + " is not locally Delaunay");
  }
  if (global) {
    for (TriId t = 0; t < nt; ++t)
      for (SiteId s = 0; s < sites_.size(); ++s) {
        if (!alive(s) || s == triangles_[3 * t] || s == triangles_[3 * t + 1] || s == triangles_[3 * t + 2]) continue;
        if (in_conflict(t, sites_[s], priority(s)))
          fail("site " + std::to_string(s) + " lies in the circumcircle of triangle " + std::to_string(t));
      }
  }

  if (report) {
    // Every input point is accounted for: it is a site, or merged into one and listed.
    std::vector<char> seen(sites_.size(), 0);
    std::size_t merged = 0;
    for (std::size_t i = 0; i < report->site_of_input.size(); ++i) {
      const SiteId s = report->site_of_input[i];
      if (s >= sites_.size()) {
        fail("input " + std::to_string(i) + " has no site");
        continue;
      }
      if (seen[s]) ++merged;
      seen[s] = 1;
    }
    if (merged != report->merges.size())
      fail("merges listed: " + std::to_string(report->merges.size()) + ", found " + std::to_string(merged));
    for (const Merge& m : report->merges)
      if (m.input >= report->site_of_input.size() || report->site_of_input[m.input] != m.site)
        fail("merge of input " + std::to_string(m.input) + " disagrees with site_of_input");
  }
  return v;
}

}  // namespace geovor
