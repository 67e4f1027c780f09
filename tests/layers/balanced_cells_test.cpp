// Balanced cells of a job's sites written to files, or nothing when the solve does not converge.
#include "geovor/layers/balanced_cells.hpp"

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

class BalancedCellsTest : public ::testing::Test {
 protected:
  BalancedCellsTest() : dir_("geovor_balanced_cells") {
    spit(dir_ / "sites.csv", "id,lat,lon,cap\nN,90,0,1\nS,-90,0,1\nA,0,0,2\nE,0,90,1\nW,0,-90,x\nF,0,180,1\n");
    input_.input = dir_ / "sites.csv";
    input_.log = log_.get();
    options_.cells.log = log_.get();
    options_.capacity_field = "cap";
  }
  testing::TempDir dir_;
  MemoryStream log_;
  SiteInput input_;
  BalancedCellsOptions options_;
};

TEST_F(BalancedCellsTest, WritesTheBalancedCellsAndTheSites) {
  options_.sites_path = dir_ / "sites_out.csv";
  const BalanceReport result = balance_to_files(input_, dir_ / "cells.geojson", options_);
  ASSERT_TRUE(result.converged);
  const std::string cells = slurp(dir_ / "cells.geojson");
  EXPECT_TRUE(contains(cells, "\"weight_m\":")) << cells.substr(0, 400);
  EXPECT_TRUE(contains(cells, "\"target_m2\":")) << cells.substr(0, 400);
  EXPECT_TRUE(contains(slurp(options_.sites_path), "site_id,lat_deg,lon_deg,weight_m,target_m2\n\"N\","));
  const std::string log = log_.text();
  EXPECT_TRUE(contains(log, input_.input + ": row 5 (line 6) rejected: cap: \"x\" is not a number\n")) << log;
  EXPECT_TRUE(contains(log, input_.input + ": 5 sites, tolerance 1e-06\n")) << log;
  EXPECT_TRUE(contains(log, "rows 6, sites 5, merged 0, rejected 1; 5 cells written to " + dir_ / "cells.geojson" +
                                ", sites to " + options_.sites_path + "\n"))
      << log;
}

TEST_F(BalancedCellsTest, NotConvergedWritesNothing) {
  options_.balance.max_iterations = 0;
  options_.sites_path = dir_ / "sites_out.csv";
  const BalanceReport result = balance_to_files(input_, dir_ / "cells.geojson", options_);
  EXPECT_FALSE(result.converged);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "cells.geojson"));
  EXPECT_FALSE(std::filesystem::exists(options_.sites_path));
}

TEST_F(BalancedCellsTest, NoPositiveCapacityIsBadDataOnceTheRowsAreListed) {
  spit(dir_ / "none.csv", "id,lat,lon,cap\na,0,0,0\nb,0,90,-1\n");
  input_.input = dir_ / "none.csv";
  const Error e = error_of([&] { balance_to_files(input_, dir_ / "cells.geojson", options_); });
  EXPECT_EQ(e.code(), ErrorCode::BadData);
  EXPECT_EQ(std::string(e.what()), input_.input + ": no row has a positive capacity");
  EXPECT_TRUE(contains(log_.text(), "row 2 (line 3) rejected: cap: capacity -1 is not positive")) << log_.text();
}

TEST_F(BalancedCellsTest, ATargetColumnOfTheInputIsKept) {
  spit(dir_ / "target.csv", "id,lat,lon,target_m2\nN,90,0,a\nS,-90,0,b\nA,0,0,c\nE,0,90,d\n");
  input_.input = dir_ / "target.csv";
  options_.capacity_field.clear();
  options_.cells.quiet = true;
  ASSERT_TRUE(balance_to_files(input_, dir_ / "cells.geojson", options_).converged);
  EXPECT_EQ(log_.text(), input_.input + ": has a column 'target_m2' already: the targets are not written\n");
}

}  // namespace
}  // namespace geovor
