// geovor: Voronoi cells, Delaunay triangulations and nearest sites on the Earth.
// A thin tool over the library (GeographicLib's Planimeter style): parse arguments, run, map
// errors to exit codes.
#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include "commands.hpp"
#include "geovor/core/error.hpp"

namespace geovor::tools {
namespace {
// What went to stdout (info's summary, a full disk behind `> file`) must not fail silently.
void check_stdout() {
  if (std::fflush(stdout) != 0 || std::ferror(stdout))
    throw geovor::Error(geovor::ErrorCode::Io, std::string("<stdout>: write error: ") + std::strerror(errno));
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

int main(int argc, char** argv) {
  using namespace geovor::tools;
  CLI::App app{"geovor: Voronoi cells, Delaunay triangulations and nearest sites on the Earth"};
  app.footer(
      "Exit codes: 0 ok, 2 usage error, 3 bad input data, 4 I/O error, 70 internal error.\n"
      "Examples:\n"
      "  geovor info datasets/weather_stations.csv\n"
      "  geovor cells datasets/weather_stations.csv -o cells.geojson\n"
      "  geovor delaunay datasets/weather_stations.csv -o triangles.geojson --edges edges.geojson\n"
      "  geovor nearest --sites datasets/weather_stations.csv --queries points.csv");
  app.require_subcommand(1);
  // Each subcommand: its name and the function that runs it.
  const std::vector<std::pair<std::string, std::function<int()>>> commands = {
      {"info", add_info_command(app)},
      {"cells", add_cells_command(app)},
      {"delaunay", add_delaunay_command(app)},
      {"relax", add_relax_command(app)},
      {"index", add_index_command(app)},
      {"nearest", add_nearest_command(app)},
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kOk : kUsage;
  }
  try {
    for (const auto& [name, run] : commands)
      if (app.got_subcommand(name)) {
        const int code = run();
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
