#include "geovor/lonlat/ellipsoid_area.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/Math.hpp>
#include <GeographicLib/PolygonArea.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>

#include "geovor/core/assert.hpp"
#include "geovor/core/small_angle.hpp"

namespace geovor {
namespace {

// WGS84, as GeographicLib::Geodesic::WGS84() has it.
constexpr double kA = 6378137.0;
constexpr double kF = 1 / 298.257223563;
constexpr double kF1 = 1 - kF;
constexpr double kE2 = kF * (2 - kF);
constexpr double kEp2 = kE2 / (1 - kE2);
constexpr double kDegree = std::numbers::pi / 180;
// Planar area (square degrees) of the whole lon/lat rectangle.
constexpr double kWholeDeg2 = 360.0 * 180.0;

// The domain of the fast path (see the header), and Newton's stopping rule.
constexpr double kMaxLon12Deg = 2.5;
constexpr double kMaxDLatDeg = 2.5;
constexpr double kMaxAbsLatDeg = 89;
constexpr double kResidualRad = 0x1p-47;
constexpr double kMaxStepRad = kSmallAngleMax;  // the range of the small-angle polynomials
constexpr int kMaxEvaluations = 8;

// 4-point Gauss-Legendre nodes +-kNode[q] on [-1, 1] and their weights.
constexpr double kNode[2] = {0.33998104358485626480266576, 0.86113631159405257522394649};
constexpr double kWeight[2] = {0.65214515486254614262693605, 0.34785484513745385737306395};

// T(y) = (t(e'^2) - t(y)) / (e'^2 - y) of I4's integrand as a polynomial in y in [0, e'^2],
// t(x) = x + sqrt(1 + 1/x) asinh(sqrt(x)) = x + g(x); the divided difference of g's Taylor
// series, summed while e'^(2n) matters (e'^2 = 0.0067: 8 terms leave 1e-18).
constexpr int kTauTerms = 8;
// I3's integrand (2 - f) / (1 + (1 - f) sqrt(1 + y)) for y = k^2 sin^2 sigma in [0, e'^2], as a
// polynomial in y (9 terms leave 1e-20).
constexpr int kI3Terms = 9;
struct Constants {
  double c2;                // authalic radius squared: the area of the ellipsoid / (4 pi)
  double tau[kTauTerms];    // T(y) = sum tau[m] y^m
  double i3[kI3Terms];      // I3's integrand = sum i3[m] y^m
  Constants() {
    const double e = std::sqrt(kE2), b = kA * kF1;
    c2 = (kA * kA + b * b * std::atanh(e) / e) / 2;
    // g(x) = sqrt(1 + x) * asinh(sqrt x) / sqrt x: product of the two Taylor series.
    constexpr int kTerms = 16;
    double asinh_series[kTerms], sqrt_series[kTerms], g[kTerms];
    for (int k = 0; k < kTerms; ++k) {
      double central = 1;  // (2k)! / (4^k k!^2)
      for (int j = 1; j <= k; ++j) central *= (2.0 * j - 1) / (2.0 * j);
      asinh_series[k] = (k % 2 ? -1 : 1) * central / (2 * k + 1);
      double binomial = 1;  // binomial(1/2, k)
      for (int j = 0; j < k; ++j) binomial *= (0.5 - j) / (j + 1);
      sqrt_series[k] = binomial;
    }
    for (int n = 0; n < kTerms; ++n) {
      g[n] = 0;
      for (int k = 0; k <= n; ++k) g[n] += asinh_series[k] * sqrt_series[n - k];
    }
    // T(y) = 1 + sum_{n >= 1} g_n (E^n - y^n) / (E - y) = 1 + sum_n g_n sum_{m < n} E^(n-1-m) y^m.
    for (int m = 0; m < kTauTerms; ++m) {
      double sum = m == 0 ? 1 : 0;
      for (int n = kTerms - 1; n > m; --n) sum += g[n] * std::pow(kEp2, n - 1 - m);
      tau[m] = sum;
    }
    // 1 / (1 + (1 - f) sqrt(1 + y)) by dividing the power series, times 2 - f.
    double d[kI3Terms];
    for (int k = 0; k < kI3Terms; ++k) d[k] = (k == 0 ? 1 : 0) + kF1 * sqrt_series[k];
    for (int n = 0; n < kI3Terms; ++n) {
      double sum = n == 0 ? 1 : 0;
      for (int k = 1; k <= n; ++k) sum -= d[k] * i3[n - k];
      i3[n] = sum / d[0];
    }
    for (double& c : i3) c *= 2 - kF;
  }
};
const Constants& constants() {
  static const Constants c;
  return c;
}

// 1 / n! for n <= 24 (within a few ulps).
struct InverseFactorials {
  double v[25];
  constexpr InverseFactorials() : v() {
    v[0] = 1;
    for (int n = 1; n <= 24; ++n) v[n] = v[n - 1] / n;
  }
};
constexpr InverseFactorials kInverseFactorial;

// sin x and cos x for |x| <= 89 degrees by their Taylor series to x^23 and x^24 (the next terms
// are below 1e-20; with Horner's roundings, within a few 1e-16 absolute, which is all the
// latitudes need), so the lanes need no libm call.
inline double sin_lat(double x) {
  const double x2 = x * x;
  double p = -kInverseFactorial.v[23];
#pragma GCC unroll 12
  for (int n = 21; n >= 1; n -= 2) p = p * x2 + ((n / 2) % 2 ? -kInverseFactorial.v[n] : kInverseFactorial.v[n]);
  return x * p;
}
inline double cos_lat(double x) {
  const double x2 = x * x;
  double p = kInverseFactorial.v[24];
#pragma GCC unroll 12
  for (int n = 22; n >= 0; n -= 2) p = p * x2 + ((n / 2) % 2 ? -kInverseFactorial.v[n] : kInverseFactorial.v[n]);
  return p;
}

constexpr int kLanes = 8;

// One batch of up to kLanes edges, as structure of arrays (the loops over lanes vectorize).
struct Lanes {
  // Canonical edge: point 1 the more poleward, in the south; lon12 >= 0.
  double phi1[kLanes], phi2[kLanes];                           // latitudes (radians)
  double sb1[kLanes], cb1[kLanes], sb2[kLanes], cb2[kLanes];  // reduced latitudes
  double lam12[kLanes], sign[kLanes];
  // Newton's unknown alpha1 and the state of the last evaluation.
  double sa1[kLanes], ca1[kLanes];
  double sa0[kLanes], ca0[kLanes], k2[kLanes];
  double sm[kLanes], cm[kLanes], h[kLanes];  // the mid-arc sigma_m (unit) and sigma12 / 2
  double i3[kLanes];  // I3(sigma2) - I3(sigma1)
  double v[kLanes], dv[kLanes];
  bool fast[kLanes];
};

// Reduces edge i to the canonical edge of the header; false if it is outside the domain.
bool canonical(const GeodesicEdge& edge, Lanes& l, int i) {
  double lat1 = edge.lat1_deg, lat2 = edge.lat2_deg;
  // lon2 - lon1 exactly, as a rounded difference plus its error (TwoSum).
  const double a = edge.lon2_deg, b = -edge.lon1_deg;
  double d = a + b;
  const double bb = d - a;
  const double err = (a - (d - bb)) + (b - bb);
  if (d > 180) d -= 360;  // exact (Sterbenz)
  else if (d < -180) d += 360;
  double sign = 1;
  if (std::fabs(lat1) < std::fabs(lat2)) {  // reversing the edge negates S12
    std::swap(lat1, lat2);
    d = -d;
    sign = -sign;
  }
  double lam = (d + (sign > 0 ? err : -err)) * kDegree;
  if (lam < 0) {  // mirroring the longitudes negates S12
    lam = -lam;
    d = -d;
    sign = -sign;
  }
  if (lat1 > 0) {  // so does mirroring the latitudes
    lat1 = -lat1;
    lat2 = -lat2;
    sign = -sign;
  }
  if (!(d > 0 && d <= kMaxLon12Deg && lam > 0 && lat1 < 0 && lat1 >= -kMaxAbsLatDeg &&
        std::fabs(lat1 - lat2) <= kMaxDLatDeg))
    return false;
  l.phi1[i] = lat1 * kDegree, l.phi2[i] = lat2 * kDegree;
  l.lam12[i] = lam;
  l.sign[i] = sign;
  return true;
}

// lambda12(alpha1) - lambda12 and its derivative in every lane, at the lanes' alpha1; keeps
// the state the area needs. The equations are Karney's (2013), eqs. 5-8, 38, 46.
[[gnu::always_inline]] inline void evaluate(Lanes& l, const Constants& k) {
  // Polynomials in y = k^2 sin^2 sigma <= e'^2 = 0.0067 instead of square roots and divisions
  // (the lanes' throughput is that of their divisions): I3's integrand to 1e-20; for Newton's
  // derivative only, sqrt(1 + y) and y / sqrt(1 + y) to y^4 (1e-10).
  auto i3_integrand = [&k](double y) {
    double p = k.i3[kI3Terms - 1];
#pragma GCC unroll 8
    for (int m = kI3Terms - 2; m >= 0; --m) p = p * y + k.i3[m];
    return p;
  };
  auto sqrt1p = [](double y) { return 1 + y * (0.5 + y * (-1.0 / 8 + y * (1.0 / 16 - y * (5.0 / 128)))); };
  auto j_integrand = [](double y) { return y * (1 + y * (-0.5 + y * (3.0 / 8 + y * (-5.0 / 16 + y * (35.0 / 128))))); };
  for (int i = 0; i < kLanes; ++i) {
    const double sb1 = l.sb1[i], cb1 = l.cb1[i], sb2 = l.sb2[i], cb2 = l.cb2[i];
    const double sa1 = l.sa1[i], ca1 = l.ca1[i];
    const double sa0 = sa1 * cb1, ca0 = std::sqrt(ca1 * ca1 + (sa1 * sb1) * (sa1 * sb1));
    const double k2 = kEp2 * ca0 * ca0;
    // sigma and omega of point 1 (tan sigma = tan beta / cos alpha, tan omega = sin alpha0 tan sigma).
    const double x1 = ca1 * cb1;
    const double r1 = 1 / std::sqrt(sb1 * sb1 + x1 * x1);
    const double ss1 = sb1 * r1, cs1 = x1 * r1;
    // cos alpha2 cos beta2 from Clairaut's relation (>= 0 for the canonical edge), in the
    // better conditioned of its two forms.
    const double dc2_cos = (cb2 - cb1) * (cb1 + cb2), dc2_sin = (sb1 - sb2) * (sb1 + sb2);
    const double dc2 = cb1 < -sb1 ? dc2_cos : dc2_sin;  // both computed: a select vectorizes
    const double x2 = std::sqrt(x1 * x1 + dc2);
    const double r2 = 1 / std::sqrt(sb2 * sb2 + x2 * x2);
    const double ss2 = sb2 * r2, cs2 = x2 * r2;
    const double sig12 = atan_small((cs1 * ss2 - ss1 * cs2) / (cs1 * cs2 + ss1 * ss2));
    const double omg12 = atan_small((x1 * sa0 * sb2 - sa0 * sb1 * x2) / (x1 * x2 + sa0 * sa0 * sb1 * sb2));
    // Quadrature around the mid-arc sigma_m (the unit bisector of sigma1 and sigma2).
    const double ms = ss1 + ss2, mc = cs1 + cs2, rm = 1 / std::sqrt(ms * ms + mc * mc);
    const double sm = ms * rm, cm = mc * rm, h = sig12 / 2;
    double i3 = 0, j = 0;
#pragma GCC unroll 2
    for (int q = 0; q < 2; ++q) {
      const double u = h * kNode[q], su = sin_small(u), cu = cos_small(u);
      const double sa = sm * cu + cm * su, sb = sm * cu - cm * su;  // sin(sigma_m +- u)
      const double ya = k2 * sa * sa, yb = k2 * sb * sb;
      i3 += kWeight[q] * (i3_integrand(ya) + i3_integrand(yb));
      j += kWeight[q] * (j_integrand(ya) + j_integrand(yb));
    }
    i3 *= h;
    j *= h;
    l.v[i] = omg12 - kF * sa0 * i3 - l.lam12[i];
    // d lambda12 / d alpha1 = m12 / (a cos alpha2 cos beta2), m12 / b the reduced length.
    const double m12b = sqrt1p(k2 * ss2 * ss2) * cs1 * ss2 - sqrt1p(k2 * ss1 * ss1) * ss1 * cs2 - cs1 * cs2 * j;
    l.dv[i] = m12b * kF1 / x2;
    l.sa0[i] = sa0, l.ca0[i] = ca0, l.k2[i] = k2;
    l.sm[i] = sm, l.cm[i] = cm, l.h[i] = h;
    l.i3[i] = i3;
  }
}

// S12 of the lanes marked fast (the others keep their value); the lanes are filled.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default")))
#endif
void solve(Lanes& l, double* s12) {
  const Constants& k = constants();
  // Reduced latitudes: tan beta = (1 - f) tan phi.
  for (int i = 0; i < kLanes; ++i) {
    const double s1 = kF1 * sin_lat(l.phi1[i]), c1 = cos_lat(l.phi1[i]);
    const double s2 = kF1 * sin_lat(l.phi2[i]), c2 = cos_lat(l.phi2[i]);
    const double r1 = 1 / std::sqrt(s1 * s1 + c1 * c1), r2 = 1 / std::sqrt(s2 * s2 + c2 * c2);
    l.sb1[i] = s1 * r1, l.cb1[i] = c1 * r1, l.sb2[i] = s2 * r2, l.cb2[i] = c2 * r2;
  }
  // Start: the great circle on the auxiliary sphere, its longitude scaled by the mean
  // (1 - f) sqrt(1 + e'^2 sin^2 beta).
  for (int i = 0; i < kLanes; ++i) {
    const double sb1 = l.sb1[i], cb1 = l.cb1[i], sb2 = l.sb2[i], cb2 = l.cb2[i];
    const double w = kF1 * (std::sqrt(1 + kEp2 * sb1 * sb1) + std::sqrt(1 + kEp2 * sb2 * sb2)) / 2;
    const double omg = l.lam12[i] / w, so = sin_small(omg), co = cos_small(omg);
    const double sa = cb2 * so, ca = (sb2 * cb1 - cb2 * sb1) + sb1 * cb2 * so * so / (1 + co);
    const double r = 1 / std::sqrt(sa * sa + ca * ca);
    l.sa1[i] = sa * r, l.ca1[i] = ca * r;
  }
  bool done[kLanes] = {};
  for (int n = 0;; ++n) {
    evaluate(l, k);
    bool all = true;
    for (int i = 0; i < kLanes; ++i) {
      done[i] = done[i] || !l.fast[i] || std::fabs(l.v[i]) <= kResidualRad;
      all = all && done[i];
    }
    if (all) break;
    if (n + 1 == kMaxEvaluations) {
      for (int i = 0; i < kLanes; ++i) l.fast[i] = l.fast[i] && done[i];
      break;
    }
    double step[kLanes];
    for (int i = 0; i < kLanes; ++i) step[i] = -l.v[i] / l.dv[i];
    for (int i = 0; i < kLanes; ++i) {
      if (done[i]) continue;
      if (!(std::fabs(step[i]) < kMaxStepRad)) {  // also NaN: not for this method
        l.fast[i] = false;
        done[i] = true;
        continue;
      }
      const double sd = sin_small(step[i]), cd = cos_small(step[i]);
      const double sa = l.sa1[i] * cd + l.ca1[i] * sd, ca = l.ca1[i] * cd - l.sa1[i] * sd;
      const double r = 1 / std::sqrt(sa * sa + ca * ca);
      l.sa1[i] = sa * r, l.ca1[i] = ca * r;
      if (!(l.sa1[i] > 0)) l.fast[i] = false, done[i] = true;
    }
  }
  // The area, from the last evaluation (at the lane's converged alpha1).
  for (int i = 0; i < kLanes; ++i) {
    const double sb1 = l.sb1[i], cb1 = l.cb1[i], sb2 = l.sb2[i], cb2 = l.cb2[i];
    // omega12 = lambda12 + f sin(alpha0) I3 at the solution (free of the residual).
    const double omg12 = l.lam12[i] + kF * l.sa0[i] * l.i3[i];
    const double so = sin_small(omg12), co = cos_small(omg12);
    // alpha2 - alpha1: the excess of the triangle (pole, point 1, point 2) on the auxiliary
    // sphere, tan(E/2) = tan(omega12/2) (tan(b1/2) + tan(b2/2)) / (1 + tan(b1/2) tan(b2/2)).
    const double e12 = 2 * atan_small((so * (sb1 * (1 + cb2) + sb2 * (1 + cb1))) /
                                      ((1 + co) * (sb1 * sb2 + (1 + cb1) * (1 + cb2))));
    const double sm = l.sm[i], cm = l.cm[i], h = l.h[i], k2 = l.k2[i];
    double i4 = 0;
#pragma GCC unroll 2
    for (int q = 0; q < 2; ++q) {
      const double u = h * kNode[q], su = sin_small(u), cu = cos_small(u);
      const double sa = sm * cu + cm * su, sb = sm * cu - cm * su;
      const double ya = k2 * sa * sa, yb = k2 * sb * sb;
      double ta = k.tau[kTauTerms - 1], tb = ta;
      for (int m = kTauTerms - 2; m >= 0; --m) ta = ta * ya + k.tau[m], tb = tb * yb + k.tau[m];
      i4 += kWeight[q] * (ta * sa + tb * sb);
    }
    i4 *= -h / 2;  // I4(sigma2) - I4(sigma1) = -int T(k^2 sin^2) sin / 2
    const double area = l.sign[i] * (k.c2 * e12 + kE2 * kA * kA * l.ca0[i] * l.sa0[i] * i4);
    s12[i] = area;
  }
}

}  // namespace

void geodesic_s12(std::span<const GeodesicEdge> edges, std::span<double> s12_m2) {
  GEOVOR_ASSERT(s12_m2.size() >= edges.size());
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  Lanes l;
  for (std::size_t begin = 0; begin < edges.size(); begin += kLanes) {
    const int n = static_cast<int>(std::min<std::size_t>(kLanes, edges.size() - begin));
    int filler = -1;  // a fast lane whose inputs fill the unused lanes (finite numbers)
    for (int i = 0; i < kLanes; ++i) {
      l.fast[i] = i < n && canonical(edges[begin + i], l, i);
      if (l.fast[i] && filler < 0) filler = i;
    }
    if (filler >= 0) {
      for (int i = 0; i < kLanes; ++i) {
        if (l.fast[i]) continue;
        l.phi1[i] = l.phi1[filler], l.phi2[i] = l.phi2[filler];
        l.lam12[i] = l.lam12[filler], l.sign[i] = 0;
      }
      double out[kLanes];
      solve(l, out);
      for (int i = 0; i < n; ++i)
        if (l.fast[i]) s12_m2[begin + i] = out[i];
    }
    for (int i = 0; i < n; ++i) {
      if (l.fast[i]) continue;
      const GeodesicEdge& e = edges[begin + i];
      double s12, t, area;
      geod.GenInverse(e.lat1_deg, e.lon1_deg, e.lat2_deg, e.lon2_deg, GeographicLib::Geodesic::AREA, s12, t, t, t, t,
                      t, area);
      s12_m2[begin + i] = area;
    }
  }
}

namespace detail {

// The antimeridian or long edges: GeographicLib's own arithmetic.
int prime_meridian_transit_general(double lon1, double lon2) {
  using GeographicLib::Math;
  const double lon12 = Math::AngDiff(lon1, lon2);
  lon1 = Math::AngNormalize(lon1);
  lon2 = Math::AngNormalize(lon2);
  return lon12 > 0 && ((lon1 < 0 && lon2 >= 0) || (lon1 > 0 && lon2 == 0)) ? 1
         : (lon12 < 0 && lon1 >= 0 && lon2 < 0 ? -1 : 0);
}

}  // namespace detail

double wgs84_area_m2() { return GeographicLib::Geodesic::WGS84().EllipsoidArea(); }

double sum_s12(std::span<const double> s12) {
  if (s12.empty()) return 0;
  if (s12.size() == 1) return s12[0];  // the Accumulator's value for one term
  CompensatedSum acc;
  for (const double x : s12) acc += x;
  return acc();
}

double ring_area_m2(CompensatedSum sum, int crossings, const Ring& ring) {
  const double whole = GeographicLib::Geodesic::WGS84().EllipsoidArea();
  sum.remainder(whole);
  if (crossings & 1) sum += (sum < 0 ? 1 : -1) * whole / 2;
  sum *= -1;  // counter-clockwise
  if (sum > whole / 2)
    sum -= whole;
  else if (sum <= -whole / 2)
    sum += whole;
  double area = 0 + sum();
  if (area < 0 && std::fabs(planar_area_deg2(ring)) > 10000) area += whole;
  return area;
}

double planar_area_deg2(const Ring& ring) {
  if (ring.size() < 4) return 0;
  const double x0 = ring[0].lon_deg, y0 = ring[0].lat_deg;
  double twice = 0;
  for (std::size_t i = 1; i + 1 < ring.size(); ++i) {
    const double x1 = ring[i].lon_deg - x0, y1 = ring[i].lat_deg - y0;
    const double x2 = ring[i + 1].lon_deg - x0, y2 = ring[i + 1].lat_deg - y0;
    twice += x1 * y2 - x2 * y1;
  }
  return twice / 2;
}

double ellipsoid_area_m2(const MultiPolygon& polygons) {
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  const double whole = geod.EllipsoidArea();
  // Signed area on the left of a ring, in (-whole/2, whole/2] from GeographicLib; a ring whose
  // lon/lat area is large is a polygon larger than half the ellipsoid, not a negative sliver.
  auto ring_area = [&](const Ring& ring, bool reverse) {
    const double planar = std::fabs(planar_area_deg2(ring));
    if (planar >= kWholeDeg2 * (1 - 1e-12)) return whole;
    GeographicLib::PolygonArea pa(geod);
    for (std::size_t i = 0; i + 1 < ring.size(); ++i) pa.AddPoint(ring[i].lat_deg, ring[i].lon_deg);
    double perimeter = 0, area = 0;
    pa.Compute(reverse, true, perimeter, area);
    // A polygon of more than half the ellipsoid has more than 2 pi rad^2 = 20626 deg^2 in lon/lat.
    if (area < 0 && planar > 10000) area += whole;
    return area;
  };
  double total = 0;
  for (const Polygon& poly : polygons) {
    total += ring_area(poly.exterior, false);
    for (const Ring& h : poly.holes) total -= ring_area(h, true);
  }
  return total;
}

}  // namespace geovor
