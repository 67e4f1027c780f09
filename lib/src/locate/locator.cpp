#include "geovor/locate/locator.hpp"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Geodesic.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <queue>
#include <unordered_set>

#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/kernel/predicates.hpp"

namespace geovor {
namespace {

constexpr const char* kNames[] = {"walk", "jump-walk", "keep-jump-walk", "hierarchy", "climb", "keep-jump-climb"};

std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Exact order of the sites at q: by nearness, or by power for weighted sites (equal to nearness
// for equal lifts). Sign of a's power minus b's.
Sign compare_at(const Vec3& q, const SphericalDelaunay& dt, SiteId a, SiteId b) {
  if (!dt.is_weighted()) return kernel::compare_dot(q, dt.site(a), dt.site(b));
  return kernel::compare_power(q, dt.site(a), dt.lift(a), dt.site(b), dt.lift(b));
}

// True if a comes before b in that order, ties to the lower id.
bool nearer(const Vec3& q, const SphericalDelaunay& dt, SiteId a, SiteId b) {
  const Sign s = compare_at(q, dt, a, b);
  return s == Sign::Positive || (s == Sign::Zero && a < b);
}

// Best-first enumeration of the sites by nearness to q from a start site: the sites nearer to q
// than any given site form a connected part of the Delaunay graph containing the nearest.
class NearestFirst {
 public:
  NearestFirst(const SphericalDelaunay& dt, const Vec3& q, SiteId start)
      : dt_(dt), q_(q), heap_(Later{&dt, &q}) {
    if (start != kNoIndex) push(start);
  }
  bool empty() const { return heap_.empty(); }
  SiteId top() const { return heap_.top(); }
  // Removes the nearest remaining site and queues its neighbours.
  SiteId pop() {
    const SiteId s = heap_.top();
    heap_.pop();
    if (dt_.num_triangles() == 0) {  // fewer than 3 sites: all of them
      for (SiteId t = 0; t < dt_.site_capacity(); ++t)
        if (dt_.is_live(t)) push(t);
      return s;
    }
    const HalfedgeId e0 = dt_.site_edge(s);
    HalfedgeId e = e0;
    do {
      push(dt_.triangles()[next_halfedge(e)]);
      e = dt_.next_around_site(e);
    } while (e != e0);
    return s;
  }

 private:
  struct Later {
    const SphericalDelaunay* dt;
    const Vec3* q;
    bool operator()(SiteId a, SiteId b) const { return nearer(*q, *dt, b, a); }
  };
  void push(SiteId s) {
    if (seen_.insert(s).second) heap_.push(s);
  }
  const SphericalDelaunay& dt_;
  const Vec3& q_;
  std::priority_queue<SiteId, std::vector<SiteId>, Later> heap_;
  std::unordered_set<SiteId> seen_;
};

}  // namespace

const char* to_string(LocateStrategy s) { return kNames[static_cast<int>(s)]; }

LocateStrategy parse_strategy(const std::string& name) {
  for (int i = 0; i < 6; ++i)
    if (name == kNames[i]) return static_cast<LocateStrategy>(i);
  throw Error(ErrorCode::InvalidArgument,
              "unknown locator '" + name +
                  "'; use walk, jump-walk, keep-jump-walk, hierarchy, climb or keep-jump-climb");
}

double great_circle_m(const Vec3& a, const Vec3& b) {
  return SiteEncoder::kEarthRadiusM * std::atan2(std::sqrt(norm2(cross(a, b))), dot(a, b));
}

namespace {

// The two layouts the strategies walk, with one interface. Nodes are WalkGraph nodes or site ids.
struct PackedView {
  const WalkGraph& g;
  int num_levels() const { return g.num_levels(); }
  bool empty(int l) const { return g.num_nodes(l) == 0; }
  std::uint32_t any(int) const { return WalkGraph::any_node(); }
  Vec3 point(int l, std::uint32_t v) const { return g.point(l, v); }
  std::uint32_t up(int l, std::uint32_t v) const { return g.up(l, v); }
  std::uint32_t down(int l, std::uint32_t v) const { return g.down(l, v); }
  SiteId site_of(std::uint32_t v) const { return g.site_of(v); }
  std::uint32_t node_of(SiteId s) const { return g.node_of(s); }
  std::uint32_t curve_start(const Vec3& q) const { return g.curve_start(q); }
  template <class F>
  void for_each_neighbour(int l, std::uint32_t v, F&& f) const {
    g.for_each_neighbour(l, v, f);
  }
};

struct HierarchyView {
  const DelaunayHierarchy& h;
  int num_levels() const { return h.num_levels(); }
  bool empty(int l) const { return h.level(l).num_sites() == 0; }
  std::uint32_t any(int l) const {
    const SphericalDelaunay& dt = h.level(l);
    for (SiteId s = 0; s < dt.site_capacity(); ++s)
      if (dt.is_live(s)) return s;
    return kNoIndex;
  }
  Vec3 point(int l, std::uint32_t v) const { return h.level(l).lifted_site(v); }
  std::uint32_t up(int l, std::uint32_t v) const { return l + 1 < h.num_levels() ? h.up(l, v) : kNoIndex; }
  std::uint32_t down(int l, std::uint32_t v) const { return h.down(l, v); }
  SiteId site_of(std::uint32_t v) const { return v; }
  std::uint32_t node_of(SiteId s) const { return s; }
  std::uint32_t curve_start(const Vec3&) const { return kNoIndex; }  // no curve index here
  template <class F>
  void for_each_neighbour(int l, std::uint32_t v, F&& f) const {
    const SphericalDelaunay& dt = h.level(l);
    if (dt.num_triangles() == 0) {  // fewer than 3 sites: each is the others' neighbour
      for (SiteId s = 0; s < dt.site_capacity(); ++s)
        if (s != v && dt.is_live(s)) f(s, dt.lifted_site(s));
      return;
    }
    const SiteId* tri = dt.triangles().data();
    const HalfedgeId e0 = dt.site_edge(v);
    HalfedgeId e = e0;
    do {
      const SiteId w = tri[next_halfedge(e)];
      f(w, dt.lifted_site(w));
      e = dt.next_around_site(e);
    } while (e != e0);
  }
};

// A climbing walk climbs only after this many steps: the first steps from a kept answer are
// short, and the level above would cost a descent back.
constexpr int kNoClimbSteps = 1;

// Above this many sites the packed copy's 32-bit record offsets could overflow: walk the hierarchy.
constexpr std::size_t kMaxPackedSites = std::size_t{1} << 28;

}  // namespace

Locator::Locator(const DelaunayHierarchy& hierarchy, const LocatorOptions& options)
    : h_(&hierarchy), options_(options) {
  reset();
}

void Locator::reset() {
  const double n = static_cast<double>(std::max<std::size_t>(h_->base().num_sites(), 2));
  num_landmarks_ = options_.landmarks;
  if (num_landmarks_ == 0) {
    switch (options_.strategy) {
      case LocateStrategy::JumpWalk: num_landmarks_ = static_cast<std::uint32_t>(std::cbrt(n)); break;
      case LocateStrategy::KeepJumpWalk: num_landmarks_ = static_cast<std::uint32_t>(std::pow(n, 0.375)); break;
      default: num_landmarks_ = static_cast<std::uint32_t>(std::log2(n)); break;
    }
  }
  num_landmarks_ = std::max<std::uint32_t>(num_landmarks_, 1);
  cos_start_.fill(-2.0);
  for (int l = 0; l + 1 < h_->num_levels(); ++l) {
    const double n_l = static_cast<double>(std::max<std::size_t>(h_->level(l).num_sites(), 1));
    const double rad = (l == 0 ? options_.far_spacings : options_.level_spacings) * std::sqrt(4 * std::numbers::pi / n_l);
    cos_start_[static_cast<std::size_t>(l)] = rad < std::numbers::pi ? std::cos(rad) : -2.0;
  }
  landmarks_.clear();
  sample_.clear();
  landmarks_ready_ = false;
  next_landmark_ = 0;
  last_.nodes.fill(kNoIndex);
  if (options_.strategy == LocateStrategy::JumpWalk) {
    // A fixed random sample of live sites.
    const SphericalDelaunay& base = h_->base();
    std::uint64_t state = options_.seed;
    for (std::uint32_t i = 0; i < num_landmarks_ && base.num_sites() > 0; ++i) {
      SiteId s;
      do {
        state = mix(state + 0x9e3779b97f4a7c15ULL);
        s = static_cast<SiteId>(state % base.site_capacity());
      } while (!base.is_live(s));
      sample_.push_back(s);
    }
  }
}

void Locator::prepare() {
  if (options_.packed && h_->base().num_sites() <= kMaxPackedSites && (graph_ == nullptr || !graph_->matches(*h_))) {
    graph_ = h_->walk_graph();
    seen_.clear();
    for (int l = 0; l < h_->num_levels(); ++l) seen_.push_back(h_->level(l).revision());
    reset();
  }
}

// Picks the layout for this query: the packed copy while it is current; otherwise the hierarchy
// itself, until rebuild_after queries found it unchanged (from the first query, or since the last
// change): a stream too short to pay for the copy never builds it.
void Locator::sync() {
  if (graph_ != nullptr && graph_->matches(*h_)) return;
  bool same = seen_.size() == static_cast<std::size_t>(h_->num_levels());
  for (std::size_t l = 0; same && l < seen_.size(); ++l) same = seen_[l] == h_->level(static_cast<int>(l)).revision();
  if (!same) {  // the first query, or the hierarchy changed
    seen_.clear();
    for (int l = 0; l < h_->num_levels(); ++l) seen_.push_back(h_->level(l).revision());
    graph_.reset();
    unchanged_queries_ = 0;
    reset();
    return;
  }
  if (!options_.packed || h_->base().num_sites() > kMaxPackedSites) return;
  const std::uint64_t after =
      options_.rebuild_after > 0 ? options_.rebuild_after : std::max<std::uint64_t>(1024, h_->base().num_sites() / 8);
  if (++unchanged_queries_ < after) return;
  graph_ = h_->walk_graph();
  reset();
}

// Greedy walk in doubles at one level: moves to the best neighbour while it is better. With
// stop_at_up (Climb), after kNoClimbSteps steps it stops as soon as a site seen on the way (the
// current site or one of its neighbours) also lives on the level above, as the thesis' walk
// stops at a cell with such a vertex (§8.4), and sets *climb; it does not stop where the walk
// ends anyway. At its end, *margin = dot(q, v) - the largest dot(q, w) of v's neighbours.
template <class G>
std::uint32_t Locator::walk(const G& g, int level, const Vec3& q, std::uint32_t v, bool stop_at_up, bool* climb,
                            double* margin) {
  if (climb) *climb = false;
  const bool can_climb = stop_at_up && level + 1 < g.num_levels();
  double best = dot(q, g.point(level, v));
  for (int step = 0;; ++step) {
    std::uint32_t next = v, up_site = kNoIndex;
    double up_best = -3, ring = -3;
    const bool look_up = can_climb && step >= kNoClimbSteps;
    g.for_each_neighbour(level, v, [&](std::uint32_t w, const Vec3& p) {
      const double d = dot(q, p);
      ring = std::max(ring, d);
      if (d > best) best = d, next = w;
      if (look_up && d > up_best && g.up(level, w) != kNoIndex) up_best = d, up_site = w;
    });
    if (next == v) {  // the nearest site of this level
      *margin = best - ring;
      return v;
    }
    if (look_up && step > 0 && g.up(level, v) != kNoIndex) up_site = v;
    if (up_site != kNoIndex) {
      *climb = true;
      return up_site;
    }
    v = next;
    ++stats_.steps;
  }
}

template <class G>
std::uint32_t Locator::descend(const G& g, const Vec3& q, int level, std::uint32_t v, double* margin) {
  for (; level > 0; --level) path_[static_cast<std::size_t>(level) - 1] = v = walk(g, level - 1, q, g.down(level, v), false, nullptr, margin);
  return v;
}

template <class G>
std::uint32_t Locator::from_top(const G& g, const Vec3& q, double* margin) {
  int top = g.num_levels() - 1;
  while (top > 0 && g.empty(top)) --top;  // cannot happen after remove()
  return from_level(g, q, top, g.any(top), margin);
}

template <class G>
std::uint32_t Locator::from_level(const G& g, const Vec3& q, int level, std::uint32_t v, double* margin) {
  path_[static_cast<std::size_t>(level)] = v = walk(g, level, q, v, false, nullptr, margin);
  return descend(g, q, level, v, margin);
}

// Thesis §8.4: walk at level 0; on meeting a site of level 1, continue the walk there, and so
// on up; when a walk ends (at the nearest site of its level), descend the hierarchy.
template <class G>
std::uint32_t Locator::climb_and_descend(const G& g, const Vec3& q, std::uint32_t v, double* margin) {
  int level = 0;
  for (;;) {
    bool climb = false;
    v = walk(g, level, q, v, true, &climb, margin);
    if (!climb) {
      path_[static_cast<std::size_t>(level)] = v;
      return descend(g, q, level, v, margin);
    }
    v = g.up(level, v);
    ++level;
    ++stats_.climbs;
  }
}

// Certified walk at level 0 with exact comparisons, then the lowest id among exact ties. A site
// with no strictly better neighbour may still not be the best: on a plateau of ties (lifted points
// on one face of the hull, a site inside it), a tied site can have a better neighbour. So the
// plateau is explored, and the walk goes on from any strictly better neighbour of it; a plateau
// without one is the global maximum (the upper level sets of a linear function on the surface of
// a convex polytope are connected).
SiteId Locator::certify(const Vec3& q, SiteId v) {
  const SphericalDelaunay& dt = h_->base();
  if (dt.num_triangles() == 0) {
    SiteId best = kNoIndex;
    for (SiteId s = 0; s < dt.site_capacity(); ++s)
      if (dt.is_live(s) && (best == kNoIndex || nearer(q, dt, s, best))) best = s;
    return best;
  }
  for (;;) {
    bool tie = false;
    for (;;) {  // strict improvements
      SiteId next = v;
      tie = false;
      const HalfedgeId e0 = dt.site_edge(v);
      HalfedgeId e = e0;
      do {
        const SiteId w = dt.triangles()[next_halfedge(e)];
        const Sign c = compare_at(q, dt, w, next);
        if (c == Sign::Positive) {
          next = w;
        } else if (c == Sign::Zero && next == v) {
          tie = true;  // a neighbour as near as v: look for the lowest id below
        }
        e = dt.next_around_site(e);
      } while (e != e0);
      if (next == v) break;
      v = next;
      ++stats_.exact_steps;
    }
    if (!tie) return v;  // strictly nearer than every neighbour, hence than every other site
    const SiteId better = explore_plateau(q, v);
    if (better == kNoIndex) return v;  // explore_plateau set v to the plateau's lowest id
    v = better;
    ++stats_.exact_steps;
  }
}

// The sites tied with v form a connected part of the graph: collects it. Returns a neighbour of
// it strictly better than v, or kNoIndex after setting v to the plateau's lowest id.
SiteId Locator::explore_plateau(const Vec3& q, SiteId& v) {
  const SphericalDelaunay& dt = h_->base();
  SiteId lowest = v;
  std::vector<SiteId> tied{v}, stack{v};
  while (!stack.empty()) {
    const SiteId s = stack.back();
    stack.pop_back();
    const HalfedgeId e0 = dt.site_edge(s);
    HalfedgeId e = e0;
    do {
      const SiteId w = dt.triangles()[next_halfedge(e)];
      if (std::find(tied.begin(), tied.end(), w) == tied.end()) {
        const Sign c = compare_at(q, dt, w, v);
        if (c == Sign::Positive) return w;
        if (c == Sign::Zero) {
          tied.push_back(w);
          stack.push_back(w);
          lowest = std::min(lowest, w);
        }
      }
      e = dt.next_around_site(e);
    } while (e != e0);
  }
  v = lowest;
  return kNoIndex;
}

template <class G>
SiteId Locator::locate(const G& g, const Vec3& q) {
  if (!landmarks_ready_) {
    for (const SiteId s : sample_) {
      Landmark l{h_->base().lifted_site(s), {}};
      l.nodes.fill(kNoIndex);
      l.nodes[0] = g.node_of(s);
      landmarks_.push_back(l);
    }
    landmarks_ready_ = true;
  }
  // The nearest of the previous answer and the landmarks.
  const Landmark* start = last_.nodes[0] != kNoIndex ? &last_ : nullptr;
  double start_d = start != nullptr ? dot(q, last_.p) : -3.0;
  for (const Landmark& l : landmarks_) {
    const double d = dot(q, l.p);
    if (d > start_d) start_d = d, start = &l;
  }
  path_.fill(kNoIndex);
  double margin = 0;
  std::uint32_t v = kNoIndex;
  const std::uint32_t v0 = start != nullptr ? start->nodes[0] : g.any(0);
  switch (options_.strategy) {
    case LocateStrategy::Walk:
    case LocateStrategy::JumpWalk:
    case LocateStrategy::KeepJumpWalk:
      v = walk(g, 0, q, v0, false, nullptr, &margin);
      break;
    case LocateStrategy::Hierarchy:
      v = from_top(g, q, &margin);
      break;
    case LocateStrategy::Climb:
      v = climb_and_descend(g, q, v0, &margin);
      break;
    case LocateStrategy::KeepJumpClimb: {
      // Near: climb from the landmark. Far: from the curve's site if it is near, else jump to the
      // landmark's nearest site on the lowest level whose spacing suits the distance, walk and
      // descend from there (from the top if the landmark's query never reached that level).
      int level = 0;
      const int top = g.num_levels() - 1;
      while (level < top && start_d < cos_start_[static_cast<std::size_t>(level)]) ++level;
      // No near landmark: try the Hilbert curve's sample first (packed copy only); its node is
      // usually near, but the curve jumps at some cell borders, hence the check.
      std::uint32_t curve = kNoIndex;
      double curve_d = -3;
      if ((start == nullptr || level > 0) && (curve = g.curve_start(q)) != kNoIndex) curve_d = dot(q, g.point(0, curve));
      if (curve != kNoIndex && curve_d > start_d && curve_d >= cos_start_[0]) {
        v = climb_and_descend(g, q, curve, &margin);
      } else if (start == nullptr) {
        v = from_top(g, q, &margin);
      } else if (level == 0) {
        v = climb_and_descend(g, q, v0, &margin);
      } else if (start->nodes[static_cast<std::size_t>(level)] != kNoIndex) {
        v = from_level(g, q, level, start->nodes[static_cast<std::size_t>(level)], &margin);
        ++stats_.climbs;
      } else {
        v = from_top(g, q, &margin);
      }
      break;
    }
  }
  // Every neighbour of v is farther by more than twice the rounding bound of a dot product
  // (gamma_3 sum |q_i p_i| <= 3.4e-16 |q|_1 for |p| <= 1 + 2^-50; with the rounding of a lifted
  // point, <= 4.5e-16 |q|_1 B for |p / c| <= B): v is exactly the unique nearest (of largest
  // power). Otherwise the exact walk decides, ties included.
  SiteId s = g.site_of(v);
  const double bound = 1e-15 * (std::fabs(q.x) + std::fabs(q.y) + std::fabs(q.z)) * h_->lifted_norm_bound() + 1e-300;
  if (!(margin > bound)) {
    s = certify(q, s);
    v = g.node_of(s);
  }
  path_[0] = v;
  last_ = {g.point(0, v), path_};
  if (options_.strategy == LocateStrategy::KeepJumpWalk || options_.strategy == LocateStrategy::KeepJumpClimb) {
    if (landmarks_.size() < num_landmarks_) {
      landmarks_.push_back(last_);
    } else {
      landmarks_[next_landmark_] = last_;
      next_landmark_ = (next_landmark_ + 1) % num_landmarks_;
    }
  }
  return s;
}

NearestResult Locator::nearest(const Vec3& q) {
  const SphericalDelaunay& base = h_->base();
  if (base.num_sites() == 0) return {};
  sync();
  ++stats_.queries;
  const SiteId s = graph_ != nullptr ? locate(PackedView{*graph_}, q) : locate(HierarchyView{*h_}, q);
  // last_.p: the answer's coordinates, already in cache (its lifted point when weighted).
  return {s, great_circle_m(q, base.is_weighted() ? base.site(s) : last_.p)};
}

std::vector<NearestResult> Locator::k_nearest(const Vec3& q, std::size_t k) {
  std::vector<NearestResult> out;
  if (k == 0) return out;
  nearest_first(q, [&](SiteId s, const Vec3& p) {
    out.push_back({s, great_circle_m(q, p)});
    return out.size() < k;
  });
  return out;
}

std::vector<NearestResult> Locator::within(const Vec3& q, double radius_m) {
  std::vector<NearestResult> out;
  if (!(radius_m >= 0)) return out;
  const SphericalDelaunay& base = h_->base();
  nearest_first(q, [&](SiteId s, const Vec3& p) {
    const double d = great_circle_m(q, p);
    if (base.is_weighted()) {  // sites come by power: stop where no later one can be near
      if (power_lower_bound_m(q, p, base.lift(s)) > radius_m) return false;
      if (d <= radius_m) out.push_back({s, d});
      return true;
    }
    if (d > radius_m) return false;  // sites come nearest first: all the others are farther
    out.push_back({s, d});
    return true;
  });
  return out;
}

double power_lower_bound_m(const Vec3& q, const Vec3& p, double lift) {
  // Every later site t has power dot(q, p_t) / c_t <= this one's, so cos d_t <= that power
  // (c_t <= 1); margins for the rounding of the power and of acos.
  const double power = dot(q, p) / lift * (1 + 1e-12) + 1e-15;
  return SiteEncoder::kEarthRadiusM * std::acos(std::min(1.0, power)) - 1e-6;
}

void Locator::nearest_first(const Vec3& q, const std::function<bool(SiteId, const Vec3&)>& visit) {
  const NearestResult first = nearest(q);
  if (first.site == kNoIndex) return;
  const SphericalDelaunay& base = h_->base();
  NearestFirst queue(base, q, first.site);
  while (!queue.empty()) {
    const SiteId s = queue.top();
    if (!visit(s, base.site(s))) return;
    queue.pop();
  }
}

NearestResult Locator::nearest_geodesic(double lat_deg, double lon_deg) {
  if (h_->is_weighted())
    throw Error(ErrorCode::InvalidArgument, "the geodesic metric needs unweighted sites; these are weighted (metric power)");
  const Vec3 q = SiteEncoder::from_lat_lon(lat_deg, lon_deg);
  const NearestResult first = nearest(q);
  if (first.site == kNoIndex) return first;
  const SphericalDelaunay& base = h_->base();
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  const double polar_radius_m = GeographicLib::Constants::WGS84_a() * (1 - GeographicLib::Constants::WGS84_f());
  NearestResult best;
  best.dist_m = INFINITY;
  NearestFirst queue(base, q, first.site);
  while (!queue.empty()) {
    const SiteId s = queue.top();
    const double angle = std::atan2(std::sqrt(norm2(cross(q, base.site(s)))), dot(q, base.site(s)));
    // Lower bound of the geodesic distance of s and of every site after it, with a margin for
    // the rounding of the angle and GeographicLib's 15 nm accuracy.
    const double lower_m = 2 * polar_radius_m * std::sin(angle / 2) * (1 - 1e-12) - 1e-6;
    if (lower_m > best.dist_m) break;
    queue.pop();
    const LatLon p = SiteEncoder::to_lat_lon(base.site(s));
    double s12 = 0;
    geod.Inverse(lat_deg, lon_deg, p.lat_deg, p.lon_deg, s12);
    if (s12 < best.dist_m || (s12 == best.dist_m && s < best.site)) best = {s, s12};
  }
  return best;
}

void nearest_batch(const DelaunayHierarchy& hierarchy, std::span<const Vec3> queries,
                   std::span<NearestResult> out, int threads, const LocatorOptions& options) {
  if (out.size() < queries.size()) throw Error(ErrorCode::InvalidArgument, "nearest_batch: output too small");
  threads = std::max(1, std::min<int>(threads, static_cast<int>(queries.size() / 1024) + 1));
  // A batch long enough to pay for the packed copy gets it now, shared by every thread.
  Locator prototype(hierarchy, options);
  const std::uint64_t after =
      options.rebuild_after > 0 ? options.rebuild_after : std::max<std::uint64_t>(1024, hierarchy.base().num_sites() / 8);
  if (queries.size() >= after) prototype.prepare();
  // Contiguous slices keep each thread's stream coherent.
  parallel_for(queries.size(), static_cast<unsigned>(threads), [&](unsigned, std::size_t begin, std::size_t end) {
    Locator locator = prototype;
    for (std::size_t i = begin; i < end; ++i) out[i] = locator.nearest(queries[i]);
  });
}

}  // namespace geovor
