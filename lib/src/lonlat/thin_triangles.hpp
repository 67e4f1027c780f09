// Private to the lonlat module: the tests by which CellGeometry's constructor finds the thin
// cells (snap rounded) and the edges to guard (Densifier::set_guards), one triangle of the
// Delaunay triangulation (a Voronoi vertex) at a time. Pure functions, here for their tests.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

#include "geovor/core/types.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor::lonlat {

/// The squared chords (unit sphere) below which a Voronoi edge or a triangle's side marks thin
/// cells, and the bound of a vertex's z^2 / (x^2 + y^2) above which its edges are guarded.
struct ThinThresholds {
  double fold2;        // an edge shorter than two decimal steps, which rounding alone can fold
  double small2;       // a triangle's side shorter than four steps
  double pole_guard2;  // where the plate carree can turn a chord by a degree at its ends
};

/// The thresholds at the grid of snap_decimals decimals (CellGeometry::thin_cell_decimals) and
/// the densification tolerance densify_m: a chord within densify_m of its arc turns by about
/// sqrt(2 densify_m tan(lat) / R) radians, a degree from tan(lat) = 1.5e-4 R / densify_m (84
/// degrees for 100 m).
inline ThinThresholds thin_thresholds(int snap_decimals, double densify_m) {
  const double step_rad = std::pow(10.0, -snap_decimals) * std::numbers::pi / 180;
  return {4 * step_rad * step_rad, 16 * step_rad * step_rad,
          std::pow(1.5e-4 * SiteEncoder::kEarthRadiusM / densify_m, 2)};
}

/// Whether the Voronoi vertex v lies beyond the latitude of pole_guard2 (thin_thresholds).
inline bool near_pole_for_chords(const Vec3& v, double pole_guard2) {
  return v.z * v.z > pole_guard2 * (v.x * v.x + v.y * v.y);
}

/// The largest float not above d2 >= 0: a lower bound kept in 4 bytes (Vertex::min_side2).
inline float round_down_to_float(double d2) {
  float f = static_cast<float>(d2);
  if (f > d2) f = std::bit_cast<float>(std::bit_cast<std::uint32_t>(f) - 1);  // f > 0: the next float down
  return f;
}

/// Whether the triangle's angle at p (on the sphere, between the great circles to q and r) is
/// within 3.6 degrees of 180.
inline bool near_straight(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 a = cross(p, q), b = cross(p, r);
  if (!(dot(a, b) < 0)) return false;
  constexpr double kSin2 = 0.003942649342761085;  // sin^2(3.6 degrees)
  return norm2(cross(a, b)) < kSin2 * norm2(a) * norm2(b);
}

/// Whether the triangle of sites ps, pu, pw, with circumcentre c and longest side of squared
/// chord longest2, is a cap: its circumradius over 8 times its longest side (an angle within 3.6
/// degrees of 180: its three cells have an angle below 3.6 degrees there, thin near it), or, for
/// a triangle with a side over 5 degrees, where that test does not hold (sites on one great
/// circle, two of them close: their lunes are as thin, but the circumradius of a triangle with a
/// far site is not 8 times its longest side), an angle within 3.6 degrees of 180 (near_straight).
/// (Below a side of 5 degrees the two tests agree: the plane's law of sines holds.)
inline bool is_cap(const Vec3& ps, const Vec3& pu, const Vec3& pw, const Vec3& c, double longest2) {
  constexpr double kLargeSide2 = 0.0076;  // squared chord of 5 degrees
  return norm2(c - ps) > 64 * longest2 ||
         (longest2 > kLargeSide2 && (near_straight(ps, pu, pw) || near_straight(pu, pw, ps) || near_straight(pw, ps, pu)));
}

}  // namespace geovor::lonlat
