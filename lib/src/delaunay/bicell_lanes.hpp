// The bi-cell tolerance of up to kBatch bi-cells at once (bicell_tolerance.cpp), for the filter's
// batches (move_filter.cpp).
#pragma once

#include <cstddef>

#include "geovor/core/types.hpp"

namespace geovor {

// Up to this many bi-cells are computed together, as lanes of fixed-length loops the compiler
// vectorizes (SSE2 on x86-64: two lanes per instruction), stage by stage, so that the square
// roots and divisions of different bi-cells overlap. Lanes at n and above are padding.
constexpr std::size_t kBatch = 16;

// The four points of each lane, coordinates apart (structure of arrays, for the vector loops).
struct BicellLanes {
  double x[4][kBatch], y[4][kBatch], z[4][kBatch];
  void set(std::size_t i, int j, const Vec3& p) { x[j][i] = p.x, y[j][i] = p.y, z[j][i] = p.z; }
  // Lanes n.. up to the next multiple of 4 copy lane 0: finite numbers, so the vector loops
  // never see garbage.
  void pad(std::size_t n) {
    for (std::size_t i = n; i < ((n + 3) & ~std::size_t{3}); ++i)
      for (int j = 0; j < 4; ++j) x[j][i] = x[j][0], y[j][i] = y[j][0], z[j][i] = z[j][0];
  }
};

// tau[i] = bicell_tolerance() of lane i's bi-cell (points a, b the shared edge, c, d the far
// sites), i < n <= kBatch; each lane's math is a scalar evaluation's (same roundings, same result).
void bicell_tolerances(const BicellLanes& in, std::size_t n, double merge_distance, double* tau);

}  // namespace geovor
