// Shared by the benchmark programs.
#pragma once

#include <fstream>
#include <string>

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

}  // namespace geovor::bench
