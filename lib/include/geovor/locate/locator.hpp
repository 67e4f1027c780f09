/// \file locator.hpp
/// \brief Exact nearest-site queries for streams of points: Keep, Jump & Climb and the other
/// strategies of de Castro's thesis (Ch. 7-8), over a DelaunayHierarchy.
///
/// The nearest site of a unit vector q is the site p maximising dot(q, p): for unit vectors the
/// angular order, and for the stored doubles exactly the order of the triangulation (each site's
/// Voronoi cell is the set of directions where it is the maximum). On the triangulation's graph,
/// which is the vertex graph of the sites' convex hull, a site none of whose neighbours is better
/// is the best of all (the simplex method's argument), so a greedy walk finds the nearest site
/// from anywhere. Every strategy below only chooses where that walk starts and how far it goes
/// at each level; they run in plain doubles (structural filtering, thesis §8.5.4), and a last walk
/// with the exact comparison kernel::compare_dot certifies the answer. Ties (q equidistant from
/// several sites) go to the lowest site index; the tied sites are found exactly.
///
/// Distances are great-circle metres on the sphere of radius SiteEncoder::kEarthRadiusM between
/// the geocentric directions (see geo/site_encoder.hpp). With nearest_geodesic() the answer is the
/// nearest site on the WGS84 ellipsoid instead (GeographicLib's geodesics).
///
/// A Locator is not thread-safe (it keeps its landmarks); use one per thread, or
/// nearest_batch(). It refers to the hierarchy, which must outlive it; after the hierarchy changes
/// (insert, remove), call reset().
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/locate/delaunay_hierarchy.hpp"

namespace geovor {

/// Where the walk to the nearest site starts (thesis Ch. 7-8).
enum class LocateStrategy {
  Walk,           ///< from the previous query's answer
  JumpWalk,       ///< from the nearest of a fixed random sample of sites (Jump & Walk)
  KeepJumpWalk,   ///< from the nearest of the last answers kept as landmarks
  Hierarchy,      ///< descend the hierarchy from its top level
  Climb,          ///< from the previous answer, climbing the hierarchy while the walk is long
  KeepJumpClimb,  ///< from the nearest landmark, climbing (the default)
};

/// The strategy's name as on the command line: walk, jump-walk, keep-jump-walk, hierarchy, climb,
/// keep-jump-climb.
const char* to_string(LocateStrategy s);
/// Parses a name of to_string(); @exception Error(InvalidArgument) for an unknown name.
LocateStrategy parse_strategy(const std::string& name);

/// Options of Locator; every default is documented.
struct LocatorOptions {
  /// DEFAULT: KeepJumpClimb.
  LocateStrategy strategy = LocateStrategy::KeepJumpClimb;
  /// Number of landmarks. DEFAULT: 0, meaning the thesis' choice for the strategy on a surface:
  /// n^(1/3) sampled sites for JumpWalk, n^(3/8) kept answers for KeepJumpWalk, and
  /// log2(n) kept answers for KeepJumpClimb.
  std::uint32_t landmarks = 0;
  /// Seed of JumpWalk's sample. DEFAULT: 1.
  std::uint64_t seed = 1;
};

/// One answer: a level-0 site and its distance.
struct NearestResult {
  SiteId site = kNoIndex;
  double dist_m = 0;  ///< great-circle metres (geodesic metres for nearest_geodesic)
};

/// Counters for the benchmark: how much walking the queries took.
struct LocatorStats {
  std::uint64_t queries = 0, steps = 0, exact_steps = 0, climbs = 0;
};

class Locator {
 public:
  /// REQUIRES: `hierarchy` outlives the Locator.
  explicit Locator(const DelaunayHierarchy& hierarchy, const LocatorOptions& options = {});

  /// The nearest site to the unit vector q (kNoIndex if there is no site), ties to the lowest id.
  NearestResult nearest(const Vec3& q);
  /// The k nearest sites, nearest first (exact order, ties to the lower id).
  std::vector<NearestResult> k_nearest(const Vec3& q, std::size_t k);
  /// Every site within radius_m metres (great circle), nearest first.
  std::vector<NearestResult> within(const Vec3& q, double radius_m);
  /// The nearest site on the WGS84 ellipsoid (geodesic distance, GeographicLib), ties to the
  /// lowest id. Sites are taken in order of their spherical angle to q until the lower bound
  /// 2 b sin(angle / 2) of the geodesic distance of every site not yet seen (b: polar radius;
  /// every site is at least b from the centre, a geodesic is no shorter than the chord) exceeds
  /// the best geodesic distance found.
  NearestResult nearest_geodesic(double lat_deg, double lon_deg);

  /// Forgets the landmarks and the previous answer (after the hierarchy changed).
  void reset();
  const LocatorStats& stats() const { return stats_; }
  const LocatorOptions& options() const { return options_; }

 private:
  SiteId start_site(const Vec3& q);
  SiteId walk(int level, const Vec3& q, SiteId v, bool stop_at_up, bool* climb);
  SiteId climb_and_descend(const Vec3& q, SiteId v);
  SiteId descend(const Vec3& q, int level, SiteId v);
  SiteId certify(const Vec3& q, SiteId v);
  SiteId any_site(int level) const;

  const DelaunayHierarchy* h_;
  LocatorOptions options_;
  std::uint32_t num_landmarks_ = 0;
  std::vector<SiteId> landmarks_;  // ring buffer of kept answers, or the fixed sample
  std::size_t next_landmark_ = 0;
  SiteId last_ = kNoIndex;
  LocatorStats stats_;
};

/// nearest() for every query, split over `threads` threads each with its own Locator; the
/// results are identical to one thread's (every answer is exact).
void nearest_batch(const DelaunayHierarchy& hierarchy, std::span<const Vec3> queries,
                   std::span<NearestResult> out, int threads, const LocatorOptions& options = {});

/// Great-circle distance in metres between two unit vectors (atan2 form, accurate at all angles).
double great_circle_m(const Vec3& a, const Vec3& b);

}  // namespace geovor
