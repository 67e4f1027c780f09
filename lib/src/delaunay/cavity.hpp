// The marks and scratch buffers of a cavity search (cavity.cpp), shared with place()
// (insertion.cpp), which leaves the triangles it found not in conflict marked for it.
#pragma once

#include <cstdint>
#include <vector>

#include "geovor/core/types.hpp"

namespace geovor {

// A face is marked during a cavity search by the high bit of one of its site entries:
// entry 0 for "in the cavity", entry 1 for "tested, not in conflict". Site ids stay below 2^31.
constexpr SiteId kMark = 0x80000000u;

// Scratch buffers are vectors whose size is their capacity: grows one, returns its new data.
template <class T>
[[gnu::noinline]] T* grow(std::vector<T>& v) {
  v.resize(2 * v.size() + 64);
  return v.data();
}

}  // namespace geovor
