// The subcommands of the geovor tool; each registers itself on the CLI11 app and returns the
// function that runs it when it was chosen.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace geovor::tools {

/// Exit codes of geovor (documented in --help and docs/).
enum ExitCode : int { kOk = 0, kUsage = 2, kBadData = 3, kIo = 4, kInternal = 70 };

/// Ends a command whose outputs are complete: stdout flushed and checked as main() does, then
/// the process exits with `code` at once, without destroying the command's data (freeing the
/// few hundred MB of small objects of a large run one by one takes about 10 ms). Sanitizer builds
/// return `code` instead, so that LeakSanitizer still checks the command.
/// @exception Error(Io) if stdout cannot be written.
int finish_command(int code);

/// A subcommand: what runs it, and whether the parsed job needs GDAL (an OGR input, or an output
/// other than GeoJSON/GeoJSONSeq). geovor, built without GDAL so that it starts in about a
/// millisecond instead of 30 (GDAL's 115 shared libraries), hands such jobs to geovor-gdal.
struct Command {
  std::function<int()> run;
  std::function<bool()> needs_gdal;
};

/// Runs the geovor tool: parses the arguments, then runs the chosen command, or re-executes the
/// same arguments with geovor-gdal (found beside this executable, or in its install's libexec
/// directory) when the job needs GDAL and `has_gdal` is false. Returns the exit code.
int run_geovor(int argc, char** argv, bool has_gdal);

Command add_info_command(CLI::App& app);
/// Adds `geovor index` (tools/index_command.cpp).
Command add_index_command(CLI::App& app);
/// Adds `geovor nearest` (tools/nearest_command.cpp).
Command add_nearest_command(CLI::App& app);

Command add_cells_command(CLI::App& app);
/// Adds `geovor delaunay` (tools/delaunay_command.cpp).
Command add_delaunay_command(CLI::App& app);
/// Adds `geovor relax` (tools/relax_command.cpp).
Command add_relax_command(CLI::App& app);
/// Adds `geovor balance` (tools/balance_command.cpp).
Command add_balance_command(CLI::App& app);
/// Adds `geovor serve` (tools/serve_command.cpp, over service/).
Command add_serve_command(CLI::App& app);

}  // namespace geovor::tools
