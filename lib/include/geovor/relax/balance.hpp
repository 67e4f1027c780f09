/// \file balance.hpp
/// \brief Balanced power cells: the radii for which every cell's mass (its WGS84 area, or another
/// SphereMeasure) is its share of the total. The semi-discrete optimal transport problem of
/// docs/weighted.md ("Balanced cells"), solved by the damped Newton method of Kitagawa, Merigot
/// and Thibert (JEMS 2019) in psi_i = log(1 / c_i), c_i = cos(r_i / R) the lift of site i.
///
/// Each iteration: the weighted triangulation of the current lifts, its power cells, their masses
/// A_i; the sparse Hessian H_ij = dA_i / dpsi_j = - integral over the shared edge of
/// rho(x) (x . q_j) / |q_i - q_j| ds (symmetric, zero row sums: a graph Laplacian); the Newton
/// step H delta = target - A with psi of one site pinned (H is singular along the constants: the
/// cells do not change when every psi moves together); then KMT's damping: the first step 2^-l
/// with every cell's mass at least eps_0 = half the smallest of (smallest target, smallest
/// starting mass) and |A - target| <= (1 - 2^-(l+1)) |A_old - target| (Euclidean norms). The
/// damping keeps every cell non-empty, so no site is ever hidden in an accepted step. psi is then
/// shifted so that its smallest value is 0 (the smallest radius is 0, the cells unchanged).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/relax/measure.hpp"

namespace geovor {

/// How the Newton system is solved.
enum class BalanceSolver : std::uint8_t {
  Cholesky,           ///< Eigen's SimplicialLDLT (AMD ordering): exact, the default
  ConjugateGradient,  ///< Eigen's ConjugateGradient with an incomplete Cholesky preconditioner
};

/// Options of balance(); every default is documented.
struct BalanceOptions {
  /// Stop when the largest relative mass error max_i |A_i - target_i| / target_i is at most this.
  /// DEFAULT: 1e-6. REQUIRES: > 0. The masses' rounding sets a floor that depends on the sites:
  /// below 1e-9 for 200 random sites (tests), about 4e-7 for the 171,075 cities, whose pairs of sites a
  /// metre apart have a shared edge that one ulp of a radius moves by ~1e-7 of their areas; below
  /// it no step 2^-l (l <= 24) decreases the error, and balance() stops, not converged.
  double tolerance = 1e-6;
  /// Newton iterations at most. DEFAULT: 50. REQUIRES: >= 0.
  int max_iterations = 50;
  /// Threads for the cells' masses and the Hessian (0: one per core). DEFAULT: 0. The result does
  /// not depend on it.
  unsigned threads = 0;
  /// DEFAULT: BalanceSolver::Cholesky (on the 171,075 cities, CG made the first iteration
  /// 29.7 s instead of 4.9 s).
  BalanceSolver solver = BalanceSolver::Cholesky;
};

/// What one Newton iteration did.
struct BalanceIteration {
  double max_relative_error = 0;  ///< max_i |A_i - target_i| / target_i after the step
  double step = 0;                ///< the damping factor accepted, 2^-l
  std::size_t hidden = 0;         ///< hidden sites met in the rejected trial steps of the iteration
  double seconds = 0;             ///< the whole iteration
};

/// The whole run.
struct BalanceReport {
  std::vector<BalanceIteration> iterations;
  bool converged = false;           ///< the tolerance was met
  double initial_relative_error = 0; ///< max relative error of the unweighted cells
  /// Per input point: its radius r = 2 R asin(sqrt((1 - c) / 2)) in metres for c = exp(-psi)
  /// (R = SiteEncoder::kEarthRadiusM), and its lift site_lift(r): exactly the double the final
  /// cells were built with (SphericalDelaunay::build(points, lifts)), and the one a reader of
  /// the radius printed with 17 digits gets back (geo/site_weights.hpp). A point merged into
  /// another has that site's lift and radius.
  std::vector<double> lifts, radii_m;
  /// Per input point: its cell's final mass (of the site it merged into, for a merged point) and
  /// its target (normalised shares; the merged points' shares summed into their site's).
  std::vector<double> masses, targets;
};

/// The radii for which the power cell of every point has mass target_shares[i] / sum(shares) times
/// measure.total(). Starts from equal lifts (the Voronoi cells). Points closer than the merge
/// distance of `delaunay` merge as in SphericalDelaunay::build(points): the shares of the points
/// merged into a site are summed into that site's target. Fewer than two sites: nothing to solve.
/// `on_iteration`, if given, is called after every iteration.
/// @exception Error(InvalidArgument) if the sizes differ, a share is not positive and finite (naming
///   its index), or the options are invalid; as SphericalDelaunay::build for the points.
BalanceReport balance(std::span<const Vec3> points, std::span<const double> target_shares,
                      const SphereMeasure& measure, const BalanceOptions& options = {},
                      const DelaunayOptions& delaunay = {},
                      const std::function<void(const BalanceIteration&)>& on_iteration = {});

/// The triangulation of the balanced cells of `result` (balance() of the same points and
/// `delaunay` options): the distinct sites balance() solved for, with their exact lifts, so that the
/// points merge exactly as balance() merged them; `report` gets those merges (site ids as a build
/// of `points` gives them) and the hidden sites (none when converged). What `geovor balance` and
/// Python's geovor.balance write.
SphericalDelaunay balanced_triangulation(std::span<const Vec3> points, const BalanceReport& result,
                                         const DelaunayOptions& delaunay, BuildReport& report);

/// The Hessian dA_i / dpsi_j of the cells of `diagram` (a weighted or unweighted diagram of sites
/// without removed ones), as triplets (i, j, value) with i != j, each pair once with i < j, in
/// order of i; the diagonal is minus the row's sum. For tests and tools; balance() uses it.
struct HessianEntry {
  SiteId i, j;
  double value;
};
std::vector<HessianEntry> balance_hessian(const VoronoiDiagram& diagram, const SphereMeasure& measure,
                                          unsigned threads = 1);

}  // namespace geovor
