// The only translation unit of the library that includes CGAL: exact fallbacks of the predicates.
#include "geovor/kernel/predicates.hpp"

#include "kernel/in_sphere_filter.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mpzf.h>

#include <array>
#include <cmath>
#include <utility>

namespace geovor::kernel {
namespace {

using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;

thread_local PredicateStats g_stats;

constexpr double kEps = 0x1p-53;
// Shewchuk's orient3d error bound, also valid (looser) for the determinant of the inputs
// themselves, where no difference is rounded.
using detail::kO3dErrBound;
// |fl(sum of 3 products) - exact| <= gamma_4 * sum |products|; doubled for the difference of two.
constexpr double kDotErrBound = 8.0 * kEps;

Sign to_sign(int s) { return s > 0 ? Sign::Positive : (s < 0 ? Sign::Negative : Sign::Zero); }
Sign to_sign(CGAL::Sign s) { return to_sign(static_cast<int>(s)); }
Sign negate(Sign s) { return static_cast<Sign>(-static_cast<int>(s)); }

Epick::Point_3 P3(const Vec3& v) { return {v.x, v.y, v.z}; }

// Sorts the four points (and their lifts) by priority, smallest first (the largest perturbation);
// returns the permutation's parity (+1 or -1).
int sort_by_priority(std::array<std::uint32_t, 4> pri, const Vec3* (&pts)[4], double (&lift)[4]) {
  int parity = 1;
  for (int i = 1; i < 4; ++i) {
    for (int j = i; j > 0 && pri[j] < pri[j - 1]; --j) {
      std::swap(pri[j], pri[j - 1]);
      std::swap(pts[j], pts[j - 1]);
      std::swap(lift[j], lift[j - 1]);
      parity = -parity;
    }
  }
  return parity;
}

Sign orient_exact(const Vec3& p, const Vec3& q, const Vec3& r) {
  static const Epick::Point_3 origin(0, 0, 0);
  return to_sign(CGAL::orientation(origin, P3(p), P3(q), P3(r)));
}

// Sign of det(a, b, c) projected on coordinates (i, j): the 2D orientation of the projections.
Sign orient2d_exact(const Vec3& a, const Vec3& b, const Vec3& c, int i, int j) {
  auto pick = [](const Vec3& v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); };
  return to_sign(CGAL::orientation(Epick::Point_2(pick(a, i), pick(a, j)),
                                   Epick::Point_2(pick(b, i), pick(b, j)),
                                   Epick::Point_2(pick(c, i), pick(c, j))));
}

}  // namespace

Sign orient(const Vec3& p, const Vec3& q, const Vec3& r) noexcept {
  ++g_stats.orient_calls;
  const double qyrz = q.y * r.z, qzry = q.z * r.y;
  const double qzrx = q.z * r.x, qxrz = q.x * r.z;
  const double qxry = q.x * r.y, qyrx = q.y * r.x;
  const double det = p.x * (qyrz - qzry) + p.y * (qzrx - qxrz) + p.z * (qxry - qyrx);
  const double perm = (std::fabs(qyrz) + std::fabs(qzry)) * std::fabs(p.x) +
                      (std::fabs(qzrx) + std::fabs(qxrz)) * std::fabs(p.y) +
                      (std::fabs(qxry) + std::fabs(qyrx)) * std::fabs(p.z);
  const double bound = kO3dErrBound * perm + detail::underflow_margin(p.x, p.y, p.z);
  if (det > bound) return Sign::Positive;
  if (-det > bound) return Sign::Negative;
  ++g_stats.orient_exact;
  return orient_exact(p, q, r);
}

namespace detail {
Sign orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) noexcept {
  return to_sign(CGAL::orientation(Epick::Point_2(ax, ay), Epick::Point_2(bx, by), Epick::Point_2(cx, cy)));
}

Sign in_sphere_exact(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) noexcept {
  ++g_stats.in_sphere_exact;
  return to_sign(CGAL::orientation(P3(p), P3(q), P3(r), P3(s)));
}
}  // namespace detail

Sign in_sphere_sign(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) noexcept {
  return detail::in_sphere_filtered(p, q, r, s);
}

