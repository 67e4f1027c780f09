// A job's sites: reading with the rows accounted for on the log, the merge distance, the build
// and the nearest-site index.
#include "geovor/layers/site_input.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
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

// Site G lies in A's circle (hidden when weighted); row 8's radius is no number; A and B repeat.
constexpr const char* kSites = "name,lat,lon,r\nA,0,0,600000\nB,0,90,0\nC,90,0,0\nD,0,180,0\nE,0,-90,0\n"
                               "F,-90,0,0\nG,0,0.05,0\nA,1,1,x\nB,0,90,0\n";

class SiteInputTest : public ::testing::Test {
 protected:
  SiteInputTest() : dir_("geovor_site_input") {
    spit(dir_ / "sites.csv", kSites);
    input_.input = dir_ / "sites.csv";
    input_.log = log_.get();
  }
  testing::TempDir dir_;
  MemoryStream log_;
  SiteInput input_;
};

TEST_F(SiteInputTest, ReadsAndAccountsForTheRows) {
  DuplicateIds duplicates;
  const SiteTable t = read_site_input(input_, &duplicates);
  EXPECT_EQ(t.rows_read, 9u);
  EXPECT_EQ(t.sites.size(), 9u);
  EXPECT_FALSE(t.weighted);
  EXPECT_EQ(duplicates.rows, 2u);
  EXPECT_EQ(log_.text(), input_.input + ": warning: 2 rows have the id of an earlier row (id column 'name'; e.g. "
                                        "'A' rows 1 8; 'B' rows 2 9); id_field '#row' makes the row number the id\n");
}

TEST_F(SiteInputTest, WeightedSitesRejectRowsWithoutARadius) {
  input_.weight_field = "r";
  input_.id_field_name = "--id-field";
  const SiteTable t = read_site_input(input_);
  EXPECT_TRUE(t.weighted);
  EXPECT_EQ(t.sites.size(), 8u);
  EXPECT_EQ(t.sites[0].weight_m, 600000);
  EXPECT_EQ(log_.text(), input_.input + ": row 8 (line 9) rejected: r: \"x\" is not a number\n" + input_.input +
                             ": warning: 1 rows have the id of an earlier row (id column 'name'; e.g. 'B' rows 2 9); "
                             "--id-field '#row' makes the row number the id\n");
}

TEST_F(SiteInputTest, NoSiteIsBadDataOnceTheRowsAreListed) {
  spit(dir_ / "none.csv", "lat,lon\nx,1\n");
  input_.input = dir_ / "none.csv";
  EXPECT_EQ(error_of([&] { read_site_input(input_); }).code(), ErrorCode::BadData);
  EXPECT_TRUE(contains(log_.text(), "row 1 (line 2) rejected")) << log_.text();
}

TEST_F(SiteInputTest, ALayerIsForOgrSources) {
  input_.layer = "sites";
  EXPECT_TRUE(site_input_needs_gdal(input_));
  Error e = error_of([&] { read_site_input(input_); });
  EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
  EXPECT_EQ(std::string(e.what()), input_.input + ": layer is for OGR sources; a CSV file has one table");
  input_.layer_name = "--layer";
  e = error_of([&] { check_site_input(input_); });
  EXPECT_EQ(std::string(e.what()), input_.input + ": --layer is for OGR sources; a CSV file has one table");
}

TEST_F(SiteInputTest, WhatNeedsGdal) {
  EXPECT_FALSE(site_input_needs_gdal(input_));
  input_.reader.s_srs = "EPSG:2154";
  EXPECT_TRUE(site_input_needs_gdal(input_));
  input_.reader.s_srs.clear();
  input_.input = dir_ / "sites.gpkg";
  EXPECT_TRUE(site_input_needs_gdal(input_));
}

TEST_F(SiteInputTest, TheMergeDistanceIsNeverBelowTheMinimumSeparation) {
  EXPECT_EQ(delaunay_options(input_).merge_distance, SphericalDelaunay::kMinSeparation);
  input_.merge_m = 1000;
  EXPECT_EQ(delaunay_options(input_).merge_distance, 1000 / SiteEncoder::kEarthRadiusM);
  input_.merge_m = 0.01;
  EXPECT_EQ(delaunay_options(input_).merge_distance, SphericalDelaunay::kMinSeparation);
}

TEST_F(SiteInputTest, BuildsAndListsTheBuild) {
  input_.weight_field = "r";
  const SiteTable t = read_site_input(input_);
  const std::vector<Vec3> points = site_points(t);
  BuildReport weighted;
  const SphericalDelaunay dt = build_sites(points, site_lifts(t), input_, weighted);
  EXPECT_EQ(dt.num_sites(), 6u);  // G hidden, the second B merged
  ASSERT_EQ(weighted.hidden.size(), 1u);
  ASSERT_EQ(weighted.merges.size(), 1u);
  MemoryStream log;
  input_.log = log.get();
  input_.quiet = true;  // no merges, but the hidden site
  list_build(input_, t, weighted);
  EXPECT_EQ(log.text(), input_.input + ": row 7 (id 'G', radius 0 m) is hidden: its power cell is empty (row 1, id "
                                       "'A', radius 600000 m, holds its position)\n");
  input_.quiet = false;
  list_build(input_, t, weighted);
  EXPECT_TRUE(contains(log.text(), "row 9 (id B) merged into the site of row 2 (id B): same position")) << log.text();
  BuildReport unweighted;
  EXPECT_EQ(build_sites(points, {}, input_, unweighted).num_sites(), 7u);  // 8 points, B twice
  EXPECT_TRUE(unweighted.hidden.empty());
}

TEST_F(SiteInputTest, BuildsTheIndexOrLoadsIt) {
  TableBuild summary;
  const SiteIndex index = build_index_from_table(input_, &summary);
  EXPECT_EQ(summary.source, input_.input);
  EXPECT_EQ(summary.rows, 9u);
  EXPECT_EQ(summary.sites, 8u);
  EXPECT_EQ(summary.merged, 1u);
  EXPECT_EQ(summary.rejected, 0u);
  EXPECT_FALSE(summary.hidden);
  EXPECT_GE(summary.read_seconds, 0);
  EXPECT_TRUE(contains(log_.text(), "merged into the site of row 2")) << log_.text();
  const std::string path = dir_ / "sites.gvi";
  save_index(path, index.hierarchy, index.attributes);
  SiteInput saved;
  saved.input = path;
  const SiteIndex loaded = load_site_index(saved);
  EXPECT_EQ(loaded.attributes.num_rows(), 9u);
  EXPECT_EQ(load_site_index(input_).hierarchy.base().num_sites(), 8u);
}

}  // namespace
}  // namespace geovor
