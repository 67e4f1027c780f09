// SphericalDelaunay: construction, build() (insertion order, final ids), inspectors and the
// arrays of an index file. Insertion, the cavity, removal, validation and relocation have their
// own files (docs/delaunay.md).
#include "geovor/delaunay/spherical_delaunay.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <utility>
#include <chrono>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <tuple>

#include "delaunay/unit_vector.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/delaunay/spatial_sort.hpp"
#include "geovor/kernel/predicates.hpp"
#include "kernel/in_sphere_filter.hpp"

namespace geovor {
namespace {

template <class T>
std::size_t bytes_of(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
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

}  // namespace

SphericalDelaunay::SphericalDelaunay(const DelaunayOptions& options) : options_(options) {
  if (!(options.merge_distance >= kMinSeparation) || !std::isfinite(options.merge_distance))
    throw Error(ErrorCode::InvalidArgument,
                "merge distance " + format_number(options.merge_distance) +
                    " is below the minimum separation 2^-24 of sites on the unit sphere");
}

std::uint64_t SphericalDelaunay::next_revision() {
  static std::atomic<std::uint64_t> counter{0};
  return counter.fetch_add(1, std::memory_order_relaxed) + 1;
}

// ---------------------------------------------------------------------------------------------
// Build

namespace {
void require_unit_points(std::span<const Vec3> points) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double r2 = norm2(points[i]);
    if (!std::isfinite(r2) || std::fabs(r2 - 1.0) > 0x1p-49)
      throw Error(ErrorCode::InvalidArgument,
                  "point " + std::to_string(i) + " is not a unit vector (|p|^2 = " + format_number(r2) + ")");
  }
}

// The point of a group at one position that the others merge into: the smallest lift, then the
// first in input order.
bool keeps_over(std::uint32_t q, std::uint32_t best, std::span<const double> lifts) {
  return lifts[q] < lifts[best] || (lifts[q] == lifts[best] && q < best);
}

// same_position_keeper() from a Hilbert order and its keys: points at one position share a cell,
// so they lie in one run of equal keys; each run with several points is sorted by position (-0
// as 0) and grouped. O(n) beside the order, which the build computes anyway.
std::vector<std::uint32_t> keeper_in_runs(std::span<const Vec3> points, std::span<const double> lifts,
                                          std::span<const std::uint32_t> order, std::span<const std::uint64_t> keys) {
  auto position = [&](std::uint32_t i) {
    const Vec3& p = points[i];
    return std::tuple(p.x + 0.0, p.y + 0.0, p.z + 0.0);
  };
  std::vector<std::uint32_t> keeper, run;
  for (std::size_t a = 0, b; a < order.size(); a = b) {
    for (b = a + 1; b < order.size() && keys[b] == keys[a]; ++b) {}
    if (b - a == 1) continue;
    run.assign(order.begin() + static_cast<std::ptrdiff_t>(a), order.begin() + static_cast<std::ptrdiff_t>(b));
    std::sort(run.begin(), run.end(), [&](std::uint32_t p, std::uint32_t q) { return position(p) < position(q); });
    for (std::size_t i = 0, j; i < run.size(); i = j) {
      std::uint32_t best = run[i];
      for (j = i + 1; j < run.size() && points[run[j]] == points[run[i]]; ++j)
        if (keeps_over(run[j], best, lifts)) best = run[j];
      if (j - i == 1) continue;
      if (keeper.empty()) keeper.assign(points.size(), kNoIndex);
      for (std::size_t k = i; k < j; ++k)
        if (run[k] != best) keeper[run[k]] = best;
    }
  }
  return keeper;
}

// For each point, the point at its position with the smallest lift (the first of them on ties)
// when that is another one, else kNoIndex; empty when no two points share a position. Sorted by a
// hash of the bits, then compared exactly within equal hashes (-0 is 0).
std::vector<std::uint32_t> same_position_keeper(std::span<const Vec3> points, std::span<const double> lifts) {
  auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v + 0.0); };
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    std::uint64_t h = bits(points[i].x) * 0x9e3779b97f4a7c15ULL;
    h = (h ^ std::rotl(bits(points[i].y), 21)) * 0xbf58476d1ce4e5b9ULL;
    h = (h ^ std::rotl(bits(points[i].z), 42)) * 0x94d049bb133111ebULL;
    keyed[i] = {h ^ (h >> 31), i};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> keeper;
  for (std::size_t a = 0, b; a < keyed.size(); a = b) {
    for (b = a + 1; b < keyed.size() && keyed[b].first == keyed[a].first; ++b) {}
    if (b - a == 1) continue;
    // A run of one hash: group its points by exact position.
    for (std::size_t i = a; i < b; ++i) {
      const std::uint32_t p = keyed[i].second;
      std::uint32_t best = p;
      for (std::size_t j = a; j < b; ++j) {
        const std::uint32_t q = keyed[j].second;
        if (points[q] == points[p] && keeps_over(q, best, lifts)) best = q;
      }
      if (best == p) continue;
      if (keeper.empty()) keeper.assign(points.size(), kNoIndex);
      keeper[p] = best;
    }
  }
  return keeper;
}
}  // namespace

