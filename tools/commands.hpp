// The subcommands of the geovor tool; each registers itself on the CLI11 app.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>

namespace geovor::tools {

/// Exit codes of geovor (documented in --help and docs/).
enum ExitCode : int { kOk = 0, kUsage = 2, kBadData = 3, kIo = 4, kInternal = 70 };

/// Adds `geovor info` to app; the returned function runs it when it was chosen.
std::function<int()> add_info_command(CLI::App& app);

}  // namespace geovor::tools
