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
/// The walks run on a WalkGraph (walk_graph.hpp), a Hilbert-ordered packed copy of the hierarchy
/// shared by the Locators of one hierarchy state, built once the stream is long enough to pay
/// for it (LocatorOptions::packed, rebuild_after) or by prepare().
/// Keep Jump & Climb climbs from its best landmark when that is near (LocatorOptions::
/// far_spacings); otherwise it starts from the site the packed copy's Hilbert-curve sample gives
/// for q (WalkGraph::curve_start) when that one is near, or else jumps to the landmark's own
/// nearest site on a level whose spacing suits the distance and descends from there.
///
/// Certification: the last walk's final ring certifies the answer when every neighbour's dot
/// product is below the answer's by more than 1e-15 |q|_1. Each dot product of q with a site
/// (|p| <= 1 + 2^-50) computed in doubles without FMA is within gamma_3 sum |q_i p_i| <=
/// 3.34e-16 |q|_1 of the exact value, so that margin exceeds both errors and the answer is
/// strictly nearer than every neighbour, hence the unique nearest site. Otherwise the exact walk
/// (kernel::compare_dot, ties to the lowest id) decides.
///
/// Weighted sites (DelaunayHierarchy::build with lifts; docs/weighted.md): the answer is the site
/// whose power cell holds q, the site of largest power dot(q, p) / c, found by the same walks on
/// the lifted points p / c (the hull's vertex graph again), certified with the margin above
/// times DelaunayHierarchy::lifted_norm_bound() (the lifted points' rounding included), else by
/// kernel::compare_power. Hidden sites own no cell and are never an answer. k_nearest,
/// nearest_first and within take the sites by decreasing power; distances stay great-circle
/// metres to the sites' centres; nearest_geodesic refuses weighted sites.
///
/// A Locator is not thread-safe (it keeps its landmarks); use one per thread, or
/// nearest_batch(). It refers to the hierarchy, which must outlive it. It notices any change of
/// the hierarchy (insert, remove, moves: SphericalDelaunay::revision()) at the next query: it
/// forgets its landmarks and walks the hierarchy itself until the packed copy is rebuilt
/// (LocatorOptions::rebuild_after).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/locate/delaunay_hierarchy.hpp"
#include "geovor/locate/walk_graph.hpp"

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
  /// Walk the shared packed copy of the hierarchy (WalkGraph: about 68 bytes per site, built in
  /// O(n log n), about as long as the hierarchy's own build) once rebuild_after queries have been
  /// answered (or after prepare()); false: always walk the hierarchy's triangulations. The answers
  /// are the same. DEFAULT: true.
  bool packed = true;
  /// The queries walk the hierarchy itself until this many have been answered with no change of
  /// the hierarchy (counted from the first query, and again after every change); then the packed
  /// copy is built or fetched, so that a short stream never pays for it and a long one spreads its
  /// cost. 0 means max(1024, n / 8). DEFAULT: 0.
  std::uint64_t rebuild_after = 0;
  /// KeepJumpClimb: when the best landmark is farther from the query than this many mean site
  /// spacings sqrt(4 pi / n) (radians), do not climb from it. Climb instead from the packed
  /// copy's curve site for q if that is within this distance; otherwise jump to the nearest site
  /// the landmark's own query had on the lowest level l >= 1 whose mean spacing sqrt(4 pi / n_l)
  /// times level_spacings exceeds the distance, walk there and descend; with no such site known,
  /// descend from the top. DEFAULT: 8.
  double far_spacings = 8;
  /// See far_spacings. DEFAULT: 3.
  double level_spacings = 3;
};

/// One answer: a level-0 site and its distance.
struct NearestResult {
  SiteId site = kNoIndex;
  double dist_m = 0;  ///< great-circle metres (geodesic metres for nearest_geodesic)
};