SphericalDelaunay SphericalDelaunay::build(std::span<const Vec3> points,
                                           const DelaunayOptions& options, BuildReport* report) {
  require_unit_points(points);
  return build_sites(points, {}, {}, options, report);
}

SphericalDelaunay SphericalDelaunay::build(std::span<const Vec3> points, std::span<const double> lifts,
                                           const DelaunayOptions& options, BuildReport* report) {
  if (lifts.size() != points.size())
    throw Error(ErrorCode::InvalidArgument, std::to_string(lifts.size()) + " lifts for " +
                                                std::to_string(points.size()) + " points");
  for (std::size_t i = 0; i < lifts.size(); ++i)
    if (!(lifts[i] > 0 && lifts[i] <= 1))
      throw Error(ErrorCode::InvalidArgument,
                  "point " + std::to_string(i) + ": lift " + format_number(lifts[i]) + " is not in (0, 1]");
  // Equal lifts: the same signs as no lifts (the determinant scales by the lift).
  const bool equal = std::all_of(lifts.begin(), lifts.end(), [&](double c) { return c == lifts[0]; });
  require_unit_points(points);  // before positions are compared (NaN)
  if (equal) return build_sites(points, {}, {}, options, report);
  // Points at one position keep the largest circle: the others are merged into it before the
  // build. (Closer than the merge distance, the insertion merges them: a vertex hidden by the new
  // circle goes into it, otherwise the new point into the vertex.)
  // The default order is a Hilbert order, whose keys find the points at one position.
  if (!options.spatial_sort || options.brio)
    return build_sites(points, lifts, same_position_keeper(points, lifts), options, report);
  std::vector<std::uint64_t> keys;
  std::vector<std::uint32_t> order = hilbert_order(points, &keys);
  const std::vector<std::uint32_t> keeper = keeper_in_runs(points, lifts, order, keys);
  std::vector<std::uint64_t>().swap(keys);
  return build_sites(points, lifts, keeper, options, report, std::move(order));
}

