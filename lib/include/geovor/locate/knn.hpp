/// \file knn.hpp
/// \brief The k nearest sites, and every site within a distance, under either metric: great
/// circles on the mean-radius sphere, or WGS84 geodesics (GeographicLib).
///
/// Both run on Locator::nearest_first (the sites in order of their spherical angle to the query).
/// The sphere answers are the first sites of that order. The geodesic ones take sites in that
/// order until the lower bound 2 b sin(angle / 2) of the geodesic distance of every site not yet
/// seen (b: the polar radius; every site is at least b from the centre and a geodesic is no
/// shorter than the chord; less a margin for rounding and GeographicLib's 15 nm accuracy) exceeds
/// the k-th geodesic distance found, or the radius. Ties go to the lower site index.
///
/// Weighted sites (docs/weighted.md) have one metric, power: the sites in order of decreasing
/// power, the first being the one whose power cell holds the query; distance_m stays the
/// great-circle distance to the site's centre. The sphere and geodesic metrics need unweighted
/// sites; on unweighted sites power is the sphere metric.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "geovor/locate/locator.hpp"

namespace geovor {

/// The distance between a query and a site.
enum class Metric {
  Sphere,    ///< great-circle metres between the geocentric directions, radius SiteEncoder::kEarthRadiusM
  Geodesic,  ///< WGS84 geodesic metres between the geodetic positions (GeographicLib)
  Power,     ///< weighted sites by decreasing power (unweighted: as Sphere); great-circle metres
};

/// "sphere", "geodesic" or "power".
const char* to_string(Metric m);
/// Parses a name of to_string(); @exception Error(InvalidArgument) for any other name.
Metric parse_metric(const std::string& name);

/// The metric of `hierarchy` when none is asked: Power for weighted sites, else Sphere.
Metric default_metric(const DelaunayHierarchy& hierarchy);
/// @exception Error(InvalidArgument) naming the metric when `metric` does not apply to the sites
///   of `hierarchy` (sphere or geodesic on weighted sites).
void check_metric(const DelaunayHierarchy& hierarchy, Metric metric);

/// The k nearest sites to (lat_deg, lon_deg) under `metric`, nearest first (ties to the lower
/// site index), into `out` (replaced; fewer than k when there are fewer sites).
/// @exception Error(InvalidArgument) as check_metric.
void k_nearest(Locator& locator, double lat_deg, double lon_deg, std::size_t k, Metric metric,
               std::vector<NearestResult>& out);

/// One query's answers as `geovor nearest`, the service and Python give them: its k nearest sites
/// under `metric` (k = 1: the Locator's own walk, or nearest_geodesic()), those farther than
/// max_distance_m left out, into `out` (replaced). @exception Error(InvalidArgument) as check_metric.
void nearest_within(Locator& locator, double lat_deg, double lon_deg, std::size_t k, Metric metric,
                    double max_distance_m, std::vector<NearestResult>& out);

/// Every site at most max_distance_m metres from (lat_deg, lon_deg) under `metric`, nearest first
/// (ties to the lower site index; Power: by decreasing power), into `out` (replaced; empty for a
/// negative or NaN distance). @exception Error(InvalidArgument) as check_metric.
void within(Locator& locator, double lat_deg, double lon_deg, double max_distance_m, Metric metric,
            std::vector<NearestResult>& out);

}  // namespace geovor
