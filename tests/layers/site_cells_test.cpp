// SiteCells: the cells of a job's sites and their row report, the same on any number of threads.
#include "geovor/layers/site_cells.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "geovor/core/error.hpp"
#include "support/file_text.hpp"
#include "support/memory_stream.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

using testing::contains;
using testing::error_of;
using testing::MemoryStream;
using testing::slurp;
using testing::spit;

class SiteCellsTest : public ::testing::Test {
 protected:
  SiteCellsTest() : dir_("geovor_site_cells") {
    spit(dir_ / "sites.csv", "id,lat,lon\na,0,0\nb,0,90\nc,90,0\nd,0,180\ne,0,-90\nf,-90,0\nb,0,90\nx,95,0\n");
    input_.input = dir_ / "sites.csv";
    input_.log = log_.get();
    options_.file.log = log_.get();
    options_.report_path = dir_ / "report.csv";
  }
  testing::TempDir dir_;
  MemoryStream log_;
  SiteInput input_;
  SiteCellsOptions options_;
};

TEST_F(SiteCellsTest, WritesTheCellsAndTheRowReport) {
  SiteCells cells(input_, dir_ / "cells.geojson", options_);
  EXPECT_EQ(cells.triangulation().num_sites(), 6u);
  EXPECT_EQ(cells.build().merges.size(), 1u);
  EXPECT_EQ(cells.cells().cells_written, 6u);
  EXPECT_EQ(cells.table().rejected.size(), 1u);
  const std::string geojson = slurp(dir_ / "cells.geojson");
  EXPECT_TRUE(contains(geojson, "\"id\":0,")) << geojson.substr(0, 400);  // ids repeat: site_index is the id
  const std::string report = slurp(dir_ / "report.csv");
  EXPECT_TRUE(contains(report, "\n7,8,\"b\",merged,1,\n")) << report;
  EXPECT_TRUE(contains(report, "\n8,9,,rejected,,")) << report;
  const std::string log = log_.text();
  EXPECT_TRUE(contains(log, "row 8 (line 9) rejected")) << log;
  EXPECT_TRUE(contains(log, "warning: 1 rows have the id of an earlier row")) << log;
  EXPECT_TRUE(contains(log, "row 7 (id b) merged into the site of row 2 (id b): same position")) << log;
  EXPECT_TRUE(contains(log, input_.input + ": rows 8, sites 6, merged 1, rejected 1; 6 cells written to " +
                                dir_ / "cells.geojson" + "\n"))
      << log;
}

TEST_F(SiteCellsTest, TheSameOnAnyNumberOfThreads) {
  options_.report_path.clear();
  options_.threads = 1;
  SiteCells one(input_, dir_ / "one.geojson", options_);
  options_.threads = 0;
  SiteCells all(input_, dir_ / "all.geojson", options_);
  EXPECT_EQ(slurp(dir_ / "one.geojson"), slurp(dir_ / "all.geojson"));
  options_.file.writer.overwrite = true;  // the old output removed meanwhile, then replaced
  SiteCells again(input_, dir_ / "all.geojson", options_);
  EXPECT_EQ(slurp(dir_ / "one.geojson"), slurp(dir_ / "all.geojson"));
}

TEST_F(SiteCellsTest, QuietSaysOnlyWhatMustNotPassUnseen) {
  input_.quiet = true;
  options_.file.quiet = true;
  SiteCells cells(input_, dir_ / "cells.geojson", options_);
  const std::string log = log_.text();
  EXPECT_TRUE(contains(log, "rejected")) << log;
  EXPECT_FALSE(contains(log, "merged")) << log;
  EXPECT_FALSE(contains(log, "cells written")) << log;
}

TEST_F(SiteCellsTest, AnExistingReportIsRefusedBeforeAnyWork) {
  spit(options_.report_path, "old");
  EXPECT_EQ(error_of([&] { SiteCells cells(input_, dir_ / "cells.geojson", options_); }).code(), ErrorCode::Io);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "cells.geojson"));
  EXPECT_EQ(log_.text(), "");  // not even read
  EXPECT_EQ(slurp(options_.report_path), "old");
}

}  // namespace
}  // namespace geovor
