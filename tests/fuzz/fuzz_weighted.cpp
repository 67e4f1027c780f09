// Fuzz target: the regular triangulation of weighted sites (issue 33, docs/weighted.md). The bytes
// are a recipe of points (point_recipes.hpp) and each point's lift cos(r / R): unweighted, one
// shared radius, radii from metres to near a quarter of the circumference, huge circles hiding
// their neighbours, nested circles at one position, lifts a few ulps apart, circles through one
// point (lifted points on one plane; on one line for sites on a great circle through it). After build(),
// validate() must pass (with the global check, which tests every hidden site against every
// triangle, on small inputs); every point is a live site, a hidden one or a listed merge; of points
// at one position the smallest lift is kept; without merges the triangles and the hidden sites do
// not depend on the insertion order (when no order merges any); equal lifts give the unweighted
// triangles. The Locator over the weighted hierarchy answers, at every site, every edge's
// midpoint and points from the bytes, the live site of largest power (exactly, ties to the
// lowest id), packed or not.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <span>
#include <vector>

#include "fuzz_check.hpp"
#include "point_recipes.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/kernel/predicates.hpp"
#include "geovor/locate/locator.hpp"

namespace {

using namespace geovor;
using namespace geovor::fuzz;

constexpr std::size_t kGlobalCheckBelow = 48;
constexpr double kQuarter = 1.5707963267948966;  // radians: the largest radius, excluded

// The lift of one point from the bytes; `previous` is the lift of the point before it.
double lift(Bytes& in, double previous) {
  const std::uint8_t kind = in.u8();
  switch (kind % 8) {
    case 0: return 1.0;
    case 1: return previous;                                              // shared radius
    case 2: return std::cos(in.range(0, 1e-3));                           // up to 6 km
    case 3: return std::cos(in.range(0, 0.1));                            // up to 600 km
    case 4: return std::cos(in.range(0.5, kQuarter * (1 - 1e-9)));        // huge circles
    case 5: return std::cos(kQuarter * (1 - std::ldexp(1.0, -(kind >> 3)))); // near the limit
    case 6: {                                                             // a few ulps off
      double c = previous;
      for (int k = kind >> 5; k >= 0; --k) c = std::nextafter(c, 0.0);
      return c > 0 ? c : previous;
    }
    default: return std::ldexp(1.0, -static_cast<int>(kind >> 3) % 40);    // powers of two
  }
}

// The Locator's answers against every live site, exactly.
void check_locator(Bytes& in, std::span<const Vec3> pts, std::span<const double> lifts, const DelaunayOptions& options) {
  HierarchyOptions levels;
  levels.ratio = 2 + in.u8() % 4;  // small inputs still get levels above
  const DelaunayHierarchy h = DelaunayHierarchy::build(pts, lifts, options, levels);
  const SphericalDelaunay& dt = h.base();
  std::vector<Vec3> queries(pts.begin(), pts.end());
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) queries.push_back(normalized(pts[i] + pts[i + 1]));
  for (int k = 0; k < 8 && !in.empty(); ++k) queries.push_back(any_lat_lon(in));
  for (const bool packed : {true, false}) {
    LocatorOptions o;
    o.packed = packed;
    o.strategy = packed ? LocateStrategy::KeepJumpClimb : LocateStrategy::Hierarchy;
    Locator locator(h, o);
    if (packed) locator.prepare();
    for (const Vec3& q : queries) {
      if (!(norm2(q) > 0.5)) continue;
      const SiteId got = locator.nearest(q).site;
      FUZZ_CHECK(dt.is_live(got), "the answer %u is no vertex", got);
      for (SiteId s = 0; s < dt.site_capacity(); ++s) {
        if (!dt.is_live(s) || s == got) continue;
        const Sign c = kernel::compare_power(q, dt.site(s), dt.lift(s), dt.site(got), dt.lift(got));
        FUZZ_CHECK(c == Sign::Negative || (c == Sign::Zero && s > got),
                   "locator (%s): site %u has %s power than the answer %u at q = (%.17g, %.17g, %.17g)",
                   packed ? "packed" : "hierarchy", s, c == Sign::Zero ? "equal" : "larger", got, q.x, q.y, q.z);
      }
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  DelaunayOptions options;
  const std::uint8_t flags = in.u8();
  options.spatial_sort = (flags & 1) != 0;
  options.brio = (flags & 2) != 0;
  options.seed = flags >> 4;
  const int ops = 1 + in.u8() % 32;
  std::vector<Vec3> pts;
  for (int k = 0; k < ops && !in.empty(); ++k) operation(in, pts);
  if (flags & 4) {  // nested circles: copies of a point with other radii
    const std::size_t n = pts.size();
    for (std::size_t k = 0; k < n && k < 8; ++k) add(pts, pts[in.u8() % n]);
  }
  std::vector<double> lifts;
  for (std::size_t i = 0; i < pts.size(); ++i) lifts.push_back(lift(in, lifts.empty() ? 0.5 : lifts.back()));
  if (flags & 8) {  // circles through one point X: the lifted points on the plane x . X = 1
    const Vec3 x = any_lat_lon(in);
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (const double d = dot(pts[i], x); d > 0 && d <= 1 && (in.u8() & 1)) lifts[i] = d;
  }

  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(pts, lifts, options, &report);
  if (std::getenv("FUZZ_WEIGHTED_VERBOSE")) {  // triage: the points, their lifts and the merges
    for (std::size_t i = 0; i < pts.size(); ++i)
      std::fprintf(stderr, "point %zu: %.17g %.17g %.17g lift %.17g\n", i, pts[i].x, pts[i].y, pts[i].z, lifts[i]);
    for (const Merge& m : report.merges)
      std::fprintf(stderr, "merge %u -> site %u (lift %.17g) chord %.3g\n", m.input, m.site, dt.lift(m.site), m.chord);
    for (const Hidden& h : report.hidden) std::fprintf(stderr, "hidden %u by %u\n", h.site, h.by);
  }
  const Validation v = dt.validate(&report, pts.size() < kGlobalCheckBelow);
  FUZZ_CHECK(v.ok(), "build: %s", v.errors.front().c_str());
  FUZZ_CHECK(dt.num_sites() + dt.num_hidden() + report.merges.size() == pts.size(),
             "%zu sites + %zu hidden + %zu merges != %zu points", dt.num_sites(), dt.num_hidden(),
             report.merges.size(), pts.size());
  FUZZ_CHECK(report.hidden.size() == dt.num_hidden(), "hidden listed %zu, found %zu", report.hidden.size(),
             dt.num_hidden());
  for (const Hidden& h : report.hidden) FUZZ_CHECK(dt.is_live(h.by), "hidden site %u: hider %u not live", h.site, h.by);
  for (const Merge& m : report.merges) {
    const SiteId s = m.site;
    FUZZ_CHECK(s < dt.site_capacity() && (dt.is_live(s) || dt.is_hidden(s)), "merge of point %u", m.input);
    // A merge may follow a chain of merges (a vertex absorbed by a larger circle), each closer
    // than the merge distance.
    FUZZ_CHECK(m.chord < options.merge_distance * static_cast<double>(report.merges.size() + 1), "merge at chord %.17g",
               m.chord);
    if (pts[m.input] == dt.site(s) && dt.is_weighted())  // (equal lifts build unweighted: lift() is 1)
      FUZZ_CHECK(dt.lift(s) <= lifts[m.input], "point %u at its site's position has a larger radius", m.input);
  }
  if (dt.num_sites() > 0) check_locator(in, pts, lifts, options);
  if (report.merges.empty()) {
    DelaunayOptions other = options;
    other.spatial_sort = !options.spatial_sort;
    BuildReport again_report;
    const SphericalDelaunay again = SphericalDelaunay::build(pts, lifts, other, &again_report);
    // Near-duplicates merge as they are inserted: in another order a point may be merged rather
    // than hidden (or into another site), and the ids shift; compare orders without merges only.
    if (!again_report.merges.empty()) return 0;
    FUZZ_CHECK(triangle_set(again) == triangle_set(dt), "the triangles depend on the insertion order");
    for (SiteId s = 0; s < dt.site_capacity(); ++s)
      FUZZ_CHECK(again.is_hidden(s) == dt.is_hidden(s), "site %u hidden in one order only", s);
    if (!dt.is_weighted())
      FUZZ_CHECK(triangle_set(SphericalDelaunay::build(pts, other)) == triangle_set(dt),
                 "equal lifts: not the unweighted triangles");
  }
  return 0;
}
