// The nearest join between files: which reader and which writer, the malformed queries on the
// log, and an output that is complete or absent.
#include "geovor/layers/nearest_join_files.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
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

SiteIndex index_of_three() {
  std::istringstream in("id,lat,lon\nparis,48.85,2.35\nsydney,-33.87,151.21\nquito,-0.18,-78.47\n");
  return build_site_index(read_sites_csv(in, "sites.csv"));
}

class NearestJoinFilesTest : public ::testing::Test {
 protected:
  NearestJoinFilesTest() : dir_("geovor_nearest_join_files") { files_.log = log_.get(); }
  testing::TempDir dir_;
  MemoryStream log_;
  NearestJoinFiles files_;
  SiteIndex index_ = index_of_three();
};

TEST_F(NearestJoinFilesTest, TheRulesOfTheQueriesAndTheOutput) {
  EXPECT_FALSE(queries_are_ogr(files_));  // standard input
  EXPECT_TRUE(writes_csv(files_));        // standard output
  EXPECT_EQ(query_source(files_), "<stdin>");
  files_.queries = dir_ / "q.gpkg";
  EXPECT_TRUE(queries_are_ogr(files_));
  EXPECT_EQ(query_source(files_), files_.queries);
  files_.queries = dir_ / "q.csv";
  EXPECT_FALSE(queries_are_ogr(files_));
  files_.query_layer = "points";
  EXPECT_TRUE(queries_are_ogr(files_));
  files_.output = "out.geojson";
  EXPECT_FALSE(writes_csv(files_));
  files_.output = "out.txt";
  EXPECT_TRUE(writes_csv(files_));
  files_.writer.format = "GPKG";
  EXPECT_FALSE(writes_csv(files_));
  EXPECT_EQ(NearestJoinFiles{}.writer.layer, "nearest");
}

TEST_F(NearestJoinFilesTest, CsvInCsvOutWithTheMalformedQueriesOnTheLog) {
  files_.queries = dir_ / "q.csv";
  files_.output = dir_ / "out.csv";
  spit(files_.queries, "lat,lon,name\n48.9,2.4,a\nx,1,b\n-1,-78,c\n");
  const NearestJoinReport report = nearest_join_files(index_, files_, {});
  EXPECT_EQ(report.answered, 2u);
  EXPECT_EQ(report.malformed, 1u);
  const std::string out = slurp(files_.output);
  EXPECT_EQ(out.substr(0, out.find('\n')), "query_id,site_index,site_id,distance_m,lat,lon,name");
  EXPECT_TRUE(contains(out, "\na,0,paris,")) << out;  // the name column is the id
  EXPECT_TRUE(contains(out, "\nc,2,quito,")) << out;
  EXPECT_EQ(log_.text(), files_.queries + ": line 3: lat: 'x' is not a number\n");
}

TEST_F(NearestJoinFilesTest, AStrictStopKeepsTheAnswersBeforeIt) {
  files_.queries = dir_ / "q.csv";
  files_.output = dir_ / "out.csv";
  spit(files_.queries, "lat,lon\n48.9,2.4\nx,1\n-1,-78\n");
  NearestJoinOptions options;
  options.strict = true;
  const NearestJoinReport report = nearest_join_files(index_, files_, options);
  EXPECT_TRUE(report.stopped);
  EXPECT_EQ(report.answered, 1u);
  EXPECT_TRUE(contains(slurp(files_.output), "\n2,0,paris,"));  // no id column: the line
}

TEST_F(NearestJoinFilesTest, OgrQueriesToPointFeatures) {
  files_.queries = dir_ / "q.geojson";
  files_.output = dir_ / "out.geojson";
  spit(files_.queries,
       "{\"type\":\"FeatureCollection\",\"features\":["
       "{\"type\":\"Feature\",\"properties\":{\"v\":7},\"geometry\":{\"type\":\"Point\",\"coordinates\":[150,-30]}},"
       "{\"type\":\"Feature\",\"properties\":{\"v\":8},\"geometry\":null}]}");
  NearestJoinOptions options;
  options.query_field_types = {{"v", FieldType::String}};  // through the reader
  const NearestJoinReport report = nearest_join_files(index_, files_, options);
  EXPECT_EQ(report.answered, 1u);
  EXPECT_EQ(report.malformed, 1u);
  const std::string out = slurp(files_.output);
  EXPECT_TRUE(contains(out, "\"site_id\":\"sydney\"")) << out;
  EXPECT_TRUE(contains(out, "\"v\":\"7\"")) << out;  // declared String
  EXPECT_TRUE(contains(log_.text(), files_.queries + ": feature 2")) << log_.text();
}

TEST_F(NearestJoinFilesTest, QueriesThatCannotBeOpenedLeaveNoOutput) {
  files_.queries = dir_ / "missing.csv";
  files_.output = dir_ / "out.csv";
  const Error e = error_of([&] { nearest_join_files(index_, files_, {}); });
  EXPECT_EQ(e.code(), ErrorCode::Io);
  EXPECT_TRUE(contains(e.what(), "missing.csv: cannot open")) << e.what();
  EXPECT_FALSE(std::filesystem::exists(files_.output));
}

TEST_F(NearestJoinFilesTest, AnExistingOutputNeedsOverwrite) {
  files_.queries = dir_ / "q.csv";
  files_.output = dir_ / "out.csv";
  spit(files_.queries, "lat,lon\n1,1\n");
  spit(files_.output, "old");
  EXPECT_EQ(error_of([&] { nearest_join_files(index_, files_, {}); }).code(), ErrorCode::Io);
  EXPECT_EQ(slurp(files_.output), "old");
  files_.writer.overwrite = true;
  nearest_join_files(index_, files_, {});
  EXPECT_TRUE(contains(slurp(files_.output), "query_id"));
}

}  // namespace
}  // namespace geovor
