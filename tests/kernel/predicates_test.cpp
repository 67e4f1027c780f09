// Tests of the exact predicates against independent exact arithmetic (CGAL::Gmpq), including the
// symbolic perturbation, checked against an actual small perturbation of the points.
#include "geovor/kernel/predicates.hpp"

#include <CGAL/Gmpq.h>
#include <CGAL/Gmpz.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "kernel/in_sphere_filter.hpp"
#include "support/generators.hpp"

namespace geovor::kernel {
namespace {

using Q = CGAL::Gmpq;

int sgn(const Q& q) { return q > 0 ? 1 : (q < 0 ? -1 : 0); }
int sgn(Sign s) { return static_cast<int>(s); }

Q det3(const std::array<Q, 3>& a, const std::array<Q, 3>& b, const std::array<Q, 3>& c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
         a[2] * (b[0] * c[1] - b[1] * c[0]);
}
std::array<Q, 3> q3(const Vec3& v) { return {Q(v.x), Q(v.y), Q(v.z)}; }
std::array<Q, 3> sub(const std::array<Q, 3>& a, const std::array<Q, 3>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

// CGAL convention: orientation(p, q, r, s) = sign det(q - p, r - p, s - p).
int exact_in_sphere(const std::array<Q, 3>& p, const std::array<Q, 3>& q,
                    const std::array<Q, 3>& r, const std::array<Q, 3>& s) {
  return sgn(det3(sub(q, p), sub(r, p), sub(s, p)));
}

// 2^-k as an exact rational.
Q pow2neg(int k) { return Q(CGAL::Gmpz(1), CGAL::Gmpz(1) << k); }

// The perturbation of the header, with concrete infinitesimals: family f (radial, z, y, x) and
// rank r (0 = smallest priority) move by eps^(2^(4f + r)) with eps = 2^-24, so each term
// dominates every later one and every product.
int perturbed_oracle(const std::array<Vec3, 4>& pts, const std::array<std::uint32_t, 4>& prio) {
  std::array<int, 4> rank{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) rank[i] += prio[j] < prio[i];
  std::array<std::array<Q, 3>, 4> moved;
  for (int i = 0; i < 4; ++i) {
    auto p = q3(pts[i]);
    const Q er = pow2neg(24 << (0 + rank[i]));
    const Q ez = pow2neg(24 << (4 + rank[i]));
    const Q ey = pow2neg(24 << (8 + rank[i]));
    const Q ex = pow2neg(24 << (12 + rank[i]));
    moved[i] = {p[0] + p[0] * er + ex, p[1] + p[1] * er + ey, p[2] + p[2] * er + ez};
  }
  return exact_in_sphere(moved[0], moved[1], moved[2], moved[3]);
}

TEST(Predicates, OrientAndInSphereMatchExactOnRandomAndNearDegenerateInput) {
  std::mt19937_64 rng(7);
  const auto pts = testing::uniform_on_sphere(400, 3);
  int zero_in_sphere = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Vec3 p = pts[rng() % pts.size()], q = pts[rng() % pts.size()], r = pts[rng() % pts.size()];
    Vec3 s = pts[rng() % pts.size()];
    if (trial % 2) {
      // Make s nearly coplanar with p, q, r: an affine combination, rounded.
      const double a = (rng() % 1000) / 1000.0, b = (rng() % 1000) / 1000.0;
      s = p + a * (q - p) + b * (r - p);
      if (trial % 4 == 1) s.x = std::nextafter(s.x, 2.0);
    }
    EXPECT_EQ(sgn(orient(p, q, r)), sgn(det3(q3(p), q3(q), q3(r))));
    const int expected = exact_in_sphere(q3(p), q3(q), q3(r), q3(s));
    EXPECT_EQ(sgn(in_sphere_sign(p, q, r, s)), expected);
    zero_in_sphere += expected == 0;
  }
  EXPECT_GT(zero_in_sphere, 0);  // the test did reach exact ties
}

// Subnormal coordinates: the floating-point products underflow, so the filters' relative error
// bounds alone certify wrong signs (found by fuzzing the triangulation: four sites nearly on the
// great circle y = 0, one with y = -2^-1072, gave an in-sphere sign that changed under a cyclic
// rotation). Every predicate must agree with exact rationals here.
TEST(Predicates, SubnormalCoordinatesMatchExact) {
  const std::array<Vec3, 4> fuzzed = {Vec3{-0x1.ecaddd3bdc6abp-2, -0x0.0000000000004p-1022, 0x1.c0d8074fb322p-1},
                                      Vec3{-0x1p+0, 0x0p+0, 0x0p+0},
                                      Vec3{-0x1.f9b84717e03fcp-5, 0x0p+0, -0x1.ff0600d41ef4bp-1},
                                      Vec3{0x0p+0, 0x0p+0, -0x1p+0}};
  std::mt19937_64 rng(11);
  std::vector<std::array<Vec3, 4>> cases = {fuzzed};
  const auto pts = testing::uniform_on_sphere(64, 5);
  for (int trial = 0; trial < 4000; ++trial) {
    // Points on the plane y = 0 (or x, z), some moved off it by a few subnormal steps.
    std::array<Vec3, 4> c;
    const int axis = trial % 3;
    for (auto& p : c) {
      p = pts[rng() % pts.size()];
      double* coord[3] = {&p.x, &p.y, &p.z};
      *coord[axis] = (rng() % 3 == 0) ? std::ldexp(double(int(rng() % 9) - 4), -1074) : 0.0;
    }
    cases.push_back(c);
  }
  for (const auto& c : cases) {
    const auto q = [&](int i) { return q3(c[static_cast<std::size_t>(i)]); };
    // Every cyclic rotation of the first three, and against the exact determinant.
    for (int rot = 0; rot < 3; ++rot) {
      const int a = rot, b = (rot + 1) % 3, d = (rot + 2) % 3;
      EXPECT_EQ(sgn(in_sphere_sign(c[a], c[b], c[d], c[3])), exact_in_sphere(q(a), q(b), q(d), q(3)));
      EXPECT_EQ(sgn(orient(c[a], c[b], c[d])), sgn(det3(q(a), q(b), q(d))));
    }
    const Q dot_diff = q(0)[0] * (q(1)[0] - q(2)[0]) + q(0)[1] * (q(1)[1] - q(2)[1]) + q(0)[2] * (q(1)[2] - q(2)[2]);
    EXPECT_EQ(sgn(compare_dot(c[0], c[1], c[2])), sgn(dot_diff));
  }
}

// Four coplanar points with integer coordinates, no three collinear, in every kind of plane.
std::array<Vec3, 4> coplanar_quad(std::mt19937_64& rng, int kind) {
  auto ri = [&](int lo, int hi) { return double(lo + int(rng() % unsigned(hi - lo + 1))); };
  for (;;) {
    Vec3 o{0, 0, 0}, u, v;
    switch (kind) {
      case 0: o = {ri(-5, 5), ri(-5, 5), ri(1, 5)}; [[fallthrough]];  // plane missing O
      case 1: u = {ri(-4, 4), ri(-4, 4), ri(-4, 4)}; v = {ri(-4, 4), ri(-4, 4), ri(-4, 4)}; break;
      case 2: u = {1, 0, 0}; v = {0, 1, 0}; break;                  // z = 0
      case 3: u = {1, 1, 0}; v = {0, 0, 1}; break;                  // x = y, holds e_z
      default: u = {0, 1, 0}; v = {0, 0, 1}; break;                 // x = 0, holds e_z and e_y
    }
    std::array<Vec3, 4> q;
    for (auto& p : q) p = o + ri(-3, 3) * u + ri(-3, 3) * v;
    bool ok = norm2(cross(u, v)) > 0;
    for (int i = 0; i < 4 && ok; ++i)
      for (int j = i + 1; j < 4 && ok; ++j)
        for (int k = j + 1; k < 4 && ok; ++k) ok = norm2(cross(q[j] - q[i], q[k] - q[i])) > 0;
    if (kind == 0) ok = ok && det3(q3(q[0]), q3(q[1]), q3(q[2])) != 0;
    if (ok) return q;
  }
}

TEST(Predicates, PerturbationIsTheSignOfAnActualSmallMotion) {
  std::mt19937_64 rng(11);
  for (int kind = 0; kind < 5; ++kind) {
    for (int trial = 0; trial < 60; ++trial) {
      const auto q = coplanar_quad(rng, kind);
      std::array<std::uint32_t, 4> prio;
      for (auto& x : prio) x = static_cast<std::uint32_t>(rng() % 1000);
      if (prio[0] == prio[1] || prio[0] == prio[2] || prio[0] == prio[3] || prio[1] == prio[2] ||
          prio[1] == prio[3] || prio[2] == prio[3])
        continue;
      ASSERT_EQ(in_sphere_sign(q[0], q[1], q[2], q[3]), Sign::Zero);
      const Sign got = perturbed_in_sphere(q[0], prio[0], q[1], prio[1], q[2], prio[2], q[3], prio[3]);
      ASSERT_NE(got, Sign::Zero);
      EXPECT_EQ(sgn(got), perturbed_oracle(q, prio)) << "kind " << kind << " trial " << trial;
    }
  }
}

TEST(Predicates, PerturbationObeysThePermutationAxiom) {
  // Cube corners: co-circular quadruples on small circles; swapping two arguments negates.
  const auto c = testing::cube_corners();
  for (std::uint32_t a = 0; a < 8; ++a)
    for (std::uint32_t b = 0; b < 8; ++b)
      for (std::uint32_t d = 0; d < 8; ++d)
        for (std::uint32_t e = 0; e < 8; ++e) {
          if (a == b || a == d || a == e || b == d || b == e || d == e) continue;
          const Sign s1 = perturbed_in_sphere(c[a], a, c[b], b, c[d], d, c[e], e);
          const Sign s2 = perturbed_in_sphere(c[b], b, c[a], a, c[d], d, c[e], e);
          const Sign s3 = perturbed_in_sphere(c[b], b, c[d], d, c[a], a, c[e], e);
          ASSERT_NE(s1, Sign::Zero);
          EXPECT_EQ(sgn(s1), -sgn(s2));
          EXPECT_EQ(sgn(s1), sgn(s3));
        }
}

TEST(Predicates, CompareDotMatchesExact) {
  std::mt19937_64 rng(5);
  const auto pts = testing::uniform_on_sphere(300, 9);
  int ties = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec3 x = pts[rng() % pts.size()];
    Vec3 a = pts[rng() % pts.size()];
    Vec3 b = pts[rng() % pts.size()];
    if (trial % 3 == 0) b = {a.y, a.x, a.z};           // tie when x.x == x.y... rarely
    if (trial % 3 == 1) b = {-a.x, a.y, a.z}, a = {a.x, a.y, a.z};
    const auto xq = q3(x), aq = q3(a), bq = q3(b);
    const Q exact = xq[0] * (aq[0] - bq[0]) + xq[1] * (aq[1] - bq[1]) + xq[2] * (aq[2] - bq[2]);
    EXPECT_EQ(sgn(compare_dot(x, a, b)), sgn(exact));
    ties += sgn(exact) == 0;
  }
  // Exact ties: x on the bisector plane of a and b.
  const Vec3 a{0.6, 0.8, 0}, b{0.8, 0.6, 0}, x{0.5, 0.5, std::sqrt(0.5)};
  EXPECT_EQ(compare_dot(x, a, b), Sign::Zero);
  EXPECT_GE(ties, 0);
}

TEST(Predicates, StatsCountTheExactStage) {
  reset_predicate_stats();
  const Vec3 p{1, 0, 0}, q{0, 1, 0}, r{-1, 0, 0}, s{0, -1, 0};
  EXPECT_EQ(in_sphere_sign(p, q, r, s), Sign::Zero);
  const auto st = predicate_stats();
  EXPECT_EQ(st.in_sphere_exact, 1u);
}

}  // namespace
}  // namespace geovor::kernel

