/// \file ellipsoid_area.hpp
/// \brief Areas on the WGS84 ellipsoid of lon/lat rings and polygons, all in one place: the area
/// of polygons as GeographicLib::PolygonArea computes it (ellipsoid_area_m2), and its pieces for
/// callers that sum a ring's edges themselves (shared edges of a tiling measured once): the S12
/// term of many short geodesics at once (geodesic_s12, about five times faster than
/// GeographicLib for the short edges of densified Voronoi cells), PolygonArea's prime-meridian
/// crossings, its sum and its reduction of a ring's sum to an area.
///
/// A ring's area from its edges, as PolygonArea does it: sum_s12 of each edge's S12 (or a
/// CompensatedSum of such sums), the crossings counted by prime_meridian_transit, then
/// ring_area_m2.
///
/// S12 (m^2) of the geodesic from point 1 to point 2 is the signed area between the geodesic,
/// the two meridians through its ends and the equator (Karney, "Algorithms for geodesics",
/// J. Geodesy 87, 2013, eq. 58):
///
///     S12 = c^2 (alpha2 - alpha1) + e^2 a^2 cos(alpha0) sin(alpha0) (I4(sigma2) - I4(sigma1)).
///
/// A closed ring's area is the sum of its edges' S12, reduced modulo the ellipsoid's area as
/// PolygonArea does (the caller's job). GeographicLib solves the inverse problem of each edge
/// with Newton's method on series expansions; for a short edge this file does the same on
/// the auxiliary sphere with the same equations but other means, which suit vector lanes:
///  - the integrals I3 (longitude), J (reduced length, for Newton's derivative) and I4 (area)
///    over [sigma1, sigma2] by 4-point Gauss-Legendre quadrature (error ~ sigma12^9, below
///    1e-20 relative for the arcs allowed here);
///  - small angles (sigma12, omega12, alpha2 - alpha1, Newton steps) by Taylor polynomials;
///  - Newton's method on alpha1 from the spherical estimate with the mean scale
///    omega12 = lambda12 / ((1 - f) w) (1.3 evaluations per edge on average), stopped when the
///    longitude residual is below 2^-47 rad; omega12 is then taken as lambda12 plus the
///    I3 term, so the residual does not reach the area.
/// Eight edges are solved together, and GCC compiles the lanes for AVX2 too where the
/// processor has it; every lane does the same operations, so a result does not depend on the
/// other edges of its batch or on the instruction set.
///
/// Domain: after GeographicLib's canonical reflections (|lat1| >= |lat2|, lat1 < 0,
/// lon12 >= 0), 0 < lon12 <= 2.5 degrees, -89 <= lat1 and |lat1 - lat2| <= 2.5 degrees. Any
/// other edge (meridional, equatorial, long, near a pole), or one whose Newton iteration does
/// not settle, goes to GeographicLib's Geodesic::GenInverse itself.
///
/// Accuracy: against GenInverse on random edges in the domain, from 1e-9 to 2.5 degrees and
/// latitudes to 89 degrees, the difference is below 2e-14 |S12| + 1e-3 m^2
/// (tests/lonlat/ellipsoid_area_test.cpp): a few units in the last place of S12, the rounding
/// level of GeographicLib itself.
#pragma once

#include <cmath>
#include <span>

#include "geovor/core/compensated_sum.hpp"
#include "geovor/lonlat/geometry.hpp"

namespace geovor {

/// The end points of one geodesic edge (degrees; latitudes in [-90, 90], longitudes anywhere
/// in [-540, 540]: only lon2 - lon1 matters, reduced to (-180, 180]).
struct GeodesicEdge {
  double lat1_deg, lon1_deg, lat2_deg, lon2_deg;
};

/// s12_m2[i] = S12 (m^2, see the file comment) of edges[i] on WGS84, as
/// GeographicLib::Geodesic::WGS84().GenInverse(lat1, lon1, lat2, lon2, AREA, ...) gives it,
/// within the file comment's bound. Thread-safe.
/// REQUIRES: s12_m2.size() >= edges.size().
void geodesic_s12(std::span<const GeodesicEdge> edges, std::span<double> s12_m2);

/// The area of the whole WGS84 ellipsoid (m^2), GeographicLib's Geodesic::EllipsoidArea().
double wgs84_area_m2();

/// Area (m^2) on the WGS84 ellipsoid of polygons in lon/lat degrees with counter-clockwise
/// exterior rings and clockwise holes, as GeographicLib::PolygonArea(Geodesic::WGS84()) computes
/// it: the edges between consecutive positions are geodesics (for densified edges this differs
/// from the straight lon/lat segment by less than the densification tolerance, and shared edges
/// cancel exactly, so the areas of a tiling sum to the ellipsoid's area). Rings around a pole
/// through (+-180, +-90) are handled by GeographicLib. An exterior ring counter-clockwise is
/// taken as the area on its left, in [0, area of the ellipsoid); the one ring whose planar area
/// is 64800 square degrees (the whole lon/lat rectangle) counts as the whole ellipsoid.
double ellipsoid_area_m2(const MultiPolygon& polygons);

/// Signed planar area of a closed ring in (lon, lat) (square degrees), positive when
/// counter-clockwise.
double planar_area_deg2(const Ring& ring);

namespace detail {
int prime_meridian_transit_general(double lon1_deg, double lon2_deg);
}

/// PolygonArea's transit(): whether the edge lon1 -> lon2 crosses the prime meridian eastwards
/// (1), westwards (-1) or not (0). Inline: it runs once per edge of every cell.
inline int prime_meridian_transit(double lon1_deg, double lon2_deg) {
  // Off the antimeridian and less than 180 apart, AngDiff is the plain difference (same sign,
  // zero only for equal longitudes) and AngNormalize the identity: no remainder() calls.
  if (std::fabs(lon1_deg) < 180 && std::fabs(lon2_deg) < 180 && std::fabs(lon2_deg - lon1_deg) < 180) {
    const double d = lon2_deg - lon1_deg;
    return d > 0 && lon1_deg < 0 && lon2_deg >= 0 ? 1 : (d < 0 && lon1_deg >= 0 && lon2_deg < 0 ? -1 : 0);
  }
  return detail::prime_meridian_transit_general(lon1_deg, lon2_deg);
}

/// The sum of S12 over a ring's consecutive geodesics, in order, as PolygonArea's Accumulator
/// sums them.
double sum_s12(std::span<const double> s12_m2);

/// The area (m^2) of `ring` from its S12 sum and its prime-meridian crossings:
/// PolygonArea::Compute(reverse = false, sign = true) negated (counter-clockwise is positive),
/// then ellipsoid_area_m2's rule for a ring larger than half the ellipsoid (a negative area
/// with |planar_area_deg2(ring)| > 10000 square degrees is the ellipsoid minus the ring; the
/// planar area is computed only then).
double ring_area_m2(CompensatedSum s12_sum, int crossings, const Ring& ring);

}  // namespace geovor
