// Private to the library: the in-sphere filter, inline so that the triangulation's hot loop does
// not pay a call. The library is compiled with -ffp-contract=off: the error bound assumes every
// product and sum is rounded on its own, so this header must not reach code built otherwise.
#pragma once

#include <cmath>

#include "geovor/kernel/predicates.hpp"

namespace geovor::kernel::detail {

/// Shewchuk's orient3d bound (7 + 56 eps) eps, eps = 2^-53, times the permanent.
inline constexpr double kO3dErrBound = (7.0 + 56.0 * 0x1p-53) * 0x1p-53;

/// The exact stage (CGAL), out of line: reached only when the filter cannot decide.
Sign in_sphere_exact(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) noexcept;

/// Static bound for points whose coordinates are at most 1 + 2^-40 in magnitude (unit vectors):
/// the differences are below 2.0001, each product of two below 4.0005, so the permanent is below
/// 3 * 2 * 4.0005 * 2.0001 < 48.01, and Shewchuk's bound below (7 + 56 eps) eps * 48.01 < 3.8e-14.
inline constexpr double kUnitStaticBound = 3.8e-14;

/// det(q - p, r - p, s - p) in doubles and, when perm is not null, the permanent of its terms
/// (the same expression with absolute values), which scales Shewchuk's error bound.
inline double in_sphere_det(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s, double* perm) noexcept {
  const double bx = q.x - p.x, by = q.y - p.y, bz = q.z - p.z;
  const double cx = r.x - p.x, cy = r.y - p.y, cz = r.z - p.z;
  const double dx = s.x - p.x, dy = s.y - p.y, dz = s.z - p.z;
  const double cydz = cy * dz, czdy = cz * dy;
  const double czdx = cz * dx, cxdz = cx * dz;
  const double cxdy = cx * dy, cydx = cy * dx;
  if (perm)
    *perm = (std::fabs(cydz) + std::fabs(czdy)) * std::fabs(bx) +
            (std::fabs(czdx) + std::fabs(cxdz)) * std::fabs(by) +
            (std::fabs(cxdy) + std::fabs(cydx)) * std::fabs(bz);
  return bx * (cydz - czdy) + by * (czdx - cxdz) + bz * (cxdy - cydx);
}

/// Shewchuk's bounds assume no underflow. A product that underflows is off by up to 2^-1075 in
/// absolute terms, and reaches the determinant multiplied by at most 1 + |bx| + |by| + |bz| (the
/// outer factors): a margin of 2^-1070 times that covers every such error with room to spare.
/// (Found by fuzzing: sites with a subnormal coordinate made the relative bound vanish.)
/// The margin used is 2^-1022 (the least normal double) times that, larger still: arithmetic on
/// subnormals takes a microcode assist of ~100 cycles on x86, which 2^-1070 x paid on every call
/// (a third of the relocation's time in Lloyd's late iterations). Only determinants below
/// ~1e-307 see the difference: they go to the exact stage, whose sign is the same.
inline double underflow_margin(double ax, double ay, double az) noexcept {
  return 0x1p-1022 * (1 + std::fabs(ax) + std::fabs(ay) + std::fabs(az));
}

/// The filter alone: +1 or -1 when the double evaluation is certified, 0 when it cannot decide.
inline int in_sphere_filter_only(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) noexcept {
  double perm;
  const double det = in_sphere_det(p, q, r, s, &perm);
  const double bound = kO3dErrBound * perm + underflow_margin(q.x - p.x, q.y - p.y, q.z - p.z);
  return (det > bound) - (-det > bound);
}

/// The filter for unit vectors: the static bound decides every test but the nearly degenerate
/// without computing the permanent; those go to the semi-static filter.
/// REQUIRES: every coordinate of p, q, r, s at most 1 + 2^-40 in magnitude.
inline int in_sphere_unit_filter(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) noexcept {
  const double det = in_sphere_det(p, q, r, s, nullptr);
  if (det > kUnitStaticBound) return 1;
  if (det < -kUnitStaticBound) return -1;
  return in_sphere_filter_only(p, q, r, s);
}

/// The weighted filter (rows (p_i, c_i), docs/weighted.md): with B = q - p, C = r - p, D = s - p
/// and w = c - cp, the sign of -det of the rows is that of
///   E = cp det(B, C, D) - p . (wq (C x D) + wr (D x B) + ws (B x C)),
/// E for equal lifts being cp times in_sphere_det. +1 or -1 when certified, 0 when not: no
/// monomial of E passes through more than 12 roundings (3 in the differences, 2 in a cross
/// product, 1 in a weight's product, 2 in the sum of three vectors, 3 in the dot product, 1 in
/// the final difference), so |error| <= gamma_12 of the permanent; 16 eps covers that and the
/// permanent's own rounding.
/// REQUIRES: every coordinate at most 1 + 2^-40 in magnitude, every lift in (0, 1].
inline constexpr double kWeightedErrBound = 16.0 * 0x1p-53;
inline constexpr double kWeightedStaticBound = 1.6e-13;  // kWeightedErrBound * 89.6, rounded up
inline int in_sphere_weighted_filter(const Vec3& p, double cp, const Vec3& q, double cq, const Vec3& r, double cr,
                                     const Vec3& s, double cs) noexcept {
  const double bx = q.x - p.x, by = q.y - p.y, bz = q.z - p.z;
  const double cx = r.x - p.x, cy = r.y - p.y, cz = r.z - p.z;
  const double dx = s.x - p.x, dy = s.y - p.y, dz = s.z - p.z;
  const double wq = cq - cp, wr = cr - cp, ws = cs - cp;
  // C x D, D x B, B x C and their permanents (absolute values of the products).
  const double cdx = cy * dz - cz * dy, cdy = cz * dx - cx * dz, cdz = cx * dy - cy * dx;
  const double dbx = dy * bz - dz * by, dby = dz * bx - dx * bz, dbz = dx * by - dy * bx;
  const double bcx = by * cz - bz * cy, bcy = bz * cx - bx * cz, bcz = bx * cy - by * cx;
  const double pcdx = std::fabs(cy * dz) + std::fabs(cz * dy), pcdy = std::fabs(cz * dx) + std::fabs(cx * dz),
               pcdz = std::fabs(cx * dy) + std::fabs(cy * dx);
  const double pdbx = std::fabs(dy * bz) + std::fabs(dz * by), pdby = std::fabs(dz * bx) + std::fabs(dx * bz),
               pdbz = std::fabs(dx * by) + std::fabs(dy * bx);
  const double pbcx = std::fabs(by * cz) + std::fabs(bz * cy), pbcy = std::fabs(bz * cx) + std::fabs(bx * cz),
               pbcz = std::fabs(bx * cy) + std::fabs(by * cx);
  const double vol = bx * cdx + by * cdy + bz * cdz;
  const double vx = wq * cdx + wr * dbx + ws * bcx, vy = wq * cdy + wr * dby + ws * bcy,
               vz = wq * cdz + wr * dbz + ws * bcz;
  const double e = cp * vol - (p.x * vx + p.y * vy + p.z * vz);
  // Static first: unit vectors and lifts in (0, 1] bound the permanent by 89.6 (differences
  // below 2.0001, the cross products' permanents below 8.0008; 48.01 + sqrt(3) 24.003).
  if (e > kWeightedStaticBound) return 1;
  if (e < -kWeightedStaticBound) return -1;
  const double awq = std::fabs(wq), awr = std::fabs(wr), aws = std::fabs(ws);
  const double perm =
      cp * (std::fabs(bx) * pcdx + std::fabs(by) * pcdy + std::fabs(bz) * pcdz) +
      std::fabs(p.x) * (awq * pcdx + awr * pdbx + aws * pbcx) + std::fabs(p.y) * (awq * pcdy + awr * pdby + aws * pbcy) +
      std::fabs(p.z) * (awq * pcdz + awr * pdbz + aws * pbcz);
  // Products that underflow: at most 2^-1075 each, times factors below 3 (see underflow_margin).
  const double bound = kWeightedErrBound * perm + 0x1p-1000;
  return (e > bound) - (-e > bound);
}

inline Sign in_sphere_filtered(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) noexcept {
  const int filtered = in_sphere_filter_only(p, q, r, s);
  if (filtered != 0) return filtered > 0 ? Sign::Positive : Sign::Negative;
  return in_sphere_exact(p, q, r, s);
}

/// The weighted test on the lifted points, a static filter ahead of in_sphere_weighted_filter:
/// sign(E) is the sign of det(Q_q - Q_p, Q_r - Q_p, Q_s - Q_p) of the exact lifted points
/// Q_i = p_i / c_i (E / (c_p c_q c_r c_s), by the scaling of the rows). Given the lifted points
/// rounded once per coordinate (lq_i = fl(p_i / c_i), within u M of Q_i) and M bounding every
/// coordinate of both, the computed determinant is within 5.2e-14 M^3 of the exact one:
/// Shewchuk's bound on a permanent below 48.01 M^3 (3.73e-14 M^3), plus, by multilinearity,
/// three terms |det(dB, C, D)| <= sqrt(3) 2uM (sqrt(3) 2M)^2 for the rounding (1.39e-14 M^3) and
/// terms of order u^2. lifted_static_bound(M) rounds that up; +1 or -1 when certified, 0 when not.
inline double lifted_static_bound(double m) noexcept { return 6e-14 * (m * m * m); }
inline int in_sphere_lifted_static(const Vec3& lp, const Vec3& lq, const Vec3& lr, const Vec3& ls, double bound) noexcept {
  const double det = in_sphere_det(lp, lq, lr, ls, nullptr);
  return (det > bound) - (-det > bound);
}

}  // namespace geovor::kernel::detail
