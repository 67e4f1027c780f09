#include "geovor/delaunay/degenerate_case.hpp"

#include "geovor/kernel/predicates.hpp"

namespace geovor {

const char* degenerate_case(const SphericalDelaunay& dt) {
  if (dt.num_sites() == 0) return "no sites";
  if (dt.num_sites() == 1) return "one site";
  if (dt.num_sites() == 2) return "two sites";
  bool all_flat = true;
  for (TriId t = 0; t < dt.num_triangles() && all_flat; ++t)
    all_flat = kernel::orient(dt.site(dt.tri_site(t, 0)), dt.site(dt.tri_site(t, 1)),
                              dt.site(dt.tri_site(t, 2))) == Sign::Zero;
  if (all_flat) return "all sites on one great circle";
  if (dt.num_ghost_triangles() > 0) return "all sites in one open hemisphere";
  return "none";
}

}  // namespace geovor
