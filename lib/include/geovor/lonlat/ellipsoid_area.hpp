/// \file geodesic_area.hpp
/// \brief The area term S12 of many short WGS84 geodesics at once: what
/// GeographicLib::PolygonArea sums over a ring's edges, computed about five times faster for
/// the short edges of densified Voronoi cells.
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
/// (tests/geo/geodesic_area_test.cpp): a few units in the last place of S12, the rounding
/// level of GeographicLib itself.
#pragma once

#include <span>

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

}  // namespace geovor
