/// \file predicates.hpp
/// \brief Exact predicates on points of R^3 given as doubles, for triangulations on the sphere.
///
/// Every function here takes its double arguments as exact rational numbers and returns the exact
/// sign. Each is a cascade: a floating-point evaluation with a certified static error bound
/// (Shewchuk's bounds, "Adaptive precision floating-point arithmetic", 1997, plus an absolute
/// margin for products that underflow, which his relative bounds assume away), and when the bound
/// cannot decide, CGAL's Exact_predicates_inexact_constructions_kernel (interval filter, then GMP).
/// No CGAL or GMP type appears in this header; only lib/src/kernel/ sees CGAL.
///
/// Axioms (for points p, q, r, s that are pairwise distinct):
///  1. orient(p, q, r) == -orient(q, p, r); cyclic rotation keeps the sign.
///  2. in_sphere_sign(p, q, r, s) changes sign under any odd permutation of its arguments.
///  3. perturbed_in_sphere never returns Zero for four distinct sites of which no three are
///     collinear in R^3 (guaranteed on the sphere by the minimum separation of
///     delaunay/spherical_delaunay.hpp), and is the sign of an actual infinitesimal motion of the
///     points, so all its answers are mutually consistent.
#pragma once

#include <cstdint>

#include "geovor/core/types.hpp"

namespace geovor::kernel {

/// Orientation on the sphere: sign of det(p, q, r) = orientation_3(O, p, q, r), O the centre.
/// Positive when r lies to the left of the great circle from p to q (seen from outside).
Sign orient(const Vec3& p, const Vec3& q, const Vec3& r) noexcept;

/// Side of the plane (p, q, r) on which s lies: CGAL's orientation_3(p, q, r, s) = sign of
/// det(q - p, r - p, s - p). For a triangle (p, q, r) of the triangulation seen counter-clockwise
/// from outside the sphere, Positive means s is beyond the triangle's plane: s lies inside the
/// triangle's circumcircle on the sphere ("in conflict"), thesis §3.2-3.3.
Sign in_sphere_sign(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) noexcept;

/// The in-circle test with ties broken by a consistent symbolic perturbation.
///
/// Each point i is moved to p_i (1 + e_i) + f_i z + g_i y + h_i x, where e, f, g, h are
/// infinitesimals with e_* >> f_* >> g_* >> h_*, and within one family the point with the smaller
/// priority value moves more. The radial terms e are a perturbation of the weights of the regular
/// triangulation (thesis Ch. 3): they decide four co-circular sites on a small circle, as the
/// lifting map would. When the four sites lie on one great circle (coplanar with O), radial motion
/// keeps them coplanar, and the axis terms decide. The returned sign is that of
/// in_sphere_sign on the moved points, for every small enough perturbation.
///
/// \param ip..is the priorities (site indices) of p..s; they must be pairwise distinct.
Sign perturbed_in_sphere(const Vec3& p, std::uint32_t ip, const Vec3& q, std::uint32_t iq,
                         const Vec3& r, std::uint32_t ir, const Vec3& s,
                         std::uint32_t is) noexcept;

/// Sign of dot(x, a) - dot(x, b): Positive when the unit vector a is nearer to x than b is in the
/// order of the triangulation (the hull's normal fan); for unit vectors, the angular order.
Sign compare_dot(const Vec3& x, const Vec3& a, const Vec3& b) noexcept;

/// \name Weighted sites (docs/weighted.md)
/// A weighted site is the homogeneous point (p, c) of R^4: its unit vector p and its lift
/// c = cos(r / R) in (0, 1], r its radius; it stands for the lifted point q = p / c of R^3.
/// Unweighted sites have c = 1 exactly. Every c is taken as the exact double it is.
///@{

/// in_sphere_sign of the lifted points: Positive when q_s lies beyond the plane of q_p, q_q, q_r
/// (oriented as in_sphere_sign), i.e. the sign of -det[[p, cp], [q, cq], [r, cr], [s, cs]].
/// Equal lifts give in_sphere_sign(p, q, r, s) (the determinant is then cp times it).
/// REQUIRES: every lift in (0, 1], every point a unit vector (|coordinate| <= 1 + 2^-40).
Sign in_sphere_weighted(const Vec3& p, double cp, const Vec3& q, double cq, const Vec3& r, double cr,
                        const Vec3& s, double cs) noexcept;

/// in_sphere_weighted with ties broken by the symbolic perturbation of perturbed_in_sphere applied
/// to the lifted points (radial motion q_i (1 + e_i), then the axis motions): the first-order
/// coefficients are those of the unweighted test times positive lifts (radial terms) or the
/// orientations of the rows (x, y, c), (z, x, c), (y, z, c) (axis terms), so equal lifts break
/// every tie as perturbed_in_sphere does. Four lifted points on one line (circles through two
/// common points) are decided by the products of two points' motions (docs/weighted.md).
/// Zero only for two equal lifted points.
Sign perturbed_in_sphere_weighted(const Vec3& p, double cp, std::uint32_t ip, const Vec3& q, double cq,
                                  std::uint32_t iq, const Vec3& r, double cr, std::uint32_t ir,
                                  const Vec3& s, double cs, std::uint32_t is) noexcept;

/// Sign of dot(x, a) / ca - dot(x, b) / cb: Positive when x has the larger power with respect to
/// the weighted site (a, ca), i.e. lies on its side of the power bisector (the order of the power
/// diagram). compare_dot when ca == cb. REQUIRES: ca, cb > 0.
Sign compare_power(const Vec3& x, const Vec3& a, double ca, const Vec3& b, double cb) noexcept;
///@}

namespace detail {
Sign orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) noexcept;
}  // namespace detail

/// Planar orientation of (a, b, c), points of the plane given as (x, y) doubles (lon/lat degrees
/// of written geometry): Positive when c lies to the left of the line from a to b, i.e. a, b, c
/// turn counter-clockwise; Zero when collinear (or two are equal). Exact: Shewchuk's orient2d
/// bound (ccwerrboundA, the differences' rounding included) with a margin for underflow, inline;
/// then CGAL's exact Orientation_2.
inline Sign orient2d(double ax, double ay, double bx, double by, double cx, double cy) noexcept {
  const double l = (ax - cx) * (by - cy), r = (ay - cy) * (bx - cx);
  const double det = l - r;
  const double bound = (3.0 + 16.0 * 0x1p-53) * 0x1p-53 * (__builtin_fabs(l) + __builtin_fabs(r)) + 0x1p-1000;
  if (det > bound) return Sign::Positive;
  if (-det > bound) return Sign::Negative;
  return detail::orient2d_exact(ax, ay, bx, by, cx, cy);
}

/// Counters of how often each stage of the cascade decided (geogram's predicate stats). The
/// in-sphere filter inlined into the triangulation is not counted, only its exact and perturbed
/// stages.
struct PredicateStats {
  std::uint64_t orient_calls = 0, orient_exact = 0;
  std::uint64_t in_sphere_exact = 0, in_sphere_perturbed = 0;
  std::uint64_t compare_dot_calls = 0, compare_dot_exact = 0;
};

/// The counters of this thread since the last reset. Counting costs one increment per call.
PredicateStats predicate_stats() noexcept;
void reset_predicate_stats() noexcept;

}  // namespace geovor::kernel
