#include "numeric_options.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace geovor::tools {

CLI::Option* add_threads_option(CLI::App* cmd, int& threads) {
  threads = 0;
  return cmd->add_option("--threads", threads, "Threads (default 0: one per core); the output is the same on any number")
      ->check(integer_in(0, kMaxThreads));
}

CLI::Validator integer_in(std::int64_t lo, std::int64_t hi) {
  const std::string range = "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        const char* begin = text.c_str();
        char* end = nullptr;
        errno = 0;
        const long long v = std::strtoll(begin, &end, 10);
        if (text.empty() || end != begin + text.size() || errno == ERANGE || v < lo || v > hi)
          return "expected " + range + ", got '" + text + "'";
        return "";
      },
      range);
}

CLI::Validator finite_above(double lo, bool inclusive) {
  char bound[32];
  std::snprintf(bound, sizeof bound, "%g", lo);
  const std::string what = std::string("a finite number ") + (inclusive ? ">= " : "> ") + bound;
  return CLI::Validator(
      [lo, inclusive, what](std::string& text) -> std::string {
        const char* begin = text.c_str();
        char* end = nullptr;
        const double v = std::strtod(begin, &end);
        if (text.empty() || end != begin + text.size() || !std::isfinite(v) || (inclusive ? v < lo : v <= lo))
          return "expected " + what + ", got '" + text + "'";
        return "";
      },
      what);
}

}  // namespace geovor::tools
