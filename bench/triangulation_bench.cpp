/// \file triangulation_bench.cpp
/// \brief geovor_bench_triangulation: build time and memory of SphericalDelaunay against CGAL's
/// Delaunay_triangulation_on_sphere_2, on uniform points and on the GeoNames cities.
///
/// Usage: geovor_bench_triangulation [--sizes 65536,262144,1048576] [--cities PATH|none]
///                                   [--repeat 3] [--seed 42]
/// Times are the best of --repeat runs (std::chrono::steady_clock, single thread). Memory is
/// measured by the counting operator new/delete below: bytes held (malloc_usable_size) at the
/// peak of one build, minus what was held before it.
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include "bench_common.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "support/cgal_oracle.hpp"
#include "support/generators.hpp"

// ---- Counting allocator: every operator new of the process goes through here. ----
namespace {

std::size_t g_current_bytes = 0;  // single-threaded benchmark: plain counters suffice
std::size_t g_peak_bytes = 0;

void* count_alloc(void* p) noexcept {
  if (p != nullptr) {
    g_current_bytes += malloc_usable_size(p);
    g_peak_bytes = std::max(g_peak_bytes, g_current_bytes);
  }
  return p;
}

void count_free(void* p) noexcept {
  if (p != nullptr) {
    g_current_bytes -= malloc_usable_size(p);
    std::free(p);
  }
}

void* raw_alloc(std::size_t n) noexcept { return count_alloc(std::malloc(n == 0 ? 1 : n)); }

void* raw_aligned_alloc(std::size_t n, std::align_val_t a) noexcept {
  void* p = nullptr;
  const std::size_t align = std::max(static_cast<std::size_t>(a), sizeof(void*));
  if (posix_memalign(&p, align, n == 0 ? 1 : n) != 0) return nullptr;
  return count_alloc(p);
}

// Starts a measurement: the peak is counted from what is held now.
std::size_t reset_peak() {
  g_peak_bytes = g_current_bytes;
  return g_current_bytes;
}

}  // namespace