SphericalDelaunay SphericalDelaunay::build_sites(std::span<const Vec3> points, std::span<const double> lifts,
                                                 std::span<const std::uint32_t> forced, const DelaunayOptions& options,
                                                 BuildReport* report, std::vector<std::uint32_t> hilbert) {
  using Clock = std::chrono::steady_clock;
  const std::size_t n = points.size();
  if (n > kMaxSites)
    throw Error(ErrorCode::InvalidArgument, "too many sites: " + std::to_string(n));
  SphericalDelaunay dt(options);

  const auto t0 = Clock::now();
  std::vector<std::uint32_t> order;
  if (options.spatial_sort) {
    order = options.brio ? brio_order(points, options.seed) : hilbert.empty() ? hilbert_order(points) : std::move(hilbert);
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
  const bool weighted = !lifts.empty();
  if (weighted) dt.lifts_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (k + kAhead < n) {
      __builtin_prefetch(&points[order[k + kAhead]]);
      if (weighted) __builtin_prefetch(&lifts[order[k + kAhead]]);
    }
    dt.sites_[k] = points[order[k]];
    if (weighted) dt.lifts_[k] = lifts[order[k]];
  }
  dt.site_edge_.assign(n, kRemoved);  // not inserted yet
  // Weighted: points at one position are merged into the largest circle there (forced, from
  // build()); closer than the merge distance, they merge as they are inserted.
  std::vector<std::uint32_t> keeper, slot_of_input;
  if (weighted) {
    dt.hidden_by_.assign(n, kNoIndex);
    dt.lift_sites();
  }
  if (!forced.empty()) {
    keeper.assign(forced.begin(), forced.end());
    slot_of_input.resize(n);
    for (std::size_t k = 0; k < n; ++k) slot_of_input[order[k]] = static_cast<std::uint32_t>(k);
  }
  const std::size_t max_tris = n >= 3 ? 2 * n - 4 : 0;
  dt.triangles_.reserve(3 * max_tris);
  dt.halfedges_.reserve(3 * max_tris);
  std::vector<std::uint32_t>().swap(order);  // priority_ holds it from here on
  std::size_t peak = dt.memory_bytes();

  std::vector<Merge> merges;  // input = slot and site = slot until renumbered below
  SiteId hint = kNoIndex;
  std::vector<SiteId> merged_into;  // weighted: the slot each merged slot went into
  if (weighted) merged_into.assign(n, kNoIndex);
  for (std::size_t k = 0; k < n; ++k) {
    if (!keeper.empty() && keeper[dt.priority_[k]] != kNoIndex) {  // resolved below
      merges.push_back({static_cast<std::uint32_t>(k), kNoIndex, 0, false});
      continue;
    }
    const InsertResult r = dt.insert_site(static_cast<SiteId>(k), hint);
    if (r.merged) {
      merges.push_back({static_cast<std::uint32_t>(k), r.site, r.chord, r.hidden});
      if (weighted) merged_into[k] = r.site;
    } else if (!r.hidden) {
      hint = static_cast<SiteId>(k);
    }
    // Weighted: vertices the new site hid within the merge distance are merged into it.
    for (const Merge& m : dt.absorbed_) merges.push_back(m), merged_into[m.input] = m.site;
    dt.absorbed_.clear();
  }
  if (weighted) {
    // A point at another's position goes where that one went; every merge follows the chain of
    // merges of its site (a site absorbed later by a larger circle).
    for (Merge& m : merges) {
      const bool skipped = m.site == kNoIndex;
      SiteId t = m.site;
      if (skipped) {
        std::uint32_t kept = dt.priority_[m.input];
        while (keeper[kept] != kNoIndex) kept = keeper[kept];  // a chain of forced merges
        t = slot_of_input[kept];
      }
      while (merged_into[t] != kNoIndex) t = merged_into[t];
      m.site = t;
      if (skipped) m.chord = std::sqrt(norm2(dt.sites_[m.input] - dt.sites_[t]));
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
      if (dt.alive(static_cast<SiteId>(k)) || dt.is_hidden(static_cast<SiteId>(k))) id_of_input[input_of_slot[k]] = 0;
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
      if (weighted) dt.lifts_.assign(lifts.begin(), lifts.end());
    } else {
      dt.sites_.reserve(next);
      for (std::size_t i = 0; i < n; ++i)
        if (id_of_input[i] != kNoIndex) dt.sites_.push_back(points[i]);
      if (weighted) {
        dt.lifts_.clear();
        for (std::size_t i = 0; i < n; ++i)
          if (id_of_input[i] != kNoIndex) dt.lifts_.push_back(lifts[i]);
      }
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
  if (weighted) dt.renumber_weights(new_id, next);
  std::vector<Vec3>().swap(dt.lifted_);
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
      // Resolved above for weighted sites; otherwise a merge target stays live during the build.
      m.input = input_of_slot[m.input];
      m.site = new_id[m.site];
      report->site_of_input[m.input] = m.site;
    }
    std::sort(merges.begin(), merges.end(),
              [](const Merge& a, const Merge& b) { return a.input < b.input; });
    report->merges = std::move(merges);
    report->hidden.clear();
    for (SiteId h = 0; h < dt.hidden_by_.size(); ++h)
      if (dt.hidden_by_[h] != kNoIndex) report->hidden.push_back({h, dt.hidden_by_[h]});
    report->sort_seconds = std::chrono::duration<double>(t1 - t0).count();
    report->insert_seconds = std::chrono::duration<double>(t2 - t1).count();
    report->peak_bytes = peak;
  }
  return dt;
}

