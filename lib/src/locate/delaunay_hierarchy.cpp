#include "geovor/locate/delaunay_hierarchy.hpp"

#include <algorithm>
#include <string>

#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/locate/walk_graph.hpp"

namespace geovor {
namespace {

std::uint64_t mix(std::uint64_t z) {  // splitmix64's finaliser
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

int DelaunayHierarchy::drawn_level(SiteId s) const {
  std::uint64_t h = mix(options_.seed * 0x9e3779b97f4a7c15ULL + s + 1);
  int l = 0;
  while (l + 1 < static_cast<int>(options_.max_levels)) {
    if (h % options_.ratio != 0) break;
    h = mix(h);
    ++l;
  }
  return l;
}

namespace {

void check_options(const HierarchyOptions& hierarchy) {
  if (hierarchy.ratio < 2 || hierarchy.max_levels < 1 || hierarchy.max_levels > 16)
    throw Error(ErrorCode::InvalidArgument, "hierarchy: ratio must be >= 2 and max_levels in 1..16");
}

}  // namespace

DelaunayHierarchy DelaunayHierarchy::build(std::span<const Vec3> points, const DelaunayOptions& options,
                                           const HierarchyOptions& hierarchy, BuildReport* report) {
  check_options(hierarchy);
  DelaunayHierarchy h;
  h.options_ = hierarchy;
  h.levels_.push_back(SphericalDelaunay::build(points, options, report));
  h.build_levels({}, options);
  return h;
}

DelaunayHierarchy DelaunayHierarchy::build(std::span<const Vec3> points, std::span<const double> lifts,
                                           const DelaunayOptions& options, const HierarchyOptions& hierarchy,
                                           BuildReport* report) {
  check_options(hierarchy);
  DelaunayHierarchy h;
  h.options_ = hierarchy;
  h.levels_.push_back(SphericalDelaunay::build(points, lifts, options, report));
  h.build_levels(h.base().lifts(), options);
  h.set_lifted_norm_bound();
  return h;
}

void DelaunayHierarchy::set_lifted_norm_bound() {
  double smallest = 1;
  for (const double c : base().lifts()) smallest = std::min(smallest, c);
  // 1 / c rounded, times 1 + 2^-50: an upper bound of the exact 1 / c and of |p| / c.
  lifted_norm_bound_ = smallest == 1 ? 1.0 : (1 / smallest) * (1 + 0x1p-50);
}

void DelaunayHierarchy::build_levels(std::span<const double> lifts, const DelaunayOptions& options) {
  // Level l+1 holds the level-l sites drawn that high, in level-0 id order, so that its
  // perturbation priorities follow the level-0 ids. Hidden sites are not live: they stay below.
  std::vector<SiteId> base_of;  // level-l site -> level-0 id
  base_of.resize(base().site_capacity());
  for (SiteId s = 0; s < base_of.size(); ++s) base_of[s] = s;
  down_.emplace_back();
  for (int l = 0; l + 1 < static_cast<int>(options_.max_levels); ++l) {
    std::vector<Vec3> pts;
    std::vector<double> pts_lifts;
    std::vector<SiteId> picked;  // level-l ids going up
    const std::size_t below_capacity = levels_.back().site_capacity();
    {
      const SphericalDelaunay& below = levels_.back();  // not used past the push_back below
      for (SiteId s = 0; s < below_capacity; ++s) {
        if (!below.is_live(s) || drawn_level(base_of[s]) <= l) continue;
        picked.push_back(s);
        pts.push_back(below.site(s));
        if (!lifts.empty()) pts_lifts.push_back(lifts[base_of[s]]);
      }
    }
    if (pts.empty()) break;
    BuildReport level_report;
    levels_.push_back(lifts.empty() ? SphericalDelaunay::build(pts, options, &level_report)
                                    : SphericalDelaunay::build(pts, pts_lifts, options, &level_report));
    // Unweighted sites stay separated in a subset. Weighted vertices may lie closer than the merge
    // distance (their radii differ): a sample then merges them, and the merged one goes no higher.
    GEOVOR_ASSERT(lifts.empty() ? level_report.merges.empty() : level_report.hidden.empty());
    const SphericalDelaunay& above = levels_.back();
    std::vector<SiteId> up(below_capacity, kNoIndex), down(above.site_capacity(), kNoIndex);
    std::vector<SiteId> next_base(above.site_capacity(), kNoIndex);
    std::vector<char> merged(pts.size(), 0);
    for (const Merge& m : level_report.merges) merged[m.input] = 1;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const SiteId u = level_report.site_of_input.empty() ? static_cast<SiteId>(i) : level_report.site_of_input[i];
      if (merged[i] || !above.is_live(u)) continue;
      up[picked[i]] = u;
      down[u] = picked[i];
      next_base[u] = base_of[picked[i]];
    }
    up_.push_back(std::move(up));
    down_.push_back(std::move(down));
    base_of = std::move(next_base);
  }
  up_.emplace_back(levels_.back().site_capacity(), kNoIndex);
}

DelaunayHierarchy DelaunayHierarchy::from_parts(const HierarchyOptions& options, std::vector<SphericalDelaunay> levels,
                                                std::vector<std::vector<SiteId>> up,
                                                std::vector<std::vector<SiteId>> down) {
  auto fail = [](const std::string& why) { throw Error(ErrorCode::BadData, "hierarchy: " + why); };
  auto at = [](std::size_t l, SiteId s) { return "level " + std::to_string(l) + " site " + std::to_string(s); };
  if (options.ratio < 2 || options.max_levels < 1 || options.max_levels > 16)
    fail("ratio must be >= 2 and max_levels in 1..16");
  const std::size_t n = levels.size();
  if (n < 1 || n > options.max_levels) fail(std::to_string(n) + " levels, expected 1 to max_levels");
  if (up.size() != n || down.size() != n) fail("links for " + std::to_string(up.size()) + " and " +
                                               std::to_string(down.size()) + " levels, expected " + std::to_string(n));
  if (!down[0].empty()) fail("level 0 has down links");
  for (std::size_t l = 0; l < n; ++l) {
    const std::size_t cap = levels[l].site_capacity();
    if (up[l].size() != cap || (l > 0 && down[l].size() != cap))
      fail("level " + std::to_string(l) + ": links differ in size from the sites");
    if (l > 0 && levels[l].num_sites() == 0) fail("level " + std::to_string(l) + " has no site");
  }
  for (const SiteId u : up[n - 1])
    if (u != kNoIndex) fail("the top level has an up link");
  for (std::size_t l = 0; l + 1 < n; ++l) {
    const SphericalDelaunay& lo = levels[l];
    const SphericalDelaunay& hi = levels[l + 1];
    double common_lift = -1;  // of the copies on a level above without weights
    for (SiteId s = 0; s < lo.site_capacity(); ++s) {
      const SiteId u = up[l][s];
      if (u == kNoIndex) continue;
      if (!lo.is_live(s) || u >= hi.site_capacity() || !hi.is_live(u) || down[l + 1][u] != s ||
          !(hi.site(u) == lo.site(s)))
        fail(at(l, s) + ": bad up link");
      // Copies keep their lift; a level without weights holds copies of one lift.
      if (!hi.is_weighted() && common_lift < 0) common_lift = lo.lift(s);
      if (hi.is_weighted() ? !lo.is_weighted() || hi.lift(u) != lo.lift(s) : lo.lift(s) != common_lift)
        fail(at(l, s) + ": its copy above has another lift");
    }
    for (SiteId u = 0; u < hi.site_capacity(); ++u) {
      const SiteId d = down[l + 1][u];
      if (hi.is_live(u) ? d >= lo.site_capacity() || up[l][d] != u : d != kNoIndex && d >= lo.site_capacity())
        fail(at(l + 1, u) + ": bad down link");
    }
  }
  DelaunayHierarchy h;
  h.options_ = options;
  h.levels_ = std::move(levels);
  h.up_ = std::move(up);
  h.down_ = std::move(down);
  h.set_lifted_norm_bound();
  const SphericalDelaunay& base = h.base();
  for (SiteId s = 0; s < base.site_capacity(); ++s) {
    if (!base.is_live(s)) continue;
    int l = 0;
    SiteId c = s;
    while (l + 1 < h.num_levels() && h.up(l, c) != kNoIndex) c = h.up(l, c), ++l;
    const int drawn = std::min(h.drawn_level(s), h.num_levels() - 1);
    if (base.is_weighted() ? l > drawn : l != drawn)  // weighted: a merge in a sample stops a site
      fail("site " + std::to_string(s) + " is on " + std::to_string(l + 1) + " levels, its draw gives " +
           std::to_string(std::min(h.drawn_level(s), h.num_levels() - 1) + 1));
  }
  return h;
}

InsertResult DelaunayHierarchy::insert(const Vec3& p) {
  walk_graph_.graph.reset();  // stale after any change: free it now
  const InsertResult r = levels_[0].insert(p);
  if (r.merged) return r;
  up_[0].push_back(kNoIndex);
  const int top = drawn_level(r.site);
  SiteId below = r.site;
  for (int l = 1; l <= top; ++l) {
    if (l == num_levels()) {  // a new level: its only site so far
      levels_.emplace_back(levels_[0].options());
      up_.emplace_back();
      down_.emplace_back();
    }
    const InsertResult rl = levels_[static_cast<std::size_t>(l)].insert(p);
    GEOVOR_ASSERT(!rl.merged);
    auto& up_below = up_[static_cast<std::size_t>(l - 1)];
    up_below[below] = rl.site;
    auto& down_here = down_[static_cast<std::size_t>(l)];
    if (down_here.size() <= rl.site) down_here.resize(rl.site + 1, kNoIndex);
    down_here[rl.site] = below;
    auto& up_here = up_[static_cast<std::size_t>(l)];
    if (up_here.size() <= rl.site) up_here.resize(rl.site + 1, kNoIndex);
    below = rl.site;
  }
  return r;
}

void DelaunayHierarchy::remove(SiteId s) {
  walk_graph_.graph.reset();  // stale after any change: free it now
  levels_[0].remove(s);  // throws if s is not live
  for (int l = 0; l + 1 < num_levels(); ++l) {
    const SiteId u = up_[static_cast<std::size_t>(l)][s];
    if (u == kNoIndex) break;
    up_[static_cast<std::size_t>(l)][s] = kNoIndex;
    levels_[static_cast<std::size_t>(l + 1)].remove(u);
    s = u;
  }
  // An emptied top level would leave walks nowhere to start: drop it (a later insert drawn that
  // high brings it back).
  while (levels_.size() > 1 && levels_.back().num_sites() == 0) {
    levels_.pop_back();
    up_.pop_back();
    down_.pop_back();
  }
}

MoveStats DelaunayHierarchy::move(SiteId s, const Vec3& p, const RelocationOptions& options) {
  walk_graph_.graph.reset();  // stale after any change: free it now
  if (!levels_[0].is_live(s)) return levels_[0].move(s, p, options);  // throws
  const Vec3 old = levels_[0].site(s);
  const MoveStats st = levels_[0].move(s, p, options);
  if (st.moved == 0) return st;
  // The copies above: a subset of the sites, so a position level 0 accepts is never within the
  // merge distance of a site above; should one be refused all the same, every level goes back.
  SiteId c = s;
  for (int l = 0; l + 1 < num_levels(); ++l) {
    const SiteId u = up_[static_cast<std::size_t>(l)][c];
    if (u == kNoIndex) break;
    const MoveStats above = levels_[static_cast<std::size_t>(l + 1)].move(u, p, options);
    if (above.refused) {
      SiteId b = c;
      for (int k = l; k >= 0; --k) {
        levels_[static_cast<std::size_t>(k)].move(b, old, options);
        if (k > 0) b = down_[static_cast<std::size_t>(k)][b];
      }
      MoveStats refused;
      refused.refused = 1;
      return refused;
    }
    c = u;
  }
  return st;
}

MoveStats DelaunayHierarchy::move_all(std::span<const Vec3> positions, const RelocationOptions& options) {
  walk_graph_.graph.reset();  // stale after any change: free it now
  MoveStats st = levels_[0].move_all(positions, options);
  std::vector<Vec3> target;
  for (std::size_t l = 1; l < levels_.size(); ++l) {
    SphericalDelaunay& level = levels_[l];
    const SphericalDelaunay& below = levels_[l - 1];
    target.assign(level.sites().begin(), level.sites().end());
    for (SiteId u = 0; u < level.site_capacity(); ++u)
      if (level.is_live(u)) target[u] = below.site(down_[l][u]);
    const MoveStats above = level.move_all(target, options);
    if (above.refused == 0) continue;
    // Never expected (see move()): the copies below go back to where this level kept the site.
    for (SiteId u = 0; u < level.site_capacity(); ++u) {
      if (!level.is_live(u) || level.site(u) == target[u]) continue;
      SiteId b = down_[l][u];
      for (std::size_t k = l; k-- > 0;) {
        levels_[k].move(b, level.site(u), options);
        if (k > 0) b = down_[k][b];
      }
      --st.moved;
      ++st.refused;
    }
  }
  return st;
}

std::shared_ptr<const WalkGraph> DelaunayHierarchy::walk_graph(unsigned threads) const {
  const std::lock_guard<std::mutex> lock(walk_graph_.mutex);  // a second caller waits for the build
  if (walk_graph_.graph == nullptr || !walk_graph_.graph->matches(*this))
    walk_graph_.graph = std::make_shared<const WalkGraph>(*this, threads);
  return walk_graph_.graph;
}

std::size_t DelaunayHierarchy::memory_bytes() const {
  std::size_t bytes = 0;
  for (const auto& level : levels_) bytes += level.memory_bytes();
  for (const auto& v : up_) bytes += v.capacity() * sizeof(SiteId);
  for (const auto& v : down_) bytes += v.capacity() * sizeof(SiteId);
  return bytes;
}

Validation DelaunayHierarchy::validate() const {
  Validation v;
  for (int l = 0; l < num_levels(); ++l) {
    const Validation vl = level(l).validate();
    for (const auto& e : vl.errors) v.errors.push_back("level " + std::to_string(l) + ": " + e);
  }
  for (int l = 0; l + 1 < num_levels(); ++l) {
    const SphericalDelaunay& lo = level(l);
    const SphericalDelaunay& hi = level(l + 1);
    for (SiteId s = 0; s < lo.site_capacity(); ++s) {
      const SiteId u = up(l, s);
      if (u == kNoIndex) continue;
      if (!lo.is_live(s) || u >= hi.site_capacity() || !hi.is_live(u) || down(l + 1, u) != s ||
          !(hi.site(u) == lo.site(s)))
        v.errors.push_back("level " + std::to_string(l) + " site " + std::to_string(s) + ": bad up link");
    }
    std::size_t live_hi = 0;
    for (SiteId u = 0; u < hi.site_capacity(); ++u) {
      if (!hi.is_live(u)) continue;
      ++live_hi;
      const SiteId d = down(l + 1, u);
      if (d >= lo.site_capacity() || up(l, d) != u)
        v.errors.push_back("level " + std::to_string(l + 1) + " site " + std::to_string(u) + ": bad down link");
    }
    if (live_hi != hi.num_sites()) v.errors.push_back("level " + std::to_string(l + 1) + ": live count");
  }
  // Every live level-0 site is on the levels its draw gives (up to the levels that exist).
  for (SiteId s = 0; s < base().site_capacity(); ++s) {
    if (!base().is_live(s)) continue;
    int l = 0;
    SiteId c = s;
    while (l + 1 < num_levels() && up(l, c) != kNoIndex) c = up(l, c), ++l;
    const int drawn = std::min(drawn_level(s), num_levels() - 1);
    if (is_weighted() ? l > drawn : l != drawn)  // weighted: a merge in a sample stops a site
      v.errors.push_back("site " + std::to_string(s) + " is on " + std::to_string(l + 1) + " levels, drawn " +
                         std::to_string(drawn_level(s) + 1));
  }
  return v;
}

}  // namespace geovor
