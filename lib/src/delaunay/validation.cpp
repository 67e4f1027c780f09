// validate(): every invariant of the triangulation checked exactly; validate_structure(): its
// combinatorial part, O(n), for loaded files.
#include <algorithm>
#include <string>
#include <vector>

#include "delaunay/conflict.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"

namespace geovor {

namespace {

constexpr std::size_t kMaxErrors = 50;
// The least items per thread: fewer and a thread costs more than it saves.
constexpr std::size_t kGrain = std::size_t{1} << 16;

unsigned threads_for(std::size_t n, unsigned threads) {
  return static_cast<unsigned>(std::min<std::size_t>(thread_count(threads), n / kGrain + 1));
}

// The errors of one slice of a check, at most kMaxErrors (no more can reach the result).
struct SliceErrors {
  std::vector<std::string> errors;
  void operator()(std::string msg) {
    if (errors.size() < kMaxErrors) errors.push_back(std::move(msg));
  }
};

// Runs check(begin, end, fail) over [0, n) cut into contiguous slices on `threads` threads; the
// messages passed to fail() reach v in slice order, so in the order of the serial loop, up to
// kMaxErrors. Returns the sum of what the calls return.
template <class Check>
std::size_t check_in_order(Validation& v, std::size_t n, unsigned threads, Check&& check) {
  const unsigned t = threads_for(n, threads);
  std::vector<SliceErrors> errors(t);
  std::vector<std::size_t> sums(t, 0);
  parallel_for(n, t, [&](unsigned slice, std::size_t begin, std::size_t end) {
    sums[slice] = check(begin, end, errors[slice]);
  });
  std::size_t sum = 0;
  for (unsigned slice = 0; slice < t; ++slice) {
    sum += sums[slice];
    for (std::string& e : errors[slice].errors)
      if (v.errors.size() < kMaxErrors) v.errors.push_back(std::move(e));
  }
  return sum;
}

}  // namespace

Validation SphericalDelaunay::validate_structure(unsigned threads) const {
  Validation v;
  auto fail = [&v](std::string msg) {
    if (v.errors.size() < kMaxErrors) v.errors.push_back(std::move(msg));
  };
  const std::size_t nh = halfedges_.size(), nt = num_triangles();
  const std::size_t live = check_in_order(v, sites_.size(), threads, [&](std::size_t begin, std::size_t end, SliceErrors&) {
    std::size_t count = 0;
    for (std::size_t s = begin; s < end; ++s) count += alive(static_cast<SiteId>(s));
    return count;
  });
  if (live != num_live_) fail("live site count " + std::to_string(live) + " != " + std::to_string(num_live_));
  if (triangles_.size() != nh) fail("triangles and halfedges differ in size");
  // Euler: a triangulated sphere with n vertices has 2n - 4 triangles.
  const std::size_t expect = live >= 3 ? 2 * live - 4 : 0;
  if (nt != expect)
    fail("Euler: " + std::to_string(nt) + " triangles for " + std::to_string(live) + " sites");
  if (!v.ok()) return v;

  check_in_order(v, nh, threads, [&](std::size_t begin, std::size_t end, SliceErrors& fail) -> std::size_t {
    for (HalfedgeId e = static_cast<HalfedgeId>(begin); e < end; ++e) {
      const HalfedgeId tw = halfedges_[e];
      if (tw >= nh || tw == e || halfedges_[tw] != e) {
        fail("half-edge " + std::to_string(e) + ": twin not symmetric");
        continue;
      }
      // Orientation: a twin runs the other way, so neighbouring triangles are oriented alike.
      if (triangles_[tw] != triangles_[next_halfedge(e)] || triangles_[next_halfedge(tw)] != triangles_[e])
        fail("half-edge " + std::to_string(e) + ": twin does not run the other way");
    }
    return 0;
  });
  check_in_order(v, nt, threads, [&](std::size_t begin, std::size_t end, SliceErrors& fail) -> std::size_t {
    for (std::size_t t = begin; t < end; ++t) {
      const SiteId a = triangles_[3 * t], b = triangles_[3 * t + 1], c = triangles_[3 * t + 2];
      if (a >= sites_.size() || b >= sites_.size() || c >= sites_.size() || !alive(a) || !alive(b) || !alive(c))
        fail("triangle " + std::to_string(t) + " uses a removed or unknown site");
      else if (a == b || b == c || c == a)
        fail("triangle " + std::to_string(t) + " repeats a site");
    }
    return 0;
  });
  if (!v.ok()) return v;

  // Every live site is a vertex whose star is one cycle: the walks around all sites together
  // meet every half-edge exactly once.
  const std::size_t visited = check_in_order(v, sites_.size(), threads, [&](std::size_t begin, std::size_t end, SliceErrors& fail) {
    std::size_t visited = 0;
    for (SiteId s = static_cast<SiteId>(begin); s < end; ++s) {
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
    return visited;
  });
  if (live >= 3 && visited != nh) fail("vertex stars do not cover every half-edge once");
  return v;
}

Validation SphericalDelaunay::validate(const BuildReport* report, bool global, unsigned threads) const {
  Validation v = validate_structure(threads);
  if (!v.ok()) return v;
  auto fail = [&v](std::string msg) {
    if (v.errors.size() < kMaxErrors) v.errors.push_back(std::move(msg));
  };
  const std::size_t nh = halfedges_.size(), nt = num_triangles();
  const std::size_t live = num_live_;

  // Local Delaunay under the perturbation: across every edge, the opposite site is outside the
  // circumcircle. (The test is the same from both sides: an even permutation.)
  if (live != 3)  // the two triangles of three sites share all their vertices
    check_in_order(v, nh, threads, [&](std::size_t begin, std::size_t end, SliceErrors& fail) -> std::size_t {
      for (HalfedgeId e = static_cast<HalfedgeId>(begin); e < end; ++e) {
        const HalfedgeId tw = halfedges_[e];
        if (tw < e) continue;
        const SiteId d = triangles_[prev_halfedge(tw)];
        if (in_conflict(tri_of(e), sites_[d], lift(d), priority(d)))
          fail("edge " + std::to_string(e) + " is not locally Delaunay");
      }
      return 0;
    });
  if (global)
    check_in_order(v, nt, threads, [&](std::size_t begin, std::size_t end, SliceErrors& fail) -> std::size_t {
      for (TriId t = static_cast<TriId>(begin); t < end; ++t)
        for (SiteId s = 0; s < sites_.size(); ++s) {
          if (!alive(s) || s == triangles_[3 * t] || s == triangles_[3 * t + 1] || s == triangles_[3 * t + 2]) continue;
          if (in_conflict(t, sites_[s], lift(s), priority(s)))
            fail("site " + std::to_string(s) + " lies in the circumcircle of triangle " + std::to_string(t));
        }
      return 0;
    });
  // A hidden weighted site lies inside the hull of the lifted points: no triangle sees it.
  for (SiteId s = 0; s < hidden_by_.size(); ++s) {
    if (!is_hidden(s)) continue;
    if (alive(s)) fail("site " + std::to_string(s) + " is both hidden and a vertex");
    if (!is_live(hidden_by_[s])) fail("hidden site " + std::to_string(s) + ": its hider is not live");
    if (!global) continue;
    for (TriId t = 0; t < nt; ++t)
      if (in_conflict(t, sites_[s], lift(s), priority(s)))
        fail("hidden site " + std::to_string(s) + " lies beyond triangle " + std::to_string(t));
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
