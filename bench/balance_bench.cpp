// geovor_bench_balance FILE [--gz] [--solver cholesky|cg] [--tolerance T] [--threads N]: the balance
// solver with equal shares on the sites of a lat/lon CSV (issue 33): each iteration's largest
// relative area error, step and time, then the total; then Lloyd's iterations (geovor relax) on the
// same sites, the other way to even out areas, with the largest relative area error they reach
// (--no-lloyd: not).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/relax/balance.hpp"
#include "geovor/relax/lloyd.hpp"
#include "geovor/relax/measure.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"
#include "support/generators.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: geovor_bench_balance FILE [--gz] [--solver cholesky|cg] [--tolerance T] [--threads N] [--no-lloyd]\n");
    return 2;
  }
  bool gz = false, no_lloyd = false;
  geovor::BalanceOptions options;
  for (int i = 2; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--gz")) gz = true;
    else if (!std::strcmp(argv[i], "--solver") && i + 1 < argc)
      options.solver = std::string(argv[++i]) == "cg" ? geovor::BalanceSolver::ConjugateGradient : geovor::BalanceSolver::Cholesky;
    else if (!std::strcmp(argv[i], "--tolerance") && i + 1 < argc) options.tolerance = std::stod(argv[++i]);
    else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) options.threads = static_cast<unsigned>(std::stoul(argv[++i]));
    else if (!std::strcmp(argv[i], "--no-lloyd")) no_lloyd = true;
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
  // The other way to even out areas: Lloyd's iterations (geovor relax) move the sites to their
  // cells' centroids. The largest relative error of the same measure after 10, 50 and 200 of them.
  if (!no_lloyd) {
    geovor::SphericalDelaunay dt = geovor::SphericalDelaunay::build(points);
    const geovor::EllipsoidAreaMeasure measure;
    const auto lloyd_start = std::chrono::steady_clock::now();
    int done = 0;
    for (const int until : {10, 50, 200}) {
      geovor::LloydOptions lloyd_options;
      lloyd_options.iterations = until - done;
      geovor::lloyd(dt, lloyd_options);
      done = until;
      const geovor::VoronoiDiagram vd(dt);
      const double target = measure.total() / static_cast<double>(dt.num_sites());
      double worst = 0;
      for (geovor::SiteId s = 0; s < dt.site_capacity(); ++s)
        if (vd.has_cell(s)) worst = std::max(worst, std::abs(measure.cell_mass(vd, s) / target - 1));
      std::printf("lloyd: %d iterations: max relative error %.3e, %.2f s (the sites moved)\n", done, worst,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - lloyd_start).count());
      std::fflush(stdout);
    }
  }
  return r.converged ? 0 : 1;
}
