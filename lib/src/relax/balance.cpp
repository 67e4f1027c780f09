#include "geovor/relax/balance.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_weights.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace geovor {
namespace {

using Clock = std::chrono::steady_clock;
using SparseMatrix = Eigen::SparseMatrix<double>;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double radius_of_lift(double c) {
  // 1 - c is exact for c >= 1/2, where acos(c) would lose half the digits.
  return 2 * SiteEncoder::kEarthRadiusM * std::asin(std::sqrt(std::max(0.0, 0.5 * (1 - c))));
}

// Lifts below e^-30 (radii within 0.6 mm of a quarter circumference) would make the power
// vertices products of underflowing terms; no balanced configuration needs them.
constexpr double kMaxPsi = 30;

// Steps halved more often than this mean the masses' rounding dominates the decrease: two sites a
// metre apart have a shared edge that one ulp of a radius moves by ~1e-7 of their areas (the
// 171,075 cities stall near 4e-7). The cities' damped phase needed 2^-13 at most.
constexpr int kMaxHalvings = 24;

// The cells of one psi: the triangulation of the lifts, its diagram and the masses.
struct State {
  std::vector<double> psi, radii_m, lifts, mass;
  VoronoiDiagram diagram;
  std::size_t hidden = 0;
  double norm = 0, max_relative = 0, min_mass = 0;
};

// Evaluates psi (shifted so that its smallest value is 0) into `state`. False if the lifts
// would underflow.
bool evaluate(std::span<const Vec3> sites, std::vector<double> psi, std::span<const double> target,
              const SphereMeasure& measure, const DelaunayOptions& delaunay, unsigned threads, State& state) {
  const double lo = *std::min_element(psi.begin(), psi.end());
  const double hi = *std::max_element(psi.begin(), psi.end());
  if (!(hi - lo <= kMaxPsi)) return false;
  const std::size_t n = sites.size();
  state.lifts.resize(n);
  state.radii_m.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    psi[i] -= lo;
    // The lift of the radius of exp(-psi), so that the radius, written with 17 digits and read
    // back (site_lift), gives this very double: `geovor cells --weight-field` rebuilds the cells.
    state.radii_m[i] = radius_of_lift(std::exp(-psi[i]));
    state.lifts[i] = site_lift(state.radii_m[i]);
  }
  state.psi = std::move(psi);
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(sites, state.lifts, delaunay, &report);
  // The sites are the distinct sites of an unweighted build: nothing merges again.
  if (!report.merges.empty())
    throw Error(ErrorCode::Internal, "balance: a weighted build merged sites that the unweighted one kept apart");
  state.hidden = report.hidden.size();
  state.diagram.assign(dt, threads);
  state.mass.assign(n, 0.0);
  parallel_for(n, threads, [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) state.mass[i] = measure.cell_mass(state.diagram, static_cast<SiteId>(i));
  });
  double sum2 = 0;
  state.max_relative = 0;
  state.min_mass = state.mass[0];
  for (std::size_t i = 0; i < n; ++i) {
    const double d = state.mass[i] - target[i];
    sum2 += d * d;
    state.max_relative = std::max(state.max_relative, std::fabs(d) / target[i]);
    state.min_mass = std::min(state.min_mass, state.mass[i]);
  }
  state.norm = std::sqrt(sum2);
  return true;
}