namespace geovor::kernel {
namespace {

// The lifted point p / c as an exact rational.
std::array<Q, 3> lifted(const Vec3& p, double c) { return {Q(p.x) / Q(c), Q(p.y) / Q(c), Q(p.z) / Q(c)}; }

// perturbed_oracle on the lifted points: radial motion q (1 + er), then the axis motions.
int perturbed_weighted_oracle(const std::array<Vec3, 4>& pts, const std::array<double, 4>& c,
                              const std::array<std::uint32_t, 4>& prio) {
  std::array<int, 4> rank{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) rank[i] += prio[j] < prio[i];
  std::array<std::array<Q, 3>, 4> moved;
  for (int i = 0; i < 4; ++i) {
    auto p = lifted(pts[i], c[i]);
    const Q er = pow2neg(24 << (0 + rank[i]));
    const Q ez = pow2neg(24 << (4 + rank[i]));
    const Q ey = pow2neg(24 << (8 + rank[i]));
    const Q ex = pow2neg(24 << (12 + rank[i]));
    moved[i] = {p[0] + p[0] * er + ex, p[1] + p[1] * er + ey, p[2] + p[2] * er + ez};
  }
  return exact_in_sphere(moved[0], moved[1], moved[2], moved[3]);
}

TEST(WeightedPredicates, InSphereMatchesTheExactLiftedOrientation) {
  std::mt19937_64 rng(21);
  const auto pts = testing::uniform_on_sphere(200, 4);
  const auto near = testing::clustered(200, 3, 1e-7, 5);  // nearly degenerate: tiny triangles
  std::uniform_real_distribution<double> radius(0.0, 1.5);
  int decided_by_exact_stage = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const auto& set = trial % 2 ? near : pts;
    std::array<Vec3, 4> p;
    std::array<double, 4> c;
    for (int i = 0; i < 4; ++i) {
      p[i] = set[rng() % set.size()];
      // Equal lifts, lifts one ulp apart, and random ones.
      c[i] = trial % 3 == 0 ? 0.75 : (trial % 3 == 1 ? std::nextafter(0.75, i % 2 ? 1.0 : 0.0) : std::cos(radius(rng)));
    }
    const int exact = exact_in_sphere(lifted(p[0], c[0]), lifted(p[1], c[1]), lifted(p[2], c[2]), lifted(p[3], c[3]));
    reset_predicate_stats();
    ASSERT_EQ(sgn(in_sphere_weighted(p[0], c[0], p[1], c[1], p[2], c[2], p[3], c[3])), exact) << trial;
    decided_by_exact_stage += predicate_stats().in_sphere_exact > 0;
    if (c[0] == c[1] && c[1] == c[2] && c[2] == c[3]) EXPECT_EQ(exact, sgn(in_sphere_sign(p[0], p[1], p[2], p[3])));
  }
  EXPECT_GT(decided_by_exact_stage, 0);  // the filter's bound is exercised
}

// The build's static filter on rounded lifted points (kernel/in_sphere_filter.hpp): whenever it
// decides, it gives the exact sign; on lifted points exactly coplanar (circles through one point)
// it never decides.
TEST(WeightedPredicates, LiftedStaticFilterIsExactWhenItDecides) {
  std::mt19937_64 rng(23);
  const auto pts = testing::uniform_on_sphere(300, 6);
  const auto near = testing::clustered(300, 3, 1e-4, 7);
  std::uniform_real_distribution<double> radius(0.0, 1.5707963);
  int decided = 0, undecided = 0;
  for (int trial = 0; trial < 30000; ++trial) {
    const auto& set = trial % 2 ? near : pts;
    std::array<Vec3, 4> p;
    std::array<double, 4> c;
    const Vec3 x = set[rng() % set.size()];
    for (int i = 0; i < 4; ++i) {
      p[i] = set[rng() % set.size()];
      switch (trial % 4) {
        case 0: c[i] = std::cos(radius(rng)); break;                      // any radius up to the limit
        case 1: c[i] = std::cos(1e-4 * radius(rng)); break;               // small radii
        case 2: c[i] = dot(p[i], x) > 1e-3 ? dot(p[i], x) : 0.5; break;  // circles through x: coplanar
        default: c[i] = std::nextafter(0.75, i % 2 ? 1.0 : 0.0);          // lifts one ulp apart
      }
    }
    double smallest = 1;
    std::array<Vec3, 4> l;
    for (int i = 0; i < 4; ++i) {
      l[i] = {p[i].x / c[i], p[i].y / c[i], p[i].z / c[i]};
      smallest = std::min(smallest, c[i]);
    }
    const int got = detail::in_sphere_lifted_static(l[0], l[1], l[2], l[3],
                                                     detail::lifted_static_bound((1 + 0x1p-39) / smallest));
    if (got == 0) {
      ++undecided;
      continue;
    }
    ++decided;
    const int exact = exact_in_sphere(lifted(p[0], c[0]), lifted(p[1], c[1]), lifted(p[2], c[2]), lifted(p[3], c[3]));
    ASSERT_EQ(got, exact) << trial;
    ASSERT_EQ(got, sgn(in_sphere_weighted(p[0], c[0], p[1], c[1], p[2], c[2], p[3], c[3]))) << trial;
  }
  EXPECT_GT(decided, 10000);
  EXPECT_GT(undecided, 100);
}

TEST(WeightedPredicates, PerturbationIsTheSignOfAnActualSmallMotionOfTheLiftedPoints) {
  std::mt19937_64 rng(12);
  const auto circle = testing::on_great_circle(40, 3);  // every quad on a plane through O: axis terms
  const auto cube = testing::cube_corners();            // co-circular with equal lifts: radial terms
  std::uniform_real_distribution<double> radius(0.0, 1.0);
  int checked = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const bool on_circle = trial % 2 == 0;
    std::array<Vec3, 4> p;
    std::array<double, 4> c;
    std::array<std::uint32_t, 4> prio;
    const double common = std::cos(radius(rng));
    for (int i = 0; i < 4; ++i) {
      const std::uint32_t k = static_cast<std::uint32_t>(rng() % (on_circle ? circle.size() : cube.size()));
      p[i] = on_circle ? circle[k] : cube[k];
      c[i] = on_circle ? std::cos(radius(rng)) : common;
      prio[i] = k;
    }
    if (prio[0] == prio[1] || prio[0] == prio[2] || prio[0] == prio[3] || prio[1] == prio[2] ||
        prio[1] == prio[3] || prio[2] == prio[3])
      continue;
    if (in_sphere_weighted(p[0], c[0], p[1], c[1], p[2], c[2], p[3], c[3]) != Sign::Zero) continue;
    const Sign got = perturbed_in_sphere_weighted(p[0], c[0], prio[0], p[1], c[1], prio[1], p[2], c[2], prio[2],
                                                  p[3], c[3], prio[3]);
    ASSERT_NE(got, Sign::Zero);
    EXPECT_EQ(sgn(got), perturbed_weighted_oracle(p, c, prio)) << trial;
    if (!on_circle)  // equal lifts break ties as the unweighted test does
      EXPECT_EQ(got, perturbed_in_sphere(p[0], prio[0], p[1], prio[1], p[2], prio[2], p[3], prio[3]));
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

TEST(WeightedPredicates, ComparePowerMatchesExact) {
  std::mt19937_64 rng(6);
  const auto pts = testing::uniform_on_sphere(300, 10);
  std::uniform_real_distribution<double> radius(0.0, 1.5);
  for (int trial = 0; trial < 20000; ++trial) {
    const Vec3 x = pts[rng() % pts.size()], a = pts[rng() % pts.size()];
    Vec3 b = pts[rng() % pts.size()];
    const double ca = std::cos(radius(rng));
    double cb = std::cos(radius(rng));
    if (trial % 4 == 0) b = a, cb = ca;  // an exact tie
    const auto xq = q3(x), aq = lifted(a, ca), bq = lifted(b, cb);
    const Q exact = xq[0] * (aq[0] - bq[0]) + xq[1] * (aq[1] - bq[1]) + xq[2] * (aq[2] - bq[2]);
    ASSERT_EQ(sgn(compare_power(x, a, ca, b, cb)), sgn(exact)) << trial;
  }
}

}  // namespace
}  // namespace geovor::kernel

