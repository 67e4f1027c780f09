// geovor_bench_weighted: the regular triangulation of weighted sites against the unweighted build of
// the same points (issue 33's target: at most 1.2x its time at 2^20), for radii small against the
// sites' spacing (few hidden) and comparable with it (many hidden). Median of --repeat runs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "support/generators.hpp"

namespace {

using geovor::BuildReport;
using geovor::SphericalDelaunay;
using geovor::Vec3;

template <class F>
double median_seconds(int repeat, F&& build) {
  std::vector<double> t;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    build();
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::size_t> sizes{1u << 16, 1u << 20};
  int repeat = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    std::string bad;
    if (a == "--sizes" && i + 1 < argc) {
      if (!geovor::bench::parse_sizes(argv[++i], 4, sizes, bad)) return std::fprintf(stderr, "bad size %s\n", bad.c_str()), 2;
    } else if (a == "--repeat" && i + 1 < argc) {
      repeat = std::max(1, std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr, "usage: geovor_bench_weighted [--sizes N,N...] [--repeat R]\n");
      return 2;
    }
  }
  std::printf("# %s, one thread, median of %d\n", geovor::bench::cpu_model().c_str(), repeat);
  std::printf("%-9s %-28s %9s %9s %7s %9s\n", "sites", "radii", "seconds", "unweighted", "ratio", "hidden");
  for (const std::size_t n : sizes) {
    const std::vector<Vec3> pts = geovor::testing::uniform_on_sphere(n, 1);
    const double plain = median_seconds(repeat, [&] { SphericalDelaunay::build(pts); });
    // The mean spacing of n uniform sites on the Earth, in metres.
    const double spacing_m = std::sqrt(4 * M_PI / static_cast<double>(n)) * 6371008.771415;
    for (const double scale : {0.1, 1.0}) {
      std::mt19937_64 rng(7);
      std::uniform_real_distribution<double> r(0, scale * spacing_m);
      std::vector<double> lifts(n);
      for (double& c : lifts) c = std::cos(r(rng) / 6371008.771415);
      BuildReport report;
      const double weighted = median_seconds(repeat, [&] { SphericalDelaunay::build(pts, lifts, {}, &report); });
      char label[64];
      std::snprintf(label, sizeof label, "uniform 0..%.1f x spacing", scale);
      std::printf("%-9zu %-28s %9.3f %9.3f %7.2f %9zu\n", n, label, weighted, plain, weighted / plain,
                  report.hidden.size());
    }
  }
  return 0;
}
