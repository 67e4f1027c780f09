// The cell layer written to a file: the companion output before the cells appear, and the cells
// written with an empty geometry listed on the log, naming the caller's options.
#include "geovor/layers/cell_file.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "geovor/geo/site_encoder.hpp"
#include "support/file_text.hpp"
#include "support/memory_stream.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

using testing::contains;
using testing::MemoryStream;

// n x n sites 0.01 degree apart near (10, 20), and one far away: at 0 decimals most cells
// collapse.
struct Grid {
  SiteTable table;
  BuildReport report;
  SphericalDelaunay dt;
  explicit Grid(int n) : dt(build(table, report, n)) {}
  static SphericalDelaunay build(SiteTable& table, BuildReport& report, int n) {
    table.source = "grid";
    table.columns = {"id"};
    table.id_column = 0;
    for (int i = 0; i <= n * n; ++i) {
      InputSite row;
      row.row = static_cast<std::uint64_t>(i + 1);
      row.id = "s" + std::to_string(i);
      row.lat_deg = i == n * n ? -50 : 10 + 0.01 * (i / n);
      row.lon_deg = i == n * n ? -100 : 20 + 0.01 * (i % n);
      row.unit = SiteEncoder::from_lat_lon(row.lat_deg, row.lon_deg);
      row.fields = {row.id};
      table.sites.push_back(row);
    }
    return SphericalDelaunay::build(site_points(table), {}, &report);
  }
};

TEST(CellFile, TheCompanionOutputComesBeforeTheCells) {
  const Grid g(2);
  testing::TempDir dir("geovor_cell_file");
  const std::string path = dir / "cells.geojson";
  MemoryStream log;
  CellFileOptions options;
  options.log = log.get();
  bool before = false;
  const CellLayerReport written = write_cell_file(path, g.table, g.report, g.dt, options, [&](const CellLayerReport& r) {
    EXPECT_EQ(r.cells_written, 5u);
    EXPECT_FALSE(std::filesystem::exists(path));  // not yet in place
    before = true;
  });
  EXPECT_TRUE(before);
  EXPECT_EQ(written.cells_written, 5u);
  EXPECT_TRUE(written.unwritten.empty());
  EXPECT_TRUE(contains(testing::slurp(path), "\"id\":\"s0\"")) << testing::slurp(path).substr(0, 300);
  EXPECT_EQ(log.text(), "");  // no progress on a stream that is no terminal
}

TEST(CellFile, ListsTheCellsWrittenWithAnEmptyGeometry) {
  const Grid g(8);
  testing::TempDir dir("geovor_cell_file");
  MemoryStream log;
  CellFileOptions options;
  options.log = log.get();
  options.writer.precision = 0;
  const CellLayerReport written = write_cell_file(dir / "cells.geojson", g.table, g.report, g.dt, options);
  ASSERT_GT(written.unwritten.size(), 20u);
  const std::string text = log.text();
  EXPECT_EQ(text.substr(0, text.find('\n')),
            std::to_string(written.unwritten.size()) +
                " cell(s) written with an empty geometry: at precision 0 they collapse or would not be valid "
                "polygons (raise precision):");
  const UnwrittenCell& first = written.unwritten[0];
  EXPECT_TRUE(contains(text, "\n  site " + std::to_string(first.site) + " (id s" + std::to_string(first.site) +
                                 "): " + to_string(first.status) + "\n"))
      << text;
  EXPECT_TRUE(contains(text, "\n  ... (" + std::to_string(written.unwritten.size() - 20) +
                                 " more; write_row_report() lists them all)\n"))
      << text;
  // The caller's names for its options.
  MemoryStream named;
  options.log = named.get();
  options.writer.overwrite = true;
  options.precision_name = "--precision";
  options.report_name = "--report";
  write_cell_file(dir / "cells.geojson", g.table, g.report, g.dt, options);
  EXPECT_TRUE(contains(named.text(), "at --precision 0 they collapse or would not be valid polygons (raise --precision):"));
  EXPECT_TRUE(contains(named.text(), " more; --report lists them all)\n"));
}

}  // namespace
}  // namespace geovor
