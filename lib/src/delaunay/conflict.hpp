// Whether a new point conflicts with a triangle (lies in its circumcircle, under the
// perturbation): the test of every cavity search, inline for the hot loops.
#pragma once

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "kernel/in_sphere_filter.hpp"

namespace geovor {

inline double chord2(const Vec3& a, const Vec3& b) { return norm2(a - b); }

// The hot path is inline and makes no call, so it needs no register spills; the exact and
// perturbed stages are out of line (insertion.cpp).
inline bool SphericalDelaunay::in_conflict(TriId t, const Vec3& p, std::uint32_t prio) const {
  const SiteId* tri = triangles_.data() + 3 * t;
  const Vec3* s = sites_.data();
  // Sites and inserted points are unit vectors (checked on input): the static filter applies.
  const int filtered = kernel::detail::in_sphere_unit_filter(s[tri[0]], s[tri[1]], s[tri[2]], p);
  if (filtered != 0) [[likely]]
    return filtered > 0;
  return in_conflict_exact(t, p, prio);
}

}  // namespace geovor
