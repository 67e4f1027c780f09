/// \file site_reader_test.cpp
/// \brief Tests of read_sites_csv: column detection, every row accounted for, reasons, errors.
#include "geovor/geo/site_reader.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor {
namespace {

SiteTable read(const std::string& text, const SiteReaderOptions& options = {}) {
  std::istringstream in(text);
  SiteTable t = read_sites_csv(in, "test.csv", options);
  EXPECT_EQ(t.rows_read, t.sites.size() + t.rejected.size());
  return t;
}

// The Error thrown by reading text, or a default one with code Internal if nothing is thrown.
Error error_of(const std::string& text, const SiteReaderOptions& options = {}) {
  try {
    read(text, options);
  } catch (const Error& e) {
    return e;
  }
  return Error(ErrorCode::Internal, "no error thrown");
}

TEST(SiteReader, ReadsSitesWithIdsAndPositions) {
  const SiteTable t = read(
      "icao,name,lat_deg,lon_deg\nAGGH,\"Honiara, SB\",-9.4166645,160.0500018\n"
      "LFPG,Paris,49.0097,2.5479\n");
  EXPECT_EQ(t.source, "test.csv");
  EXPECT_EQ(t.columns, (std::vector<std::string>{"icao", "name", "lat_deg", "lon_deg"}));
  EXPECT_EQ(t.lat_column, 2);
  EXPECT_EQ(t.lon_column, 3);
  EXPECT_EQ(t.id_column, 0);
  EXPECT_TRUE(t.ecef_columns.empty());
  ASSERT_EQ(t.sites.size(), 2u);
  EXPECT_EQ(t.rows_read, 2u);
  const InputSite& s = t.sites[0];
  EXPECT_EQ(s.row, 1u);
  EXPECT_EQ(s.line, 2u);
  EXPECT_EQ(s.id, "AGGH");
  EXPECT_EQ(s.lat_deg, -9.4166645);
  EXPECT_EQ(s.lon_deg, 160.0500018);
  EXPECT_EQ(s.height_m, 0.0);
  EXPECT_EQ(s.unit, SiteEncoder::from_lat_lon(-9.4166645, 160.0500018));
  EXPECT_EQ(s.fields,
            (std::vector<std::string>{"AGGH", "Honiara, SB", "-9.4166645", "160.0500018"}));
  EXPECT_EQ(t.sites[1].id, "LFPG");
  EXPECT_EQ(t.sites[1].row, 2u);
  EXPECT_EQ(t.sites[1].line, 3u);
}

TEST(SiteReader, HeaderOnlyIsZeroRows) {
  const SiteTable t = read("lat,lon\n");
  EXPECT_EQ(t.rows_read, 0u);
  EXPECT_TRUE(t.sites.empty());
  EXPECT_TRUE(t.rejected.empty());
  EXPECT_EQ(read("lat,lon").rows_read, 0u);
}

TEST(SiteReader, EmptyFileThrowsBadData) {
  for (const std::string text : {"", "\xEF\xBB\xBF", "\n\n"}) {
    const Error e = error_of(text);
    EXPECT_EQ(e.code(), ErrorCode::BadData);
    EXPECT_STREQ(e.what(), "test.csv: empty file, no header");
  }
}

TEST(SiteReader, GzipInputIsNamed) {
  const Error e = error_of(std::string("\x1f\x8b\x08\x00\x01,garbage\n", 14));
  EXPECT_EQ(e.code(), ErrorCode::BadData);
  EXPECT_NE(std::string(e.what()).find("gzip"), std::string::npos) << e.what();
}

TEST(SiteReader, MissingColumnsThrowWithColumnList) {
  const Error e = error_of("a,b,c\n1,2,3\n");
  EXPECT_EQ(e.code(), ErrorCode::BadData);
  const std::string what = e.what();
  EXPECT_NE(what.find("test.csv: no latitude/longitude columns"), std::string::npos) << what;
  EXPECT_NE(what.find("found columns: a, b, c"), std::string::npos) << what;
  EXPECT_NE(what.find("--lat-field/--lon-field"), std::string::npos) << what;
  EXPECT_NE(what.find("decimalLatitude"), std::string::npos) << what;  // says what was looked for
  const Error half = error_of("name,latitude\nx,1\n");
  EXPECT_EQ(half.code(), ErrorCode::BadData);
  EXPECT_NE(std::string(half.what()).find("found columns: name, latitude"), std::string::npos);
}

TEST(SiteReader, DetectsEveryAlias) {
  const std::vector<std::string> lats = {"lat", "latitude", "lat_deg", "y"};
  const std::vector<std::string> lons = {"lon", "lng", "long", "longitude", "lon_deg", "x"};
  for (const auto& lat : lats) {
    for (const auto& lon : lons) {
      const SiteTable t = read("name," + lon + "," + lat + "\nA,10,20\n");
      ASSERT_EQ(t.lat_column, 2) << lat << " " << lon;
      ASSERT_EQ(t.lon_column, 1) << lat << " " << lon;
      ASSERT_EQ(t.sites.size(), 1u);
      EXPECT_EQ(t.sites[0].lat_deg, 20.0);
      EXPECT_EQ(t.sites[0].lon_deg, 10.0);
    }
  }
}

TEST(SiteReader, DetectionIsCaseInsensitiveAndTrimmed) {
  const SiteTable t = read(" Latitude ,LONGITUDE\r\n1,2\r\n");
  EXPECT_EQ(t.lat_column, 0);
  EXPECT_EQ(t.lon_column, 1);
  EXPECT_EQ(t.columns[0], " Latitude ");  // kept as read
  ASSERT_EQ(t.sites.size(), 1u);
}

TEST(SiteReader, BetterNameWinsAndEqualOnesAreAmbiguous) {
  const SiteTable t = read("y,x,stop_lat,stop_lon,lat,lon\n1,2,3,4,5,6\n");
  EXPECT_EQ(t.lat_column, 4);
  EXPECT_EQ(t.lon_column, 5);
  EXPECT_EQ(t.sites[0].lat_deg, 5.0);
  const SiteTable u = read("x,y,stop_lon,stop_lat\n1,2,3,4\n");
  EXPECT_EQ(u.lon_column, 2);
  EXPECT_EQ(u.lat_column, 3);
  const Error e = error_of("longitude,lng,latitude\n1,2,3\n");
  EXPECT_EQ(e.code(), ErrorCode::BadData);
  EXPECT_STREQ(e.what(), "test.csv: ambiguous longitude column: 'longitude', 'lng' are equally likely; choose one with --lon-field");
  SiteReaderOptions o;
  o.lon_field = "lng";  // a named column wins
  EXPECT_EQ(read("longitude,lng,latitude\n1,2,3\n", o).lon_column, 1);
}

TEST(SiteReader, DelimitersAreSniffedFromTheHeader) {
  for (const std::string d : {",", ";", "\t", "|"}) {
    const SiteTable t = read("id" + d + "lat" + d + "lon" + d + "name\nA" + d + "10" + d + "20" + d + "\"x" + d + "y\"\n");
    ASSERT_EQ(t.sites.size(), 1u) << d;
    EXPECT_EQ(t.columns, (std::vector<std::string>{"id", "lat", "lon", "name"})) << d;
    EXPECT_EQ(t.sites[0].fields, (std::vector<std::string>{"A", "10", "20", "x" + d + "y"})) << d;
    EXPECT_EQ(t.delimiter, d[0]);
  }
  // A quoted delimiter in the header does not count: two ';' beat one quoted ',' and none outside.
  const SiteTable q = read("\"a,b\";lat;lon\nx;1;2\n");
  EXPECT_EQ(q.columns, (std::vector<std::string>{"a,b", "lat", "lon"}));
  // A given delimiter wins.
  SiteReaderOptions o;
  o.delimiter = ',';
  EXPECT_EQ(read("lat,lon,a;b;c;d\n1,2,x\n", o).columns.size(), 3u);
  EXPECT_EQ(read("lat,lon,a;b;c;d\n1,2,x\n", o).delimiter, ',');
  // A quote is special only at a field's start, which the delimiter decides: with ';' the quotes
  // in 1,"2 are text and the row ends at its line end (fuzz_site_reader, regression
  // semicolon_header_quotes_after_commas).
  const SiteTable s = read("lat;lon\n1,\"2;3\n4;5\n\"x\n");
  EXPECT_EQ(s.rows_read, 3u);
  ASSERT_EQ(s.sites.size(), 1u);
  EXPECT_EQ(s.sites[0].lat_deg, 4.0);
}

TEST(SiteReader, DecimalCommaWhereTheDelimiterIsNotAComma) {
  const SiteTable t = read("name;lat;lon\nParis;48,8566;2,3522\nbad;1,2,3;4\nmixed;1.000,5;2\n");
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].lat_deg, 48.8566);
  EXPECT_EQ(t.sites[0].lon_deg, 2.3522);
  EXPECT_EQ(t.sites[0].fields[1], "48,8566");  // kept as read
  ASSERT_EQ(t.rejected.size(), 2u);
  EXPECT_EQ(t.rejected[0].reason, "lat: '1,2,3' is not a number");
  EXPECT_EQ(t.rejected[1].reason, "lat: '1.000,5' is not a number");
  const SiteTable tab = read("lat\tlon\n-33,5\t151,25\n");
  ASSERT_EQ(tab.sites.size(), 1u);
  EXPECT_EQ(tab.sites[0].lat_deg, -33.5);
  // With ',' as delimiter, "48,85" is two fields.
  EXPECT_EQ(read("lat,lon\n\"48,85\",2\n").rejected.at(0).reason, "lat: '48,85' is not a number");
}