Sign perturbed_in_sphere(const Vec3& p, std::uint32_t ip, const Vec3& q, std::uint32_t iq,
                         const Vec3& r, std::uint32_t ir, const Vec3& s,
                         std::uint32_t is) noexcept {
  const Sign exact = in_sphere_sign(p, q, r, s);
  if (exact != Sign::Zero) return exact;
  ++g_stats.in_sphere_perturbed;

  const Vec3* pts[4] = {&p, &q, &r, &s};
  double unused[4] = {};
  const int parity = sort_by_priority({ip, iq, ir, is}, pts, unused);
  // With D(a,b,c,d) = det[[a,1],[b,1],[c,1],[d,1]], in_sphere_sign = -sign(D). Moving point k by
  // eps*v adds eps * (-1)^k * det(v, b - a, c - a), (a, b, c) the other points in order. The
  // first non-zero term in the order of the infinitesimals decides (see the header).
  auto others = [&](int k, const Vec3*& a, const Vec3*& b, const Vec3*& c) {
    const Vec3* o[3];
    for (int i = 0, n = 0; i < 4; ++i)
      if (i != k) o[n++] = pts[i];
    a = o[0], b = o[1], c = o[2];
  };
  auto finish = [&](Sign term, int k) {
    // term is the sign of D's first non-zero coefficient, for the sorted order.
    int d = static_cast<int>(term) * ((k % 2 == 0) ? 1 : -1) * parity;
    return negate(to_sign(d));
  };
  // Radial terms: with the four points coplanar, det(p_k, b - a, c - a) = det(a, b, c).
  for (int k = 0; k < 4; ++k) {
    const Vec3 *a, *b, *c;
    others(k, a, b, c);
    const Sign t = orient(*a, *b, *c);
    if (t != Sign::Zero) return finish(t, k);
  }
  // The four points lie on a plane through O: move them along z, then y, then x.
  // det(e_z, u, v) = u_x v_y - u_y v_x: the orientation of the projections on (x, y), etc.
  constexpr int kAxes[3][2] = {{0, 1}, {2, 0}, {1, 2}};
  for (const auto& axis : kAxes) {
    for (int k = 0; k < 4; ++k) {
      const Vec3 *a, *b, *c;
      others(k, a, b, c);
      const Sign t = orient2d_exact(*a, *b, *c, axis[0], axis[1]);
      if (t != Sign::Zero) return finish(t, k);
    }
  }
  return Sign::Zero;  // four points on one line: excluded by the minimum separation of sites
}

namespace {
using CGAL::Mpzf;

// The determinant of a 4x4 matrix of exact numbers (cofactors along the first row).
Mpzf det4(const std::array<std::array<Mpzf, 4>, 4>& a) {
  auto det3 = [&](int c0, int c1, int c2) {
    return a[1][c0] * (a[2][c1] * a[3][c2] - a[2][c2] * a[3][c1]) - a[1][c1] * (a[2][c0] * a[3][c2] - a[2][c2] * a[3][c0]) +
           a[1][c2] * (a[2][c0] * a[3][c1] - a[2][c1] * a[3][c0]);
  };
  return a[0][0] * det3(1, 2, 3) - a[0][1] * det3(0, 2, 3) + a[0][2] * det3(0, 1, 3) - a[0][3] * det3(0, 1, 2);
}

// E of in_sphere_weighted_filter, exactly: Mpzf holds sums and products of doubles exactly.
Sign in_sphere_weighted_exact(const Vec3& p, double cp, const Vec3& q, double cq, const Vec3& r, double cr,
                              const Vec3& s, double cs) {
  ++g_stats.in_sphere_exact;
  const Mpzf px(p.x), py(p.y), pz(p.z);
  const Mpzf bx = Mpzf(q.x) - px, by = Mpzf(q.y) - py, bz = Mpzf(q.z) - pz;
  const Mpzf cx = Mpzf(r.x) - px, cy = Mpzf(r.y) - py, cz = Mpzf(r.z) - pz;
  const Mpzf dx = Mpzf(s.x) - px, dy = Mpzf(s.y) - py, dz = Mpzf(s.z) - pz;
  const Mpzf mcp(cp), wq = Mpzf(cq) - mcp, wr = Mpzf(cr) - mcp, ws = Mpzf(cs) - mcp;
  const Mpzf cdx = cy * dz - cz * dy, cdy = cz * dx - cx * dz, cdz = cx * dy - cy * dx;
  const Mpzf dbx = dy * bz - dz * by, dby = dz * bx - dx * bz, dbz = dx * by - dy * bx;
  const Mpzf bcx = by * cz - bz * cy, bcy = bz * cx - bx * cz, bcz = bx * cy - by * cx;
  const Mpzf vol = bx * cdx + by * cdy + bz * cdz;
  const Mpzf e = mcp * vol - (px * (wq * cdx + wr * dbx + ws * bcx) + py * (wq * cdy + wr * dby + ws * bcy) +
                              pz * (wq * cdz + wr * dbz + ws * bcz));
  return to_sign(CGAL::sign(e));
}
}  // namespace

