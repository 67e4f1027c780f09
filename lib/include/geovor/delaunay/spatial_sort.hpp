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
/// (2^16 x 2^16 cells per face; key < 6 * 2^32). Nearby points get nearby keys, with jumps at
/// face borders.
std::uint64_t hilbert_key(const Vec3& p) noexcept;

/// Indices of `points` in Hilbert-key order (ties by index), on a grid of about 4 cells per point.
/// With `keys`, also the key of each point of the order (keys[k] of order[k]): points at one
/// position share a cell, hence a run of equal keys.
std::vector<std::uint32_t> hilbert_order(std::span<const Vec3> points, std::vector<std::uint64_t>* keys = nullptr);

/// A BRIO order: each point is drawn (deterministically from `seed` and its index) into one of
/// rounds of geometrically growing size (about half the points in the last round, a quarter in
/// the one before, at least 64 in the first), each round sorted along the Hilbert curve. The
/// random rounds bound the expected cost of incremental Delaunay; the sorting makes walks short.
std::vector<std::uint32_t> brio_order(std::span<const Vec3> points, std::uint64_t seed);

}  // namespace geovor
