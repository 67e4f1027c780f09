// geovor_bench_csv_read: reading a CSV table of sites (e.g. the 171,075 GeoNames cities) with the
// streaming reader that came before (tests/support/reference_site_reader.cpp) and with
// CsvSiteScan, in the same process and interleaved: open() on N threads, finish() on one, and the
// whole read_sites_csv_file. Medians over the repetitions, and ratios to the reference.
//
//   gunzip -c datasets/geonames_cities.csv.gz > /tmp/cities.csv
//   geovor_bench_csv_read /tmp/cities.csv [repetitions=21] [threads=2]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_common.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/csv_site_scan.hpp"
#include "geovor/geo/site_reader.hpp"
#include "support/reference_site_reader.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// "median (min)": on a shared machine the minimum shows what the code costs without contention.
std::string both(const std::vector<double>& v) {
  char text[64];
  std::snprintf(text, sizeof text, "%7.2f ms (min %6.2f)", median(v), *std::min_element(v.begin(), v.end()));
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace geovor;
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s FILE.csv [repetitions=21] [threads=2]\n", argv[0]);
    return 2;
  }
  const std::string path = argv[1];
  const int reps = argc > 2 ? std::max(1, std::atoi(argv[2])) : 21;
  const unsigned threads = argc > 3 ? static_cast<unsigned>(std::atoi(argv[3])) : 2u;
  SiteReaderOptions parallel;
  parallel.threads = threads;

  try {
    std::vector<double> reference_ms, open_ms, finish_ms, whole_ms, whole1_ms;
    std::size_t sites = 0, rejected = 0;
    for (int r = 0; r < reps; ++r) {
      auto t0 = Clock::now();
      const SiteTable ref = testing::reference_read_sites_csv_file(path);
      reference_ms.push_back(ms_since(t0));

      t0 = Clock::now();
      CsvSiteScan scan = CsvSiteScan::open(path, parallel);
      open_ms.push_back(ms_since(t0));
      t0 = Clock::now();
      const SiteTable two_stage = std::move(scan).finish();
      finish_ms.push_back(ms_since(t0));

      t0 = Clock::now();
      const SiteTable whole = read_sites_csv_file(path, parallel);
      whole_ms.push_back(ms_since(t0));
      t0 = Clock::now();
      const SiteTable whole1 = read_sites_csv_file(path);
      whole1_ms.push_back(ms_since(t0));

      if (two_stage.sites.size() != ref.sites.size() || whole.rejected.size() != ref.rejected.size() ||
          whole1.sites.size() != ref.sites.size()) {
        std::fprintf(stderr, "tables differ: %zu/%zu sites\n", two_stage.sites.size(), ref.sites.size());
        return 1;
      }
      sites = ref.sites.size();
      rejected = ref.rejected.size();
    }
    const double ref = median(reference_ms);
    std::printf("%s\n%s: %zu sites, %zu rejected; %d repetitions, medians\n", bench::cpu_model().c_str(),
                path.c_str(), sites, rejected, reps);
    std::printf("  reference (streaming CsvReader)   %s\n", both(reference_ms).c_str());
    std::printf("  CsvSiteScan::open, %u threads      %s  %.2fx of the reference\n", threads,
                both(open_ms).c_str(), median(open_ms) / ref);
    std::printf("  finish(), 1 thread                %s  %.2fx\n", both(finish_ms).c_str(), median(finish_ms) / ref);
    std::printf("  read_sites_csv_file, %u threads    %s  %.2fx\n", threads, both(whole_ms).c_str(),
                median(whole_ms) / ref);
    std::printf("  read_sites_csv_file, 1 thread     %s  %.2fx\n", both(whole1_ms).c_str(), median(whole1_ms) / ref);
  } catch (const Error& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
