// Fuzz target: the lon/lat cells (CellGeometry) of degenerate but ordinary site sets, checked as
// written. The first byte picks a recipe (lat/lon grids with steps of a mantissa times 10^-k
// degree anywhere, the poles and +-180 included; one latitude row; one meridian; a small circle
// of any radius around any point; clusters at 0.5 to 2 times the merge distance; a
// near-co-circular ring with tiny noise; random points in one hemisphere; 1 to 10 raw lat/lon
// doubles), the next bytes the precision (0..17 decimals or kFullPrecision), the options and the
// recipe's parameters; at most kMaxSites sites, through normalize_lat_lon and
// SiteEncoder::from_lat_lon. For every live site, CellGeometry::polygon(s, mp, area_m2) must give:
// when Written, a valid MultiPolygon (polygon_problem), every coordinate on the decimal grid and
// in range, cell_areas_agree with the cell's area on the sphere, and area_m2 equal to
// ellipsoid_area_m2(mp) within 1e-9 relative or 0.25 m^2; otherwise Collapsed, with an empty mp
// and area 0, never Unwritable (FUZZ_CELLS_STRICT=0 allows it within a degree or three decimal
// steps of a pole, for triage, as fuzzing did while cells there were open). With no
// cell unwritable, the written areas sum to the ellipsoid's and tile the plate carree (64800 square
// degrees), at every precision. One input in 8 also builds the cells on 2 threads, which must
// give the same bits. The Delaunay triangles of
// the same sites (DelaunayGeometry::triangle_polygon, same precision and densification), when
// Written, must be valid, on the grid and in range, with an ellipsoidal area that
// cell_areas_agree with their area on the sphere (a sliver at a pole had been written as the
// whole Earth).
// For triage: FUZZ_CELLS_VERBOSE=1 prints the cell counts by status; FUZZ_CELLS_DUMP=<site> prints
// that site and its written cell, FUZZ_CELLS_DUMP=all every site with its status, and
// FUZZ_CELLS_DUMP=sites only the sites, as a CSV for `geovor cells` (17 digits: the same doubles).
// For triage: FUZZ_CELLS_STRICT=0 allows an unwritable cell near a pole (above).
#include <GeographicLib/Geodesic.hpp>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "fuzz_bytes.hpp"
#include "fuzz_check.hpp"
#include "geovor/core/coordinate_grid.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/lonlat/cell_geometry.hpp"
#include "geovor/lonlat/delaunay_geometry.hpp"
#include "geovor/lonlat/ellipsoid_area.hpp"
#include "geovor/lonlat/polygon_validity.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace {

using namespace geovor;

constexpr std::size_t kMaxSites = 400;
constexpr double kSep = SphericalDelaunay::kMinSeparation;  // the merge distance, 2^-24 radians
constexpr double kPi = std::numbers::pi;

// splitmix64, for the recipes that need more numbers than the input holds.
class Random {
 public:
  explicit Random(std::uint64_t seed) : s_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1p-53; }  // [0, 1)

 private:
  std::uint64_t s_;
};

const char* const kRecipeName[] = {"grid",   "latitude row", "meridian",   "small circle",
                                   "clusters", "co-circular ring", "hemisphere", "raw lat/lon"};

// A mantissa in [1, 10) times 10^-k, k in 0..kmax.
double decimal_step(Bytes& in, int kmax) {
  const double mantissa = 1 + 9 * (in.u8() / 256.0);
  return mantissa * std::pow(10.0, -(in.u8() % (kmax + 1)));
}

// A lat/lon origin: anywhere, or at / just off a pole or the antimeridian.
void origin(Bytes& in, double& lat, double& lon) {
  const std::uint8_t pick = in.u8();
  lat = in.range(-90, 90);
  lon = in.range(-180, 180);
  const std::uint8_t kb = in.u8();
  const double off = kb % 16 >= 13 ? 0.0 : (1 + 9 * (kb >> 4) / 16.0) * std::pow(10.0, -(kb % 16));
  switch (pick % 6) {
    case 2: lat = 90 - off; break;
    case 3: lat = -90 + off; break;
    case 4: lon = 180 - off; break;
    case 5: lon = -180 + off; break;
    default: break;
  }
}

