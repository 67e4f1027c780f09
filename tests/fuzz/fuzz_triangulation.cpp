// Fuzz target: the triangulation on adversarial coordinates. The bytes are a recipe: a list of
// operations adding points (uniform lat/lon, near-duplicates at multiples of the merge distance,
// lat/lon grids, near-co-circular sets, great circles, poles and the antimeridian, antipodes,
// perturbations by a few ulps), options, then insertions and removals, then moves (move() and
// move_all() by steps from a few ulps to the merge distance and across the tolerances, with
// each relocation option). After build() and after every edit, validate() must pass (with the
// global check on small inputs), every input point must be a site or a listed merge, without
// merges the triangles must not depend on the insertion order, and after moves the triangles
// must be those of a fresh build of the live sites' positions.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <numbers>
#include <set>
#include <vector>

#include "fuzz_check.hpp"
#include "point_recipes.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace {

using namespace geovor;
using namespace geovor::fuzz;

constexpr std::size_t kGlobalCheckBelow = 48;  // validate(report, true) is O(n^2)

void check_valid(const SphericalDelaunay& dt, const BuildReport* report, const char* when) {
  const Validation v = dt.validate(report, dt.num_sites() < kGlobalCheckBelow);
  FUZZ_CHECK(v.ok(), "%s: %s", when, v.errors.front().c_str());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  DelaunayOptions options;
  const std::uint8_t flags = in.u8();
  options.spatial_sort = (flags & 1) != 0;
  options.brio = (flags & 2) != 0;
  options.seed = flags >> 4;
  static constexpr double kMerge[] = {1, 1, 1, 1.5, 2, 1024};
  options.merge_distance = kSep * kMerge[(flags >> 2) & 3];
  const int ops = 1 + in.u8() % 32;
  std::vector<Vec3> pts;
  for (int k = 0; k < ops && !in.empty(); ++k) operation(in, pts);

  BuildReport report;
  SphericalDelaunay dt = SphericalDelaunay::build(pts, options, &report);
  check_valid(dt, &report, "build");
  FUZZ_CHECK(report.site_of_input.size() == pts.size(), "site_of_input has %zu entries for %zu points",
             report.site_of_input.size(), pts.size());
  FUZZ_CHECK(dt.num_sites() + report.merges.size() == pts.size(), "%zu sites + %zu merges != %zu points",
             dt.num_sites(), report.merges.size(), pts.size());
  for (const Merge& m : report.merges) {
    FUZZ_CHECK(m.input < pts.size() && report.site_of_input[m.input] == m.site && dt.is_live(m.site),
               "merge of point %u", m.input);
    FUZZ_CHECK(m.hidden || (m.chord >= 0 && m.chord < options.merge_distance), "merge at chord %.17g", m.chord);
  }
  if (report.merges.empty()) {
    // The perturbed triangulation is a function of the sites and their indices only.
    DelaunayOptions other = options;
    other.spatial_sort = !options.spatial_sort;
    const SphericalDelaunay again = SphericalDelaunay::build(pts, other);
    FUZZ_CHECK(again.num_sites() == dt.num_sites() && triangle_set(again) == triangle_set(dt),
               "the triangles depend on the insertion order");
  }

  // Edits: insertions of new recipe points and removals of live sites.
  std::vector<Vec3> more;
  for (int k = 0; k < 8 && !in.empty(); ++k) {
    const std::uint8_t what = in.u8();
    if ((what & 1) && dt.num_sites() > 0) {
      SiteId s = static_cast<SiteId>(in.u16() % dt.site_capacity());
      while (!dt.is_live(s)) s = static_cast<SiteId>((s + 1) % dt.site_capacity());
      dt.remove(s);
      FUZZ_CHECK(!dt.is_live(s), "site %u still live after its removal", s);
    } else {
      more = pts;
      const std::size_t before = more.size();
      operation(in, more);
      for (std::size_t i = before; i < more.size(); ++i) {
        const std::size_t live = dt.num_sites();
        const InsertResult r = dt.insert(more[i]);
        FUZZ_CHECK(dt.is_live(r.site), "insert gave a dead site");
        FUZZ_CHECK(dt.num_sites() == live + (r.merged ? 0 : 1), "site count after an insertion");
      }
    }
    check_valid(dt, nullptr, "edits");
  }

  // Moves (SphericalDelaunay::move/move_all; the filter's tolerances, flips, remove + insert).
  static constexpr double kStep[] = {0, 0x1p-52, 0x1p-40, 0.5 * kSep, kSep, 1.5 * kSep, 1e-7, 1e-5, 1e-3, 0.05, 1};
  for (int k = 0; k < 6 && !in.empty() && dt.num_sites() > 0; ++k) {
    const std::uint8_t what = in.u8();
    RelocationOptions ro;
    ro.filter = (what & 8) == 0;
    ro.flips = (what & 16) == 0;
    ro.rebuild_when_faster = (what & 32) == 0;
    const double step = kStep[in.u8() % std::size(kStep)];
    auto moved = [&](const Vec3& p, std::uint8_t pick) {
      Vec3 q = ulps(normalized(p + step * tangent(p, pick)), pick);
      return usable(q) ? q : p;
    };
    if (what & 1) {  // every live site at once, each by `step` in a direction of its own
      std::vector<Vec3> target(dt.sites().begin(), dt.sites().end());
      for (SiteId s = 0; s < target.size(); ++s)
        if (dt.is_live(s)) target[s] = moved(target[s], static_cast<std::uint8_t>(in.u8() + s));
      const MoveStats st = dt.move_all(target, ro);
      FUZZ_CHECK(st.moved == st.filtered + st.flipped + st.reinserted + st.rebuilt, "move_all stats do not add up");
      for (SiteId s = 0; s < target.size(); ++s)
        FUZZ_CHECK(!dt.is_live(s) || dt.site(s) == target[s] || st.refused > 0, "site %u not moved", s);
    } else {  // one site, by `step` or onto (near) another site
      SiteId s = static_cast<SiteId>(in.u16() % dt.site_capacity());
      while (!dt.is_live(s)) s = static_cast<SiteId>((s + 1) % dt.site_capacity());
      Vec3 p = moved(dt.site(s), in.u8());
      if (what & 2) {
        const SiteId onto = static_cast<SiteId>(in.u16() % dt.site_capacity());
        p = moved(dt.site(onto), in.u8());
      }
      if (!usable(p)) continue;
      const MoveStats st = dt.move(s, p, ro);
      FUZZ_CHECK(st.moved + st.refused <= 1 && st.moved == st.filtered + st.flipped + st.reinserted, "move stats");
      FUZZ_CHECK(st.refused > 0 || dt.site(s) == p, "site %u not moved and not refused", s);
    }
    check_valid(dt, nullptr, "moves");
    // The same triangles as a fresh build of the live sites (in id order, so that the
    // perturbation orders them alike), unless two of them are within the merge distance.
    std::vector<Vec3> live;
    std::vector<SiteId> id_of;
    for (SiteId s = 0; s < dt.site_capacity(); ++s)
      if (dt.is_live(s)) live.push_back(dt.site(s)), id_of.push_back(s);
    BuildReport fresh_report;
    const SphericalDelaunay fresh = SphericalDelaunay::build(live, options, &fresh_report);
    if (!fresh_report.merges.empty()) continue;
    FUZZ_CHECK(triangle_set(fresh, &id_of) == triangle_set(dt), "after moves: not the triangles of a fresh build");
  }
  return 0;
}