void SphericalDelaunay::lift_sites() {
  lifted_.resize(sites_.size());
  double smallest = 1;
  for (std::size_t k = 0; k < sites_.size(); ++k) {
    const double c = lifts_[k];
    lifted_[k] = {sites_[k].x / c, sites_[k].y / c, sites_[k].z / c};
    smallest = std::min(smallest, c);
  }
  // Every coordinate of an exact or rounded lifted point: at most (1 + 2^-40) / c (1 + u).
  lifted_bound_ = kernel::detail::lifted_static_bound((1 + 0x1p-39) / smallest);
}

void SphericalDelaunay::renumber_weights(std::span<const SiteId> new_id, std::size_t num_ids) {
  std::vector<SiteId> hidden(num_ids, kNoIndex);
  for (std::size_t k = 0; k < new_id.size(); ++k) {
    if (new_id[k] == kNoIndex || hidden_by_[k] == kNoIndex) continue;
    // The site that hid it during the build, or the one that hid that one, ...: a live site
    // nearby, where the walk below starts.
    // (Slots here: a slot with an id and no hider is live; one merged has no id.)
    SiteId by = hidden_by_[k];
    for (int steps = 0; by != kNoIndex && hidden_by_[by] != kNoIndex && steps < 64; ++steps) by = hidden_by_[by];
    hidden[new_id[k]] = by != kNoIndex && hidden_by_[by] == kNoIndex && new_id[by] != kNoIndex ? new_id[by] : 0;
  }
  hidden_by_ = std::move(hidden);
  // Who hides a site: the live site of largest power at its position, whose cell holds it.
  const SiteId any = any_live_site();
  for (SiteId h = 0; h < hidden_by_.size(); ++h) {
    if (hidden_by_[h] == kNoIndex) continue;
    const SiteId start = alive(hidden_by_[h]) && site_edge_[hidden_by_[h]] != kNoIndex ? hidden_by_[h] : any;
    hidden_by_[h] = start == kNoIndex ? kNoIndex : walk_to_nearest(sites_[h], start);
  }
}

std::size_t SphericalDelaunay::num_hidden() const {
  return static_cast<std::size_t>(std::count_if(hidden_by_.begin(), hidden_by_.end(), [](SiteId h) { return h != kNoIndex; }));
}

// ---------------------------------------------------------------------------------------------
// Inspectors and the arrays of an index file

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
  return {sites_, triangles_, halfedges_, site_edge_, lifts_, hidden_by_};
}