Sign in_sphere_weighted(const Vec3& p, double cp, const Vec3& q, double cq, const Vec3& r, double cr,
                        const Vec3& s, double cs) noexcept {
  const int filtered = detail::in_sphere_weighted_filter(p, cp, q, cq, r, cr, s, cs);
  if (filtered != 0) return filtered > 0 ? Sign::Positive : Sign::Negative;
  return in_sphere_weighted_exact(p, cp, q, cq, r, cr, s, cs);
}

Sign perturbed_in_sphere_weighted(const Vec3& p, double cp, std::uint32_t ip, const Vec3& q, double cq,
                                  std::uint32_t iq, const Vec3& r, double cr, std::uint32_t ir,
                                  const Vec3& s, double cs, std::uint32_t is) noexcept {
  const Sign exact = in_sphere_weighted(p, cp, q, cq, r, cr, s, cs);
  if (exact != Sign::Zero) return exact;
  ++g_stats.in_sphere_perturbed;
  // As perturbed_in_sphere, with D the determinant of the rows (p_i, c_i).
  const Vec3* pts[4] = {&p, &q, &r, &s};
  double lift[4] = {cp, cq, cr, cs};
  const int parity = sort_by_priority({ip, iq, ir, is}, pts, lift);
  auto finish = [&](Sign term, int k) {
    int d = static_cast<int>(term) * ((k % 2 == 0) ? 1 : -1) * parity;
    return negate(to_sign(d));
  };
  // Radial motion q_k (1 + e) is the row (p_k (1 + e), c_k): coefficient c_k (-1)^k det(others).
  for (int k = 0; k < 4; ++k) {
    const Vec3* o[3];
    for (int i = 0, n = 0; i < 4; ++i)
      if (i != k) o[n++] = pts[i];
    const Sign t = orient(*o[0], *o[1], *o[2]);
    if (t != Sign::Zero) return finish(t, k);
  }
  // Motion of q_k along an axis: the row (p_k + e c_k axis, c_k); coefficient c_k (-1)^k times
  // the determinant of the others' rows (coordinate i, coordinate j, c).
  constexpr int kAxes[3][2] = {{0, 1}, {2, 0}, {1, 2}};
  auto pick = [](const Vec3& v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); };
  for (const auto& axis : kAxes) {
    for (int k = 0; k < 4; ++k) {
      Vec3 o[3];
      for (int i = 0, n = 0; i < 4; ++i)
        if (i != k) o[n++] = {pick(*pts[i], axis[0]), pick(*pts[i], axis[1]), lift[i]};
      const Sign t = orient_exact(o[0], o[1], o[2]);
      if (t != Sign::Zero) return finish(t, k);
    }
  }
  // The four lifted points on one line (circles through two common points): every first-order
  // term vanishes. The infinitesimals are e_m = e t^(2^m), m = 4 family + rank, e << every power
  // of t: all first-order terms come first, then the products e_m e_n (points apart) in the order
  // of 2^m + 2^n. Their coefficient, the determinant with the two rows replaced by the motions,
  // is det(motion_m, motion_n, direction of the line) up to a positive factor: some pair of axes
  // gives a non-zero one.
  auto motion = [&](int family, int k, std::array<Mpzf, 4>& row) {
    row = {Mpzf(0.0), Mpzf(0.0), Mpzf(0.0), Mpzf(0.0)};
    if (family == 0) row = {Mpzf(pts[k]->x), Mpzf(pts[k]->y), Mpzf(pts[k]->z), Mpzf(0.0)};
    else row[3 - family] = Mpzf(lift[k]);  // z (family 1), y (2), x (3)
  };
  for (int n = 1; n < 16; ++n) {
    for (int m = 0; m < n; ++m) {
      if (m % 4 == n % 4) continue;
      std::array<std::array<Mpzf, 4>, 4> rows;
      for (int k = 0; k < 4; ++k) rows[k] = {Mpzf(pts[k]->x), Mpzf(pts[k]->y), Mpzf(pts[k]->z), Mpzf(lift[k])};
      motion(m / 4, m % 4, rows[m % 4]);
      motion(n / 4, n % 4, rows[n % 4]);
      const int d = static_cast<int>(to_sign(CGAL::sign(det4(rows))));
      if (d != 0) return negate(to_sign(d * parity));
    }
  }
  return Sign::Zero;  // two lifted points equal: excluded by the merge of sites at one position
}