/// Counters for the benchmark: how much walking the queries took. climbs counts the levels
/// climbed and Keep Jump & Climb's jumps to a landmark's site on a level above; exact_steps the
/// moves of the exact walk (run only when the last ring's margin does not certify the answer).
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
  /// Every site within radius_m metres (great circle), nearest first (weighted: by power).
  std::vector<NearestResult> within(const Vec3& q, double radius_m);
  /// Visits the sites in order of nearness to q (the exact order, ties to the lower id), from
  /// nearest(q) on, until visit(site, its unit vector) returns false or every site was visited:
  /// a best-first search on the Delaunay graph (the sites nearer to q than any given site form a
  /// connected part of it). What k_nearest, within and locate/knn.hpp are made of.
  void nearest_first(const Vec3& q, const std::function<bool(SiteId, const Vec3&)>& visit);
  /// The nearest site on the WGS84 ellipsoid (geodesic distance, GeographicLib), ties to the
  /// lowest id. @exception Error(InvalidArgument) for weighted sites. Sites are taken in order of their spherical angle to q until the lower bound
  /// 2 b sin(angle / 2) of the geodesic distance of every site not yet seen (b: polar radius;
  /// every site is at least b from the centre, a geodesic is no shorter than the chord) exceeds
  /// the best geodesic distance found.
  NearestResult nearest_geodesic(double lat_deg, double lon_deg);

  /// Forgets the landmarks and the previous answer (done by itself when the hierarchy changes).
  void reset();
  /// Gets the packed copy now (DelaunayHierarchy::walk_graph(): built unless current) rather than at
  /// the first query; copies of this Locator share it. No effect without options().packed.
  void prepare();
  /// The packed copy in use, or null (not yet built, walking the hierarchy after a change, or
  /// options().packed is false).
  const WalkGraph* walk_graph() const { return graph_.get(); }
  const LocatorStats& stats() const { return stats_; }
  const DelaunayHierarchy& hierarchy() const { return *h_; }
  const LocatorOptions& options() const { return options_; }

 private:
  static constexpr int kMaxLevels = 16;  // HierarchyOptions::max_levels <= 16
  using Path = std::array<std::uint32_t, kMaxLevels>;
  struct Landmark {
    Vec3 p;      // the site's coordinates, so that jumping reads no graph
    Path nodes;  // nodes[l]: the nearest level-l site of the kept query, kNoIndex if not found;
                 // nodes in the view walked (WalkGraph nodes, or site ids)
  };
  void sync();
  template <class G>
  SiteId locate(const G& g, const Vec3& q);
  template <class G>
  std::uint32_t walk(const G& g, int level, const Vec3& q, std::uint32_t v, bool stop_at_up, bool* climb,
                     double* margin);
  template <class G>
  std::uint32_t climb_and_descend(const G& g, const Vec3& q, std::uint32_t v, double* margin);
  template <class G>
  std::uint32_t descend(const G& g, const Vec3& q, int level, std::uint32_t v, double* margin);
  template <class G>
  std::uint32_t from_top(const G& g, const Vec3& q, double* margin);
  template <class G>
  std::uint32_t from_level(const G& g, const Vec3& q, int level, std::uint32_t v, double* margin);
  SiteId certify(const Vec3& q, SiteId v);
  SiteId explore_plateau(const Vec3& q, SiteId& v);

  const DelaunayHierarchy* h_;
  LocatorOptions options_;
  std::uint32_t num_landmarks_ = 0;
  std::array<double, kMaxLevels> cos_start_{};  // KeepJumpClimb: start on level l if dot(q, p) >= it
  Path path_{};                      // the nearest site of this query on each level walked to its end
  std::vector<SiteId> sample_;       // JumpWalk's fixed sample (site ids)
  std::vector<Landmark> landmarks_;  // ring buffer of kept answers, or the fixed sample
  bool landmarks_ready_ = false;     // the sample is in landmarks_ (nodes of the view walked)
  std::size_t next_landmark_ = 0;
  Landmark last_{};                  // the previous answer (last_.nodes[0] == kNoIndex: none)
  std::shared_ptr<const WalkGraph> graph_;  // null: walk the hierarchy itself
  std::vector<std::uint64_t> seen_;          // the levels' revisions at the last query
  std::uint64_t unchanged_queries_ = 0;      // queries since the hierarchy last changed
  LocatorStats stats_;
};

/// nearest() for every query, split over `threads` threads (core/parallel.hpp: contiguous slices,
/// each with its own Locator); the results are identical to one thread's (every answer is exact).
void nearest_batch(const DelaunayHierarchy& hierarchy, std::span<const Vec3> queries,
                   std::span<NearestResult> out, int threads, const LocatorOptions& options = {});

/// Great-circle distance in metres between two unit vectors (atan2 form, accurate at all angles).
double great_circle_m(const Vec3& a, const Vec3& b);

/// A lower bound of the great-circle distance (metres) from q of every site whose power at q is
/// at most that of the weighted site (p, lift): cos d <= power for lifts <= 1. What ends a
/// search by power for the sites within a distance.
double power_lower_bound_m(const Vec3& q, const Vec3& p, double lift);

}  // namespace geovor
