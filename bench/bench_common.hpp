// Shared by the benchmark programs.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace geovor::bench {

/// The CPU model from /proc/cpuinfo, so that saved outputs say which machine they come from.
inline std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  }
  return "unknown CPU";
}

/// The comma-separated items of a list option ("1,2,3"; an empty item stays, as "").
inline std::vector<std::string> split_commas(const std::string& value) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= value.size()) {
    const std::size_t comma = std::min(value.find(',', start), value.size());
    out.push_back(value.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

/// Parses a --sizes list: every item a decimal count of at least `min`; false on a bad item,
/// which `bad` then holds.
inline bool parse_sizes(const std::string& value, std::size_t min, std::vector<std::size_t>& sizes,
                        std::string& bad) {
  sizes.clear();
  for (const std::string& item : split_commas(value)) {
    char* end = nullptr;
    const unsigned long long n = std::strtoull(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || n < min) {
      bad = item;
      return false;
    }
    sizes.push_back(static_cast<std::size_t>(n));
  }
  return true;
}

}  // namespace geovor::bench
