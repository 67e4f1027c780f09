// Uses an installed geovor: the Delaunay triangulation of the 8 corners of a cube inscribed in
// the unit sphere has 12 triangles (2n - 4) and is valid. Exit 0 iff so.
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"

int main() {
  try {
    const double c = 1.0 / std::sqrt(3.0);
    std::vector<geovor::Vec3> corners;
    for (double x : {-c, c})
      for (double y : {-c, c})
        for (double z : {-c, c}) corners.push_back({x, y, z});

    const auto dt = geovor::SphericalDelaunay::build(corners);
    const auto validation = dt.validate();
    std::printf("sites: %zu\ntriangles: %zu\nvalid: %s\n", dt.num_sites(), dt.num_triangles(),
                validation.ok() ? "yes" : "no");
    for (const auto& error : validation.errors) std::printf("error: %s\n", error.c_str());
    return dt.num_triangles() == 12 && validation.ok() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "geovor_consumer: %s\n", e.what());
    return 1;
  }
}
