// geovor_bench_balance FILE [--gz] [--solver cholesky|cg] [--tolerance T] [--threads N]: the balance
// solver with equal shares on the sites of a lat/lon CSV (issue 33): each iteration's largest
// relative area error, step and time, then the total.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "geovor/relax/balance.hpp"
#include "support/generators.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: geovor_bench_balance FILE [--gz] [--solver cholesky|cg] [--tolerance T] [--threads N]\n");
    return 2;
  }
  bool gz = false;
  geovor::BalanceOptions options;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--gz")) gz = true;
    else if (!std::strcmp(argv[i], "--solver") && i + 1 < argc)
      options.solver = std::string(argv[++i]) == "cg" ? geovor::BalanceSolver::ConjugateGradient : geovor::BalanceSolver::Cholesky;
    else if (!std::strcmp(argv[i], "--tolerance") && i + 1 < argc) options.tolerance = std::stod(argv[++i]);
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) options.threads = static_cast<unsigned>(std::stoul(argv[++i]));
  }
  const std::vector<geovor::Vec3> points =
      gz ? geovor::testing::load_lat_lon_csv_gz_unit_vectors(argv[1]) : geovor::testing::load_lat_lon_csv_unit_vectors(argv[1]);
  const auto t0 = std::chrono::steady_clock::now();
  int k = 0;
  const geovor::BalanceReport r = geovor::balance(
      points, std::vector<double>(points.size(), 1.0), geovor::EllipsoidAreaMeasure(), options, {},
      [&](const geovor::BalanceIteration& it) {
        std::printf("iteration %d: max relative error %.3e, step %g, hidden in rejected trials %zu, %.2f s\n", ++k,
                    it.max_relative_error, it.step, it.hidden, it.seconds);
        std::fflush(stdout);
      });
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  double largest = 0;
  for (const double x : r.radii_m) largest = std::max(largest, x);
  std::printf("%zu points: initial error %.3e, %s after %zu iterations, %.2f s in all; largest radius %.0f m\n",
              points.size(), r.initial_relative_error, r.converged ? "converged" : "NOT converged", r.iterations.size(),
              seconds, largest);
  return r.converged ? 0 : 1;
}
