/// \file query_line_test.cpp
/// \brief Tests of the query-line parser: format detection, numbers, fields (against CsvReader
/// on random lines), and the reasons of malformed lines.
#include "geovor/geo/query_line.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/csv_reader.hpp"

namespace geovor {
namespace {

std::vector<std::string> split(std::string_view line, const char** why = nullptr) {
  std::vector<std::string_view> views;
  std::string scratch;
  const char* r = split_query_fields(line, views, scratch);
  if (why) *why = r;
  return {views.begin(), views.end()};
}

TEST(QueryLine, DetectsHeaderlessLines) {
  const QueryFormat f = detect_query_format("45.5,-73.25,a", "q.csv");
  EXPECT_FALSE(f.header);
  EXPECT_EQ(f.lat, 0);
  EXPECT_EQ(f.lon, 1);
  EXPECT_TRUE(detect_query_format(" +1 ,2\r", "q.csv").columns.empty());
}

TEST(QueryLine, DetectsHeaderColumns) {
  const QueryFormat f = detect_query_format("name, Longitude ,LAT,extra\r", "q.csv");
  EXPECT_TRUE(f.header);
  EXPECT_EQ(f.fields, 4u);
  EXPECT_EQ(f.columns, (std::vector<std::string>{"name", "Longitude", "LAT", "extra"}));
  EXPECT_EQ(f.lat, 2);
  EXPECT_EQ(f.lon, 1);
  EXPECT_EQ(f.id, 0);
  EXPECT_EQ(detect_query_format("query_id,id,lat,lon", "q.csv").id, 0);  // query_id preferred
}

// Columns named by the caller: any name, case-insensitively; a named column makes the first line
// a header even when its fields are numbers; the id is still detected unless named.
TEST(QueryLine, NamedColumns) {
  QueryColumns names;
  names.lat_field = "pickup_latitude";
  names.lon_field = "Pickup_Longitude";
  const QueryFormat f = detect_query_format("vendor,pickup_longitude,pickup_latitude,id,lat", "q.csv", names);
  EXPECT_TRUE(f.header);
  EXPECT_EQ(f.lat, 2);
  EXPECT_EQ(f.lon, 1);
  EXPECT_EQ(f.id, 3);
  names = {};
  names.lat_field = "10";
  names.lon_field = "20";
  names.id_field = "30";
  const QueryFormat numbers = detect_query_format("20,10,30", "q.csv", names);
  EXPECT_TRUE(numbers.header);
  EXPECT_EQ(numbers.lat, 1);
  EXPECT_EQ(numbers.lon, 0);
  EXPECT_EQ(numbers.id, 2);
  names = {};
  names.lon_field = "dropoff_longitude";
  try {
    detect_query_format("lat,lon", "q.csv", names);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_EQ(std::string(e.what()), "q.csv: --query-lon-field 'dropoff_longitude' is not a column of the header (lat, lon)");
  }
}

TEST(QueryLine, HeaderWithoutCoordinatesIsBadData) {
  for (const char* first : {"a,b", "lat", "", "\"unterminated,lat,lon"}) {
    try {
      detect_query_format(first, "q.csv");
      ADD_FAILURE() << "no error for '" << first << "'";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::BadData);
      EXPECT_NE(std::string(e.what()).find("q.csv: no latitude/longitude columns"), std::string::npos);
    }
  }
  // A name twice is a header error, as in a site table; two equally good names are ambiguous.
  try {
    detect_query_format("lat,lat", "q.csv");
    ADD_FAILURE() << "no error for 'lat,lat'";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadData);
    EXPECT_NE(std::string(e.what()).find("q.csv: header: column 2 'lat' has the same name as column 1 'lat'"),
              std::string::npos) << e.what();
  }
  try {
    detect_query_format("pickup_lat,dropoff_lat,lon", "q.csv");
    ADD_FAILURE() << "no error for two latitudes";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadData);
    EXPECT_NE(std::string(e.what()).find("choose one with --query-lat-field"), std::string::npos) << e.what();
  }
}

TEST(QueryLine, Numbers) {
  double v = 0;
  EXPECT_STREQ(parse_query_number(" +12.5\t", v), "");
  EXPECT_EQ(v, 12.5);
  EXPECT_STREQ(parse_query_number("-1e-3", v), "");
  EXPECT_EQ(v, -1e-3);
  EXPECT_STREQ(parse_query_number("1e400", v), "is out of the range of a double");
  EXPECT_STREQ(parse_query_number("  ", v), "empty value");
  EXPECT_STREQ(parse_query_number("", v), "empty value");
  for (const char* bad : {"abc", "+-1", "++1", "1.5x", "0x10", "1,5", "+"})
    EXPECT_STREQ(parse_query_number(bad, v), "is not a number") << bad;
  EXPECT_STREQ(parse_query_number("nan", v), "");  // a number; normalize_lat_lon rejects it
  EXPECT_TRUE(std::isnan(v));
}