// The Newton step: H delta = rhs with delta_0 = 0 (H restricted to the other sites is positive
// definite when the cells' adjacency graph is connected, which the damping keeps).
std::vector<double> newton_step(const std::vector<HessianEntry>& entries, std::span<const double> rhs,
                                BalanceSolver solver) {
  const Eigen::Index n = static_cast<Eigen::Index>(rhs.size());
  std::vector<double> diagonal(rhs.size(), 0.0);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(2 * entries.size() + rhs.size());
  for (const HessianEntry& e : entries) {
    diagonal[e.i] -= e.value;
    diagonal[e.j] -= e.value;
    if (e.i == 0 || e.j == 0) continue;  // psi_0 pinned
    triplets.emplace_back(e.i - 1, e.j - 1, e.value);
    triplets.emplace_back(e.j - 1, e.i - 1, e.value);
  }
  for (Eigen::Index i = 1; i < n; ++i) triplets.emplace_back(i - 1, i - 1, diagonal[i]);
  SparseMatrix h(n - 1, n - 1);
  h.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::VectorXd b(n - 1);
  for (Eigen::Index i = 1; i < n; ++i) b[i - 1] = rhs[i];
  Eigen::VectorXd x;
  if (solver == BalanceSolver::Cholesky) {
    Eigen::SimplicialLDLT<SparseMatrix> ldlt(h);
    if (ldlt.info() != Eigen::Success) throw Error(ErrorCode::Internal, "balance: the Hessian's factorization failed");
    x = ldlt.solve(b);
  } else {
    Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper, Eigen::IncompleteCholesky<double>> cg;
    cg.setTolerance(1e-12);
    cg.setMaxIterations(static_cast<Eigen::Index>(10 * n));
    cg.compute(h);
    x = cg.solve(b);
    if (cg.info() != Eigen::Success) throw Error(ErrorCode::Internal, "balance: conjugate gradients did not converge");
  }
  std::vector<double> delta(rhs.size(), 0.0);
  for (Eigen::Index i = 1; i < n; ++i) delta[i] = x[i - 1];
  return delta;
}

}  // namespace

std::vector<HessianEntry> balance_hessian(const VoronoiDiagram& vd, const SphereMeasure& measure, unsigned threads) {
  const std::size_t n = vd.site_capacity();
  threads = thread_count(threads);
  std::vector<std::vector<HessianEntry>> slices(threads);
  // Slices of ids in order, concatenated in order: the same list with any number of threads.
  parallel_for(n, threads, [&](unsigned slice, std::size_t begin, std::size_t end) {
    std::vector<GreatArc> arcs;
    std::vector<HessianEntry>& out = slices[slice];
    for (std::size_t s = begin; s < end; ++s) {
      const SiteId i = static_cast<SiteId>(s);
      cell_arcs(vd, i, arcs);
      const std::span<const SiteId> nbrs = vd.cell_neighbors(i);
      const std::size_t first = out.size();
      for (std::size_t e = 0; e < arcs.size(); ++e) {
        const SiteId j = nbrs[e];
        if (j <= i || arcs[e].angle_rad == 0) continue;  // each pair from its smaller id
        const double ci = vd.lift(i), cj = vd.lift(j);
        // |q_i - q_j| = |c_j p_i - c_i p_j| / (c_i c_j), and x . q_j = (x . p_j) / c_j.
        const double gap = std::sqrt(norm2(cj * vd.site(i) - ci * vd.site(j)));
        const double value = -measure.edge_moment(arcs[e], vd.site(j)) * ci / gap;
        // Two cells may share several edges (few sites): one entry per pair.
        auto it = std::find_if(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(),
                               [&](const HessianEntry& h) { return h.j == j; });
        if (it == out.end()) out.push_back({i, j, value});
        else it->value += value;
      }
    }
  });
  std::vector<HessianEntry> all;
  for (auto& slice : slices) all.insert(all.end(), slice.begin(), slice.end());
  return all;
}

