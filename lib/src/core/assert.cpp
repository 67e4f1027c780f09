#include "geovor/core/assert.hpp"

#include <cstdio>
#include <cstdlib>

namespace geovor::detail {
void assertion_failed(const char* expr, const char* file, int line) noexcept {
  std::fprintf(stderr, "geovor: internal error: assertion '%s' failed at %s:%d\n", expr, file, line);
  std::abort();
}
}  // namespace geovor::detail