TEST(SiteReader, DegreesMinutesSecondsAreNamed) {
  const SiteTable t = read("lat,lon\n\"40°26'46\"\"N\",\"79°58'56\"\"W\"\n");
  ASSERT_EQ(t.rejected.size(), 1u);
  EXPECT_EQ(t.rejected[0].reason,
            "lat: '40°26'46\"N' is in degrees, minutes and seconds; geovor reads decimal degrees");
}

TEST(SiteReader, InvalidUtf8RejectsTheRowWithItsColumn) {
  // "Zürich" in ISO-8859-1: 0xFC is not UTF-8.
  const SiteTable t = read("id,name,lat,lon\nA,Z\xFCrich,47.37,8.54\nB,Z\xC3\xBCrich,47.37,8.55\n");
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].id, "B");
  ASSERT_EQ(t.rejected.size(), 1u);
  EXPECT_EQ(t.rejected[0].row, 1u);
  EXPECT_EQ(t.rejected[0].reason,
            "name: not valid UTF-8 (byte 0xFC at byte 2 of the field); give the file's encoding, e.g. --encoding ISO-8859-1");
  // Overlong forms and surrogates are not UTF-8 either.
  EXPECT_EQ(read("lat,lon,n\n1,2,\xC0\xAF\n").rejected.size(), 1u);
  EXPECT_EQ(read("lat,lon,n\n1,2,\xED\xA0\x80\n").rejected.size(), 1u);
  // In the header: the file.
  const Error e = error_of("id,n\xE4me,lat,lon\n");
  EXPECT_EQ(e.code(), ErrorCode::BadData);
  EXPECT_STREQ(e.what(),
               "test.csv: header: column 2: not valid UTF-8 (byte 0xE4 at byte 2 of the field); give the file's "
               "encoding, e.g. --encoding ISO-8859-1");
}

