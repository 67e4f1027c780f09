// The balance solver: convergence on random, unequal, clustered and polar sites; the final cells
// recomputed independently (a fresh build from the reported lifts, and a brute-force grid of the
// sphere given to the largest power); the Hessian against central differences of the masses;
// input validation and merged points.
#include "geovor/relax/balance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

constexpr double kPi = std::numbers::pi;

// The masses of the cells of points with lifts, from scratch.
std::vector<double> masses(const std::vector<Vec3>& points, const std::vector<double>& lifts, const SphereMeasure& m) {
  const VoronoiDiagram vd(SphericalDelaunay::build(points, lifts));
  std::vector<double> out(points.size());
  for (SiteId s = 0; s < points.size(); ++s) out[s] = m.cell_mass(vd, s);
  return out;
}

// Solves, then checks the report and a fresh recomputation of every cell against its target.
BalanceReport solve_and_check(const std::vector<Vec3>& points, const std::vector<double>& shares,
                              const SphereMeasure& m, double tolerance, int max_iterations) {
  BalanceOptions options;
  options.tolerance = tolerance;
  const BalanceReport r = balance(points, shares, m, options);
  EXPECT_TRUE(r.converged);
  EXPECT_LE(static_cast<int>(r.iterations.size()), max_iterations);
  double share_sum = 0;
  for (const double s : shares) share_sum += s;
  const std::vector<double> fresh = masses(points, r.lifts, m);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double target = shares[i] / share_sum * m.total();
    EXPECT_NEAR(r.targets[i], target, 1e-13 * target);
    EXPECT_NEAR(fresh[i], target, tolerance * target) << i;
    EXPECT_EQ(fresh[i], r.masses[i]) << i;
    EXPECT_GT(r.lifts[i], 0);
    EXPECT_LE(r.lifts[i], 1);
    EXPECT_EQ(std::cos(r.radii_m[i] / SiteEncoder::kEarthRadiusM), r.lifts[i]);
  }
  // Rejected trial steps may hide sites (BalanceIteration::hidden); accepted ones never do.
  const SphericalDelaunay final_dt = SphericalDelaunay::build(points, r.lifts);
  for (SiteId s = 0; s < final_dt.site_capacity(); ++s) EXPECT_FALSE(final_dt.is_hidden(s)) << s;
  std::string trace;
  for (const BalanceIteration& it : r.iterations)
    trace += " " + std::to_string(it.max_relative_error) + " (step " + std::to_string(it.step) + ")";
  std::printf("%zu sites, %zu iterations:%s\n", points.size(), r.iterations.size(), trace.c_str());
  return r;
}

TEST(Balance, EqualSharesConvergeQuickly) {
  const EllipsoidAreaMeasure m;
  const std::vector<Vec3> points = testing::uniform_on_sphere(200, 1);
  const BalanceReport r = solve_and_check(points, std::vector<double>(200, 1.0), m, 1e-9, 14);
  EXPECT_GT(r.initial_relative_error, 0.1);
  // The smallest radius is 0.
  double smallest = 1e300;
  for (const double x : r.radii_m) smallest = std::min(smallest, x);
  EXPECT_EQ(smallest, 0);
}

TEST(Balance, UnequalShares) {
  const EllipsoidAreaMeasure m;
  const std::vector<Vec3> points = testing::uniform_on_sphere(150, 2);
  std::vector<double> shares;
  for (std::size_t i = 0; i < points.size(); ++i) shares.push_back(1 + 9.0 * static_cast<double>(i % 10) / 9);
  solve_and_check(points, shares, m, 1e-9, 25);
}

// 40 sites in one region 0.2 rad across among 100 spread ones: the cluster's cells reach far out.
// (Equal shares for sites all in one hemisphere have no solution: the sites of any set J can
// hold at most the mass of the union of their hemispheres, docs/weighted.md.)
TEST(Balance, ClusteredSites) {
  const EllipsoidAreaMeasure m;
  std::vector<Vec3> points = testing::clustered(40, 1, 0.1, 4);
  for (const Vec3& p : testing::uniform_on_sphere(100, 8)) points.push_back(p);
  solve_and_check(points, std::vector<double>(points.size(), 1.0), m, 1e-9, 40);
}

TEST(Balance, SitesNearThePoles) {
  const EllipsoidAreaMeasure m;
  std::vector<Vec3> points;
  for (int i = 0; i < 40; ++i) {
    const double lat = (i % 2 ? 1 : -1) * (85.0 + 4.9 * std::fabs(std::sin(i * 1.3)));
    points.push_back(SiteEncoder::from_lat_lon(lat, std::fmod(i * 47.0 + 540, 360) - 180));
  }
  points.push_back({0, 0, 1});
  for (const Vec3& p : testing::uniform_on_sphere(60, 6)) points.push_back(p);
  solve_and_check(points, std::vector<double>(points.size(), 1.0), m, 1e-9, 40);
}

