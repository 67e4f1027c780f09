// The row report: every row of the table and what became of it.
#include "geovor/layers/row_report.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "geovor/geo/site_weights.hpp"
#include "support/memory_stream.hpp"

namespace geovor {
namespace {

using testing::MemoryStream;

TEST(RowReport, EveryRowSitesFirstThenTheRejected) {
  std::istringstream in("id,lat,lon,r\nA,0,0,600000\nB,0,90,0\nC,90,0,0\nD,0,180,0\nE,0,-90,0\nF,-90,0,0\n"
                        "G,0,0.05,0\n\"B\"\"\n2\",0,90,0\nbad,95,0,0\nH,10,10,x\n");
  SiteTable t = read_sites_csv(in, "t.csv");
  read_site_weights(t, "r");
  BuildReport report;
  (void)SphericalDelaunay::build(site_points(t), site_lifts(t), {}, &report);
  ASSERT_EQ(report.hidden.size(), 1u);  // G, in A's circle
  ASSERT_EQ(report.merges.size(), 1u);  // B2 into B
  const std::vector<UnwrittenCell> unwritten = {{2, CellStatus::Collapsed}};  // C's cell, say
  MemoryStream out;
  write_row_report(out.get(), t, report, unwritten, "at precision 3");
  EXPECT_EQ(out.text(),
            "row,line,id,status,site_index,detail\n"
            "1,2,\"A\",site,0,\n"
            "2,3,\"B\",site,1,\n"
            "3,4,\"C\",site,2,\"cell collapsed at precision 3: empty geometry\"\n"
            "4,5,\"D\",site,3,\n"
            "5,6,\"E\",site,4,\n"
            "6,7,\"F\",site,5,\n"
            "7,8,\"G\",hidden,6,\"power cell empty: site 0 holds its position\"\n"
            "8,9,\"B\"\"\\n2\",merged,1,\n"  // one line: the line break escaped
            "9,11,,rejected,,\"lat: latitude 95 is beyond +-90\"\n"
            "10,12,,rejected,,\"r: \"\"x\"\" is not a number\"\n");
}

}  // namespace
}  // namespace geovor
