/// \file generators.hpp
/// \brief Named deterministic point sets on the unit sphere for tests, oracles and benchmarks.
///
/// Random sets use std::mt19937_64 (its output is fixed by the standard) and turn 53 random bits
/// into doubles by hand, so the same seed gives the same points with any standard library; only
/// the generators that call sin/cos depend on the platform's libm.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "geovor/core/types.hpp"

namespace geovor::testing {

/// p / sqrt(p.p): the normalisation every generator uses (except on_small_circle, see there).
Vec3 normalized(const Vec3& p);

/// `n` points uniform on the sphere (rejection from the cube, no libm call: bit-portable).
std::vector<Vec3> uniform_on_sphere(std::size_t n, std::uint64_t seed);

/// `n` points around `clusters` centres uniform on the sphere, each displaced by up to about
/// `spread_rad` (uniform in a ball of that radius around the centre, then normalised).
std::vector<Vec3> clustered(std::size_t n, std::size_t clusters, double spread_rad, std::uint64_t seed);

/// `n` random points on the equator: z is exactly 0 (all sites on one great circle).
std::vector<Vec3> on_great_circle(std::size_t n, std::uint64_t seed);

/// `n` random points at geocentric latitude `lat_deg`: p = (cos lat cos lon, cos lat sin lon, sin lat),
/// NOT renormalised, so that every point has the bit-identical z = sin lat (co-circular sites).
std::vector<Vec3> on_small_circle(std::size_t n, double lat_deg, std::uint64_t seed);

/// `n` points uniform on the cap z > 0.1 (all sites in one open hemisphere: ghost triangles).
std::vector<Vec3> in_hemisphere(std::size_t n, std::uint64_t seed);

/// Grid lat = lat_min + i step, lon = lon_min + j step (both bounds included, except lon_max when
/// the range spans 360 degrees), plain spherical conversion; a pole in range is given once only.
std::vector<Vec3> lat_lon_grid(double step_deg, double lat_min = -90, double lat_max = 90,
                               double lon_min = -180, double lon_max = 180);

/// The 8 points (+-1, +-1, +-1) / sqrt(3): six groups of four co-circular sites.
std::vector<Vec3> cube_corners();

/// The thesis' hard set S_n: (cos t sin f, sin t sin f, cos f) for t in {0, pi/n, ..., pi},
/// f = (t^2 + 1) pi / 2, then (1,0,0), (0,1,0), (0,0,1), -(1,1,1)/sqrt(3); n + 5 points.
/// The first point (t = 0) is (1, 0, cos(pi/2)) ~ (1, 0, 6e-17): a near-duplicate of (1,0,0).
std::vector<Vec3> skinny_set(std::size_t n);

/// k copies of the north pole (0,0,1), then k of the south pole (0,0,-1) (what any longitude
/// gives at latitude +-90), then rings of k points at latitude +89.9999 and k at -89.9999.
std::vector<Vec3> poles_with_longitudes(std::size_t k);

/// Reads a CSV with a header naming columns lat_deg and lon_deg (RFC 4180 quoting, so names may
/// contain commas) and converts with the plain spherical formulas (benchmarks and oracles only).
/// @exception Error(Io) if the file cannot be read; Error(BadData) for a missing column or bad number.
std::vector<Vec3> load_lat_lon_csv_unit_vectors(const std::string& path);

/// Same, for a gzip-compressed CSV, read through `gzip -dc` (e.g. datasets/geonames_cities.csv.gz).
std::vector<Vec3> load_lat_lon_csv_gz_unit_vectors(const std::string& path);

}  // namespace geovor::testing