namespace geovor::kernel {
namespace {

// The weighted perturbation's second stage with concrete infinitesimals e_m = e t^(2^m),
// m = 4 family + rank, t = 2^-2 and e = t^(2^16) 2^-64 (smaller than every first-order term's
// ratio to a second-order one): the exact sign of the moved lifted points.
int collinear_oracle(const std::array<Vec3, 4>& pts, const std::array<double, 4>& c,
                     const std::array<std::uint32_t, 4>& prio) {
  std::array<int, 4> rank{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) rank[i] += prio[j] < prio[i];
  const Q e = pow2neg(2 << 16) * pow2neg(64);
  auto em = [&](int m) { return e * pow2neg(2 << m); };  // e t^(2^m), t = 2^-2
  std::array<std::array<Q, 3>, 4> moved;
  for (int i = 0; i < 4; ++i) {
    const auto q = lifted(pts[i], c[i]);
    const Q er = em(0 + rank[i]), ez = em(4 + rank[i]), ey = em(8 + rank[i]), ex = em(12 + rank[i]);
    moved[i] = {q[0] + q[0] * er + ex, q[1] + q[1] * er + ey, q[2] + q[2] * er + ez};
  }
  return exact_in_sphere(moved[0], moved[1], moved[2], moved[3]);
}

TEST(WeightedPredicates, CollinearLiftedPointsAreDecidedBySecondOrderTerms) {
  // Sites on the equator at longitude l with radius |l|: the lifted points (1, tan l, 0) are
  // collinear (cos l / cos |l| is exactly 1), so every first-order term vanishes.
  std::mt19937_64 rng(3);
  int checked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::array<Vec3, 4> p;
    std::array<double, 4> c;
    std::array<std::uint32_t, 4> prio;
    std::set<int> used;
    for (int i = 0; i < 4; ++i) {
      int k;
      do k = static_cast<int>(rng() % 17) - 8; while (!used.insert(k).second);
      const double l = 0.15 * k;
      p[i] = {std::cos(l), std::sin(l), 0};
      c[i] = std::cos(std::fabs(l));
      prio[i] = static_cast<std::uint32_t>(k + 8);
    }
    ASSERT_EQ(in_sphere_weighted(p[0], c[0], p[1], c[1], p[2], c[2], p[3], c[3]), Sign::Zero);
    const Sign got = perturbed_in_sphere_weighted(p[0], c[0], prio[0], p[1], c[1], prio[1], p[2], c[2], prio[2],
                                                  p[3], c[3], prio[3]);
    ASSERT_NE(got, Sign::Zero) << trial;
    EXPECT_EQ(sgn(got), collinear_oracle(p, c, prio)) << trial;
    // An odd permutation negates it.
    EXPECT_EQ(perturbed_in_sphere_weighted(p[1], c[1], prio[1], p[0], c[0], prio[0], p[2], c[2], prio[2], p[3], c[3],
                                           prio[3]),
              got == Sign::Positive ? Sign::Negative : Sign::Positive);
    ++checked;
  }
  EXPECT_EQ(checked, 40);
}

}  // namespace
}  // namespace geovor::kernel
