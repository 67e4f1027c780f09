/// \file assert.hpp
/// \brief GEOVOR_ASSERT: an always-on check of a cheap invariant; failure is a bug and aborts.
#pragma once

namespace geovor::detail {
[[noreturn]] void assertion_failed(const char* expr, const char* file, int line) noexcept;
}  // namespace geovor::detail

#define GEOVOR_ASSERT(expr) \
  ((expr) ? static_cast<void>(0) : ::geovor::detail::assertion_failed(#expr, __FILE__, __LINE__))
