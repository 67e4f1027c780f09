/// \file ascii.hpp
/// \brief ASCII case folding for names (columns, formats, extensions): locale-independent, bytes
/// outside A-Z (UTF-8 included) unchanged.
#pragma once

#include <string>
#include <string_view>

namespace geovor {

/// `text` with A-Z folded to a-z.
inline std::string ascii_lower(std::string_view text) {
  std::string s(text);
  for (char& c : s)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return s;
}

/// Whether a and b are equal once A-Z are folded to a-z.
inline bool ascii_iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const char x = a[i] >= 'A' && a[i] <= 'Z' ? static_cast<char>(a[i] - 'A' + 'a') : a[i];
    const char y = b[i] >= 'A' && b[i] <= 'Z' ? static_cast<char>(b[i] - 'A' + 'a') : b[i];
    if (x != y) return false;
  }
  return true;
}

}  // namespace geovor
