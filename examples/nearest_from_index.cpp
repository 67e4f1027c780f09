// nearest_from_index INDEX.gvi QUERIES.csv: the nearest site of every query (lat,lon[,id] lines)
// from an index saved by `geovor index`, as CSV on stdout (what `geovor nearest` does).
#include <cstdio>
#include <exception>
#include <memory>

#include <geovor/layers/nearest_join.hpp>
#include <geovor/locate/index_file.hpp>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: nearest_from_index INDEX.gvi QUERIES.csv\n");
    return 2;
  }
  try {
    const geovor::SiteIndex index = geovor::load_index(argv[1]);
    const std::unique_ptr<std::FILE, int (*)(std::FILE*)> queries(std::fopen(argv[2], "rb"), &std::fclose);
    if (!queries) {
      std::perror(argv[2]);
      return 1;
    }
    geovor::NearestJoinOptions options;
    options.threads = 0;  // one per core; the output keeps the input's order
    const geovor::NearestJoinReport report = geovor::nearest_join(
        index, queries.get(), argv[2], options, [](std::string_view rows) { std::fwrite(rows.data(), 1, rows.size(), stdout); },
        [&](const geovor::MalformedQuery& q) {
          std::fprintf(stderr, "%s: line %llu: %s\n", argv[2], static_cast<unsigned long long>(q.line), q.reason.c_str());
        });
    std::fprintf(stderr, "%llu queries answered, %llu malformed lines\n", static_cast<unsigned long long>(report.answered),
                 static_cast<unsigned long long>(report.malformed));
    return std::fflush(stdout) == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "nearest_from_index: %s\n", e.what());
    return 1;
  }
}
