/// \file exact_geometry.hpp
/// \brief Oracles in binary128 for tests: geometry of doubles computed far beyond their rounding.
#pragma once

#include <cmath>

#include "geovor/core/types.hpp"

namespace geovor::testing {

/// The unit normal of the plane through three doubles, (b - a) x (c - a), in binary128: the
/// differences of doubles within a factor 2^60 of each other are exact there, and the products'
/// rounding (2^-113) stays far below a double's ulp even after the cancellation of a sliver.
inline Vec3 exact_circumcentre(const Vec3& a, const Vec3& b, const Vec3& c) {
  using Q = __float128;
  const Q ux = Q(b.x) - Q(a.x), uy = Q(b.y) - Q(a.y), uz = Q(b.z) - Q(a.z);
  const Q wx = Q(c.x) - Q(a.x), wy = Q(c.y) - Q(a.y), wz = Q(c.z) - Q(a.z);
  const Q nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
  const long double len = std::sqrt(static_cast<long double>(nx * nx + ny * ny + nz * nz));
  return {static_cast<double>(static_cast<long double>(nx) / len), static_cast<double>(static_cast<long double>(ny) / len),
          static_cast<double>(static_cast<long double>(nz) / len)};
}

}  // namespace geovor::testing