void* operator new(std::size_t n) {
  if (void* p = raw_alloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  if (void* p = raw_alloc(n)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return raw_alloc(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return raw_alloc(n); }
void* operator new(std::size_t n, std::align_val_t a) {
  if (void* p = raw_aligned_alloc(n, a)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n, std::align_val_t a) {
  if (void* p = raw_aligned_alloc(n, a)) return p;
  throw std::bad_alloc();
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return raw_aligned_alloc(n, a);
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return raw_aligned_alloc(n, a);
}
void operator delete(void* p) noexcept { count_free(p); }
void operator delete[](void* p) noexcept { count_free(p); }
void operator delete(void* p, std::size_t) noexcept { count_free(p); }
void operator delete[](void* p, std::size_t) noexcept { count_free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { count_free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { count_free(p); }
void operator delete(void* p, std::align_val_t) noexcept { count_free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { count_free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { count_free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { count_free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { count_free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { count_free(p); }

#ifndef GEOVOR_SOURCE_DIR
#define GEOVOR_SOURCE_DIR "."  // bench/CMakeLists.txt defines it; this keeps a bare compile working
#endif

namespace {

using Clock = std::chrono::steady_clock;

struct Args {
  std::vector<std::size_t> sizes{std::size_t{1} << 16, std::size_t{1} << 18, std::size_t{1} << 20};
  std::string cities;  // empty: look in the default places; "none": skip
  int repeat = 3;
  std::uint64_t seed = 42;
  geovor::DelaunayOptions options;  // --brio: BRIO rounds instead of the default order
};

[[noreturn]] void usage(const char* argv0, const char* why) {
  std::fprintf(stderr,
               "%s\nusage: %s [--sizes N1,N2,...] [--cities PATH|none] [--repeat N] [--seed S] [--brio]\n",
               why, argv0);
  std::exit(2);
}

Args parse_args(int argc, char** argv) {
  Args args;
  for (int i = 1; i < argc; ++i) {
    const std::string opt = argv[i];
    if (opt == "--help" || opt == "-h") usage(argv[0], "geovor_bench_triangulation: ours vs CGAL");
    if (opt == "--brio") {
      args.options.brio = true;
      continue;
    }
    if (i + 1 >= argc) usage(argv[0], ("missing value after " + opt).c_str());
    const std::string value = argv[++i];
    if (opt == "--sizes") {
      std::string bad;
      if (!geovor::bench::parse_sizes(value, 4, args.sizes, bad)) usage(argv[0], ("bad size: " + bad).c_str());
      std::sort(args.sizes.begin(), args.sizes.end());
    } else if (opt == "--cities") {
      args.cities = value;
    } else if (opt == "--repeat") {
      args.repeat = std::atoi(value.c_str());
      if (args.repeat < 1) usage(argv[0], "--repeat must be >= 1");
    } else if (opt == "--seed") {
      args.seed = std::strtoull(value.c_str(), nullptr, 10);
    } else {
      usage(argv[0], ("unknown option " + opt).c_str());
    }
  }
  return args;
}

using geovor::bench::cpu_model;

std::string find_cities(const std::string& given) {
  if (given == "none") return {};
  if (!given.empty()) return given;
  for (const char* rel : {"/datasets/geonames_cities.csv.gz", "/../shared/datasets/geonames_cities.csv.gz"}) {
    const std::string path = std::string(GEOVOR_SOURCE_DIR) + rel;
    if (std::filesystem::exists(path)) return path;
  }
  return {};
}

void print_header() {
  std::printf("%-10s %9s %9s %10s %10s %8s %9s %11s %11s %7s\n", "input", "n", "sites", "ours_s",
              "cgal_s", "speedup", "B/site", "peak_B/site", "cgal_peak", "merged");
}

void run_case(const std::string& name, const std::vector<geovor::Vec3>& points, int repeat, bool validate,
              const geovor::DelaunayOptions& options) {
  const std::size_t n = points.size();
  double ours_best = 1e300, cgal_best = 1e300;
  std::size_t ours_peak = 0, cgal_peak = 0, bytes = 0, sites = 0, cgal_vertices = 0, merged = 0;
  std::string validation;
  try {
    for (int r = 0; r < repeat; ++r) {
      geovor::BuildReport report;
      const std::size_t base = reset_peak();
      const auto t0 = Clock::now();
      const geovor::SphericalDelaunay dt = geovor::SphericalDelaunay::build(points, options, &report);
      const auto t1 = Clock::now();
      ours_best = std::min(ours_best, std::chrono::duration<double>(t1 - t0).count());
      if (r == 0) {
        ours_peak = g_peak_bytes - base;
        bytes = dt.memory_bytes();
        sites = dt.num_sites();
        merged = report.merges.size();
        if (validate) {
          const geovor::Validation v = dt.validate(&report);
          validation = v.ok() ? "ok" : std::to_string(v.errors.size()) + " errors, first: " + v.errors.front();
        }
      }
    }
  } catch (const std::exception& e) {
    std::printf("%-10s %9zu   our build failed: %s\n", name.c_str(), n, e.what());
    return;
  }
  for (int r = 0; r < repeat; ++r) {
    const std::size_t base = reset_peak();
    cgal_best = std::min(cgal_best, geovor::testing::cgal_build_seconds(points, &cgal_vertices));
    if (r == 0) cgal_peak = g_peak_bytes - base;
  }
  const double per_site = sites ? static_cast<double>(bytes) / static_cast<double>(sites) : 0.0;
  std::printf("%-10s %9zu %9zu %10.4f %10.4f %8.2f %9.1f %11.1f %11.1f %7zu\n", name.c_str(), n, sites,
              ours_best, cgal_best, cgal_best / ours_best, per_site,
              static_cast<double>(ours_peak) / static_cast<double>(n),
              static_cast<double>(cgal_peak) / static_cast<double>(n), merged);
  if (cgal_vertices != sites) {
    std::printf("  note: CGAL kept %zu vertices, ours %zu sites\n", cgal_vertices, sites);
  }
  if (validate) std::printf("  validate() at n=%zu: %s\n", n, validation.c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = parse_args(argc, argv);
  std::printf("geovor_bench_triangulation: SphericalDelaunay::build vs CGAL Delaunay_triangulation_on_sphere_2"
              " (Epick, insert(begin,end) with CGAL's spatial sort)\n");
  std::printf("machine: %s, %u hardware threads; every build runs on a single thread\n", cpu_model().c_str(),
              std::thread::hardware_concurrency());
  std::printf("times: best of %d runs (steady_clock); speedup = cgal_s / ours_s; B/site = memory_bytes()/num_sites()"
              " after the build; peaks = heap bytes (operator new, malloc_usable_size) at the peak of a build / n\n",
              args.repeat);
#ifndef NDEBUG
  std::printf("WARNING: assertions enabled (not a Release build): times are not representative\n");
#endif
  std::printf("insertion order: %s\n", args.options.brio ? "BRIO rounds along the Hilbert curve (--brio)" : "Hilbert curve, sparse rounds first from 1024 points (default)");
  print_header();
  for (std::size_t i = 0; i < args.sizes.size(); ++i) {
    const std::vector<geovor::Vec3> points = geovor::testing::uniform_on_sphere(args.sizes[i], args.seed);
    run_case("uniform", points, args.repeat, i == 0, args.options);
  }
  const std::string cities = find_cities(args.cities);
  if (cities.empty()) {
    std::printf("cities: skipped (no geonames_cities.csv.gz in datasets/ or ../shared/datasets/, or --cities none)\n");
    return 0;
  }
  try {
    const std::vector<geovor::Vec3> points = geovor::testing::load_lat_lon_csv_gz_unit_vectors(cities);
    run_case("cities", points, args.repeat, false, args.options);
  } catch (const std::exception& e) {
    std::printf("cities: skipped (%s)\n", e.what());
  }
  return 0;
}
