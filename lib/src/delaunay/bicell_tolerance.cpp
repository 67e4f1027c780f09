// The certified tolerance of a bi-cell, kBatch at a time as vector lanes. The bound and its proof:
// docs/delaunay.md, "The bi-cell tolerance".
#include "delaunay/bicell_lanes.hpp"

#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "geovor/delaunay/bicell_tolerance.hpp"
#include "kernel/in_sphere_filter.hpp"

namespace geovor {
namespace {

inline double vmin(double a, double b) { return b < a ? b : a; }
inline double vmax(double a, double b) { return a < b ? b : a; }

// The square of an upper bound of the largest product |u| |v| over the seven pairs of edges
// (u, v) that bound the width of the tetrahedron: two edges of each face (the face's least
// product, as 2 x area is at most the product of any two of its edges) and the three pairs of
// opposite edges. q_k bounds the squared length of edge k, in the order 01, 02, 03, 12, 13, 23.
// Its root times (1 + 2^-44) covers the roundings (each q within a relative 2^-49 of its exact
// bound, each product and the root within 2^-52). Inlined into the lanes' loop, it vectorizes.
inline double largest_product2(double q0, double q1, double q2, double q3, double q4, double q5) {
  const double f012 = vmin(vmin(q0 * q1, q0 * q3), q1 * q3);
  const double f013 = vmin(vmin(q0 * q2, q0 * q4), q2 * q4);
  const double f023 = vmin(vmin(q1 * q2, q1 * q5), q2 * q5);
  const double f123 = vmin(vmin(q3 * q4, q3 * q5), q4 * q5);
  return vmax(vmax(vmax(f012, f013), vmax(f023, f123)), vmax(vmax(q0 * q5, q1 * q4), q2 * q3));
}

// The stretch of the map T (docs/delaunay.md): 1/4 suits the nearly co-circular bi-cells, which
// set the tolerances. kInvNorm = 1/sqrt(lambda^2 + 1), rounded down.
constexpr double kLambda = 0.25;
constexpr double kInvNorm = 0.9701425001453318;

// x[i] = sqrt(x[i]) for the kBatch lanes, two at a time on x86-64 (std::sqrt's errno handling
// keeps the compiler from vectorizing the loops that call it).
inline void sqrt_lanes(double* x, std::size_t lanes) {
#if defined(__SSE2__)
  for (std::size_t i = 0; i < lanes; i += 2) _mm_storeu_pd(x + i, _mm_sqrt_pd(_mm_loadu_pd(x + i)));
#else
  for (std::size_t i = 0; i < lanes; ++i) x[i] = std::sqrt(x[i]);
#endif
}

// The lanes' function is also compiled for AVX2 (four lanes per instruction) and picked at run
// time where the processor has it (GCC on x86-64): about 8% of the late Lloyd iterations.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define GEOVOR_LANE_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define GEOVOR_LANE_CLONES
#endif

}  // namespace

GEOVOR_LANE_CLONES void bicell_tolerances(const BicellLanes& in, std::size_t n, double merge_distance,
                                          double* tau) {
  constexpr std::size_t N = kBatch;
  const std::size_t L = (n + 3) & ~std::size_t{3};  // lanes computed: n, padded to the vector width
  const auto& X = in.x;
  const auto& Y = in.y;
  const auto& Z = in.z;
  double volume6[N], l2[6][N], c2[N], cmx[N], cmy[N], cmz[N];
  for (std::size_t i = 0; i < L; ++i) {
    // 6 x the volume of the tetrahedron, |det(b - a, c - a, d - a)|, minus Shewchuk's bound of
    // its rounding (kernel::detail::in_sphere_det and underflow_margin, lane by lane).
    const double bx = X[1][i] - X[0][i], by = Y[1][i] - Y[0][i], bz = Z[1][i] - Z[0][i];
    const double cx = X[2][i] - X[0][i], cy = Y[2][i] - Y[0][i], cz = Z[2][i] - Z[0][i];
    const double dx = X[3][i] - X[0][i], dy = Y[3][i] - Y[0][i], dz = Z[3][i] - Z[0][i];
    const double cydz = cy * dz, czdy = cz * dy;
    const double czdx = cz * dx, cxdz = cx * dz;
    const double cxdy = cx * dy, cydx = cy * dx;
    const double perm = (std::fabs(cydz) + std::fabs(czdy)) * std::fabs(bx) +
                        (std::fabs(czdx) + std::fabs(cxdz)) * std::fabs(by) +
                        (std::fabs(cxdy) + std::fabs(cydx)) * std::fabs(bz);
    const double det = bx * (cydz - czdy) + by * (czdx - cxdz) + bz * (cxdy - cydx);
    volume6[i] = std::fabs(det) - kernel::detail::kO3dErrBound * perm -
                 0x1p-1022 * (1 + std::fabs(bx) + std::fabs(by) + std::fabs(bz));
    // Squared edge lengths 01, 02, 03, 12, 13, 23, each within a relative 2^-50 of the exact one.
    const double ex[3] = {X[2][i] - X[1][i], X[3][i] - X[1][i], X[3][i] - X[2][i]};
    const double ey[3] = {Y[2][i] - Y[1][i], Y[3][i] - Y[1][i], Y[3][i] - Y[2][i]};
    const double ez[3] = {Z[2][i] - Z[1][i], Z[3][i] - Z[1][i], Z[3][i] - Z[2][i]};
    l2[0][i] = (bx * bx + by * by + bz * bz) * (1 + 0x1p-49);
    l2[1][i] = (cx * cx + cy * cy + cz * cz) * (1 + 0x1p-49);
    l2[2][i] = (dx * dx + dy * dy + dz * dz) * (1 + 0x1p-49);
    for (int k = 0; k < 3; ++k) l2[3 + k][i] = (ex[k] * ex[k] + ey[k] * ey[k] + ez[k] * ez[k]) * (1 + 0x1p-49);
    cmx[i] = X[0][i] + X[1][i] + X[2][i] + X[3][i];
    cmy[i] = Y[0][i] + Y[1][i] + Y[2][i] + Y[3][i];
    cmz[i] = Z[0][i] + Z[1][i] + Z[2][i] + Z[3][i];
    c2[i] = cmx[i] * cmx[i] + cmy[i] * cmy[i] + cmz[i] * cmz[i];
  }
  double s0[N], inv_smin[N], t[4][N], root[N] = {};  // (zeroed: the compiler cannot see that L lanes are set)
  // Spread over the sphere (c2 <= 1/4): the isotropic bound does as well; the stretch's numbers
  // are computed all the same (from c2 = 1/4) and left unused.
  for (std::size_t i = 0; i < L; ++i) root[i] = vmax(c2[i], 0.25);
  sqrt_lanes(root, L);
  for (std::size_t i = 0; i < L; ++i) {
    const double r = 1 / root[i];
    const double ux = r * cmx[i], uy = r * cmy[i], uz = r * cmz[i];
    // s0: the largest sine of the angle between c and a point, |c x f| / (|c| |f|), rounded up
    // (|c|^2 and |f|^2 are within 2^-48 of 1).
    double m = 0;
    for (int j = 0; j < 4; ++j) {
      const double kx = uy * Z[j][i] - uz * Y[j][i], ky = uz * X[j][i] - ux * Z[j][i], kz = ux * Y[j][i] - uy * X[j][i];
      m = vmax(m, kx * kx + ky * ky + kz * kz);
      t[j][i] = X[j][i] * ux + Y[j][i] * uy + Z[j][i] * uz;
    }
    root[i] = m;
  }
  sqrt_lanes(root, L);
  // Every S below is at least s_min, and the bound on |T u|^2 falls as S grows: the edge
  // products at s_min bound those at any S. (Rounded up. The loops with a division have no
  // select, and the other way round: the compiler vectorizes neither mix.)
  for (std::size_t i = 0; i < L; ++i) {
    s0[i] = root[i] * (1 + 0x1p-46) + 0x1p-48;
    inv_smin[i] = vmin(s0[i], 1.0);
  }
  for (std::size_t i = 0; i < L; ++i) inv_smin[i] = (1 / inv_smin[i]) * (1 + 0x1p-51);
  double q[6][N];
  for (std::size_t i = 0; i < L; ++i) {
    // u.c for the edge f_j - f_i is t_j - t_i, t_i = f_i.c; each computed t is within 2^-49 of
    // f_i.c for the exact unit c (the computed c is within 2^-50 of it), their difference
    // within a relative 2^-52 more: 2^-47 covers it.
    const double inv = inv_smin[i] * (1 / kLambda);  // a power of two: exact
    const double dt[6] = {t[1][i] - t[0][i], t[2][i] - t[0][i], t[3][i] - t[0][i],
                          t[2][i] - t[1][i], t[3][i] - t[1][i], t[3][i] - t[2][i]};
    for (int k = 0; k < 6; ++k) {
      const double uc = (std::fabs(dt[k]) + 0x1p-47) * inv;
      q[k][i] = (l2[k][i] + uc * uc) * (1 + 0x1p-50);
    }
  }
  for (std::size_t i = 0; i < L; ++i) {
    root[i] = largest_product2(q[0][i], q[1][i], q[2][i], q[3][i], q[4][i], q[5][i]);  // its root below
  }
  sqrt_lanes(root, L);
  double K[N], cap1[N], S1[N];
  for (std::size_t i = 0; i < L; ++i) {
    // D < (6 V / (2 M) - eps) / (S sqrt(lambda^2 + 1)) = K / S keeps the sign (docs/delaunay.md).
    K[i] = (volume6[i] / (2 * (root[i] * (1 + 0x1p-44))) - 0x1p-48) * kInvNorm;
  }
  for (std::size_t i = 0; i < L; ++i) {
    // cap = min(K / S(cap1), cap1), cap1 = K / s0, has K / S(cap) >= cap (docs/delaunay.md).
    cap1[i] = vmin(K[i] * inv_smin[i], 0.5);
  }
  for (std::size_t i = 0; i < L; ++i) {
    const double k = 1 + (cap1[i] * cap1[i] / 20 + 0x1p-52);  // k(cap) grows with cap: k(cap1) bounds
    S1[i] = vmin(k * (s0[i] + k * (cap1[i] + 0x1p-49)), 1.0);
  }
  for (std::size_t i = 0; i < L; ++i) S1[i] = K[i] / S1[i];
  double half_width[N];
  for (std::size_t i = 0; i < L; ++i)
    half_width[i] = ((c2[i] > 0.25) & (K[i] > 0)) ? vmin(S1[i], cap1[i]) : 0.0;
  const double md = merge_distance * (1 + 0x1p-40);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(volume6[i] > 0)) {  // coplanar (a tie), or too close to tell
      tau[i] = 0;
      continue;
    }
    double hw = half_width[i];
    // Any motion in R^3 by less than half the width keeps the sign too: the better bound for
    // bi-cells spanning a large part of the sphere.
    if (!(c2[i] > 0.25) || s0[i] > 0.2) {
      const double M = std::sqrt(largest_product2(l2[0][i], l2[1][i], l2[2][i], l2[3][i], l2[4][i], l2[5][i]));
      hw = std::max(hw, volume6[i] / (2 * (M * (1 + 0x1p-44))));
    }
    // The shared edge a-b must stay longer than the merge distance (with room for the rounding
    // of the merge test's own chord): (|a - b| - merge) / 2, whose root is needed only when the
    // edge is short.
    const double need = 2 * hw + md;
    if (!(l2[0][i] >= need * need * (1 + 0x1p-44))) {
      const double ab2 = (X[1][i] - X[0][i]) * (X[1][i] - X[0][i]) + (Y[1][i] - Y[0][i]) * (Y[1][i] - Y[0][i]) +
                         (Z[1][i] - Z[0][i]) * (Z[1][i] - Z[0][i]);
      hw = std::min(hw, (std::sqrt(ab2) - md) / 2);
    }
    // The few roundings above are each within a relative 2^-52: a 2^-46 margin covers them all.
    const double x = hw * (1 - 0x1p-46);
    tau[i] = x > 0 ? x : 0;
  }
}


double bicell_tolerance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double merge_distance) {
  BicellLanes lanes;
  lanes.set(0, 0, a), lanes.set(0, 1, b), lanes.set(0, 2, c), lanes.set(0, 3, d);
  lanes.pad(1);
  double tau[kBatch];
  bicell_tolerances(lanes, 1, merge_distance, tau);
  return tau[0];
}

}  // namespace geovor