// The weights of from_arrays' input: sized as the sites, lifts in (0, 1] and not all equal (equal
// lifts are dropped by build()), hidden sites no vertices, each hidden by a vertex.
void SphericalDelaunay::check_weights(const Arrays& arrays) {
  auto fail = [](const std::string& why) { throw Error(ErrorCode::BadData, "triangulation: " + why); };
  const std::size_t n = arrays.sites.size();
  if (arrays.lifts.empty()) {
    if (!arrays.hidden_by.empty()) fail("hidden sites without weights");
    return;
  }
  if (arrays.lifts.size() != n || arrays.hidden_by.size() != n) fail("weight arrays differ in size from the sites");
  bool all_equal = true;
  for (std::size_t i = 0; i < n; ++i) {
    if (!(arrays.lifts[i] > 0 && arrays.lifts[i] <= 1)) fail("site " + std::to_string(i) + ": lift out of (0, 1]");
    all_equal = all_equal && arrays.lifts[i] == arrays.lifts[0];
  }
  if (all_equal) fail("weighted sites with equal lifts");
  for (std::size_t i = 0; i < n; ++i) {
    const SiteId by = arrays.hidden_by[i];
    if (by == kNoIndex) continue;
    if (arrays.site_edge[i] != kRemoved) fail("site " + std::to_string(i) + " is both hidden and a vertex");
    if (by >= n || arrays.site_edge[by] == kRemoved) fail("hidden site " + std::to_string(i) + ": its hider is no vertex");
  }
}

namespace {

// The first i in [0, n) with bad(i), or n; on `threads` threads (contiguous slices, each stopping
// at its first), for n large enough to pay for them.
template <class Bad>
std::size_t first_bad(std::size_t n, unsigned threads, Bad&& bad) {
  const unsigned t = static_cast<unsigned>(std::min<std::size_t>(thread_count(threads), n / (std::size_t{1} << 16) + 1));
  std::vector<std::size_t> first(t, n);
  parallel_for(n, t, [&](unsigned slice, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (bad(i)) {
        first[slice] = i;
        return;
      }
  });
  return *std::min_element(first.begin(), first.end());
}

}  // namespace

SphericalDelaunay SphericalDelaunay::from_arrays(Arrays arrays, const DelaunayOptions& options, unsigned threads) {
  SphericalDelaunay dt(options);
  auto fail = [](const std::string& why) { throw Error(ErrorCode::BadData, "triangulation: " + why); };
  if (arrays.site_edge.size() != arrays.sites.size()) fail("site arrays differ in size");
  if (arrays.triangles.size() != arrays.halfedges.size() || arrays.triangles.size() % 3 != 0)
    fail("triangle arrays differ in size");
  if (arrays.sites.size() >= kMaxSites) fail("too many sites");
  const std::size_t n = arrays.sites.size(), nh = arrays.halfedges.size();
  if (const std::size_t i = first_bad(n, threads, [&](std::size_t i) { return !is_unit(arrays.sites[i]); }); i < n)
    fail("site " + std::to_string(i) + " is not a unit vector");
  if (first_bad(nh, threads, [&](std::size_t i) { return arrays.triangles[i] >= n; }) < nh)
    fail("a triangle names an unknown site");
  if (first_bad(nh, threads, [&](std::size_t i) { return arrays.halfedges[i] >= nh; }) < nh)
    fail("a half-edge's twin is out of range");
  std::size_t live = 0;
  for (const HalfedgeId e : arrays.site_edge) live += e != kRemoved;
  if (first_bad(n, threads, [&](std::size_t i) {
        const HalfedgeId e = arrays.site_edge[i];
        return e != kRemoved && e != kNoIndex && e >= nh;
      }) < n)
    fail("a site's half-edge is out of range");
  if (!arrays.lifts.empty() && arrays.hidden_by.empty()) arrays.hidden_by.assign(arrays.sites.size(), kNoIndex);
  check_weights(arrays);
  dt.sites_ = std::move(arrays.sites);
  dt.lifts_ = std::move(arrays.lifts);
  dt.hidden_by_ = std::move(arrays.hidden_by);
  dt.triangles_ = std::move(arrays.triangles);
  dt.halfedges_ = std::move(arrays.halfedges);
  dt.site_edge_ = std::move(arrays.site_edge);
  dt.num_live_ = live;
  const Validation v = dt.validate_structure(threads);
  if (!v.ok()) fail(v.errors.front());
  dt.last_site_ = dt.any_live_site();
  return dt;
}

}  // namespace geovor
