// Whether a new point conflicts with a triangle (lies in its circumcircle, under the
// perturbation): the test of every cavity search, inline for the hot loops.
#pragma once

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "kernel/in_sphere_filter.hpp"

namespace geovor {

inline double chord2(const Vec3& a, const Vec3& b) { return norm2(a - b); }

// The hot path is inline and makes no call, so it needs no register spills; the exact and
// perturbed stages are out of line (insertion.cpp).
inline bool SphericalDelaunay::in_conflict(TriId t, const Vec3& p, double c, std::uint32_t prio) const {
  const SiteId* tri = triangles_.data() + 3 * t;
  const Vec3* s = sites_.data();
  int filtered;
  if (lifts_.empty()) [[likely]] {
    // Sites and inserted points are unit vectors (checked on input): the static filter applies.
    filtered = kernel::detail::in_sphere_unit_filter(s[tri[0]], s[tri[1]], s[tri[2]], p);
  } else {
    filtered = 0;
    if (!lifted_.empty()) {  // the build: the static filter on the lifted points first
      const Vec3* l = lifted_.data();
      filtered = kernel::detail::in_sphere_lifted_static(l[tri[0]], l[tri[1]], l[tri[2]], {p.x / c, p.y / c, p.z / c},
                                                         lifted_bound_);
    }
    const double* w = lifts_.data();
    if (filtered == 0)
      filtered = kernel::detail::in_sphere_weighted_filter(s[tri[0]], w[tri[0]], s[tri[1]], w[tri[1]], s[tri[2]],
                                                           w[tri[2]], p, c);
  }
  if (filtered != 0) [[likely]]
    return filtered > 0;
  return in_conflict_exact(t, p, c, prio);
}

}  // namespace geovor
