// trim: a field or column name without its surrounding white space, as every reader compares them.
#pragma once

#include <string_view>

namespace geovor {

/// `s` without leading and trailing spaces, tabs, CR, LF, VT and FF.
inline std::string_view trim(std::string_view s) {
  constexpr std::string_view kSpace = " \t\r\n\v\f";
  const auto first = s.find_first_not_of(kSpace);
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(kSpace) - first + 1);
}

}  // namespace geovor