Vec3 normalized(const Vec3& v) {
  const double r = std::sqrt(norm2(v));
  return {v.x / r, v.y / r, v.z / r};
}

// A unit vector orthogonal to u (unit), chosen by `pick`.
Vec3 tangent(const Vec3& u, std::uint8_t pick) {
  const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3 a = axes[pick % 3];
  if (std::fabs(dot(a, u)) > 0.9) a = axes[(pick + 1) % 3];
  Vec3 t = normalized(cross(u, a));
  if (pick & 4) t = normalized(cross(u, t));
  return t;
}

// The point at angle `radius` (radians) from c in direction angle a of the frame (t1, t2).
Vec3 on_circle(const Vec3& c, const Vec3& t1, const Vec3& t2, double radius, double a) {
  const double s = std::sin(radius), co = std::cos(radius), ca = std::cos(a), sa = std::sin(a);
  return normalized({co * c.x + s * (ca * t1.x + sa * t2.x), co * c.y + s * (ca * t1.y + sa * t2.y),
                     co * c.z + s * (ca * t1.z + sa * t2.z)});
}

struct Recipe {
  std::vector<LatLon> sites;  // before normalize_lat_lon
  void add(double lat, double lon) {
    if (sites.size() < kMaxSites) sites.push_back({lat, lon});
  }
  // A point of the sphere, through its lat/lon (as a user would give it).
  void add(const Vec3& p) {
    const LatLon ll = SiteEncoder::to_lat_lon(p);
    add(ll.lat_deg, ll.lon_deg);
  }
};

