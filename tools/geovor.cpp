// geovor: Voronoi cells, Delaunay triangulations and nearest sites on the Earth.
// A thin tool over the library (GeographicLib's Planimeter style): parse arguments, run, map
// errors to exit codes.
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "geovor/core/ascii.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/output_target.hpp"

namespace geovor::tools {
namespace {
// What went to stdout (info's summary, a full disk behind `> file`) must not fail silently.
void check_stdout() {
  if (std::fflush(stdout) != 0 || std::ferror(stdout))
    throw geovor::Error(geovor::ErrorCode::Io, std::string("<stdout>: write error: ") + std::strerror(errno));
}

// The directory of this executable, from /proc/self/exe ("" if unknown).
std::string executable_dir() {
  std::string path(4096, '\0');
  const ssize_t n = ::readlink("/proc/self/exe", path.data(), path.size());
  if (n <= 0 || static_cast<std::size_t>(n) >= path.size()) return "";
  path.resize(static_cast<std::size_t>(n));
  return path.substr(0, path.rfind('/') + 1);
}

// Runs the same arguments with geovor-gdal: beside this executable (the build tree), else where
// the install puts it (GEOVOR_GDAL_TOOL_FROM_BIN, relative to the bin directory). Returns only
// on failure, with the exit code.
int hand_to_gdal_tool(char** argv) {
  const std::string dir = executable_dir();
  const std::vector<std::string> candidates = {dir + "geovor-gdal", dir + GEOVOR_GDAL_TOOL_FROM_BIN};
  for (const std::string& path : candidates) {
    if (::access(path.c_str(), X_OK) != 0) continue;
    std::fflush(stdout);
    std::fflush(stderr);
    ::execv(path.c_str(), argv);
    std::fprintf(stderr, "geovor: cannot run %s: %s\n", path.c_str(), std::strerror(errno));
    return kInternal;
  }
  std::fprintf(stderr, "geovor: this job needs GDAL (an OGR input or an output other than GeoJSON), which geovor hands to geovor-gdal, but there is no executable %s nor %s\n",
               candidates[0].c_str(), candidates[1].c_str());
  return kInternal;
}

// glibc reads its malloc tunables only when a program starts: the tool runs itself again, once,
// with transparent huge pages for malloc's memory (glibc.malloc.hugetlb=1), which halves the page
// faults of a large job (docs/design.md, "Speed"). A hugetlb tunable already set is kept (=0 turns
// this off); if the new run cannot start, this one goes on as it is.
void rerun_with_huge_pages(char** argv) {
  const char* old = std::getenv("GLIBC_TUNABLES");
  if (old != nullptr && std::strstr(old, "glibc.malloc.hugetlb") != nullptr) return;
  const std::string saved = old != nullptr ? old : "";
  const std::string value = saved.empty() ? "glibc.malloc.hugetlb=1" : saved + ":glibc.malloc.hugetlb=1";
  if (::setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  if (old != nullptr)
    ::setenv("GLIBC_TUNABLES", saved.c_str(), 1);
  else
    ::unsetenv("GLIBC_TUNABLES");
}

// "unknown command 'cels'; did you mean 'cells'?" (exit 2), or the list of commands when none is close.
int unknown_command(const std::string& name, const std::vector<std::string>& commands) {
  std::string best, all;
  std::size_t best_distance = 3;  // at most two edits away, or a prefix
  for (const std::string& c : commands) {
    all += (all.empty() ? "" : ", ") + c;
    const std::size_t d = c.starts_with(ascii_lower(name)) && !name.empty() ? 1 : edit_distance(ascii_lower(name), c);
    if (d < best_distance) best_distance = d, best = c;
  }
  if (!best.empty())
    std::fprintf(stderr, "geovor: unknown command '%s'; did you mean '%s'?\n", name.c_str(), best.c_str());
  else
    std::fprintf(stderr, "geovor: unknown command '%s'; the commands are %s (geovor --help)\n", name.c_str(), all.c_str());
  return kUsage;
}

}  // namespace

int finish_command(int code) {
  check_stdout();
#if defined(__SANITIZE_ADDRESS__)
  return code;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
  return code;
#endif
#endif
  std::fflush(stderr);
  std::_Exit(code);
}

}  // namespace geovor::tools

namespace geovor::tools {

int run_geovor(int argc, char** argv, bool has_gdal) {
  rerun_with_huge_pages(argv);
  // Named, so that usage lines say "geovor", not the path it was run by.
  CLI::App app{"geovor: Voronoi cells, Delaunay triangulations and nearest sites on the Earth", "geovor"};
  app.set_version_flag("--version", "geovor " GEOVOR_VERSION, "Print the version and exit");
  app.footer(
      "geovor help COMMAND is geovor COMMAND --help.\n"
      "Exit codes: 0 ok, 2 usage error, 3 bad input data, 4 I/O error, 70 internal error.\n"
      "Examples:\n"
      "  geovor info datasets/weather_stations.csv\n"
      "  geovor cells datasets/weather_stations.csv -o cells.geojson\n"
      "  geovor delaunay datasets/weather_stations.csv -o triangles.geojson --edges edges.geojson\n"
      "  geovor nearest --sites datasets/weather_stations.csv --queries points.csv");
  app.require_subcommand(1);
  // Each subcommand: its name and the function that runs it.
  const std::vector<std::pair<std::string, Command>> commands = {
      {"info", add_info_command(app)},
      {"cells", add_cells_command(app)},
      {"delaunay", add_delaunay_command(app)},
      {"relax", add_relax_command(app)},
      {"balance", add_balance_command(app)},
      {"index", add_index_command(app)},
      {"nearest", add_nearest_command(app)},
      {"serve", add_serve_command(app)},
  };
  std::vector<std::string> names;
  for (const auto& command : commands) names.push_back(command.first);
  auto known = [&](const std::string& name) { return std::find(names.begin(), names.end(), name) != names.end(); };
  // `geovor help [COMMAND]` is `geovor [COMMAND] --help`; a first word that is no command is named.
  std::vector<std::string> words(argv, argv + argc);
  if (argc >= 2 && words[1] == "help") {
    if (argc > 3) {
      std::fprintf(stderr, "geovor: help takes one command, e.g. geovor help cells\n");
      return kUsage;
    }
    if (argc == 3 && !known(words[2])) return unknown_command(words[2], names);
    words = argc == 3 ? std::vector<std::string>{words[0], words[2], "--help"} : std::vector<std::string>{words[0], "--help"};
  } else if (argc >= 2 && !words[1].empty() && words[1][0] != '-' && !known(words[1])) {
    return unknown_command(words[1], names);
  }
  std::vector<char*> args;
  for (std::string& w : words) args.push_back(w.data());
  args.push_back(nullptr);
  try {
    app.parse(static_cast<int>(words.size()), args.data());
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kOk : kUsage;
  }
  // Ctrl-C, SIGTERM and SIGHUP remove the temporaries of the outputs being written, then end
  // the process by the same signal (exit status 130, 143, 129).
  install_output_cleanup();
  try {
    for (const auto& [name, command] : commands)
      if (app.got_subcommand(name)) {
        if (!has_gdal && command.needs_gdal()) return hand_to_gdal_tool(argv);
        const int code = command.run();
        geovor::tools::check_stdout();
        return code;
      }
  } catch (const geovor::Error& e) {
    std::fprintf(stderr, "geovor: %s\n", e.what());
    switch (e.code()) {
      case geovor::ErrorCode::InvalidArgument: return kUsage;
      case geovor::ErrorCode::BadData: return kBadData;
      case geovor::ErrorCode::Io: return kIo;
      case geovor::ErrorCode::Internal: return kInternal;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "geovor: internal error: %s\n", e.what());
    return kInternal;
  }
  return kUsage;
}

}  // namespace geovor::tools