TEST(SiteReader, EncodingConvertsToUtf8) {
  SiteReaderOptions o;
  o.encoding = "ISO-8859-1";
  const SiteTable t = read("id,name,lat,lon\nA,Z\xFCrich,47.37,8.54\n", o);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].fields[1], "Z\xC3\xBCrich");
  o.encoding = "UTF-16LE";
  const std::string utf16 = std::string("l\0a\0t\0,\0l\0o\0n\0\n\0" "1\0,\0" "2\0\n\0", 22);
  const SiteTable u = read(utf16, o);
  ASSERT_EQ(u.sites.size(), 1u);
  EXPECT_EQ(u.sites[0].lon_deg, 2.0);
  o.encoding = "NO-SUCH-ENCODING";
  EXPECT_EQ(error_of("lat,lon\n", o).code(), ErrorCode::InvalidArgument);
}

TEST(SiteReader, HeaderNamesMustTellColumnsApart) {
  const Error twice = error_of("id,lat,lon,lat\nA,1,2,3\n");
  EXPECT_EQ(twice.code(), ErrorCode::BadData);
  EXPECT_STREQ(twice.what(), "test.csv: header: column 4 'lat' has the same name as column 2 'lat'; rename one of them");
  EXPECT_EQ(error_of("id,,lat,lon\n").code(), ErrorCode::BadData);
  // A trailing delimiter from a spreadsheet: dropped while every row leaves it empty (or omits it).
  const SiteTable t = read("id,lat,lon,\nA,1,2,\nB,3,4\nC,5,6, \n");
  EXPECT_EQ(t.columns, (std::vector<std::string>{"id", "lat", "lon"}));
  ASSERT_EQ(t.sites.size(), 3u);
  EXPECT_EQ(t.sites[0].fields, (std::vector<std::string>{"A", "1", "2"}));
  EXPECT_EQ(t.sites[2].fields, (std::vector<std::string>{"C", "5", "6"}));
  const Error value = error_of("id,lat,lon,\nA,1,2,\nB,3,4,lost\n");
  EXPECT_EQ(value.code(), ErrorCode::BadData);
  EXPECT_STREQ(value.what(), "test.csv: header: column 4 has no name, but row 2 (line 3) has a value there: 'lost'; name the column");
}

