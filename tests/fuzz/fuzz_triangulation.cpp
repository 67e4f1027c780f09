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

#include "fuzz_bytes.hpp"
#include "fuzz_check.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace {

using namespace geovor;

constexpr std::size_t kMaxPoints = 160;
constexpr std::size_t kGlobalCheckBelow = 48;  // validate(report, true) is O(n^2)
constexpr double kSep = SphericalDelaunay::kMinSeparation;

Vec3 normalized(const Vec3& v) {
  const double r = std::sqrt(norm2(v));
  return {v.x / r, v.y / r, v.z / r};
}

bool usable(const Vec3& v) {
  const double r2 = norm2(v);
  return std::isfinite(r2) && std::fabs(r2 - 1) <= 0x1p-49;
}

// A vector orthogonal to u (unit), chosen by `pick`.
Vec3 tangent(const Vec3& u, std::uint8_t pick) {
  const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3 a = axes[pick % 3];
  if (std::fabs(dot(a, u)) > 0.9) a = axes[(pick + 1) % 3];
  Vec3 t = normalized(cross(u, a));
  if (pick & 4) t = normalized(cross(u, t));  // the other direction
  return t;
}

// Moves p by `steps` ulps in each coordinate (steps in -4..3, per coordinate from `bits`).
Vec3 ulps(Vec3 p, std::uint8_t bits) {
  double* c[3] = {&p.x, &p.y, &p.z};
  for (int k = 0; k < 3; ++k) {
    int steps = static_cast<int>((bits >> (2 * k)) & 7) - 4;
    for (; steps > 0; --steps) *c[k] = std::nextafter(*c[k], 2.0);
    for (; steps < 0; ++steps) *c[k] = std::nextafter(*c[k], -2.0);
  }
  return p;
}

// Distances near the merge distance: multiples and fractions of 2^-24, and just off them.
double near_sep(std::uint8_t b) {
  static constexpr double kFactors[] = {0, 0.5, 1, 1 - 0x1p-20, 1 + 0x1p-20, 1.5, 2, 2 - 0x1p-30, 3, 4, 16, 0x1p-10};
  return kSep * kFactors[b % std::size(kFactors)];
}

void add(std::vector<Vec3>& pts, const Vec3& p) {
  if (pts.size() < kMaxPoints && usable(p)) pts.push_back(p);
}

// A lat/lon position, latitude read first (a call's arguments are evaluated in no fixed order).
Vec3 any_lat_lon(Bytes& in) {
  const double lat = in.range(-90, 90);
  return SiteEncoder::from_lat_lon(lat, in.range(-180, 180));
}

// Appends the points of one recipe operation.
void operation(Bytes& in, std::vector<Vec3>& pts) {
  const std::uint8_t op = in.u8();
  const auto any = [&]() -> const Vec3& { return pts[in.u8() % pts.size()]; };
  switch (op % 9) {
    case 0:  // a lat/lon position
      add(pts, any_lat_lon(in));
      break;
    case 1:  // near-duplicate of an existing point, at a distance near the merge distance
      if (!pts.empty()) {
        const Vec3 p = any();
        const Vec3 t = tangent(p, in.u8());
        const double d = near_sep(in.u8());
        add(pts, normalized({p.x + d * t.x, p.y + d * t.y, p.z + d * t.z}));
      }
      break;
    case 2: {  // a lat/lon grid (ties everywhere: four co-circular sites per cell)
      const int rows = 1 + in.u8() % 6, cols = 1 + in.u8() % 8;
      const double step = std::ldexp(1.0, -static_cast<int>(in.u8() % 24));  // 1 degree .. 2^-23
      const double lat0 = in.range(-90, 90), lon0 = in.range(-180, 180);
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) {
          const double lat = std::clamp(lat0 + i * step, -90.0, 90.0);
          add(pts, SiteEncoder::from_lat_lon(lat, lon0 + j * step));
        }
      break;
    }
    case 3: {  // near-co-circular: points on a small circle, each moved by a few ulps
      const Vec3 c = any_lat_lon(in);
      const Vec3 t1 = tangent(c, in.u8());
      const Vec3 t2 = cross(c, t1);
      const double mantissa = in.range(0.5, 1);
      const double radius = std::ldexp(mantissa, -static_cast<int>(in.u8() % 26));
      const int m = 3 + in.u8() % 8;
      const double phase = in.range(0, 2 * std::numbers::pi);
      for (int k = 0; k < m; ++k) {
        const double a = phase + 2 * std::numbers::pi * k / m;
        const double s = std::sin(radius), co = std::cos(radius);
        const Vec3 p = normalized({co * c.x + s * (std::cos(a) * t1.x + std::sin(a) * t2.x),
                                   co * c.y + s * (std::cos(a) * t1.y + std::sin(a) * t2.y),
                                   co * c.z + s * (std::cos(a) * t1.z + std::sin(a) * t2.z)});
        add(pts, ulps(p, in.u8()));
      }
      break;
    }
    case 4: {  // points on one great circle (coplanar with the centre)
      const Vec3 n = any_lat_lon(in);
      const Vec3 t1 = tangent(n, in.u8());
      const Vec3 t2 = cross(n, t1);
      const int m = 1 + in.u8() % 12;
      for (int k = 0; k < m; ++k) {
        const double a = in.range(0, 2 * std::numbers::pi);
        add(pts, normalized({std::cos(a) * t1.x + std::sin(a) * t2.x, std::cos(a) * t1.y + std::sin(a) * t2.y,
                             std::cos(a) * t1.z + std::sin(a) * t2.z}));
      }
      break;
    }
    case 5: {  // poles, the antimeridian, and just off them
      static constexpr double kLat[] = {90, -90, 89.999999999, -89.99999999, 0, 1e-300, 45};
      static constexpr double kLon[] = {180, -180, 179.99999999999997, -179.99999999999997, 0, 540, -540, 90};
      const double lat = kLat[in.u8() % std::size(kLat)];
      add(pts, SiteEncoder::from_lat_lon(lat, kLon[in.u8() % std::size(kLon)]));
      break;
    }
    case 6:  // an existing point moved by a few ulps (not renormalised)
      if (!pts.empty()) add(pts, ulps(any(), in.u8()));
      break;
    case 7:  // the antipode of an existing point
      if (!pts.empty()) {
        const Vec3 p = any();
        add(pts, {-p.x, -p.y, -p.z});
      }
      break;
    case 8:  // a unit vector from raw doubles (any bits), kept only if of unit length
      add(pts, Vec3{std::bit_cast<double>(in.u64()), std::bit_cast<double>(in.u64()), std::bit_cast<double>(in.u64())});
      break;
  }
}

// The triangles as a set of id triples, each rotated to start at its smallest; `label`, if
// given, renames the ids first.
std::set<std::array<SiteId, 3>> triangle_set(const SphericalDelaunay& dt, const std::vector<SiteId>* label = nullptr) {
  std::set<std::array<SiteId, 3>> out;
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    std::array<SiteId, 3> tri{dt.tri_site(t, 0), dt.tri_site(t, 1), dt.tri_site(t, 2)};
    if (label != nullptr) tri = {(*label)[tri[0]], (*label)[tri[1]], (*label)[tri[2]]};
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());  // keeps the orientation
    out.insert(tri);
  }
  return out;
}

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