TEST(QueryLine, Fields) {
  EXPECT_EQ(split("1,2,"), (std::vector<std::string>{"1", "2", ""}));
  EXPECT_EQ(split("\"a,b\",\"say \"\"hi\"\"\",\"ab\"c,d\"e"),
            (std::vector<std::string>{"a,b", "say \"hi\"", "abc", "d\"e"}));
  EXPECT_EQ(split("\"\""), (std::vector<std::string>{""}));
  const char* why = nullptr;
  split("1,\"open", &why);
  EXPECT_STREQ(why, "unterminated quoted field (a query cannot span lines)");
}

// Oracle: on a line without line ends and with its quotes closed, the fields are CsvReader's.
TEST(QueryLine, FieldsAgreeWithCsvReaderOnRandomLines) {
  std::mt19937_64 rng(5);
  const std::string alphabet = "ab,\" 1";
  int compared = 0;
  for (int iter = 0; iter < 20000; ++iter) {
    std::string line(rng() % 12 + 1, ' ');
    for (char& c : line) c = alphabet[rng() % alphabet.size()];
    const char* why = nullptr;
    const std::vector<std::string> ours = split(line, &why);
    std::istringstream in(line);
    CsvReader reader(in);
    std::vector<std::string> theirs;
    ASSERT_TRUE(reader.next(theirs));
    if (*why) {
      EXPECT_FALSE(reader.error().empty()) << line;  // both see the quote left open
      continue;
    }
    EXPECT_EQ(ours, theirs) << line;
    ++compared;
  }
  EXPECT_GT(compared, 5000);
}

TEST(QueryLine, ParsesHeaderlessQueries) {
  QueryLineParser p(detect_query_format("1,2", "q"));
  QueryLine q;
  std::string reason;
  ASSERT_TRUE(p.parse("45.5, 180", q, reason));
  EXPECT_EQ(q.lat_deg, 45.5);
  EXPECT_EQ(q.lon_deg, -180);  // normalised
  EXPECT_EQ(q.id.data(), nullptr);
  ASSERT_TRUE(p.parse("-90,33,\"x,y\"", q, reason));
  EXPECT_EQ(q.lat_deg, -90);
  EXPECT_EQ(q.lon_deg, 0);  // every longitude at a pole is one point
  EXPECT_EQ(q.id, "x,y");
  EXPECT_TRUE(q.id_quoted);
  const std::string line = "1,2,plain";
  ASSERT_TRUE(p.parse(line, q, reason));
  EXPECT_EQ(q.id, "plain");
  EXPECT_FALSE(q.id_quoted);
  EXPECT_EQ(q.id.data(), line.data() + 4);  // a view of the line, no copy
  ASSERT_TRUE(p.parse("1,2,", q, reason));
  EXPECT_NE(q.id.data(), nullptr);  // an empty id is still an id
  EXPECT_TRUE(q.id.empty());
  EXPECT_TRUE(reason.empty());
}

TEST(QueryLine, ReasonsOfMalformedLines) {
  QueryLineParser p(detect_query_format("1,2", "q"));
  QueryLine q;
  auto why = [&](std::string_view line) {
    std::string reason;
    EXPECT_FALSE(p.parse(line, q, reason)) << line;
    return reason;
  };
  EXPECT_EQ(why("1"), "expected 2 or 3 (lat,lon[,id]) fields, found 1");
  EXPECT_EQ(why("1,2,3,4"), "expected 2 or 3 (lat,lon[,id]) fields, found 4");
  EXPECT_EQ(why(" abc ,2"), "lat: 'abc' is not a number");
  EXPECT_EQ(why("1,"), "lon: empty value");
  EXPECT_EQ(why("1,1e999"), "lon: '1e999' is out of the range of a double");
  EXPECT_EQ(why("1," + std::string(50, 'z')), "lon: '" + std::string(40, 'z') + "...' (50 characters) is not a number");
  EXPECT_EQ(why("91,0"), "latitude 91 is beyond +-90");
  EXPECT_NE(why("nan,0").find("latitude"), std::string::npos);
  EXPECT_EQ(why("1,\"2"), "unterminated quoted field (a query cannot span lines)");

  QueryLineParser h(detect_query_format("id,y,x", "q"));
  std::string reason;
  EXPECT_FALSE(h.parse("a,1", q, reason));
  EXPECT_EQ(reason, "expected 3 fields, found 2");
  EXPECT_FALSE(h.parse("a,north,1", q, reason));
  EXPECT_EQ(reason, "y: 'north' is not a number");
  ASSERT_TRUE(h.parse("a,1,600", q, reason) == false);
  EXPECT_NE(reason.find("longitude 600"), std::string::npos);
  ASSERT_TRUE(h.parse("\"a\"\"b\",10,20", q, reason));
  EXPECT_EQ(q.id, "a\"b");
  EXPECT_EQ(q.lat_deg, 10);
  EXPECT_EQ(q.lon_deg, 20);
}

}  // namespace
}  // namespace geovor