void make_sites(Bytes& in, int recipe, Recipe& r) {
  switch (recipe) {
    case 0: {  // a lat/lon grid
      double lat0, lon0;
      origin(in, lat0, lon0);
      const int rows = 1 + in.u8() % 20, cols = 1 + in.u8() % 20;
      const double step = decimal_step(in, 7);
      const std::uint8_t dir = in.u8();
      const double dlat = dir & 1 ? -step : step, dlon = dir & 2 ? -step : step;
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < cols; ++j) r.add(std::clamp(lat0 + i * dlat, -90.0, 90.0), lon0 + j * dlon);
      break;
    }
    case 1: {  // one latitude row: a decimal step, or evenly around the whole parallel
      double lat0, lon0;
      origin(in, lat0, lon0);
      const int n = 2 + in.u16() % 200;
      const std::uint8_t how = in.u8();
      const double step = how & 1 ? 360.0 / n : decimal_step(in, 7);
      for (int j = 0; j < n; ++j) r.add(lat0, lon0 + j * step);
      break;
    }
    case 2: {  // one meridian (and, on one input in 4, its opposite meridian too)
      double lat0, lon0;
      origin(in, lat0, lon0);
      const int n = 2 + in.u16() % 200;
      const std::uint8_t how = in.u8();
      const double step = how & 1 ? 180.0 / (n - 1) : decimal_step(in, 7);
      if (how & 1) lat0 = -90;
      for (int i = 0; i < n; ++i) {
        const double lat = std::clamp(lat0 + i * step, -90.0, 90.0);
        r.add(lat, (how & 6) == 6 && i % 2 ? lon0 + 180 : lon0);
      }
      break;
    }
    case 3: {  // points on a circle of any radius around any point, perhaps with its centre
      double lat0, lon0;
      origin(in, lat0, lon0);
      if (in.u8() % 4 == 0) lat0 = lat0 < 0 ? -90 : 90;
      if (normalize_lat_lon(lat0, lon0) != "") return;
      const Vec3 c = SiteEncoder::from_lat_lon(lat0, lon0);
      const std::uint8_t pick = in.u8();
      const Vec3 t1 = tangent(c, pick), t2 = cross(c, t1);
      const std::uint8_t rb = in.u8();
      const double radius = rb & 0x80 ? in.range(0.001, kPi - 0.001)
                                      : (1 + 9 * (in.u8() / 256.0)) * std::pow(10.0, -(rb % 10)) * (kPi / 180);
      const int m = 3 + in.u8() % 60;
      const double phase = in.range(0, 2 * kPi);
      for (int k = 0; k < m; ++k) r.add(on_circle(c, t1, t2, radius, phase + 2 * kPi * k / m));
      if (pick & 8) r.add(lat0, lon0);
      break;
    }
    case 4: {  // clusters of points 0.5 to 2 merge distances from their centre, in a background
      Random rnd(in.u64());
      const int clusters = 1 + in.u8() % 8;
      const int background = in.u8() % 32;
      for (int c = 0; c < clusters; ++c) {
        double lat0, lon0;
        origin(in, lat0, lon0);
        if (normalize_lat_lon(lat0, lon0) != "") continue;
        const Vec3 centre = SiteEncoder::from_lat_lon(lat0, lon0);
        r.add(lat0, lon0);
        const int m = 1 + in.u8() % 8;
        const Vec3 t1 = tangent(centre, in.u8()), t2 = cross(centre, t1);
        for (int k = 0; k < m; ++k) {
          const double d = kSep * (0.5 + 1.5 * (in.u8() / 255.0));
          r.add(on_circle(centre, t1, t2, d, 2 * kPi * rnd.uniform()));
        }
      }
      for (int k = 0; k < background; ++k) {
        const double lat = std::asin(2 * rnd.uniform() - 1) * 180 / kPi;
        r.add(lat, 360 * rnd.uniform() - 180);
      }
      break;
    }
    case 5: {  // a near-co-circular ring: points on a circle moved by tiny noise, perhaps the centre
      double lat0, lon0;
      origin(in, lat0, lon0);
      if (normalize_lat_lon(lat0, lon0) != "") return;
      const Vec3 c = SiteEncoder::from_lat_lon(lat0, lon0);
      const std::uint8_t pick = in.u8();
      const Vec3 t1 = tangent(c, pick), t2 = cross(c, t1);
      const double mantissa = in.range(0.5, 1);
      const double radius = std::ldexp(mantissa, -static_cast<int>(in.u8() % 28));
      const int m = 4 + in.u8() % 40;
      const double noise = std::ldexp(1.0, -30 - static_cast<int>(in.u8() % 24));  // 2^-30 .. 2^-53 rad
      Random rnd(in.u64());
      const double phase = in.range(0, 2 * kPi);
      for (int k = 0; k < m; ++k) {
        const Vec3 p = on_circle(c, t1, t2, radius, phase + 2 * kPi * k / m);
        const Vec3 e = {noise * (2 * rnd.uniform() - 1), noise * (2 * rnd.uniform() - 1), noise * (2 * rnd.uniform() - 1)};
        r.add(normalized({p.x + e.x, p.y + e.y, p.z + e.z}));
      }
      if (pick & 8) r.add(lat0, lon0);
      break;
    }
    case 6: {  // random points in one hemisphere (an empty other half)
      double lat0, lon0;
      origin(in, lat0, lon0);
      if (normalize_lat_lon(lat0, lon0) != "") return;
      const Vec3 c = SiteEncoder::from_lat_lon(lat0, lon0);
      const Vec3 t1 = tangent(c, in.u8()), t2 = cross(c, t1);
      const int n = 3 + in.u16() % (kMaxSites - 2);
      const double cap = in.u8() & 1 ? kPi / 2 : in.range(0.01, kPi / 2);
      Random rnd(in.u64());
      for (int k = 0; k < n; ++k) {
        // uniform on the cap: cos(radius) uniform in [cos(cap), 1]
        const double radius = std::acos(1 - rnd.uniform() * (1 - std::cos(cap)));
        r.add(on_circle(c, t1, t2, radius, 2 * kPi * rnd.uniform()));
      }
      break;
    }
    case 7: {  // raw lat/lon doubles (any bits; non-finite become 0, clamped to the valid ranges)
      const int n = 1 + in.u8() % 10;
      for (int k = 0; k < n; ++k) {
        double lat = std::bit_cast<double>(in.u64()), lon = std::bit_cast<double>(in.u64());
        if (!std::isfinite(lat)) lat = 0;
        if (!std::isfinite(lon)) lon = 0;
        r.add(std::clamp(lat, -90.0, 90.0), std::clamp(lon, -540.0, 540.0));
      }
      break;
    }
  }
}

