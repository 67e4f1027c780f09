#include "geovor/locate/locator.hpp"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Geodesic.hpp>

#include <algorithm>
#include <cmath>
#include <queue>
#include <thread>
#include <unordered_set>

#include "geovor/core/error.hpp"
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

// Exact order of sites by nearness to q, ties to the lower id: true if a comes before b.
bool nearer(const Vec3& q, const SphericalDelaunay& dt, SiteId a, SiteId b) {
  const Sign s = kernel::compare_dot(q, dt.site(a), dt.site(b));
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
  landmarks_.clear();
  next_landmark_ = 0;
  last_ = kNoIndex;
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
      landmarks_.push_back(s);
    }
  }
}

SiteId Locator::any_site(int level) const {
  const SphericalDelaunay& dt = h_->level(level);
  for (SiteId s = 0; s < dt.site_capacity(); ++s)
    if (dt.is_live(s)) return s;
  return kNoIndex;
}

// Greedy walk in doubles at one level: moves to the best neighbour while it is better. With
// stop_at_up (Climb), it stops as soon as a site seen on the way (the current site or one of
// its neighbours) also lives on the level above, as the thesis' walk stops at a cell with such a
// vertex (§8.4), and sets *climb; it does not stop where the walk ends anyway.
SiteId Locator::walk(int level, const Vec3& q, SiteId v, bool stop_at_up, bool* climb) {
  if (climb) *climb = false;
  const SphericalDelaunay& dt = h_->level(level);
  if (dt.num_triangles() == 0) {  // fewer than 3 sites: look at all of them
    for (SiteId s = 0; s < dt.site_capacity(); ++s)
      if (dt.is_live(s) && dot(q, dt.site(s)) > dot(q, dt.site(v))) v = s;
    return v;
  }
  const bool can_climb = stop_at_up && level + 1 < h_->num_levels();
  double best = dot(q, dt.site(v));
  const SiteId* tri = dt.triangles().data();
  bool first = true;
  for (;;) {
    const HalfedgeId e0 = dt.site_edge(v);
    HalfedgeId e = e0;
    SiteId next = v, up_site = kNoIndex;
    double up_best = -3;
    do {
      const SiteId w = tri[next_halfedge(e)];
      const double d = dot(q, dt.site(w));
      if (d > best) best = d, next = w;
      if (can_climb && d > up_best && h_->up(level, w) != kNoIndex) up_best = d, up_site = w;
      e = dt.next_around_site(e);
    } while (e != e0);
    if (next == v) return v;  // the nearest site of this level
    if (can_climb && !first && h_->up(level, v) != kNoIndex) up_site = v;
    if (up_site != kNoIndex) {
      *climb = true;
      return up_site;
    }
    v = next;
    first = false;
    ++stats_.steps;
  }
}

SiteId Locator::descend(const Vec3& q, int level, SiteId v) {
  for (; level > 0; --level) v = walk(level - 1, q, h_->down(level, v), false, nullptr);
  return v;
}

// Thesis §8.4: walk at level 0; on meeting a site of level 1, continue the walk there, and so
// on up; when a walk ends (at the nearest site of its level), descend the hierarchy.
SiteId Locator::climb_and_descend(const Vec3& q, SiteId v) {
  int level = 0;
  for (;;) {
    bool climb = false;
    v = walk(level, q, v, true, &climb);
    if (!climb) return descend(q, level, v);
    v = h_->up(level, v);
    ++level;
    ++stats_.climbs;
  }
}