TEST(SiteReader, RowNumberAsId) {
  SiteReaderOptions o;
  o.id_field = std::string(kRowNumberId);
  const SiteTable t = read("name,lat,lon\nX,1,2\nX,3,4\n", o);
  EXPECT_EQ(t.id_column, -1);
  ASSERT_EQ(t.sites.size(), 2u);
  EXPECT_EQ(t.sites[0].id, "1");
  EXPECT_EQ(t.sites[1].id, "2");
  EXPECT_EQ(find_duplicate_ids(t).rows, 0u);
}

TEST(SiteReader, DuplicateIdsAreFound) {
  const SiteTable t = read("name,lat,lon\nSan Jose,1,1\nA,2,2\nSan Jose,3,3\nB,4,4\nA,5,5\nSan Jose,6,6\nSan Jose,7,7\n");
  const DuplicateIds d = find_duplicate_ids(t);
  EXPECT_EQ(d.rows, 4u);
  ASSERT_EQ(d.examples.size(), 2u);
  EXPECT_EQ(d.examples[0].id, "San Jose");
  EXPECT_EQ(d.examples[0].rows, (std::vector<std::uint64_t>{1, 3, 6}));
  EXPECT_EQ(d.examples[1].id, "A");
  EXPECT_EQ(d.examples[1].rows, (std::vector<std::uint64_t>{2, 5}));
}

TEST(SiteReader, SitePointsAreTheAcceptedRowsUnitVectors) {
  const SiteTable t = read("id,lat,lon\na,10,20\nb,x,0\nc,-30,40\n");
  const std::vector<Vec3> points = site_points(t);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0], SiteEncoder::from_lat_lon(10, 20));
  EXPECT_EQ(points[1], SiteEncoder::from_lat_lon(-30, 40));
  EXPECT_TRUE(site_points(SiteTable{}).empty());
}

