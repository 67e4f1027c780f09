/// \file lloyd_bench.cpp
/// \brief geovor_bench_lloyd: keeping a triangulation right while its sites move (thesis ch. 5):
/// rebuilding from scratch, naive relocation (remove + insert) and filtered relocation
/// (SphericalDelaunay::move_all), on Lloyd's iterations and on random small moves.
///
/// Usage: geovor_bench_lloyd [--sizes 65536,1048576] [--iterations 100] [--rounds 5]
///                           [--scale 0.1] [--seed 42] [--threads 1] [--lockstep]
///                           [--repeat 1] [--no-lloyd] [--no-moves]
/// Lloyd: each strategy runs its --iterations from the same uniform random sites, one strategy
/// after the other, as `geovor relax` runs one; each iteration's centroid step (VoronoiDiagram +
/// centroids, the same work for all three) and relocation step are timed apart (steady_clock,
/// inside lloyd()). With --lockstep the three run in lockstep instead, one iteration each in
/// turn, so that a busy machine slows them alike; but then each step starts after the other two
/// strategies' steps have pushed its arrays out of the caches, which costs the filtered
/// relocation, whose steps are the shortest, the most (its arrays come back from memory: about
/// 0.45 ms of 2.6 at 2^16). --repeat R runs the Lloyd experiment R times and ends with the
/// median of the runs' late and whole-run ratios (single runs vary by about 10% on a shared
/// virtual machine). Moves: --rounds rounds in which 1%, 10% or 100% of the sites
/// (a random subset) move by a random tangent step of up to --scale times the mean site spacing
/// sqrt(4 pi / n); each strategy applies the same moves in turn.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "bench_common.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/relax/lloyd.hpp"
#include "support/generators.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using geovor::Relocation;
using geovor::SphericalDelaunay;
using geovor::Vec3;

struct Args {
  std::vector<std::size_t> sizes{std::size_t{1} << 16, std::size_t{1} << 20};
  int iterations = 100;
  int rounds = 5;
  double scale = 0.1;
  std::uint64_t seed = 42;
  unsigned threads = 1;
  bool lloyd = true, moves = true;
  bool lockstep = false;
  int repeat = 1;
};

[[noreturn]] void usage(const char* argv0, const std::string& why) {
  std::fprintf(stderr,
               "%s\nusage: %s [--sizes N1,N2,...] [--iterations N] [--rounds N] [--scale S] [--seed S] "
               "[--threads T] [--lockstep] [--repeat R] [--no-lloyd] [--no-moves]\n",
               why.c_str(), argv0);
  std::exit(2);
}

Args parse_args(int argc, char** argv) {
  Args args;
  for (int i = 1; i < argc; ++i) {
    const std::string opt = argv[i];
    if (opt == "--help" || opt == "-h") usage(argv[0], "geovor_bench_lloyd: rebuild vs naive vs filtered relocation");
    if (opt == "--no-lloyd") {
      args.lloyd = false;
      continue;
    }
    if (opt == "--no-moves") {
      args.moves = false;
      continue;
    }
    if (opt == "--lockstep") {
      args.lockstep = true;
      continue;
    }
    if (i + 1 >= argc) usage(argv[0], "missing value after " + opt);
    const std::string value = argv[++i];
    if (opt == "--sizes") {
      std::string bad;
      if (!geovor::bench::parse_sizes(value, 4, args.sizes, bad)) usage(argv[0], "bad size: " + bad);
    } else if (opt == "--iterations") {
      args.iterations = std::atoi(value.c_str());
      if (args.iterations < 1) usage(argv[0], "--iterations must be >= 1");
    } else if (opt == "--rounds") {
      args.rounds = std::atoi(value.c_str());
      if (args.rounds < 1) usage(argv[0], "--rounds must be >= 1");
    } else if (opt == "--scale") {
      args.scale = std::atof(value.c_str());
      if (!(args.scale > 0)) usage(argv[0], "--scale must be > 0");
    } else if (opt == "--repeat") {
      args.repeat = std::atoi(value.c_str());
      if (args.repeat < 1) usage(argv[0], "--repeat must be >= 1");
    } else if (opt == "--seed") {
      args.seed = std::strtoull(value.c_str(), nullptr, 10);
    } else if (opt == "--threads") {
      args.threads = static_cast<unsigned>(std::atoi(value.c_str()));
    } else {
      usage(argv[0], "unknown option " + opt);
    }
  }
  return args;
}

