/// \file cgal_hull_oracle.hpp
/// \brief Independent oracle for weighted sites: CGAL's exact 3D convex hull of the lifted points.
///
/// No CGAL type appears here, so that tests need not include CGAL headers.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "geovor/core/types.hpp"

namespace geovor::testing {

/// The faces of the convex hull of the points points[i] / lifts[i], computed by CGAL's
/// convex_hull_3 in exact rational arithmetic (Epeck, homogeneous points (p, c)), as input
/// indices, each triangle counter-clockwise seen from outside and rotated to start at its smallest
/// index, the list sorted. Input in general position only (no four lifted points on a plane):
/// CGAL triangulates coplanar facets its own way. `vertices`, if not null, receives the input
/// indices of the hull's vertices, sorted.
std::vector<std::array<std::uint32_t, 3>> cgal_lifted_hull(std::span<const Vec3> points,
                                                           std::span<const double> lifts,
                                                           std::vector<std::uint32_t>* vertices = nullptr);

}  // namespace geovor::testing
