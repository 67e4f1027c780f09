#pragma once
/// @file copy_short.hpp
/// Inline copies of the short texts that make up JSON features (ids, numbers, keys), where a
/// call to memcpy per piece costs more than the copy.

#include <cstddef>
#include <cstring>
#include <string_view>

namespace geovor {

/// Copies `text` to `out`, which has room for text.size() characters; returns one past the end.
/// Up to 16 characters by two overlapping copies of fixed size (compiled inline), longer ones by
/// memcpy. Writes nothing outside [out, out + text.size()).
inline char* copy_short(char* out, std::string_view text) {
  const std::size_t n = text.size();
  const char* in = text.data();
  if (n >= 8 && n <= 16) {
    std::memcpy(out, in, 8);
    std::memcpy(out + n - 8, in + n - 8, 8);
  } else if (n >= 4 && n < 8) {
    std::memcpy(out, in, 4);
    std::memcpy(out + n - 4, in + n - 4, 4);
  } else if (n > 16) {
    std::memcpy(out, in, n);
  } else if (n > 0) {  // 1 to 3
    out[0] = in[0];
    out[n / 2] = in[n / 2];
    out[n - 1] = in[n - 1];
  }
  return out + n;
}

}  // namespace geovor
