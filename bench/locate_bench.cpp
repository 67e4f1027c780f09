/// \file locate_bench.cpp
/// \brief geovor_bench_locate: nearest-site queries with every Locator strategy, against a
/// nanoflann k-d tree on the unit vectors and CGAL's point location on the sphere, in the two
/// scenarios of de Castro's thesis §8.5.3.
///
/// Usage: geovor_bench_locate [--sites N] [--queries M] [--repeat R] [--seed S]
///                            [--fractions 1,0.5,0.1,0.01,0.001] [--walkers 1,2,4,8,20]
///                            [--step F] [--turn RAD] [--sample K] [--leaf L]
///                            [--strategies walk,jump-walk,...] [--max-seconds T] [--no-cgal]
///                            [--site-order input|hilbert] [--kd-hilbert] [--clock wall|cpu]
///
///  - Sites: N points uniform on the sphere (testing::uniform_on_sphere, default 2^20).
///  - Scenario I (proximity): M queries uniform in a spherical cap around a fixed centre whose
///    area is the given fraction of the sphere (so it holds that fraction of the sites in
///    expectation), independent draws, i.e. in random order within the cap.
///  - Scenario II (coherence): W random walkers, each starting at a random point with a random
///    heading, step F times the mean site spacing sqrt(4 pi / N) along its heading, then turn the
///    heading by a uniform angle in [-RAD, RAD]; the M queries are the walkers' positions,
///    interleaved round-robin (walker i % W gives query i).
///  - --site-order hilbert numbers the same sites along geovor's Hilbert curve instead of in their
///    random input order (site ids index every array of the triangulation, so this shows how much
///    of each method's time is memory latency); the k-d tree and CGAL get the sites in id order.
///  - --kd-hilbert adds a second k-d tree over the same sites renumbered along the Hilbert curve
///    (answers mapped back to site ids), an extra column: the targets are against the plain one.
///  - --clock cpu times each run by the thread's CPU time instead of the wall clock, so that on a
///    shared machine the time the benchmark spends descheduled is not counted.
///  - The Locators share one WalkGraph (the packed copy of the hierarchy, walk_graph.hpp), built
///    before the first row and printed with the builds.
/// Every method sees the same query sequence. Times are the best of R runs (steady_clock, single
/// thread), the methods taking turns within each round; a method whose run took more than T
/// seconds is not run again, and a Locator or CGAL run is cut short after T seconds (its rate is
/// then measured on the queries done, marked '*': a plain walk across 2^20 random queries takes
/// minutes). Each Locator run gets a fresh Locator (no landmarks, no previous
/// answer) created before the clock starts, each CGAL run starts without a hint. Build times
/// (hierarchy, k-d tree, CGAL) are printed separately and are not part of any rate.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <nanoflann.hpp>

#include "bench_common.hpp"
#include "geovor/core/types.hpp"
#include "geovor/delaunay/spatial_sort.hpp"
#include "geovor/locate/delaunay_hierarchy.hpp"
#include "geovor/locate/locator.hpp"
#include "support/cgal_oracle.hpp"
#include "support/generators.hpp"