constexpr Relocation kStrategies[3] = {Relocation::Rebuild, Relocation::Naive, Relocation::Filtered};

struct Sums {
  double centroid = 0, relocation = 0;
  std::size_t moved = 0, filtered = 0, reanchored = 0, flipped = 0, reinserted = 0, rebuilt = 0, iterations = 0;
  void add(const geovor::LloydIteration& it) {
    centroid += it.centroid_seconds;
    relocation += it.relocation_seconds;
    moved += it.moves.moved;
    filtered += it.moves.filtered;
    flipped += it.moves.flipped;
    reinserted += it.moves.reinserted;
    reanchored += it.moves.reanchored;
    rebuilt += it.moves.rebuilt;
    ++iterations;
  }
  double per(double s) const { return iterations ? s / static_cast<double>(iterations) : 0; }
};

std::pair<double, double> run_lloyd(std::size_t n, const Args& args) {
  const std::vector<Vec3> points = geovor::testing::uniform_on_sphere(n, args.seed);
  const SphericalDelaunay start = SphericalDelaunay::build(points);
  SphericalDelaunay dt[3] = {start, start, start};
  const int iters = args.iterations;
  const int window = std::min(10, iters);
  // sums[strategy][0: first `window` iterations, 1: last `window`, 2: all]
  Sums sums[3][3];
  double first_energy = 0, last_energy = 0, last_max_m = 0;
  auto record = [&](int k, int it, const geovor::LloydIteration& x) {
    if (it <= window) sums[k][0].add(x);
    if (it > iters - window) sums[k][1].add(x);
    sums[k][2].add(x);
    if (k == 2) {
      if (it == 1) first_energy = x.energy;
      last_energy = x.energy;
      last_max_m = x.max_move_m;
    }
  };
  geovor::LloydOptions options;
  options.threads = args.threads;
  if (args.lockstep) {
    options.iterations = 1;
    for (int it = 1; it <= iters; ++it)
      for (int k = 0; k < 3; ++k) {
        options.relocation = kStrategies[k];
        record(k, it, geovor::lloyd(dt[k], options).iterations.front());
      }
  } else {  // one lloyd() call per strategy, as geovor relax makes
    options.iterations = iters;
    for (int k = 0; k < 3; ++k) {
      options.relocation = kStrategies[k];
      geovor::lloyd(dt[k], options, [&](const geovor::LloydIteration& x) { record(k, x.iteration, x); });
    }
  }
  const bool same = std::equal(dt[0].sites().begin(), dt[0].sites().end(), dt[1].sites().begin()) &&
                    std::equal(dt[0].sites().begin(), dt[0].sites().end(), dt[2].sites().begin());
  std::printf("\nLloyd, n = %zu uniform random sites, %d iterations (%s); energy %.6e -> %.6e, last largest move "
              "%.1f m; positions identical for the three strategies: %s\n",
              n, iters, args.lockstep ? "the strategies in lockstep" : "one strategy after the other", first_energy,
              last_energy, last_max_m, same ? "yes" : "NO");
  const char* range_name[3] = {"", "", "all"};
  char first_name[32], last_name[32];
  std::snprintf(first_name, sizeof first_name, "1-%d", window);
  std::snprintf(last_name, sizeof last_name, "%d-%d", iters - window + 1, iters);
  range_name[0] = first_name;
  range_name[1] = last_name;
  // filtered includes re-anchored (the second test); rebuilt: move_all's rebuild in place.
  std::printf("%-9s %-8s %12s %12s %12s %9s %9s %9s %9s %9s\n", "iters", "strategy", "reloc_ms/it", "centroid_ms",
              "total_ms/it", "filtered", "reanch", "flipped", "reinsert", "rebuilt");
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) {
      const Sums& s = sums[k][r];
      const double moved = static_cast<double>(std::max<std::size_t>(1, s.moved));
      std::printf("%-9s %-8s %12.3f %12.3f %12.3f %8.1f%% %8.1f%% %8.1f%% %8.1f%% %8.1f%%\n", range_name[r],
                  to_string(kStrategies[k]), 1e3 * s.per(s.relocation), 1e3 * s.per(s.centroid),
                  1e3 * s.per(s.relocation + s.centroid), k == 0 ? 0.0 : 100 * s.filtered / moved,
                  k == 0 ? 0.0 : 100 * s.reanchored / moved, k == 0 ? 0.0 : 100 * s.flipped / moved,
                  k == 0 ? 0.0 : 100 * s.reinserted / moved, k == 0 ? 0.0 : 100 * s.rebuilt / moved);
    }
  }
  std::printf("ratios (time / rebuild time; < 1 is faster than rebuilding):\n");
  std::printf("%-9s %18s %18s %18s %18s\n", "iters", "filtered reloc", "naive reloc", "filtered whole it", "naive whole it");
  for (int r = 0; r < 3; ++r) {
    const Sums& b = sums[0][r];
    const Sums& nv = sums[1][r];
    const Sums& f = sums[2][r];
    std::printf("%-9s %18.3f %18.3f %18.3f %18.3f\n", range_name[r], f.relocation / b.relocation,
                nv.relocation / b.relocation, (f.relocation + f.centroid) / (b.relocation + b.centroid),
                (nv.relocation + nv.centroid) / (b.relocation + b.centroid));
  }
  const double late_speedup = sums[0][1].relocation / sums[2][1].relocation;
  std::printf("targets: filtered relocation %.2fx faster than rebuild in iterations %s (target >= 5x: %s); "
              "over all %d iterations %.2fx (target > 1x: %s)\n",
              late_speedup, last_name, late_speedup >= 5 ? "met" : "MISSED", iters,
              sums[0][2].relocation / sums[2][2].relocation,
              sums[0][2].relocation > sums[2][2].relocation ? "met" : "MISSED");
  return {late_speedup, sums[0][2].relocation / sums[2][2].relocation};
}

