/// \file bicell_tolerance.hpp
/// \brief The certified tolerance of a bi-cell for moving sites (thesis Ch. 5 carried to the
/// sphere; the bound and its proof: docs/delaunay.md, "The bi-cell tolerance").
#pragma once

#include "geovor/core/types.hpp"

namespace geovor {

/// A lower bound of how far (chord on the unit sphere) each of the four sites of the bi-cell
/// (a, b the shared edge, c, d the far sites) may move on the sphere before the sign of
/// orientation_3(a, b, c, d) can change or the edge a-b can come within merge_distance; 0 for a
/// coplanar (tied) bi-cell. REQUIRES: unit vectors (|p|^2 within 2^-49 of 1).
double bicell_tolerance(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, double merge_distance);

}  // namespace geovor
