/// \file ascii.hpp
/// \brief ASCII case folding for names (columns, formats, extensions): locale-independent, bytes
/// outside A-Z (UTF-8 included) unchanged; the edit distance of names; and control characters
/// made visible for messages.
#pragma once

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

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

/// Levenshtein distance of a and b in bytes (insertions, deletions, substitutions), for "did you
/// mean" on a mistyped name: fold the case first (ascii_lower) to ignore it. O(|a| |b|).
inline std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
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
