// StagedSiteInput: the same table, positions and accounting as read_site_input(), in two stages.
#include "geovor/layers/staged_site_input.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_weights.hpp"
#include "support/file_text.hpp"
#include "support/memory_stream.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

using testing::contains;
using testing::error_of;
using testing::MemoryStream;
using testing::spit;

constexpr const char* kSites = "name,lat,lon,r\nA,0,0,600000\nB,0,90,0\nC,90,0,0\nD,0,180,0\nE,0,-90,0\n"
                               "F,-90,0,0\nG,0,0.05,x\nA,1,1,0\nH,95,0,0\n";

class StagedSiteInputTest : public ::testing::Test {
 protected:
  StagedSiteInputTest() : dir_("geovor_staged_site_input") {
    spit(dir_ / "sites.csv", kSites);
    input_.input = dir_ / "sites.csv";
  }
  // What read_site_input() reads and says.
  std::pair<SiteTable, std::string> whole() {
    MemoryStream log;
    SiteInput input = input_;
    input.log = log.get();
    SiteTable t = read_site_input(input);
    return {std::move(t), log.text()};
  }
  testing::TempDir dir_;
  SiteInput input_;
};

void expect_same_table(const SiteTable& a, const SiteTable& b) {
  EXPECT_EQ(a.rows_read, b.rows_read);
  ASSERT_EQ(a.sites.size(), b.sites.size());
  for (std::size_t i = 0; i < a.sites.size(); ++i) {
    EXPECT_EQ(a.sites[i].row, b.sites[i].row);
    EXPECT_EQ(a.sites[i].fields, b.sites[i].fields);
    EXPECT_EQ(a.sites[i].weight_m, b.sites[i].weight_m);
  }
  EXPECT_EQ(a.rejected.size(), b.rejected.size());
}

TEST_F(StagedSiteInputTest, TheSameAsReadingWholeInTheForegroundAndTheBackground) {
  for (const bool background : {false, true}) {
    const auto [expected, said] = whole();
    MemoryStream log;
    input_.log = log.get();
    std::atomic<int> thens = 0;
    const std::size_t expected_sites = expected.sites.size();  // clang 14 captures no structured binding
    StagedSiteInput staged(input_, background, [&](const SiteTable& t) {
      EXPECT_EQ(t.sites.size(), expected_sites);
      ++thens;
    });
    EXPECT_EQ(staged.positions().size(), expected.sites.size());
    EXPECT_TRUE(staged.lifts().empty());
    expect_same_table(staged.table(), expected);
    EXPECT_EQ(thens, 1);
    EXPECT_TRUE(staged.ids_repeat());  // A
    for (std::size_t i = 0; i < expected.sites.size(); ++i) EXPECT_EQ(staged.positions()[i], expected.sites[i].unit);
    (void)staged.table();  // said once
    EXPECT_EQ(log.text(), said);
    EXPECT_TRUE(contains(said, "row 9 (line 10) rejected")) << said;
  }
}

TEST_F(StagedSiteInputTest, WeightedSitesHaveTheirLiftsAtOnce) {
  input_.weight_field = "r";
  const auto [expected, said] = whole();
  MemoryStream log;
  input_.log = log.get();
  StagedSiteInput staged(input_, true);
  EXPECT_EQ(staged.lifts().size(), expected.sites.size());  // G and H rejected
  EXPECT_EQ(staged.lifts()[0], site_lift(600000));
  expect_same_table(staged.table(), expected);
  EXPECT_EQ(log.text(), said);
}

TEST_F(StagedSiteInputTest, NoSiteIsBadDataAtOnceAfterTheRowsAreListed) {
  spit(dir_ / "none.csv", "lat,lon\nx,1\n");
  input_.input = dir_ / "none.csv";
  MemoryStream log;
  input_.log = log.get();
  EXPECT_EQ(error_of([&] { StagedSiteInput staged(input_, true); }).code(), ErrorCode::BadData);
  EXPECT_TRUE(contains(log.text(), "row 1 (line 2) rejected")) << log.text();
}

TEST_F(StagedSiteInputTest, ALayerIsForOgrSources) {
  input_.layer = "x";
  EXPECT_EQ(error_of([&] { StagedSiteInput staged(input_, false); }).code(), ErrorCode::InvalidArgument);
}

}  // namespace
}  // namespace geovor
