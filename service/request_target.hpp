/// \file request_target.hpp
/// \brief An HTTP request's target ("/path?name=value&..."), split and percent-decoded (RFC 3986;
/// '+' is a space in the query, as HTML forms send it). Boost 1.74, the Boost of Debian 12 that
/// CGAL depends on, has no Boost.URL, and Beast leaves the target as it came.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "nearest_service.hpp"

namespace geovor::service {

struct RequestTarget {
  std::string path;  ///< decoded; starts with '/'
  Params query;      ///< decoded names and values, repeated names kept in order
};

/// The target split and decoded; nullopt when it is no absolute path (origin form), or holds a
/// '%' not followed by two hexadecimal digits, or a '#'.
std::optional<RequestTarget> parse_request_target(std::string_view target);

}  // namespace geovor::service