// Against a std::map: the count of rows repeating an earlier id, and each example's first rows,
// with ids from small alphabets (many repeats, long probe chains) and tables up to 20,000 rows.
TEST(SiteReader, DuplicateIdsAsAMapCountsThem) {
  std::mt19937 rng(7);
  for (const std::size_t n : {1u, 2u, 17u, 1000u, 20000u}) {
    for (const int letters : {1, 2, 3}) {
      SiteTable t;
      t.id_column = 0;
      std::uniform_int_distribution<int> letter(0, 4), length(0, letters);
      for (std::size_t i = 0; i < n; ++i) {
        InputSite site;
        for (int k = length(rng); k > 0; --k) site.id += static_cast<char>('a' + letter(rng));
        site.row = i + 1;
        t.sites.push_back(site);
      }
      std::map<std::string, std::vector<std::uint64_t>> rows;
      std::uint64_t repeats = 0;
      std::vector<std::string> repeated;  // in order of their first repeat
      for (const InputSite& site : t.sites) {
        std::vector<std::uint64_t>& r = rows[site.id];
        if (!r.empty()) {
          ++repeats;
          if (r.size() == 1) repeated.push_back(site.id);
        }
        r.push_back(site.row);
      }
      const DuplicateIds d = find_duplicate_ids(t);
      EXPECT_EQ(d.rows, repeats) << n << " rows, " << letters;
      ASSERT_EQ(d.examples.size(), std::min<std::size_t>(3, repeated.size()));
      for (std::size_t k = 0; k < d.examples.size(); ++k) {
        EXPECT_EQ(d.examples[k].id, repeated[k]);
        const std::vector<std::uint64_t>& r = rows[repeated[k]];
        EXPECT_EQ(d.examples[k].rows, std::vector<std::uint64_t>(r.begin(), r.begin() + std::min<std::size_t>(3, r.size())));
      }
    }
  }
}

TEST(SiteReader, RequireSites) {
  const auto message = [](const std::string& text) -> std::string {
    try {
      require_sites(read(text));
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::BadData);
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(message("lat,lon\n1,2\n"), "");
  EXPECT_EQ(message("lat,lon\n"), "test.csv: no usable site (0 rows, 0 rejected): the table has no data row");
  EXPECT_EQ(message("lat,lon\nabc,1\n1\n"),
            "test.csv: no usable site (2 rows, 2 rejected): every row was rejected, the first (row 1) for lat: 'abc' is "
            "not a number");
  EXPECT_EQ(message("lat,lon\n4649776,500000\n"),
            "test.csv: no usable site (1 rows, 1 rejected): every row was rejected, the first (row 1) for lat: latitude "
            "4649776 is beyond +-90; projected coordinates (metres)? give their CRS with --s-srs");
}

TEST(SiteReader, ProjectedRowsAreKeptAsRead) {
  SiteReaderOptions o;
  o.s_srs = "EPSG:2154";
  const SiteTable t = read("name,X,Y\nParis,652469,6862035\nbad,inf,1\n", o);
  EXPECT_EQ(t.lon_column, 1);
  EXPECT_EQ(t.lat_column, 2);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].lon_deg, 652469.0);
  EXPECT_EQ(t.sites[0].lat_deg, 6862035.0);
  ASSERT_EQ(t.rejected.size(), 1u);
  EXPECT_EQ(t.rejected[0].reason, "X: 'inf' is not a finite number");
}

TEST(SiteReader, IdColumnPriority) {
  EXPECT_EQ(read("name,code,lat,lon\n").id_column, 1);
  EXPECT_EQ(read("name,icao,lat,lon\n").id_column, 1);
  EXPECT_EQ(read("icao,ID,lat,lon\n").id_column, 1);
  EXPECT_EQ(read("Name,lat,lon\n").id_column, 0);
  const SiteTable t = read("lat,lon\n1,2\nbad,2\n3,4\n");
  EXPECT_EQ(t.id_column, -1);
  ASSERT_EQ(t.sites.size(), 2u);
  EXPECT_EQ(t.sites[0].id, "1");
  EXPECT_EQ(t.sites[1].id, "3");  // the row number, not the index among accepted sites
}

TEST(SiteReader, NamedFields) {
  SiteReaderOptions o;
  o.lat_field = "B";
  o.lon_field = "a";
  o.id_field = "c";
  const SiteTable t = read("a,b,c,lat,lon\n1,2,k,80,80\n", o);
  EXPECT_EQ(t.lat_column, 1);
  EXPECT_EQ(t.lon_column, 0);
  EXPECT_EQ(t.id_column, 2);
  EXPECT_EQ(t.sites[0].lat_deg, 2.0);
  EXPECT_EQ(t.sites[0].lon_deg, 1.0);
  EXPECT_EQ(t.sites[0].id, "k");
}