// A random tangent step of length up to `step` (radians, small) at p.
Vec3 jitter(const Vec3& p, double step, std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> u(0, 1);
  Vec3 t{g(rng), g(rng), g(rng)};
  t = t - dot(t, p) * p;
  const double len = std::sqrt(norm2(t));
  return geovor::testing::normalized(p + (step * u(rng) / len) * t);
}

void run_moves(std::size_t n, const Args& args) {
  const std::vector<Vec3> points = geovor::testing::uniform_on_sphere(n, args.seed + 1);
  const double spacing = std::sqrt(4 * 3.141592653589793 / static_cast<double>(n));
  const double step = args.scale * spacing;
  std::printf("\nRandom moves, n = %zu uniform random sites, steps up to %.3g x spacing (%.3g rad), %d rounds\n", n,
              args.scale, step, args.rounds);
  std::printf("%-8s %-8s %12s %10s %9s %9s %9s %9s %10s\n", "share", "strategy", "ms/round", "/rebuild", "filtered",
              "flipped", "reinsert", "rebuilt", "refused");
  std::mt19937_64 rng(args.seed + 7);
  for (const double share : {0.01, 0.1, 1.0}) {
    SphericalDelaunay dt[3];
    dt[0] = SphericalDelaunay::build(points);
    dt[1] = dt[0];
    dt[2] = dt[0];
    double seconds[3] = {0, 0, 0};
    geovor::MoveStats stats[3];
    std::vector<Vec3> current = points;
    std::vector<std::uint32_t> ids(n);
    for (std::uint32_t i = 0; i < n; ++i) ids[i] = i;
    const std::size_t k = std::max<std::size_t>(1, static_cast<std::size_t>(share * static_cast<double>(n)));
    for (int round = 0; round < args.rounds; ++round) {
      std::vector<Vec3> next = current;
      std::shuffle(ids.begin(), ids.end(), rng);
      for (std::size_t i = 0; i < k; ++i) next[ids[i]] = jitter(current[ids[i]], step, rng);
      for (int s = 0; s < 3; ++s) {
        const auto t0 = Clock::now();
        if (kStrategies[s] == Relocation::Rebuild) {
          dt[s] = SphericalDelaunay::build(next);
        } else {
          geovor::RelocationOptions options;
          options.filter = options.flips = kStrategies[s] == Relocation::Filtered;
          stats[s] += dt[s].move_all(next, options);
        }
        seconds[s] += std::chrono::duration<double>(Clock::now() - t0).count();
      }
      current = next;
    }
    for (int s = 0; s < 3; ++s) {
      const double moved = static_cast<double>(std::max<std::size_t>(1, stats[s].moved));
      char label[16];
      std::snprintf(label, sizeof label, "%g%%", 100 * share);
      std::printf("%-8s %-8s %12.3f %10.3f %8.1f%% %8.1f%% %8.1f%% %8.1f%% %10zu\n", label, to_string(kStrategies[s]),
                  1e3 * seconds[s] / args.rounds, seconds[s] / seconds[0], s == 0 ? 0.0 : 100 * stats[s].filtered / moved,
                  s == 0 ? 0.0 : 100 * stats[s].flipped / moved, s == 0 ? 0.0 : 100 * stats[s].reinserted / moved,
                  s == 0 ? 0.0 : 100 * stats[s].rebuilt / moved, stats[s].refused);
    }
    if (dt[2].site_capacity() <= 70000 && !dt[2].validate().ok()) std::printf("  filtered: validate() FAILED\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = parse_args(argc, argv);
  std::printf("geovor_bench_lloyd: rebuild vs naive (remove + insert) vs filtered relocation (move_all)\n");
  std::printf("machine: %s, %u hardware threads; relocation single-threaded, centroids on %u thread(s)\n",
              geovor::bench::cpu_model().c_str(), std::thread::hardware_concurrency(), args.threads);
#ifndef NDEBUG
  std::printf("WARNING: assertions enabled (not a Release build): times are not representative\n");
#endif
  for (const std::size_t n : args.sizes) {
    if (args.lloyd) {
      std::vector<double> late, whole;
      for (int r = 0; r < args.repeat; ++r) {
        const auto [l, w] = run_lloyd(n, args);
        late.push_back(l);
        whole.push_back(w);
        std::fflush(stdout);
      }
      if (args.repeat > 1) {
        std::printf("n = %zu, %d runs: filtered relocation vs rebuild, last iterations:", n, args.repeat);
        for (const double x : late) std::printf(" %.2fx", x);
        std::printf("; all iterations:");
        for (const double x : whole) std::printf(" %.2fx", x);
        std::sort(late.begin(), late.end());
        std::sort(whole.begin(), whole.end());
        std::printf("\nmedians: %.2fx (target >= 5x: %s), %.2fx (target > 1x: %s)\n", late[late.size() / 2],
                    late[late.size() / 2] >= 5 ? "met" : "MISSED", whole[whole.size() / 2],
                    whole[whole.size() / 2] > 1 ? "met" : "MISSED");
      }
    }
    if (args.moves) run_moves(n, args);
    std::fflush(stdout);
  }
  return 0;
}
