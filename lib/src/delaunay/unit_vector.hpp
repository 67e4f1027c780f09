// Input points are unit vectors: the check made by build(), insert(), move() and from_arrays().
#pragma once

#include <cmath>
#include <cstdio>
#include <string>

#include "geovor/core/types.hpp"

namespace geovor {

// |p|^2 within 2^-49 of 1: the sites' bound (docs/delaunay.md, "Sites").
inline bool is_unit(const Vec3& p) {
  const double r2 = norm2(p);
  return std::isfinite(r2) && std::fabs(r2 - 1.0) <= 0x1p-49;
}

// A double in full precision, for the error messages.
inline std::string format_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

}  // namespace geovor