TEST(SiteReader, NamedFieldThatDoesNotExistIsInvalidArgument) {
  for (int which = 0; which < 4; ++which) {
    SiteReaderOptions o;
    if (which == 0) o.lat_field = "nope";
    if (which == 1) o.lon_field = "nope";
    if (which == 2) o.id_field = "nope";
    if (which == 3) o.ecef_fields = {"lat", "lon", "nope"};
    const Error e = error_of("lat,lon\n1,2\n", o);
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << which;
    EXPECT_NE(std::string(e.what()).find("'nope'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("found columns: lat, lon"), std::string::npos);
  }
  SiteReaderOptions two;
  two.ecef_fields = {"lat", "lon"};
  EXPECT_EQ(error_of("lat,lon\n", two).code(), ErrorCode::InvalidArgument);
  SiteReaderOptions same;
  same.lat_field = same.lon_field = "lat";
  EXPECT_EQ(error_of("lat,lon\n", same).code(), ErrorCode::InvalidArgument);
}

TEST(SiteReader, RejectionReasonsNameTheColumn) {
  const std::string text =
      "id,lat_deg,lon_deg\n"
      "nan,NaN,0\n"         // row 1
      "inf,inf,0\n"         // row 2
      "big,1e308,0\n"       // row 3
      "huge,1e999,0\n"      // row 4
      "n91,91,0\n"          // row 5
      "e541,0,541\n"        // row 6
      "ninf,0,-inf\n"       // row 7
      "abc,abc,0\n"         // row 8
      "empty,,0\n"          // row 9
      "blank,  ,0\n"        // row 10
      "garbage,12.5x,0\n"   // row 11
      "missing,10\n"        // row 12
      "extra,1,2,3\n"       // row 13
      "ok, 12.5 ,+13.25\n"  // row 14: surrounding spaces and a plus sign are fine
      "two signs,+-1,0\n"   // row 15
      "hex,0x10,0\n";       // row 16
  const SiteTable t = read(text);
  EXPECT_EQ(t.rows_read, 16u);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].id, "ok");
  EXPECT_EQ(t.sites[0].row, 14u);
  EXPECT_EQ(t.sites[0].lat_deg, 12.5);
  EXPECT_EQ(t.sites[0].lon_deg, 13.25);
  const std::vector<std::pair<std::uint64_t, std::string>> expected = {
      {1, "lat_deg: latitude is not a finite number"},
      {2, "lat_deg: latitude is not a finite number"},
      {3, "lat_deg: latitude 1e+308 is beyond +-90"},
      {4, "lat_deg: '1e999' is out of the range of a double"},
      {5, "lat_deg: latitude 91 is beyond +-90"},
      {6, "lon_deg: longitude 541 is out of range [-540, 540]"},
      {7, "lon_deg: longitude is not a finite number"},
      {8, "lat_deg: 'abc' is not a number"},
      {9, "lat_deg: empty value"},
      {10, "lat_deg: empty value"},
      {11, "lat_deg: '12.5x' is not a number"},
      {12, "found 2 fields, expected 3 as in the header (no value for lon_deg)"},
      {13, "found 4 fields, expected 3 as in the header"},
      {15, "lat_deg: '+-1' is not a number"},
      {16, "lat_deg: '0x10' is not a number"},
  };
  ASSERT_EQ(t.rejected.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(t.rejected[i].row, expected[i].first);
    EXPECT_EQ(t.rejected[i].line, expected[i].first + 1);
    EXPECT_EQ(t.rejected[i].reason, expected[i].second);
  }
}