Sign compare_power(const Vec3& x, const Vec3& a, double ca, const Vec3& b, double cb) noexcept {
  if (ca == cb) return compare_dot(x, a, b);
  ++g_stats.compare_dot_calls;
  // sign(cb dot(x, a) - ca dot(x, b)), both lifts positive.
  const double xa = x.x * a.x, ya = x.y * a.y, za = x.z * a.z;
  const double xb = x.x * b.x, yb = x.y * b.y, zb = x.z * b.z;
  const double diff = cb * (xa + ya + za) - ca * (xb + yb + zb);
  const double mag = cb * (std::fabs(xa) + std::fabs(ya) + std::fabs(za)) +
                     ca * (std::fabs(xb) + std::fabs(yb) + std::fabs(zb));
  // Each monomial passes through at most 5 roundings (product, two sums, weight, difference).
  const double bound = 8.0 * kEps * mag + 0x1p-1020;
  if (diff > bound) return Sign::Positive;
  if (-diff > bound) return Sign::Negative;
  ++g_stats.compare_dot_exact;
  const Mpzf e = Mpzf(cb) * (Mpzf(x.x) * Mpzf(a.x) + Mpzf(x.y) * Mpzf(a.y) + Mpzf(x.z) * Mpzf(a.z)) -
                 Mpzf(ca) * (Mpzf(x.x) * Mpzf(b.x) + Mpzf(x.y) * Mpzf(b.y) + Mpzf(x.z) * Mpzf(b.z));
  return to_sign(CGAL::sign(e));
}

Sign compare_dot(const Vec3& x, const Vec3& a, const Vec3& b) noexcept {
  ++g_stats.compare_dot_calls;
  const double xa = x.x * a.x, ya = x.y * a.y, za = x.z * a.z;
  const double xb = x.x * b.x, yb = x.y * b.y, zb = x.z * b.z;
  const double diff = (xa + ya + za) - (xb + yb + zb);
  const double mag = std::fabs(xa) + std::fabs(ya) + std::fabs(za) + std::fabs(xb) +
                     std::fabs(yb) + std::fabs(zb);
  // Six products may underflow, each by up to 2^-1075 (see detail::underflow_margin); 2^-1022,
  // a normal double, covers them without subnormal arithmetic.
  const double bound = kDotErrBound * mag + 0x1p-1022;
  if (diff > bound) return Sign::Positive;
  if (-diff > bound) return Sign::Negative;
  ++g_stats.compare_dot_exact;
  // Mpzf holds sums and products of doubles exactly.
  const CGAL::Mpzf e = CGAL::Mpzf(x.x) * (CGAL::Mpzf(a.x) - CGAL::Mpzf(b.x)) +
                       CGAL::Mpzf(x.y) * (CGAL::Mpzf(a.y) - CGAL::Mpzf(b.y)) +
                       CGAL::Mpzf(x.z) * (CGAL::Mpzf(a.z) - CGAL::Mpzf(b.z));
  return to_sign(CGAL::sign(e));
}

PredicateStats predicate_stats() noexcept { return g_stats; }
void reset_predicate_stats() noexcept { g_stats = PredicateStats{}; }

}  // namespace geovor::kernel
