// The sites' capacities read from a column of their table: the rows without one rejected.
#include "geovor/relax/capacities.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "support/file_text.hpp"

namespace geovor {
namespace {

using testing::error_of;

SiteTable read(const std::string& text) {
  std::istringstream in(text);
  return read_sites_csv(in, "t.csv");
}

TEST(Capacities, ParsesPositiveNumbers) {
  double v = 0;
  EXPECT_EQ(parse_capacity(" 2.5\t", false, v), "");
  EXPECT_EQ(v, 2.5);
  EXPECT_EQ(parse_capacity("+3", false, v), "");
  EXPECT_EQ(v, 3);
  EXPECT_EQ(parse_capacity("1,5", true, v), "");  // a decimal comma beside another delimiter
  EXPECT_EQ(v, 1.5);
  EXPECT_EQ(parse_capacity("1,5", false, v), "\"1,5\" is not a number");
  EXPECT_EQ(parse_capacity("  ", false, v), "empty: a site needs a positive capacity");
  EXPECT_EQ(parse_capacity("x", false, v), "\"x\" is not a number");
  EXPECT_EQ(parse_capacity("inf", false, v), "\"inf\" is not a number");
  EXPECT_EQ(parse_capacity("0", false, v), "capacity 0 is not positive");
  EXPECT_EQ(parse_capacity("-1", false, v), "capacity -1 is not positive");
}

TEST(Capacities, RowsWithoutOneAreRejectedInRowOrder) {
  SiteTable t = read("id,lat,lon,Cap\na,0,0,1\nb,x,0,2\nc,0,90,-1\nd,90,0,\ne,0,180,4\nf,-90,0,5\ng,0,-90\n");
  ASSERT_EQ(t.rejected.size(), 2u);  // b: its latitude; g: a field short
  t.sites[4].fields.resize(3);       // f: a short row, as a table may have
  const CapacityReport report = read_capacities(t, " cap ");
  EXPECT_EQ(report.capacities, (std::vector<double>{1, 4}));
  ASSERT_EQ(t.sites.size(), 2u);
  EXPECT_EQ(t.sites[1].id, "e");
  ASSERT_EQ(report.rejected.size(), 3u);
  EXPECT_EQ(report.rejected[0].row, 3u);
  EXPECT_EQ(report.rejected[0].line, 4u);
  EXPECT_EQ(report.rejected[0].reason, "Cap: capacity -1 is not positive");
  EXPECT_EQ(report.rejected[1].reason, "Cap: empty: a site needs a positive capacity");
  EXPECT_EQ(report.rejected[2].reason, "Cap: empty: a site needs a positive capacity");  // the short row
  std::vector<std::uint64_t> rows;
  for (const RejectedRow& r : t.rejected) rows.push_back(r.row);
  EXPECT_EQ(rows, (std::vector<std::uint64_t>{2, 3, 4, 6, 7}));
  EXPECT_EQ(t.rows_read, 7u);
}

TEST(Capacities, NoColumnGivesEqualShares) {
  SiteTable t = read("id,lat,lon\na,0,0\nb,0,90\n");
  EXPECT_EQ(read_capacities(t, "").capacities, (std::vector<double>{1, 1}));
}

TEST(Capacities, AnUnknownColumnIsNamedWithTheColumns) {
  SiteTable t = read("id,lat,lon\na,0,0\n");
  const Error e = error_of([&] { read_capacities(t, "trucks"); });
  EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
  EXPECT_EQ(std::string(e.what()), "t.csv: no capacity column 'trucks' (columns: id, lat, lon)");
}

TEST(Capacities, NoSiteLeftIsTheCallersToSay) {
  SiteTable t = read("id,lat,lon,cap\na,0,0,0\n");
  const CapacityReport report = read_capacities(t, "cap");
  EXPECT_TRUE(t.sites.empty());
  EXPECT_TRUE(report.capacities.empty());
  EXPECT_EQ(report.rejected.size(), 1u);
}

}  // namespace
}  // namespace geovor