// Rows converted on several threads: the same sites and rejected rows, in row order, with rows
// rejected while reading (field count) and while converting (coordinates) interleaved.
TEST(SiteReader, ThreadsGiveTheSameTable) {
  std::string text = "id,lat,lon\n";
  for (int i = 0; i < 50000; ++i) {
    if (i % 997 == 5) {
      text += "short," + std::to_string(i % 80) + "\n";  // one field missing
    } else if (i % 1009 == 7) {
      text += "bad" + std::to_string(i) + ",91.5,10\n";  // latitude out of range
    } else {
      text += "s" + std::to_string(i) + "," + std::to_string((i * 37) % 170 - 85) + "." + std::to_string(i % 10) +
              "," + std::to_string((i * 53) % 360 - 180) + "\n";
    }
  }
  SiteReaderOptions threaded;
  threaded.threads = 3;
  const SiteTable one = read(text), three = read(text, threaded);
  ASSERT_EQ(one.sites.size(), three.sites.size());
  ASSERT_EQ(one.rejected.size(), three.rejected.size());
  EXPECT_EQ(one.rows_read, 50000u);
  EXPECT_EQ(one.sites.size() + one.rejected.size(), 50000u);
  for (std::size_t i = 0; i < one.sites.size(); ++i) {
    ASSERT_EQ(one.sites[i].row, three.sites[i].row);
    ASSERT_EQ(one.sites[i].id, three.sites[i].id);
    ASSERT_EQ(one.sites[i].unit, three.sites[i].unit);
  }
  for (std::size_t i = 0; i < one.rejected.size(); ++i) {
    ASSERT_EQ(one.rejected[i].row, three.rejected[i].row);
    ASSERT_EQ(one.rejected[i].reason, three.rejected[i].reason);
    if (i > 0) ASSERT_LT(one.rejected[i - 1].row, one.rejected[i].row);
  }
  EXPECT_GT(std::count_if(one.rejected.begin(), one.rejected.end(),
                          [](const RejectedRow& r) { return r.reason.find("lat") != std::string::npos; }),
            10);
}

TEST(SiteReader, LongBadValueIsCutInTheReason) {
  const SiteTable t = read("lat,lon\n" + std::string(1000, '7') + "q,0\n");
  ASSERT_EQ(t.rejected.size(), 1u);
  EXPECT_LT(t.rejected[0].reason.size(), 120u);
  EXPECT_NE(t.rejected[0].reason.find("1001 characters"), std::string::npos);
}

TEST(SiteReader, UnterminatedQuoteIsRejected) {
  const SiteTable t = read("name,lat,lon\nA,1,2\nB,3,\"4\n");
  EXPECT_EQ(t.rows_read, 2u);
  ASSERT_EQ(t.sites.size(), 1u);
  ASSERT_EQ(t.rejected.size(), 1u);
  EXPECT_EQ(t.rejected[0].row, 2u);
  EXPECT_EQ(t.rejected[0].line, 3u);
  EXPECT_EQ(t.rejected[0].reason, "lon: unterminated quoted field starting on line 3");
}

TEST(SiteReader, LineNumbersFollowEmbeddedNewlines) {
  const SiteTable t = read("name,lat,lon\n\"multi\nline\",1,2\nbad,x,2\n");
  ASSERT_EQ(t.rejected.size(), 1u);
  EXPECT_EQ(t.rejected[0].row, 2u);
  EXPECT_EQ(t.rejected[0].line, 4u);
}

TEST(SiteReader, AntimeridianAndExtraTurnAreOnePoint) {
  const SiteTable t = read("lat,lon\n12.5,180\n12.5,-180\n12.5,540\n12.5,-540\n");
  ASSERT_EQ(t.sites.size(), 4u);
  for (const auto& s : t.sites) {
    EXPECT_EQ(s.lon_deg, -180.0);
    EXPECT_EQ(s.unit, t.sites[0].unit);
  }
  const SiteTable p = read("lat,lon\n90,10\n90,-170\n-90,33\n-90,0\n");
  EXPECT_EQ(p.sites[0].unit, p.sites[1].unit);
  EXPECT_EQ(p.sites[0].lon_deg, 0.0);
  EXPECT_EQ(p.sites[2].unit, p.sites[3].unit);
}

