/// \file cgal_oracle.hpp
/// \brief Independent oracle: CGAL's own Delaunay triangulation on the sphere, as sorted index triples.
///
/// No CGAL type appears here so that tests and the benchmark need not include CGAL (GPL) headers.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "geovor/core/types.hpp"

namespace geovor::testing {

using Tri = std::array<std::uint32_t, 3>;

/// Triangles of CGAL's Delaunay_triangulation_on_sphere_2<Delaunay_triangulation_on_sphere_traits_2<Epick>>
/// built on `points` (unit vectors; CGAL sphere centre (0,0,0), radius 1), as indices into `points`, each
/// rotated so that its smallest index comes first (orientation kept: counter-clockwise seen from outside),
/// the list sorted. Includes CGAL's ghost faces (all faces of the TDS) when dimension()==2, else empty.
/// Points CGAL rejects (too close, not on sphere, exact duplicates) are reported in `rejected`
/// (sorted input indices) if non-null.
///
/// Of exact duplicates, the smallest index is the vertex. Otherwise insertion follows CGAL's
/// spatial_sort_on_sphere (fixed seed), so which one of two too-close points survives is
/// deterministic but not necessarily the smaller index. CGAL's "too close" is a chord <= 2^-23,
/// twice geovor's kMinSeparation: points 2^-24..2^-23 apart are merged by CGAL only.
/// All sites on one plane (a great or small circle) leave CGAL in dimension 1: no triangles, and
/// its 1D insertion is quadratic (20,000 points on the equator take ~17 s), so keep such n small.
std::vector<Tri> cgal_triangles(std::span<const Vec3> points,
                                std::vector<std::uint32_t>* rejected = nullptr);

/// CGAL's build time (seconds) for the benchmark, inserting the range with CGAL's own spatial sort
/// (insert(begin, end)); the conversion to CGAL points is done lazily inside CGAL's own copy, so
/// it is timed and adds no extra buffer to the memory peak.
double cgal_build_seconds(std::span<const Vec3> points, std::size_t* num_vertices = nullptr);

}  // namespace geovor::testing
