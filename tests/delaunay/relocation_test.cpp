// SphericalDelaunay::move()/move_all(): after any sequence of moves the triangulation validates
// exactly and equals a fresh build of the final positions; the filter's tolerance is certified.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/kernel/predicates.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

using Tri = std::array<SiteId, 3>;

// The triangle set, each triple rotated to start at its smallest id, sorted.
std::vector<Tri> triangle_set(const SphericalDelaunay& dt) {
  std::vector<Tri> out;
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    Tri x{dt.tri_site(t, 0), dt.tri_site(t, 1), dt.tri_site(t, 2)};
    std::rotate(x.begin(), std::min_element(x.begin(), x.end()), x.end());
    out.push_back(x);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// validate() passes and the triangles are those of a fresh build of the current positions.
void expect_as_rebuilt(const SphericalDelaunay& dt, const std::string& what) {
  const Validation v = dt.validate();
  ASSERT_TRUE(v.ok()) << what << ": " << v.errors.front();
  std::vector<Vec3> pts(dt.sites().begin(), dt.sites().end());
  BuildReport rep;
  const SphericalDelaunay fresh = SphericalDelaunay::build(pts, dt.options(), &rep);
  ASSERT_TRUE(rep.merges.empty()) << what;
  EXPECT_EQ(triangle_set(dt), triangle_set(fresh)) << what;
}

Vec3 unit(const Vec3& p) { return testing::normalized(p); }

// p displaced by a random tangent step of chord length about `step`.
Vec3 jitter(const Vec3& p, double step, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  const Vec3 r{g(rng), g(rng), g(rng)};
  return unit(p + (step / std::sqrt(3.0)) * r);
}

TEST(Relocation, SmallMediumLargeMovesOfRandomSites) {
  auto pts = testing::uniform_on_sphere(2000, 11);
  SphericalDelaunay dt = SphericalDelaunay::build(pts);
  std::mt19937_64 rng(3);
  for (const double step : {1e-5, 1e-3, 3e-2, 1.0}) {
    std::vector<Vec3> target(dt.sites().begin(), dt.sites().end());
    for (Vec3& p : target) p = jitter(p, step, rng);
    const MoveStats st = dt.move_all(target);
    EXPECT_EQ(st.moved, st.filtered + st.flipped + st.reinserted);
    EXPECT_EQ(st.moved + st.refused, target.size());
    expect_as_rebuilt(dt, "step " + std::to_string(step));
  }
}

}  // namespace
}  // namespace geovor