// On the unit sphere the masses are areas; a grid of the sphere, each point given to the site of
// largest x . p / c by brute force, checks the cells (and so the sign conventions) without the
// triangulation.
TEST(Balance, BruteForceAreasOnTheSphere) {
  const EllipsoidAreaMeasure sphere(1, 0);
  const std::vector<Vec3> points = testing::uniform_on_sphere(24, 3);
  std::vector<double> shares;
  for (std::size_t i = 0; i < points.size(); ++i) shares.push_back(1 + static_cast<double>(i % 4));
  BalanceOptions options;
  options.tolerance = 1e-10;
  const BalanceReport r = balance(points, shares, sphere, options);
  ASSERT_TRUE(r.converged);
  std::vector<double> area(points.size(), 0.0);
  const int n_lat = 600, n_lon = 1200;
  for (int i = 0; i < n_lat; ++i) {
    const double lat = -kPi / 2 + (i + 0.5) * kPi / n_lat;
    const double da = std::cos(lat) * (kPi / n_lat) * (2 * kPi / n_lon);
    for (int j = 0; j < n_lon; ++j) {
      const double lon = -kPi + (j + 0.5) * 2 * kPi / n_lon;
      const Vec3 x{std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
      std::size_t best = 0;
      for (std::size_t k = 1; k < points.size(); ++k)
        if (dot(x, points[k]) / r.lifts[k] > dot(x, points[best]) / r.lifts[best]) best = k;
      area[best] += da;
    }
  }
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_NEAR(area[i], r.targets[i], 3e-3 * r.targets[i]) << i;
}

TEST(Balance, HessianMatchesCentralDifferences) {
  const EllipsoidAreaMeasure m;
  const std::vector<Vec3> points = testing::uniform_on_sphere(40, 12);
  std::vector<double> psi(points.size());
  for (std::size_t i = 0; i < psi.size(); ++i) psi[i] = 0.01 + 0.05 * static_cast<double>((i * 7) % 11);  // radii to 2,000 km
  auto lifts_of = [](const std::vector<double>& p) {
    std::vector<double> c(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) c[i] = std::exp(-p[i]);
    return c;
  };
  const VoronoiDiagram vd(SphericalDelaunay::build(points, lifts_of(psi)));
  const std::size_t n = points.size();
  std::vector<double> h(n * n, 0.0);
  for (const HessianEntry& e : balance_hessian(vd, m)) {
    ASSERT_LT(e.i, e.j);
    EXPECT_LE(e.value, 0);
    h[e.i * n + e.j] = h[e.j * n + e.i] = e.value;
    h[e.i * n + e.i] -= e.value;
    h[e.j * n + e.j] -= e.value;
  }
  const double step = 1e-5;
  for (std::size_t j = 0; j < n; ++j) {
    std::vector<double> up = psi, down = psi;
    up[j] += step;
    down[j] -= step;
    const std::vector<double> a = masses(points, lifts_of(up), m), b = masses(points, lifts_of(down), m);
    double scale = 0;
    for (std::size_t i = 0; i < n; ++i) scale = std::max(scale, std::fabs(h[i * n + j]));
    for (std::size_t i = 0; i < n; ++i)
      EXPECT_NEAR((a[i] - b[i]) / (2 * step), h[i * n + j], 1e-6 * scale) << i << ", " << j;
  }
}

TEST(Balance, OneIterationIsNotEnough) {
  const EllipsoidAreaMeasure m;
  BalanceOptions options;
  options.max_iterations = 1;
  const std::vector<Vec3> points = testing::uniform_on_sphere(100, 5);
  const BalanceReport r = balance(points, std::vector<double>(100, 1.0), m, options);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.iterations.size(), 1u);
  EXPECT_LT(r.iterations[0].max_relative_error, r.initial_relative_error);
}

TEST(Balance, InvalidInput) {
  const EllipsoidAreaMeasure m;
  const std::vector<Vec3> points = testing::uniform_on_sphere(10, 5);
  std::vector<double> shares(10, 1.0);
  EXPECT_THROW(balance(points, std::vector<double>(9, 1.0), m), Error);
  for (const double bad : std::vector<double>{0.0, -1.0, std::nan(""), INFINITY}) {
    shares[3] = bad;
    try {
      balance(points, shares, m);
      ADD_FAILURE() << bad;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
      EXPECT_NE(std::string(e.what()).find("share 3"), std::string::npos) << e.what();
    }
  }
  shares[3] = 1;
  BalanceOptions options;
  options.tolerance = 0;
  EXPECT_THROW(balance(points, shares, m, options), Error);
}

TEST(Balance, MergedPointsPoolTheirShares) {
  const EllipsoidAreaMeasure m;
  std::vector<Vec3> points = testing::uniform_on_sphere(30, 9);
  points.push_back(points[4]);  // a duplicate of point 4
  std::vector<double> shares(points.size(), 1.0);
  BalanceOptions options;
  options.tolerance = 1e-9;
  const BalanceReport r = balance(points, shares, m, options);
  ASSERT_TRUE(r.converged);
  EXPECT_EQ(r.lifts[30], r.lifts[4]);
  EXPECT_NEAR(r.targets[4], 2 * m.total() / 31, 1e-12 * m.total());
  EXPECT_NEAR(r.masses[4], r.targets[4], 1e-9 * r.targets[4]);
}

TEST(Balance, FewSites) {
  const EllipsoidAreaMeasure m;
  const BalanceReport one = balance(testing::uniform_on_sphere(1, 1), std::vector<double>{2.0}, m);
  EXPECT_TRUE(one.converged);
  EXPECT_EQ(one.lifts[0], 1);
  BalanceOptions options;
  options.tolerance = 1e-10;
  // Two sites: the cells are two hemispheres whatever the radii (their bisector plane passes
  // through the centre), of equal area by the ellipsoid's central symmetry.
  const BalanceReport two = balance(testing::uniform_on_sphere(2, 1), std::vector<double>{1.0, 1.0}, m, options);
  EXPECT_TRUE(two.converged);
  EXPECT_TRUE(two.iterations.empty());
  EXPECT_FALSE(balance(testing::uniform_on_sphere(2, 1), std::vector<double>{1.0, 3.0}, m, options).converged);
}

}  // namespace
}  // namespace geovor