// Certified walk at level 0 with exact comparisons, then the lowest id among exact ties.
SiteId Locator::certify(const Vec3& q, SiteId v) {
  const SphericalDelaunay& dt = h_->base();
  if (dt.num_triangles() == 0) {
    SiteId best = kNoIndex;
    for (SiteId s = 0; s < dt.site_capacity(); ++s)
      if (dt.is_live(s) && (best == kNoIndex || nearer(q, dt, s, best))) best = s;
    return best;
  }
  bool tie = false;
  for (;;) {
    SiteId next = v;
    tie = false;
    const HalfedgeId e0 = dt.site_edge(v);
    HalfedgeId e = e0;
    do {
      const SiteId w = dt.triangles()[next_halfedge(e)];
      const Sign c = kernel::compare_dot(q, dt.site(w), dt.site(next));
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
  // The sites tied with v form a connected part of the graph (a face of the hull): collect it.
  SiteId best = v;
  std::vector<SiteId> tied{v}, stack{v};
  while (!stack.empty()) {
    const SiteId s = stack.back();
    stack.pop_back();
    const HalfedgeId e0 = dt.site_edge(s);
    HalfedgeId e = e0;
    do {
      const SiteId w = dt.triangles()[next_halfedge(e)];
      if (std::find(tied.begin(), tied.end(), w) == tied.end() &&
          kernel::compare_dot(q, dt.site(w), dt.site(v)) == Sign::Zero) {
        tied.push_back(w);
        stack.push_back(w);
        best = std::min(best, w);
      }
      e = dt.next_around_site(e);
    } while (e != e0);
  }
  return best;
}

SiteId Locator::start_site(const Vec3& q) {
  const SphericalDelaunay& base = h_->base();
  const bool last_ok = last_ != kNoIndex && base.is_live(last_);
  auto best_landmark = [&]() {
    SiteId best = last_ok ? last_ : kNoIndex;
    double best_d = best == kNoIndex ? -2.0 : dot(q, base.site(best));
    for (const SiteId s : landmarks_) {
      if (!base.is_live(s)) continue;
      const double d = dot(q, base.site(s));
      if (d > best_d) best_d = d, best = s;
    }
    return best == kNoIndex ? any_site(0) : best;
  };
  switch (options_.strategy) {
    case LocateStrategy::Walk:
      return walk(0, q, last_ok ? last_ : any_site(0), false, nullptr);
    case LocateStrategy::JumpWalk:
    case LocateStrategy::KeepJumpWalk:
      return walk(0, q, best_landmark(), false, nullptr);
    case LocateStrategy::Hierarchy: {
      int top = h_->num_levels() - 1;
      while (top > 0 && h_->level(top).num_sites() == 0) --top;  // cannot happen after remove()
      return descend(q, top, walk(top, q, any_site(top), false, nullptr));
    }
    case LocateStrategy::Climb:
      return climb_and_descend(q, last_ok ? last_ : any_site(0));
    case LocateStrategy::KeepJumpClimb:
      return climb_and_descend(q, best_landmark());
  }
  return any_site(0);
}

NearestResult Locator::nearest(const Vec3& q) {
  const SphericalDelaunay& base = h_->base();
  if (base.num_sites() == 0) return {};
  ++stats_.queries;
  const SiteId v = certify(q, start_site(q));
  last_ = v;
  if (options_.strategy == LocateStrategy::KeepJumpWalk || options_.strategy == LocateStrategy::KeepJumpClimb) {
    if (landmarks_.size() < num_landmarks_) {
      landmarks_.push_back(v);
    } else {
      landmarks_[next_landmark_] = v;
      next_landmark_ = (next_landmark_ + 1) % num_landmarks_;
    }
  }
  return {v, great_circle_m(q, base.site(v))};
}

std::vector<NearestResult> Locator::k_nearest(const Vec3& q, std::size_t k) {
  std::vector<NearestResult> out;
  if (k == 0) return out;
  const NearestResult first = nearest(q);
  if (first.site == kNoIndex) return out;
  const SphericalDelaunay& base = h_->base();
  NearestFirst queue(base, q, first.site);
  while (out.size() < k && !queue.empty()) {
    const SiteId s = queue.pop();
    out.push_back({s, great_circle_m(q, base.site(s))});
  }
  return out;
}

std::vector<NearestResult> Locator::within(const Vec3& q, double radius_m) {
  std::vector<NearestResult> out;
  const NearestResult first = nearest(q);
  if (first.site == kNoIndex || !(radius_m >= 0)) return out;
  const SphericalDelaunay& base = h_->base();
  NearestFirst queue(base, q, first.site);
  while (!queue.empty()) {
    const double d = great_circle_m(q, base.site(queue.top()));
    if (d > radius_m) break;  // sites come nearest first: all the others are farther
    out.push_back({queue.pop(), d});
  }
  return out;
}

NearestResult Locator::nearest_geodesic(double lat_deg, double lon_deg) {
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
  auto run = [&](std::size_t begin, std::size_t end) {
    Locator locator(hierarchy, options);
    for (std::size_t i = begin; i < end; ++i) out[i] = locator.nearest(queries[i]);
  };
  if (threads == 1) {
    run(0, queries.size());
    return;
  }
  // Contiguous blocks keep each thread's stream coherent.
  std::vector<std::thread> pool;
  const std::size_t block = (queries.size() + threads - 1) / threads;
  for (int t = 0; t < threads; ++t) {
    const std::size_t begin = std::min(queries.size(), block * t), end = std::min(queries.size(), begin + block);
    pool.emplace_back(run, begin, end);
  }
  for (auto& th : pool) th.join();
}

}  // namespace geovor
