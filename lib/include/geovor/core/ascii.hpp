/// \file ascii.hpp
/// \brief ASCII case folding for names (columns, formats, extensions): locale-independent, bytes
/// outside A-Z (UTF-8 included) unchanged; and control characters made visible for messages.
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

/// `text` with every ASCII control character (0x00-0x1F, 0x7F) written as an escape (\0, \t,
/// \n, \r, else \xHH), so that a message or a report line stays one line and a NUL cannot cut
/// it. Other bytes (UTF-8 included) are unchanged.
inline std::string printable(std::string_view text) {
  std::string s;
  s.reserve(text.size());
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7F) {
      s += c;
    } else if (c == '\0') {
      s += "\\0";
    } else if (c == '\t') {
      s += "\\t";
    } else if (c == '\n') {
      s += "\\n";
    } else if (c == '\r') {
      s += "\\r";
    } else {
      constexpr char kHex[] = "0123456789ABCDEF";
      s += "\\x";
      s += kHex[u >> 4];
      s += kHex[u & 15];
    }
  }
  return s;
}

}  // namespace geovor
