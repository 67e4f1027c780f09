// Checks of numeric options, run on the text before CLI11 converts it: CLI11 reads "-1" into an
// unsigned option as 2^64-1 and lets NaN pass its range checks. A failure is a usage error (exit 2)
// whose message names the option ("--k: expected an integer from 1 to ..., got '-1'").
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <string>

namespace geovor::tools {

/// The most threads an option may ask for (more than the system gives run as fewer).
inline constexpr std::int64_t kMaxThreads = 1000000;

/// Adds --threads N to a command, the same on every command: the threads of its parallel stages,
/// 0 (the default) one per core; the output does not depend on it. Anything but an integer from 0
/// to kMaxThreads is a usage error naming --threads (integer_in).
CLI::Option* add_threads_option(CLI::App* cmd, int& threads);

/// An integer, written in decimal, from `lo` to `hi`.
CLI::Validator integer_in(std::int64_t lo, std::int64_t hi);

/// A finite real number above `lo` (`lo` itself allowed when `inclusive`); NaN and infinities refused.
CLI::Validator finite_above(double lo, bool inclusive);

}  // namespace geovor::tools