TEST(SiteReader, EcefInput) {
  // Paris (48.8566, 2.3522, 35 m), ECEF from N = a / sqrt(1 - e^2 sin^2 phi).
  const double a = 6378137, f = 1 / 298.257223563, e2 = f * (2 - f);
  const double phi = 48.8566 * std::numbers::pi / 180, lam = 2.3522 * std::numbers::pi / 180,
               h = 35;
  const double n = a / std::sqrt(1 - e2 * std::sin(phi) * std::sin(phi));
  char row[200];
  std::snprintf(row, sizeof row, "%.17g,%.17g,%.17g", (n + h) * std::cos(phi) * std::cos(lam),
                (n + h) * std::cos(phi) * std::sin(lam), (n * (1 - e2) + h) * std::sin(phi));
  SiteReaderOptions o;
  o.ecef_fields = {"X", "Y", "Z"};
  const SiteTable t =
      read(std::string("name,x,y,z\nParis,") + row + "\nbad,1,q,3\ncentre,0,0,0\n", o);
  EXPECT_EQ(t.lat_column, -1);
  EXPECT_EQ(t.lon_column, -1);
  EXPECT_EQ(t.ecef_columns, (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(t.id_column, 0);
  ASSERT_EQ(t.sites.size(), 1u);
  const InputSite& s = t.sites[0];
  EXPECT_EQ(s.id, "Paris");
  EXPECT_NEAR(s.lat_deg, 48.8566, 1e-9);
  EXPECT_NEAR(s.lon_deg, 2.3522, 1e-9);
  EXPECT_NEAR(s.height_m, 35, 1e-6);
  EXPECT_EQ(s.unit, SiteEncoder::from_lat_lon(s.lat_deg, s.lon_deg));
  ASSERT_EQ(t.rejected.size(), 2u);
  EXPECT_EQ(t.rejected[0].reason, "y: 'q' is not a number");
  EXPECT_NE(t.rejected[1].reason.find("x, y, z: "), std::string::npos);
}

TEST(SiteReader, FileErrors) {
  try {
    read_sites_csv_file("/nonexistent/dir/sites.csv");
    FAIL() << "expected geovor::Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Io);
    EXPECT_STREQ(e.what(), "/nonexistent/dir/sites.csv: cannot open: No such file or directory");
  }
  const auto dir = std::filesystem::temp_directory_path();
  try {
    read_sites_csv_file(dir.string());
    FAIL() << "expected geovor::Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Io);
    EXPECT_NE(std::string(e.what()).find(dir.string()), std::string::npos);
  }
}

TEST(SiteReader, ReadsFileAndStdin) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("geovor_site_reader_test_" + std::to_string(::getpid()) + ".csv");
  {
    std::ofstream out(path, std::ios::binary);
    out << "\xEF\xBB\xBFid,lat,lon\r\nA,1,2\r\n";
  }
  const SiteTable t = read_sites_csv_file(path.string());
  std::filesystem::remove(path);
  EXPECT_EQ(t.source, path.string());
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].id, "A");

  std::istringstream fake_stdin("lat,lon\n3,4\n");
  auto* const saved = std::cin.rdbuf(fake_stdin.rdbuf());
  const SiteTable s = read_sites_csv_file("-");
  std::cin.rdbuf(saved);
  EXPECT_EQ(s.source, "<stdin>");
  ASSERT_EQ(s.sites.size(), 1u);
  EXPECT_EQ(s.sites[0].lat_deg, 3.0);
}

TEST(SiteReader, BundledWeatherStations) {
  const std::string path = GEOVOR_SOURCE_DIR "/datasets/weather_stations.csv";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is missing";
  const SiteTable t = read_sites_csv_file(path);
  EXPECT_EQ(t.rows_read, 5634u);
  EXPECT_EQ(t.sites.size(), 5634u);
  for (const auto& r : t.rejected) ADD_FAILURE() << "row " << r.row << ": " << r.reason;
  ASSERT_GE(t.id_column, 0);
  EXPECT_EQ(t.columns[static_cast<std::size_t>(t.id_column)], "icao");
  ASSERT_FALSE(t.sites.empty());
  EXPECT_EQ(t.sites[0].id, "AGGH");
  for (const auto& s : t.sites) {
    ASSERT_LE(std::fabs(norm2(s.unit) - 1), 0x1p-49) << s.id;
    ASSERT_GE(s.lon_deg, -180.0);
    ASSERT_LT(s.lon_deg, 180.0);
  }
}

}  // namespace
}  // namespace geovor
