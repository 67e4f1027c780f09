// The fuzz targets' recipes of points on the sphere (fuzz_triangulation, fuzz_weighted): each
// operation appends points read from the bytes: uniform lat/lon, near-duplicates at multiples of
// the merge distance, lat/lon grids, near-co-circular sets, great circles, poles and the
// antimeridian, antipodes, perturbations by a few ulps, raw doubles.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <numbers>
#include <set>
#include <vector>

#include "fuzz_bytes.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor::fuzz {

inline constexpr std::size_t kMaxPoints = 160;
inline constexpr double kSep = SphericalDelaunay::kMinSeparation;

inline Vec3 normalized(const Vec3& v) {
  const double r = std::sqrt(norm2(v));
  return {v.x / r, v.y / r, v.z / r};
}

inline bool usable(const Vec3& v) {
  const double r2 = norm2(v);
  return std::isfinite(r2) && std::fabs(r2 - 1) <= 0x1p-49;
}

// A vector orthogonal to u (unit), chosen by `pick`.
inline Vec3 tangent(const Vec3& u, std::uint8_t pick) {
  const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  Vec3 a = axes[pick % 3];
  if (std::fabs(dot(a, u)) > 0.9) a = axes[(pick + 1) % 3];
  Vec3 t = normalized(cross(u, a));
  if (pick & 4) t = normalized(cross(u, t));  // the other direction
  return t;
}

// Moves p by `steps` ulps in each coordinate (steps in -4..3, per coordinate from `bits`).
inline Vec3 ulps(Vec3 p, std::uint8_t bits) {
  double* c[3] = {&p.x, &p.y, &p.z};
  for (int k = 0; k < 3; ++k) {
    int steps = static_cast<int>((bits >> (2 * k)) & 7) - 4;
    for (; steps > 0; --steps) *c[k] = std::nextafter(*c[k], 2.0);
    for (; steps < 0; ++steps) *c[k] = std::nextafter(*c[k], -2.0);
  }
  return p;
}

// Distances near the merge distance: multiples and fractions of 2^-24, and just off them.
inline double near_sep(std::uint8_t b) {
  static constexpr double kFactors[] = {0, 0.5, 1, 1 - 0x1p-20, 1 + 0x1p-20, 1.5, 2, 2 - 0x1p-30, 3, 4, 16, 0x1p-10};
  return kSep * kFactors[b % std::size(kFactors)];
}

inline void add(std::vector<Vec3>& pts, const Vec3& p) {
  if (pts.size() < kMaxPoints && usable(p)) pts.push_back(p);
}

// A lat/lon position, latitude read first (a call's arguments are evaluated in no fixed order).
inline Vec3 any_lat_lon(Bytes& in) {
  const double lat = in.range(-90, 90);
  return SiteEncoder::from_lat_lon(lat, in.range(-180, 180));
}

// Appends the points of one recipe operation.
inline void operation(Bytes& in, std::vector<Vec3>& pts) {
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
inline std::set<std::array<SiteId, 3>> triangle_set(const SphericalDelaunay& dt, const std::vector<SiteId>* label = nullptr) {
  std::set<std::array<SiteId, 3>> out;
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    std::array<SiteId, 3> tri{dt.tri_site(t, 0), dt.tri_site(t, 1), dt.tri_site(t, 2)};
    if (label != nullptr) tri = {(*label)[tri[0]], (*label)[tri[1]], (*label)[tri[2]]};
    std::rotate(tri.begin(), std::min_element(tri.begin(), tri.end()), tri.end());  // keeps the orientation
    out.insert(tri);
  }
  return out;
}

}  // namespace geovor::fuzz
