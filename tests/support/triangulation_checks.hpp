/// \file triangulation_checks.hpp
/// \brief Checks shared by the tests of lib/src/delaunay/: triangle sets, checked builds, and
/// "equals a fresh build" after edits or moves.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "support/cgal_oracle.hpp"

namespace geovor::testing {

/// The triangles, each rotated to start at its smallest site (renamed by `label` when given), sorted.
std::vector<Tri> triangle_set(const SphericalDelaunay& dt, const std::vector<std::uint32_t>& label = {});

/// build() then validate(report, global), expected to pass.
SphericalDelaunay build_checked(const std::vector<Vec3>& pts, BuildReport* report = nullptr, bool global = false,
                                const DelaunayOptions& options = {});

/// validate() passes and the triangles are those of a fresh build of the live sites' positions
/// (in id order, so the perturbation orders them alike).
void expect_as_rebuilt(const SphericalDelaunay& dt, const std::string& what);

/// p displaced by a random vector of norm about `step`, normalised.
Vec3 jitter(const Vec3& p, double step, std::mt19937_64& rng);

/// The sites of datasets/weather_stations.csv, without its exact duplicates.
std::vector<Vec3> weather_station_sites();

}  // namespace geovor::testing
