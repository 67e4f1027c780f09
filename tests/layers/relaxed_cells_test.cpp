// Lloyd's iterations on a job's sites, then the cells and the sites written to files.
#include "geovor/layers/relaxed_cells.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "geovor/core/error.hpp"
#include "geovor/core/output_target.hpp"
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

class RelaxedCellsTest : public ::testing::Test {
 protected:
  RelaxedCellsTest() : dir_("geovor_relaxed_cells") {
    spit(dir_ / "sites.csv", "id,lat,lon\na,10,10\nb,12,40\nc,60,0\nd,-5,170\ne,-30,-90\nf,-70,20\ng,30,-120\n");
    input_.input = dir_ / "sites.csv";
    input_.log = log_.get();
    options_.cells.log = log_.get();
    options_.lloyd.iterations = 3;
  }
  testing::TempDir dir_;
  MemoryStream log_;
  SiteInput input_;
  RelaxedCellsOptions options_;
};

TEST_F(RelaxedCellsTest, WhereTheSitesGo) {
  options_.sites_path = dir_ / "a.gpkg";
  EXPECT_TRUE(sites_in_cells_source(dir_ / "a.gpkg", options_));
  EXPECT_FALSE(sites_in_cells_source(dir_ / "b.gpkg", options_));
  options_.sites_path = dir_ / "a.geojson";
  EXPECT_FALSE(sites_in_cells_source(dir_ / "a.geojson", options_));  // one layer per file
  options_.sites_path.clear();
  EXPECT_FALSE(sites_in_cells_source(dir_ / "a.gpkg", options_));
}

TEST_F(RelaxedCellsTest, OutputsAreCheckedBeforeAnyWork) {
  options_.sites_path = dir_ / "a.geojson";
  Error e = error_of([&] { check_relaxed_outputs(dir_ / "a.geojson", options_, "--output", "--sites-output"); });
  EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
  EXPECT_TRUE(contains(e.what(), "--output " + dir_ / "a.geojson" + " and --sites-output")) << e.what();
  options_.sites_path = dir_ / "a.gpkg";
  check_relaxed_outputs(dir_ / "a.gpkg", options_);  // two layers of one data source
  spit(dir_ / "old.geojson", "old");
  options_.sites_path = dir_ / "s.geojson";
  e = error_of([&] { check_relaxed_outputs(dir_ / "old.geojson", options_); });
  EXPECT_EQ(e.code(), ErrorCode::Io);
  EXPECT_EQ(std::string(e.what()), output_exists(dir_ / "old.geojson"));
  options_.cells.writer.overwrite = true;
  check_relaxed_outputs(dir_ / "old.geojson", options_);
}

TEST_F(RelaxedCellsTest, IteratesThenWritesTheCellsAndTheSites) {
  options_.sites_path = dir_ / "sites.geojson";
  const LloydReport report = relax_to_files(input_, dir_ / "cells.geojson", options_);
  EXPECT_EQ(report.iterations.size(), 3u);
  EXPECT_TRUE(contains(slurp(dir_ / "cells.geojson"), "\"site_id\":\"a\""));
  const std::string sites = slurp(dir_ / "sites.geojson");
  EXPECT_TRUE(contains(sites, "\"name\":\"sites\"")) << sites.substr(0, 200);
  EXPECT_TRUE(contains(sites, "\"moved_m\":")) << sites.substr(0, 400);
  const std::string log = log_.text();
  EXPECT_TRUE(contains(log, input_.input + ": 7 sites, 3 iterations (filtered relocation)\n")) << log;
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1 + 1 + 3 + 1 + 1) << log;  // header, 3 lines, energy, counts
  EXPECT_TRUE(contains(log, "\nfinal energy ")) << log;
  EXPECT_TRUE(contains(log, "; 7 cells written to " + dir_ / "cells.geojson" + ", sites to " + options_.sites_path + "\n"))
      << log;
}

TEST_F(RelaxedCellsTest, TheSitesAsASecondLayerOfTheCellsDataSource) {
  options_.sites_path = dir_ / "relaxed.gpkg";
  options_.cells.quiet = true;
  relax_to_files(input_, dir_ / "relaxed.gpkg", options_);
  EXPECT_EQ(log_.text(), "");
  EXPECT_TRUE(std::filesystem::exists(dir_ / "relaxed.gpkg"));
  // Again: the cells' layer replaced, the sites' too, in the same file.
  options_.cells.writer.overwrite = true;
  relax_to_files(input_, dir_ / "relaxed.gpkg", options_);
}

}  // namespace
}  // namespace geovor
