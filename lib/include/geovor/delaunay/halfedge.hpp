/// \file halfedge.hpp
/// \brief Index algebra of the flat half-edge arrays (delaunator's convention).
///
/// Triangle t owns half-edges 3t, 3t+1, 3t+2. Half-edge e starts at site triangles[e] and ends at
/// triangles[next(e)]; its twin halfedges[e] runs the other way in the adjacent triangle.
#pragma once

#include "geovor/core/types.hpp"

namespace geovor {

constexpr TriId tri_of(HalfedgeId e) { return e / 3; }
constexpr HalfedgeId next_halfedge(HalfedgeId e) { return (e % 3 == 2) ? e - 2 : e + 1; }
constexpr HalfedgeId prev_halfedge(HalfedgeId e) { return (e % 3 == 0) ? e + 2 : e - 1; }
constexpr HalfedgeId first_halfedge(TriId t) { return 3 * t; }

}  // namespace geovor