namespace {

using geovor::Vec3;
using Clock = std::chrono::steady_clock;

// The clock of the timed runs: wall (steady_clock, the default) or this thread's CPU time
// (--clock cpu: on a shared machine, time spent descheduled is not counted).
bool g_cpu_clock = false;
double now_s() {
  if (g_cpu_clock) {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

constexpr double kPi = 3.14159265358979323846;

const std::vector<geovor::LocateStrategy> kAllStrategies = {
    geovor::LocateStrategy::Walk,      geovor::LocateStrategy::JumpWalk, geovor::LocateStrategy::KeepJumpWalk,
    geovor::LocateStrategy::Hierarchy, geovor::LocateStrategy::Climb,    geovor::LocateStrategy::KeepJumpClimb,
};

// ---- Options ----

struct Args {
  std::size_t sites = std::size_t{1} << 20;
  std::size_t queries = std::size_t{1} << 20;
  int repeat = 3;
  std::uint64_t seed = 42;
  std::vector<double> fractions{1.0, 0.5, 0.1, 0.01, 0.001};
  std::vector<double> walkers{1, 2, 4, 8, 20};
  double step = 1.0;  // in mean site spacings
  double turn = 0.5;  // radians
  std::size_t sample = 10000;
  std::size_t leaf = 10;
  std::vector<geovor::LocateStrategy> strategies = kAllStrategies;
  double max_seconds = 10;
  bool cgal = true;
  bool hilbert_ids = false;  // --site-order hilbert
  bool kd_hilbert = false;   // --kd-hilbert
  bool cpu_clock = false;    // --clock cpu
};

[[noreturn]] void usage(const char* argv0, const std::string& why) {
  std::fprintf(stderr,
               "%s\nusage: %s [--sites N] [--queries M] [--repeat R] [--seed S] [--fractions F1,F2,...|none]\n"
               "          [--walkers W1,W2,...|none] [--step SPACINGS] [--turn RAD] [--sample K] [--leaf L]\n"
               "          [--strategies S1,S2,...] [--max-seconds T] [--site-order input|hilbert] [--no-cgal]\n"
               "          [--kd-hilbert] [--clock wall|cpu]\n",
               why.c_str(), argv0);
  std::exit(2);
}

double parse_double(const char* argv0, const std::string& s) {
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || *end != '\0' || !std::isfinite(v)) usage(argv0, "bad number: " + s);
  return v;
}

std::size_t parse_size(const char* argv0, const std::string& s) {
  char* end = nullptr;
  const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0') usage(argv0, "bad integer: " + s);
  return static_cast<std::size_t>(v);
}

Args parse_args(int argc, char** argv) {
  Args args;
  for (int i = 1; i < argc; ++i) {
    const std::string opt = argv[i];
    if (opt == "--help" || opt == "-h") usage(argv[0], "geovor_bench_locate: Locator vs k-d tree vs CGAL locate");
    if (opt == "--no-cgal") {
      args.cgal = false;
      continue;
    }
    if (opt == "--kd-hilbert") {
      args.kd_hilbert = true;
      continue;
    }
    if (i + 1 >= argc) usage(argv[0], "missing value after " + opt);
    const std::string value = argv[++i];
    if (opt == "--sites") {
      args.sites = parse_size(argv[0], value);
      if (args.sites < 4) usage(argv[0], "--sites must be >= 4");
    } else if (opt == "--queries") {
      args.queries = parse_size(argv[0], value);
      if (args.queries < 1) usage(argv[0], "--queries must be >= 1");
    } else if (opt == "--repeat") {
      args.repeat = static_cast<int>(parse_size(argv[0], value));
      if (args.repeat < 1) usage(argv[0], "--repeat must be >= 1");
    } else if (opt == "--seed") {
      args.seed = parse_size(argv[0], value);
    } else if (opt == "--fractions") {
      args.fractions.clear();
      for (const std::string& s : value == "none" ? std::vector<std::string>{} : geovor::bench::split_commas(value)) {
        const double f = parse_double(argv[0], s);
        if (!(f > 0 && f <= 1)) usage(argv[0], "fractions must be in (0, 1]");
        args.fractions.push_back(f);
      }
    } else if (opt == "--walkers") {
      args.walkers.clear();
      for (const std::string& s : value == "none" ? std::vector<std::string>{} : geovor::bench::split_commas(value)) {
        const std::size_t w = parse_size(argv[0], s);
        if (w < 1) usage(argv[0], "walkers must be >= 1");
        args.walkers.push_back(static_cast<double>(w));
      }
    } else if (opt == "--step") {
      args.step = parse_double(argv[0], value);
      if (!(args.step > 0)) usage(argv[0], "--step must be > 0");
    } else if (opt == "--turn") {
      args.turn = parse_double(argv[0], value);
    } else if (opt == "--sample") {
      args.sample = parse_size(argv[0], value);
    } else if (opt == "--leaf") {
      args.leaf = parse_size(argv[0], value);
      if (args.leaf < 1) usage(argv[0], "--leaf must be >= 1");
    } else if (opt == "--strategies") {
      args.strategies.clear();
      for (const std::string& s : geovor::bench::split_commas(value)) {
        try {
          args.strategies.push_back(geovor::parse_strategy(s));
        } catch (const std::exception& e) {
          usage(argv[0], e.what());
        }
      }
    } else if (opt == "--max-seconds") {
      args.max_seconds = parse_double(argv[0], value);
      if (!(args.max_seconds > 0)) usage(argv[0], "--max-seconds must be > 0");
    } else if (opt == "--clock") {
      if (value != "wall" && value != "cpu") usage(argv[0], "--clock is wall or cpu");
      args.cpu_clock = value == "cpu";
    } else if (opt == "--site-order") {
      if (value != "input" && value != "hilbert") usage(argv[0], "--site-order is input or hilbert");
      args.hilbert_ids = value == "hilbert";
    } else {
      usage(argv[0], "unknown option " + opt);
    }
  }
  return args;
}

using geovor::bench::cpu_model;

// ---- Query generators ----

// 53 random bits to a double in [0, 1), as tests/support/generators.cpp.
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

Vec3 normalized(const Vec3& p) { return (1.0 / std::sqrt(geovor::norm2(p))) * p; }

// A unit vector orthogonal to the unit vector p.
Vec3 any_orthogonal(const Vec3& p) {
  const Vec3 axis = std::abs(p.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return normalized(geovor::cross(p, axis));
}

// The fixed centre of scenario I's caps: a generic direction (no axis, no cube face centre).
const Vec3 kCapCentre = normalized(Vec3{0.3, -0.5, 0.8});

/// Scenario I: m points uniform in the cap of area fraction f of the sphere around kCapCentre.
std::vector<Vec3> cap_queries(std::size_t m, double fraction, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  const Vec3 c = kCapCentre, u = any_orthogonal(c), v = geovor::cross(c, u);
  const double hmax = 2 * fraction;  // cap height: area 2 pi h = fraction * 4 pi
  std::vector<Vec3> out;
  out.reserve(m);
  for (std::size_t i = 0; i < m; ++i) {
    const double h = hmax * uniform01(rng);  // 1 - cos(angle to c): uniform in area
    const double r = std::sqrt(h * (2 - h));
    const double phi = 2 * kPi * uniform01(rng);
    out.push_back(normalized((1 - h) * c + r * (std::cos(phi) * u + std::sin(phi) * v)));
  }
  return out;
}

/// Scenario II: w walkers, round-robin; step_rad along the heading, then a random turn.
std::vector<Vec3> walker_queries(std::size_t m, std::size_t w, double step_rad, double turn_rad,
                                 std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec3> pos(w), heading(w);
  for (std::size_t i = 0; i < w; ++i) {
    Vec3 p;
    do {
      p = {2 * uniform01(rng) - 1, 2 * uniform01(rng) - 1, 2 * uniform01(rng) - 1};
    } while (geovor::norm2(p) > 1 || geovor::norm2(p) < 1e-6);
    pos[i] = normalized(p);
    const Vec3 u = any_orthogonal(pos[i]), v = geovor::cross(pos[i], u);
    const double phi = 2 * kPi * uniform01(rng);
    heading[i] = std::cos(phi) * u + std::sin(phi) * v;
  }
  const double cs = std::cos(step_rad), sn = std::sin(step_rad);
  std::vector<Vec3> out;
  out.reserve(m);
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t i = k % w;
    Vec3& p = pos[i];
    Vec3& t = heading[i];
    out.push_back(p);
    // Move along the great circle of the heading, carrying the heading along.
    const Vec3 np = normalized(cs * p + sn * t);
    Vec3 nt = cs * t - sn * p;
    // Turn the heading about the new position.
    const double beta = turn_rad * (2 * uniform01(rng) - 1);
    nt = std::cos(beta) * nt + std::sin(beta) * geovor::cross(np, nt);
    nt = normalized(nt - geovor::dot(nt, np) * np);
    p = np;
    t = nt;
  }
  return out;
}

// ---- k-d tree (nanoflann) ----

struct SiteCloud {
  const std::vector<Vec3>* pts;
  std::size_t kdtree_get_point_count() const { return pts->size(); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const {
    const Vec3& p = (*pts)[i];
    return d == 0 ? p.x : d == 1 ? p.y : p.z;
  }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, SiteCloud>, SiteCloud, 3,
                                                   std::uint32_t>;

std::uint32_t kd_nearest(const KdTree& tree, const Vec3& q) {
  const double qq[3] = {q.x, q.y, q.z};
  std::uint32_t index = 0;
  double dist2 = 0;
  tree.knnSearch(qq, 1, &index, &dist2);
  return index;
}

// ---- One scenario row ----

struct Timing {
  double best = 1e300;
  int runs = 0;
  std::uint64_t checksum = 0;
  geovor::LocatorStats stats;
  bool done = false;        // no more runs (slow)
  bool complete = false;    // some run did every query (best and checksum are from such runs)
  std::size_t partial = 0;  // if !complete: the run was cut short after this many queries
};

struct RowResult {
  std::string scenario, param;
  std::vector<Timing> strategies;
  Timing kd, kd_hilbert, cgal;
  std::size_t sample = 0, strategy_mismatches = 0, kd_ties = 0, kd_wrong = 0;
  bool checksums_agree = true;
};

double chord(const Vec3& a, const Vec3& b) { return std::sqrt(geovor::norm2(a - b)); }

struct Bench {
  const Args& args;
  const geovor::DelaunayHierarchy& h;
  const std::vector<Vec3>& sites;
  const KdTree& kd;
  const geovor::testing::CgalSphereLocator* cgal;
  const KdTree* kd_hilbert;                       // the same sites in Hilbert order (--kd-hilbert)
  const std::vector<std::uint32_t>* hilbert_ids;  // its point i is site hilbert_ids[i]

  RowResult run(const std::string& scenario, const std::string& param, const std::vector<Vec3>& queries) const {
    RowResult row;
    row.scenario = scenario;
    row.param = param;
    row.strategies.resize(args.strategies.size());
    auto note = [&](Timing& t, double s, std::uint64_t sum) {
      t.best = t.complete ? std::min(t.best, s) : s;
      t.checksum = sum;
      t.complete = true;
      ++t.runs;
      if (s > args.max_seconds) t.done = true;
    };
    // A run cut short after `done` queries: its time scaled to the whole stream, no checksum;
    // the method is not run again.
    auto note_partial = [&](Timing& t, double s, std::size_t done) {
      ++t.runs;
      t.done = true;
      if (t.complete) return;
      t.partial = done;
      t.best = std::min(t.best, s * static_cast<double>(queries.size()) / static_cast<double>(done));
    };
    for (int r = 0; r < args.repeat; ++r) {
      for (std::size_t k = 0; k < args.strategies.size(); ++k) {
        Timing& t = row.strategies[k];
        if (t.done) continue;
        geovor::LocatorOptions options;
        options.strategy = args.strategies[k];
        geovor::Locator locator(h, options);
        locator.prepare();  // the keeper's WalkGraph, not built again
        std::uint64_t sum = 0;
        std::size_t done = 0;
        const double t0 = now_s();
        double t1 = t0;
        // In blocks, so that a hopeless strategy (a plain walk across 2^20 sites) can be cut
        // short after max_seconds: its rate is then measured on the queries it did.
        while (done < queries.size()) {
          const std::size_t end = std::min(queries.size(), done + 4096);
          for (; done < end; ++done) sum += locator.nearest(queries[done]).site;
          t1 = now_s();
          if (t1 - t0 > args.max_seconds) break;
        }
        const double secs = t1 - t0;
        if (done < queries.size()) {
          note_partial(t, secs, done);
        } else {
          note(t, secs, sum);
        }
        if (done == queries.size() || !t.complete) t.stats = locator.stats();
      }
      if (!row.kd.done) {
        std::uint64_t sum = 0;
        const double t0 = now_s();
        for (const Vec3& q : queries) sum += kd_nearest(kd, q);
        note(row.kd, now_s() - t0, sum);
      }
      if (kd_hilbert != nullptr && !row.kd_hilbert.done) {  // answers mapped back to site ids
        std::uint64_t sum = 0;
        const double t0 = now_s();
        for (const Vec3& q : queries) sum += (*hilbert_ids)[kd_nearest(*kd_hilbert, q)];
        note(row.kd_hilbert, now_s() - t0, sum);
      }
      if (cgal != nullptr && !row.cgal.done) {
        std::uint64_t sum = 0;
        std::size_t done = 0;
        const double s = cgal->locate_seconds(queries, &sum, args.max_seconds, &done);
        if (done < queries.size()) {
          note_partial(row.cgal, s, done);
        } else {
          note(row.cgal, s, sum);
        }
      }
    }
    const Timing* full = nullptr;  // checksums of the runs that did every query
    for (const Timing& t : row.strategies) {
      if (!t.complete) continue;
      if (full == nullptr) full = &t;
      if (t.checksum != full->checksum) row.checksums_agree = false;
    }

    // Agreement on a sample, in stream order, with fresh locators (not timed).
    if (args.sample > 0 && !args.strategies.empty()) {
      const std::size_t stride = std::max<std::size_t>(1, queries.size() / args.sample);
      std::vector<Vec3> sample;
      for (std::size_t i = 0; i < queries.size() && sample.size() < args.sample; i += stride)
        sample.push_back(queries[i]);
      row.sample = sample.size();
      std::vector<geovor::SiteId> reference;
      for (std::size_t k = 0; k < args.strategies.size(); ++k) {
        geovor::LocatorOptions options;
        options.strategy = args.strategies[k];
        geovor::Locator locator(h, options);
        for (std::size_t i = 0; i < sample.size(); ++i) {
          const geovor::SiteId s = locator.nearest(sample[i]).site;
          if (k == 0) {
            reference.push_back(s);
          } else if (s != reference[i]) {
            ++row.strategy_mismatches;
          }
        }
      }
      for (std::size_t i = 0; i < sample.size(); ++i) {
        const std::uint32_t s = kd_nearest(kd, sample[i]);
        if (s == reference[i]) continue;
        if (std::abs(chord(sample[i], sites[s]) - chord(sample[i], sites[reference[i]])) > 1e-15) {
          ++row.kd_wrong;
        } else {
          ++row.kd_ties;
        }
      }
    }
    return row;
  }
};

double mqps(const Timing& t, std::size_t m) { return t.runs ? static_cast<double>(m) / t.best / 1e6 : 0.0; }

const char* short_name(geovor::LocateStrategy s) {
  switch (s) {
    case geovor::LocateStrategy::Walk: return "walk";
    case geovor::LocateStrategy::JumpWalk: return "jump-w";
    case geovor::LocateStrategy::KeepJumpWalk: return "kj-walk";
    case geovor::LocateStrategy::Hierarchy: return "hierarchy";
    case geovor::LocateStrategy::Climb: return "climb";
    case geovor::LocateStrategy::KeepJumpClimb: return "kj-climb";
  }
  return "?";
}

}  // namespace

int main(int argc, char** argv) {
  const Args args = parse_args(argc, argv);
  g_cpu_clock = args.cpu_clock;
  std::printf("geovor_bench_locate: Locator::nearest (every strategy) vs nanoflann k-d tree (knnSearch k=1, L2 on the"
              " unit vectors) vs CGAL Delaunay_triangulation_on_sphere_2::locate (Epick, hint = previous face)\n");
  std::printf("machine: %s, %u hardware threads; every run on a single thread\n", cpu_model().c_str(),
              std::thread::hardware_concurrency());
#ifndef NDEBUG
  std::printf("WARNING: assertions enabled (not a Release build): times are not representative\n");
#endif
  const double spacing = std::sqrt(4 * kPi / static_cast<double>(args.sites));
  std::printf("sites: %zu uniform (seed %llu), ids in %s order; queries per row: %zu; times: best of %d runs (a method whose run"
              " exceeds %.0f s is not repeated), %s\n",
              args.sites, static_cast<unsigned long long>(args.seed),
              args.hilbert_ids ? "Hilbert-curve (--site-order hilbert)" : "input (random)", args.queries, args.repeat, args.max_seconds,
              args.cpu_clock ? "thread CPU time (--clock cpu; CGAL: wall)" : "wall clock");
  std::printf("scenario I: uniform in a cap (area fraction f) around a fixed centre; scenario II: W walkers"
              " round-robin, step %.3g x mean spacing sqrt(4pi/n) = %.3g rad (%.1f km), turn +-%.2f rad per step\n",
              args.step, args.step * spacing, args.step * spacing * 6371.0088, args.turn);

  // ---- Builds (not part of any rate) ----
  std::vector<Vec3> points = geovor::testing::uniform_on_sphere(args.sites, args.seed);
  if (args.hilbert_ids) {  // the same sites, numbered along the Hilbert curve
    const std::vector<std::uint32_t> order = geovor::hilbert_order(points);
    std::vector<Vec3> sorted(points.size());
    for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = points[order[i]];
    points = std::move(sorted);
  }
  auto t0 = Clock::now();
  const geovor::DelaunayHierarchy h = geovor::DelaunayHierarchy::build(points);
  auto t1 = Clock::now();
  const double hierarchy_s = std::chrono::duration<double>(t1 - t0).count();
  const geovor::SphericalDelaunay& base = h.base();
  std::vector<Vec3> sites(base.site_capacity());
  for (geovor::SiteId s = 0; s < sites.size(); ++s) sites[s] = base.site(s);
  std::string levels;
  for (int l = 0; l < h.num_levels(); ++l) {
    if (l > 0) levels += '/';
    levels += std::to_string(h.level(l).num_sites());
  }
  std::printf("build: DelaunayHierarchy %.3f s (%d levels, sites %s)", hierarchy_s, h.num_levels(), levels.c_str());
  // The Locators' shared packed copy (WalkGraph), built once here and held for the whole run:
  // every timed Locator gets it without building (it is otherwise built at a Locator's first query).
  geovor::Locator keeper(h);
  t0 = Clock::now();
  keeper.prepare();
  t1 = Clock::now();
  if (keeper.walk_graph() != nullptr)
    std::printf("; WalkGraph %.3f s (%.1f bytes/site)", std::chrono::duration<double>(t1 - t0).count(),
                static_cast<double>(keeper.walk_graph()->memory_bytes()) / static_cast<double>(base.num_sites()));

  const SiteCloud cloud{&sites};
  t0 = Clock::now();
  const KdTree kd(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(args.leaf));
  t1 = Clock::now();
  std::printf("; k-d tree %.3f s (leaf size %zu)", std::chrono::duration<double>(t1 - t0).count(), args.leaf);
  // Optional extra reference: a k-d tree over the same sites renumbered along the Hilbert curve,
  // to show how much of the k-d tree's time is memory layout (the targets use the plain one).
  std::vector<std::uint32_t> hilbert_ids;
  std::vector<Vec3> hilbert_sites;
  std::unique_ptr<KdTree> kd_hilbert;
  const SiteCloud hilbert_cloud{&hilbert_sites};
  if (args.kd_hilbert) {
    hilbert_ids = geovor::hilbert_order(sites);
    for (const std::uint32_t i : hilbert_ids) hilbert_sites.push_back(sites[i]);
    t0 = Clock::now();
    kd_hilbert = std::make_unique<KdTree>(3, hilbert_cloud, nanoflann::KDTreeSingleIndexAdaptorParams(args.leaf));
    t1 = Clock::now();
    std::printf("; Hilbert-ordered k-d tree %.3f s", std::chrono::duration<double>(t1 - t0).count());
  }
  std::unique_ptr<geovor::testing::CgalSphereLocator> cgal;
  if (args.cgal) {
    double cgal_s = 0;
    cgal = std::make_unique<geovor::testing::CgalSphereLocator>(sites, &cgal_s);
    std::printf("; CGAL %.3f s (%zu vertices)", cgal_s, cgal->num_vertices());
  }
  std::printf("\n");
  const double n = static_cast<double>(base.num_sites());
  std::printf("landmarks (LocatorOptions defaults): jump-walk n^(1/3) = %u sampled, keep-jump-walk n^(3/8) = %u kept,"
              " keep-jump-climb log2(n) = %u kept\n",
              static_cast<unsigned>(std::cbrt(n)), static_cast<unsigned>(std::pow(n, 0.375)),
              static_cast<unsigned>(std::log2(n)));
  std::printf("rates in millions of queries per second (Mq/s); kjc/kd and kjc/hier are ratios of kj-climb's rate to the"
              " k-d tree's and to hierarchy's;\ncolumns: walk, jump-w = jump-walk, kj-walk = keep-jump-walk, hierarchy, climb,"
              " kj-climb = keep-jump-climb, kd-tree = nanoflann, cgal = CGAL locate (a face, not the nearest site);\nkd-hilb = the k-d tree over the sites in Hilbert order (--kd-hilbert, not a target), kjc/kdh its ratio;\n* = run cut short after --max-seconds %.0f s, rate over the queries done"
              " (LocatorStats likewise)\n\n", args.max_seconds);

  // ---- Header ----
  std::printf("%-12s %-7s", "scenario", "param");
  for (const geovor::LocateStrategy s : args.strategies) std::printf(" %9s", short_name(s));
  std::printf(" %9s %9s %7s %8s", "kd-tree", "cgal", "kjc/kd", "kjc/hier");
  if (args.kd_hilbert) std::printf(" %9s %8s", "kd-hilb", "kjc/kdh");
  std::printf("\n");
  std::fflush(stdout);

  const Bench bench{args, h, sites, kd, cgal.get(), kd_hilbert.get(), &hilbert_ids};
  std::vector<RowResult> rows;
  auto find = [&](const RowResult& row, geovor::LocateStrategy s) -> const Timing* {
    for (std::size_t k = 0; k < args.strategies.size(); ++k)
      if (args.strategies[k] == s) return &row.strategies[k];
    return nullptr;
  };
  auto print_row = [&](const RowResult& row) {
    std::printf("%-12s %-7s", row.scenario.c_str(), row.param.c_str());
    for (const Timing& t : row.strategies) {
      if (!t.complete) {
        std::printf(" %8.3f*", mqps(t, args.queries));
      } else {
        std::printf(" %9.3f", mqps(t, args.queries));
      }
    }
    std::printf(" %9.3f", mqps(row.kd, args.queries));
    if (cgal) {
      std::printf(!row.cgal.complete ? " %8.3f*" : " %9.3f", mqps(row.cgal, args.queries));
    } else {
      std::printf(" %9s", "-");
    }
    const Timing* kjc = find(row, geovor::LocateStrategy::KeepJumpClimb);
    const Timing* hier = find(row, geovor::LocateStrategy::Hierarchy);
    if (kjc != nullptr) {
      std::printf(" %7.2f", row.kd.best / kjc->best);
      if (hier != nullptr) {
        std::printf(" %8.2f", hier->best / kjc->best);
      } else {
        std::printf(" %8s", "-");
      }
      if (args.kd_hilbert) std::printf(" %9.3f %8.2f", mqps(row.kd_hilbert, args.queries), row.kd_hilbert.best / kjc->best);
    }
    std::printf("\n");
    std::fflush(stdout);
  };

  std::uint64_t qseed = args.seed * 1000003 + 17;
  for (const double f : args.fractions) {
    char param[32];
    std::snprintf(param, sizeof param, "%g%%", f * 100);
    const std::vector<Vec3> queries = cap_queries(args.queries, f, ++qseed);
    rows.push_back(bench.run("I-proximity", param, queries));
    print_row(rows.back());
  }
  for (const double w : args.walkers) {
    char param[32];
    std::snprintf(param, sizeof param, "%g", w);
    const std::vector<Vec3> queries =
        walker_queries(args.queries, static_cast<std::size_t>(w), args.step * spacing, args.turn, ++qseed);
    rows.push_back(bench.run("II-walkers", param, queries));
    print_row(rows.back());
  }

  // ---- LocatorStats ----
  std::printf("\nLocatorStats per query: steps (double walk steps, all levels) / climbs / exact_steps (certifying walk)\n");
  std::printf("%-12s %-7s", "scenario", "param");
  for (const geovor::LocateStrategy s : args.strategies) std::printf(" %20s", short_name(s));
  std::printf("\n");
  for (const RowResult& row : rows) {
    std::printf("%-12s %-7s", row.scenario.c_str(), row.param.c_str());
    for (const Timing& t : row.strategies) {
      const double q = static_cast<double>(std::max<std::uint64_t>(t.stats.queries, 1));
      char cell[64];
      std::snprintf(cell, sizeof cell, "%.2f/%.3f/%.3f", static_cast<double>(t.stats.steps) / q,
                    static_cast<double>(t.stats.climbs) / q, static_cast<double>(t.stats.exact_steps) / q);
      std::printf(" %20s", cell);
    }
    std::printf("\n");
  }

  // ---- Checks ----
  std::printf("\nchecks: checksum = sum of the answers' site ids over all queries (must be equal for every strategy);"
              " sample = every (queries/K)-th query:\n  strategies' answers compared with %s's (must agree);"
              " k-d tree: other site at equal distance (|chord difference| <= 1e-15, a tie) / farther site\n",
              args.strategies.empty() ? "-" : geovor::to_string(args.strategies.front()));
  std::printf("%-12s %-7s %12s %8s %10s %8s %8s %s\n", "scenario", "param", "checksums", "sample", "strat_diff",
              "kd_tie", "kd_wrong", "runs(strategies,kd,cgal)");
  bool all_ok = true;
  for (const RowResult& row : rows) {
    std::string runs;
    for (const Timing& t : row.strategies) runs += std::to_string(t.runs) + ",";
    runs += std::to_string(row.kd.runs) + "," + std::to_string(row.cgal.runs);
    std::printf("%-12s %-7s %12s %8zu %10zu %8zu %8zu %s\n", row.scenario.c_str(), row.param.c_str(),
                row.checksums_agree ? "equal" : "DIFFER", row.sample, row.strategy_mismatches, row.kd_ties,
                row.kd_wrong, runs.c_str());
    if (!row.checksums_agree || row.strategy_mismatches != 0) all_ok = false;
  }
  std::printf("strategies agree: %s\n", all_ok ? "yes" : "NO");

  // ---- Targets (reported, not asserted) ----
  std::printf("\ntargets:\n");
  bool have_kjc = false;
  for (const RowResult& row : rows) {
    const Timing* kjc = find(row, geovor::LocateStrategy::KeepJumpClimb);
    const Timing* hier = find(row, geovor::LocateStrategy::Hierarchy);
    if (kjc == nullptr) continue;
    have_kjc = true;
    if (row.scenario == "II-walkers" && std::atof(row.param.c_str()) <= 4) {
      const double r = row.kd.best / kjc->best;
      std::printf("  %-12s %-5s kj-climb / k-d tree   = %5.2f (target >= 2)  %s\n", row.scenario.c_str(),
                  row.param.c_str(), r, r >= 2 ? "holds" : "MISSED");
    }
    if (hier != nullptr) {
      const double r = hier->best / kjc->best;
      std::printf("  %-12s %-5s kj-climb / hierarchy  = %5.2f (target >= 1)  %s\n", row.scenario.c_str(),
                  row.param.c_str(), r, r >= 1 ? "holds" : "MISSED");
    }
  }
  if (!have_kjc) std::printf("  (keep-jump-climb not run)\n");
  return all_ok ? 0 : 1;
}
