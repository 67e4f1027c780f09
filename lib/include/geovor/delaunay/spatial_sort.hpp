/// \file spatial_sort.hpp
/// \brief Spatially coherent insertion orders on the sphere: Hilbert curves on the cube's faces and
/// BRIO rounds (Amenta, Choi, Rote 2003), as CGAL's spatial_sort does in the plane.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "geovor/core/types.hpp"

namespace geovor {

/// Position of a unit vector along a Hilbert curve drawn on the six faces of the cube
/// (2^20 x 2^20 cells per face). Nearby points get nearby keys, with jumps at face borders.
std::uint64_t hilbert_key(const Vec3& p) noexcept;

/// Indices of `points` in Hilbert-key order (ties by index).
std::vector<std::uint32_t> hilbert_order(std::span<const Vec3> points);

/// A BRIO order: a deterministic shuffle with `seed`, then rounds of geometrically growing size
/// (the last half, the half before...), each round sorted along the Hilbert curve. The random
/// rounds bound the expected cost of incremental Delaunay; the sorting makes walks short.
std::vector<std::uint32_t> brio_order(std::span<const Vec3> points, std::uint64_t seed);

}  // namespace geovor
