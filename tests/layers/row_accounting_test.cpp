// The accounting of a site table's rows on a log: rejected rows, repeated ids, merges, hidden
// sites and the counts, each said exactly as the geovor command says them on stderr.
#include "geovor/layers/row_accounting.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_weights.hpp"
#include "support/memory_stream.hpp"

namespace geovor {
namespace {

using testing::MemoryStream;

SiteTable read(const std::string& text) {
  std::istringstream in(text);
  return read_sites_csv(in, "t.csv");
}

BuildReport build(const SiteTable& table, const DelaunayOptions& options = {}) {
  BuildReport report;
  const std::vector<Vec3> points = site_points(table);
  if (table.weighted)
    (void)SphericalDelaunay::build(points, site_lifts(table), options, &report);
  else
    (void)SphericalDelaunay::build(points, options, &report);
  return report;
}

TEST(RowAccounting, ListsEachRejectedRowOnOneLine) {
  SiteTable t = read("id,lat,lon\na,1,2\nb,x,2\nc,95,0\n");
  t.rejected.push_back({7, 0, "feature 7 (FID 6): null\ngeometry"});  // an OGR feature: no line
  MemoryStream log;
  list_rejected_rows(log.get(), t);
  EXPECT_EQ(log.text(),
            "t.csv: row 2 (line 3) rejected: lat: 'x' is not a number\n"
            "t.csv: row 3 (line 4) rejected: lat: latitude 95 is beyond +-90\n"
            "t.csv: row 7 rejected: feature 7 (FID 6): null\\ngeometry\n");
}

TEST(RowAccounting, WarnsOnceOfRepeatedIdsNamingTheCallersOption) {
  const SiteTable t = read("name,lat,lon\nSan Jose,1,1\nA,2,2\nSan Jose,3,3\nA,4,4\n");
  MemoryStream log;
  warn_duplicate_ids(log.get(), t, find_duplicate_ids(t));
  warn_duplicate_ids(log.get(), t, find_duplicate_ids(t), "--id-field");
  EXPECT_EQ(log.text(),
            "t.csv: warning: 2 rows have the id of an earlier row (id column 'name'; e.g. 'San Jose' rows 1 3; "
            "'A' rows 2 4); id_field '#row' makes the row number the id\n"
            "t.csv: warning: 2 rows have the id of an earlier row (id column 'name'; e.g. 'San Jose' rows 1 3; "
            "'A' rows 2 4); --id-field '#row' makes the row number the id\n");
  MemoryStream none;
  warn_duplicate_ids(none.get(), t, DuplicateIds{});
  EXPECT_EQ(none.text(), "");
}

TEST(RowAccounting, ListsMergesWithTheRowTheirSiteWasBuiltFrom) {
  const SiteTable t = read("id,lat,lon\na,10,10\nb,-20,100\nc,10,10\nd,45,-60\ne,45,-60.00001\n");
  DelaunayOptions options;
  options.merge_distance = 10 / SiteEncoder::kEarthRadiusM;  // 10 m: d and e (0.79 m apart) merge
  MemoryStream log;
  list_merges(log.get(), t, build(t, options));
  const std::string text = log.text();
  EXPECT_NE(text.find("t.csv: row 3 (id c) merged into the site of row 1 (id a): same position\n"), std::string::npos)
      << text;
  EXPECT_NE(text.find(" m apart, closer than the merge distance\n"), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2);
}

TEST(RowAccounting, ListsHiddenSitesWithTheSiteHoldingThem) {
  SiteTable t = read("id,lat,lon,radius_m\nA,0,0,600000\nB,0,90,0\nC,90,0,0\nD,0,180,0\nE,0,-90,0\nF,-90,0,0\n"
                     "G,0,0.05,0\n");
  read_site_weights(t, "radius_m");
  MemoryStream log;
  list_hidden(log.get(), t, build(t));
  EXPECT_EQ(log.text(),
            "t.csv: row 7 (id 'G', radius 0 m) is hidden: its power cell is empty (row 1, id 'A', radius 600000 m, "
            "holds its position)\n");
}

TEST(RowAccounting, ANullLogSaysNothing) {
  const SiteTable t = read("id,lat,lon\na,1,1\na,1,1\nb,x,0\n");
  const BuildReport report = build(t);
  ASSERT_EQ(report.merges.size(), 1u);
  list_rejected_rows(nullptr, t);
  warn_duplicate_ids(nullptr, t, find_duplicate_ids(t));
  list_merges(nullptr, t, report);
  list_hidden(nullptr, t, report);
}

TEST(RowAccounting, RowCounts) {
  const SiteTable t = read("id,lat,lon\na,1,1\nb,1,1\nc,x,0\nd,5,5\n");
  EXPECT_EQ(row_counts(t, 2, 1), "t.csv: rows 4, sites 2, merged 1, rejected 1");
}

}  // namespace
}  // namespace geovor