BalanceReport balance(std::span<const Vec3> points, std::span<const double> shares, const SphereMeasure& measure,
                      const BalanceOptions& options, const DelaunayOptions& delaunay,
                      const std::function<void(const BalanceIteration&)>& on_iteration) {
  if (points.size() != shares.size())
    throw Error(ErrorCode::InvalidArgument, "balance: " + std::to_string(points.size()) + " points but " +
                                                std::to_string(shares.size()) + " shares");
  for (std::size_t i = 0; i < shares.size(); ++i)
    if (!(shares[i] > 0) || !std::isfinite(shares[i]))
      throw Error(ErrorCode::InvalidArgument,
                  "balance: share " + std::to_string(i) + " is not positive and finite (" + std::to_string(shares[i]) + ")");
  if (!(options.tolerance > 0)) throw Error(ErrorCode::InvalidArgument, "balance: tolerance must be > 0");
  if (options.max_iterations < 0) throw Error(ErrorCode::InvalidArgument, "balance: max_iterations must be >= 0");
  const unsigned threads = thread_count(options.threads);

  // The distinct sites: an unweighted build merges the points closer than the merge distance.
  BuildReport build;
  const SphericalDelaunay plain = SphericalDelaunay::build(points, delaunay, &build);
  const std::span<const Vec3> sites = plain.sites();
  const std::size_t n = sites.size();
  std::vector<double> target(n, 0.0);
  double share_sum = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    target[build.site_of_input[i]] += shares[i];
    share_sum += shares[i];
  }
  for (double& t : target) t *= measure.total() / share_sum;

  BalanceReport report;
  State state;
  if (n >= 2) {
    evaluate(sites, std::vector<double>(n, 0.0), target, measure, delaunay, threads, state);
    report.initial_relative_error = state.max_relative;
    const double floor = 0.5 * std::min(*std::min_element(target.begin(), target.end()), state.min_mass);
    for (int it = 0; it < options.max_iterations && state.max_relative > options.tolerance; ++it) {
      const auto t0 = Clock::now();
      BalanceIteration r;
      std::vector<double> rhs(n);
      for (std::size_t i = 0; i < n; ++i) rhs[i] = target[i] - state.mass[i];
      const std::vector<double> delta =
          newton_step(balance_hessian(state.diagram, measure, threads), rhs, options.solver);
      State trial;
      bool accepted = false;
      for (int l = 0; l <= kMaxHalvings && !accepted; ++l) {
        const double step = std::ldexp(1.0, -l);
        std::vector<double> psi(n);
        for (std::size_t i = 0; i < n; ++i) psi[i] = state.psi[i] + step * delta[i];
        if (!evaluate(sites, std::move(psi), target, measure, delaunay, threads, trial)) continue;
        r.hidden += trial.hidden;
        if (trial.min_mass >= floor && trial.norm <= (1 - std::ldexp(1.0, -(l + 1))) * state.norm) {
          accepted = true;
          r.step = step;
        }
      }
      if (!accepted) break;  // no decrease at any step: not converged
      r.hidden -= trial.hidden;  // those of the accepted step (0 by the damping) are not rejected trials'
      state = std::move(trial);
      r.max_relative_error = state.max_relative;
      r.seconds = seconds_since(t0);
      report.iterations.push_back(r);
      if (on_iteration) on_iteration(r);
    }
    report.converged = state.max_relative <= options.tolerance;
  } else {
    state.lifts.assign(n, 1.0);
    state.radii_m.assign(n, 0.0);
    state.mass.assign(n, measure.total());
    report.converged = true;
  }
  report.lifts.resize(points.size());
  report.radii_m.resize(points.size());
  report.masses.resize(points.size());
  report.targets.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SiteId s = build.site_of_input[i];
    report.lifts[i] = state.lifts[s];
    report.radii_m[i] = state.radii_m[s];
    report.masses[i] = state.mass[s];
    report.targets[i] = target[s];
  }
  return report;
}

SphericalDelaunay balanced_triangulation(std::span<const Vec3> points, const BalanceReport& result,
                                         const DelaunayOptions& delaunay, BuildReport& report) {
  if (result.lifts.size() != points.size())
    throw Error(ErrorCode::InvalidArgument, "balanced_triangulation: the result is not of these points");
  const SphericalDelaunay plain = SphericalDelaunay::build(points, delaunay, &report);
  std::vector<double> lifts(plain.site_capacity(), 1.0);
  for (std::size_t i = 0; i < points.size(); ++i) lifts[report.site_of_input[i]] = result.lifts[i];
  BuildReport weighted;
  SphericalDelaunay dt = SphericalDelaunay::build(plain.sites(), lifts, delaunay, &weighted);
  if (!weighted.merges.empty()) throw Error(ErrorCode::Internal, "balance: the distinct sites merged again");
  report.hidden = std::move(weighted.hidden);  // none when converged: every balanced cell has its area
  return dt;
}

}  // namespace geovor