bool same(const MultiPolygon& a, const MultiPolygon& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].holes.size() != b[i].holes.size() || a[i].exterior.size() != b[i].exterior.size()) return false;
    auto bits_equal = [](const Ring& x, const Ring& y) {
      for (std::size_t k = 0; k < x.size(); ++k)
        if (std::bit_cast<std::uint64_t>(x[k].lon_deg) != std::bit_cast<std::uint64_t>(y[k].lon_deg) ||
            std::bit_cast<std::uint64_t>(x[k].lat_deg) != std::bit_cast<std::uint64_t>(y[k].lat_deg))
          return false;
      return true;
    };
    if (!bits_equal(a[i].exterior, b[i].exterior)) return false;
    for (std::size_t h = 0; h < a[i].holes.size(); ++h)
      if (a[i].holes[h].size() != b[i].holes[h].size() || !bits_equal(a[i].holes[h], b[i].holes[h])) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Bytes in(data, size);
  const int recipe = in.u8() % 8;
  const char* name = kRecipeName[recipe];
  const std::uint8_t pb = in.u8();
  CellGeometryOptions options;
  options.precision = pb % 24 >= 18 ? kFullPrecision : pb % 24;
  const std::uint8_t flags = in.u8();
  static constexpr double kDensify[] = {100, 1000, 10000, 100000};  // fewer positions: faster runs
  options.densify_m = kDensify[(flags >> 3) & 3];
  const bool threads_too = (flags & 7) == 0;

  Recipe r;
  make_sites(in, recipe, r);
  const char* dump = std::getenv("FUZZ_CELLS_DUMP");
  const bool dump_csv = dump != nullptr && std::string(dump) == "sites";
  if (dump_csv) std::printf("id,lat,lon\n");
  std::vector<Vec3> pts;
  for (LatLon ll : r.sites)
    if (normalize_lat_lon(ll.lat_deg, ll.lon_deg).empty()) {
      if (dump_csv) std::printf("%zu,%.17g,%.17g\n", pts.size(), ll.lat_deg, ll.lon_deg);
      pts.push_back(SiteEncoder::from_lat_lon(ll.lat_deg, ll.lon_deg));
    }
  if (pts.empty() || dump_csv) return 0;

  const SphericalDelaunay dt = SphericalDelaunay::build(pts);
  const VoronoiDiagram vd(dt);
  const CellGeometry geom(vd, options);
  const int precision = options.precision;

  const long dump_site = dump == nullptr ? -1 : std::string(dump) == "all" ? -2 : std::atol(dump);
  MultiPolygon mp;
  double area_m2 = -1;
  double sum = 0, planar_sum = 0;
  std::size_t positions = 0;
  std::size_t counts[3] = {0, 0, 0};
  std::vector<CellStatus> statuses(vd.site_capacity(), CellStatus::Collapsed);
  std::vector<MultiPolygon> cells(vd.site_capacity());
  std::vector<double> areas(vd.site_capacity(), 0);
  for (SiteId s = 0; s < vd.site_capacity(); ++s) {
    FUZZ_CHECK(vd.has_cell(s) == dt.is_live(s), "%s, precision %d, site %u: has_cell differs from is_live", name,
               precision, s);
    if (!vd.has_cell(s)) continue;
    area_m2 = -1;
    const CellStatus status = geom.polygon(s, mp, area_m2);
    ++counts[static_cast<int>(status)];
    statuses[s] = status;
    areas[s] = area_m2;
    if (threads_too) cells[s] = mp;
    if (dump_site == -2) {  // FUZZ_CELLS_DUMP=all: every site and its status
      const LatLon ll = SiteEncoder::to_lat_lon(vd.site(s));
      std::fprintf(stderr, "site %u at lat %.17g lon %.17g: %s, %.17g sr\n", s, ll.lat_deg, ll.lon_deg,
                   to_string(status), vd.cell_area_sr(s));
    }
    // A cell is written, or collapsed to nothing at this precision; never left out as a hole,
    // near a pole either (a pole is a line of the plate carree, where the pole rules draw the
    // cells: docs/design.md), unless FUZZ_CELLS_STRICT=0.
    if (status == CellStatus::Unwritable) {
      double max_abs_lat = std::fabs(SiteEncoder::to_lat_lon(vd.site(s)).lat_deg);
      for (const TriId t : vd.cell_vertices(s))
        max_abs_lat = std::max(max_abs_lat, std::fabs(SiteEncoder::to_lat_lon(vd.vertex(t)).lat_deg));
      const bool near_pole = max_abs_lat >= 89 || (precision >= 0 && 90 - max_abs_lat <= 3 * std::pow(10.0, -precision));
      static const bool strict = !std::getenv("FUZZ_CELLS_STRICT") || std::string(std::getenv("FUZZ_CELLS_STRICT")) != "0";
      FUZZ_CHECK(near_pole && !strict, "%s, precision %d, site %u of %zu: unwritable, %.17g degrees from a pole", name, precision, s,
                 dt.num_sites(), 90 - max_abs_lat);
    }
    if (status != CellStatus::Written) {
      FUZZ_CHECK(mp.empty() && area_m2 == 0, "%s, precision %d, site %u: %s cell with %zu parts and area %.17g", name,
                 precision, s, to_string(status), mp.size(), area_m2);
      continue;
    }
    if (dump_site == static_cast<long>(s)) {  // FUZZ_CELLS_DUMP=<site>: the site and its written cell
      const LatLon ll = SiteEncoder::to_lat_lon(vd.site(s));
      std::fprintf(stderr, "site %u at lat %.17g lon %.17g, area %.17g m^2, %.17g sr\n", s, ll.lat_deg, ll.lon_deg,
                   area_m2, vd.cell_area_sr(s));
      for (const Polygon& poly : mp) {
        std::fprintf(stderr, "part:");
        for (const LonLat& c : poly.exterior) std::fprintf(stderr, " (%.17g %.17g)", c.lon_deg, c.lat_deg);
        std::fprintf(stderr, "\n");
      }
    }
    const std::string problem = polygon_problem(mp);
    FUZZ_CHECK(problem.empty(), "%s, precision %d, site %u of %zu: written cell invalid: %s", name, precision, s,
               pts.size(), problem.c_str());
    for (const Polygon& poly : mp) {
      FUZZ_CHECK(poly.holes.empty(), "%s, precision %d, site %u: a hole", name, precision, s);
      for (const LonLat& c : poly.exterior) {
        FUZZ_CHECK(snap_to_decimals(c.lon_deg, precision) == c.lon_deg &&
                       snap_to_decimals(c.lat_deg, precision) == c.lat_deg,
                   "%s, precision %d, site %u: position (%.17g, %.17g) off the decimal grid", name, precision, s,
                   c.lon_deg, c.lat_deg);
        FUZZ_CHECK(c.lon_deg >= -180 && c.lon_deg <= 180 && c.lat_deg >= -90 && c.lat_deg <= 90,
                   "%s, precision %d, site %u: position (%.17g, %.17g) out of range", name, precision, s, c.lon_deg,
                   c.lat_deg);
      }
    }
    const double area_sr = vd.cell_area_sr(s);
    FUZZ_CHECK(cell_areas_agree(area_m2, area_sr, mp, options.densify_m, precision),
               "%s, precision %d, site %u: area %.17g m^2 disagrees with %.17g sr", name, precision, s, area_m2, area_sr);
    const double measured = ellipsoid_area_m2(mp);
    FUZZ_CHECK(std::fabs(area_m2 - measured) <= std::max(1e-9 * std::fabs(measured), 0.25),
               "%s, precision %d, site %u: area %.17g m^2 but ellipsoid_area_m2 %.17g", name, precision, s, area_m2,
               measured);
    sum += area_m2;
    for (const Polygon& poly : mp) positions += poly.exterior.size(), planar_sum += planar_area_deg2(poly.exterior);
  }
  // The written cells tile the sphere (snap rounding keeps the tiling where rounding collapses
  // thin parts): with no cell unwritable, their areas sum to the ellipsoid's, collapsed cells
  // having none. At every precision: at 2 decimals or fewer every cell is snap rounded, since a
  // whole group of cells can fall into one step (a grid of 72 sites 0.01 degree apart at 0
  // decimals had overlapped by 2e-7 of the ellipsoid).
  if (counts[static_cast<int>(CellStatus::Unwritable)] == 0) {
    const double total = GeographicLib::Geodesic::WGS84().EllipsoidArea();
    FUZZ_CHECK(std::fabs(sum - total) <= 1e-9 * total,
               "%s, precision %d, %zu sites: the cells sum to %.17g m^2, the ellipsoid is %.17g", name, precision,
               dt.num_sites(), sum, total);
    // And they tile the plate carree: a sliver there (two cells drawing one edge differently
    // near a pole) has no area on the ellipsoid. Each term of the shoelace sums is within
    // 4e-12 square degrees.
    FUZZ_CHECK(std::fabs(planar_sum - 64800) <= 1e-6 + 4e-12 * static_cast<double>(positions),
               "%s, precision %d, %zu sites: the cells' planar areas sum to %.17g square degrees, not 64800", name,
               precision, dt.num_sites(), planar_sum);
  }

  // The Delaunay triangles, written at the same precision.
  DelaunayGeometryOptions tri_options;
  tri_options.precision = precision;
  tri_options.densify_m = options.densify_m;
  const DelaunayGeometry triangles(dt, tri_options);
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    const WrittenStatus status = triangles.triangle_polygon(t, mp);
    if (status != WrittenStatus::Written) {
      FUZZ_CHECK(mp.empty(), "%s, precision %d, triangle %u: %s with %zu parts", name, precision, t, to_string(status),
                 mp.size());
      continue;
    }
    const std::string problem = polygon_problem(mp);
    FUZZ_CHECK(problem.empty(), "%s, precision %d, triangle %u (%s) of %zu sites: invalid: %s", name, precision, t,
               to_string(triangles.kind(t)), pts.size(), problem.c_str());
    for (const Polygon& poly : mp)
      for (const LonLat& c : poly.exterior)
        FUZZ_CHECK(snap_to_decimals(c.lon_deg, precision) == c.lon_deg &&
                       snap_to_decimals(c.lat_deg, precision) == c.lat_deg && c.lon_deg >= -180 &&
                       c.lon_deg <= 180 && c.lat_deg >= -90 && c.lat_deg <= 90,
                   "%s, precision %d, triangle %u: position (%.17g, %.17g) off the grid or out of range", name,
                   precision, t, c.lon_deg, c.lat_deg);
    const double tri_m2 = ellipsoid_area_m2(mp), tri_sr = triangles.triangle_area_sr(t);
    FUZZ_CHECK(cell_areas_agree(tri_m2, tri_sr, mp, options.densify_m, precision),
               "%s, precision %d, triangle %u (%s) of %zu sites: written %.17g m^2, %.17g sr on the sphere", name,
               precision, t, to_string(triangles.kind(t)), pts.size(), tri_m2, tri_sr);
  }

  if (threads_too) {
    CellGeometryOptions two = options;
    two.threads = 2;
    const CellGeometry geom2(vd, two);
    for (SiteId s = 0; s < vd.site_capacity(); ++s) {
      if (!vd.has_cell(s)) continue;
      area_m2 = -1;
      const CellStatus status = geom2.polygon(s, mp, area_m2);
      FUZZ_CHECK(status == statuses[s] && same(mp, cells[s]) &&
                     std::bit_cast<std::uint64_t>(area_m2) == std::bit_cast<std::uint64_t>(areas[s]),
                 "%s, precision %d, site %u: 2 threads give %s, area %.17g; 1 thread %s, area %.17g", name, precision, s,
                 to_string(status), area_m2, to_string(statuses[s]), areas[s]);
    }
  }
  if (std::getenv("FUZZ_CELLS_VERBOSE") != nullptr)
    std::fprintf(stderr, "%s, precision %d: %zu sites, %zu written, %zu collapsed, %zu unwritable, %zu positions\n", name,
                 precision, dt.num_sites(), counts[0], counts[1], counts[2], positions);
  return 0;
}
