// read_sites() picks the CSV reader for "-", .csv and .txt (any case) and the OGR reader for
// everything else; is_csv_site_path() says which.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/io/ogr_site_reader.hpp"

namespace geovor {
namespace {

TEST(SiteSource, CsvPathsByExtension) {
  for (const char* path : {"-", "a.csv", "a.CSV", "dir.x/a.Csv", "a.txt", "a.TXT", "/tmp/b.c.csv", "a.tsv", "a.dat", "a.PSV"})
    EXPECT_TRUE(is_csv_site_path(path)) << path;
  for (const char* path : {"a.gpkg", "a.geojson", "a.shp", "a.csv.gz", "a", "csv", "a.csvx", "dir.csv/a", "/vsizip/a.zip/b.shp"})
    EXPECT_FALSE(is_csv_site_path(path)) << path;
}

// Any other extension, or none: delimited text by its first bytes; GDAL's formats never.
TEST(SiteSource, DelimitedTextByContent) {
  const std::string dir = testing::TempDir();
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir + name, std::ios::binary) << text;
    return dir + name;
  };
  EXPECT_TRUE(is_csv_site_path(write("stations", "id;lat;lon\nA;1;2\n")));
  EXPECT_TRUE(is_csv_site_path(write("stations.xyz", "lat\tlon\n1\t2\n")));
  EXPECT_TRUE(is_csv_site_path(write("stations.2024", "\xEF\xBB\xBFlat|lon\n1|2\n")));
  EXPECT_FALSE(is_csv_site_path(write("points", "{\"type\":\"FeatureCollection\",\"features\":[]}")));
  EXPECT_FALSE(is_csv_site_path(write("points.xyz", "<?xml version=\"1.0\"?><kml/>")));
  EXPECT_FALSE(is_csv_site_path(write("db", std::string("SQLite format 3\0,;", 19))));
  EXPECT_FALSE(is_csv_site_path(write("oneword", "hello\n")));
  EXPECT_FALSE(is_csv_site_path(write("points.json", "lat,lon\n1,2\n")));  // GDAL's extension: GDAL's
  const SiteTable t = read_sites(dir + "stations");
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].line, 2u);  // read as text, with lines
}

// UTF-16 text holds NUL bytes: with its encoding given, its head is judged decoded.
TEST(SiteSource, EncodedTextByContent) {
  const std::string path = testing::TempDir() + "stations_utf16";
  const char text[] = "\xFF\xFEi\0d\0;\0l\0a\0t\0;\0l\0o\0n\0\n\0A\0;\0\x31\0;\0\x32\0\n\0";
  const std::string utf16le(text, sizeof text - 1);
  std::ofstream(path, std::ios::binary) << utf16le;
  EXPECT_FALSE(is_csv_site_path(path));
  EXPECT_TRUE(is_csv_site_path(path, "UTF-16"));
  SiteReaderOptions options;
  options.encoding = "UTF-16";
  const SiteTable t = read_sites(path, options);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].id, "A");
  EXPECT_DOUBLE_EQ(t.sites[0].lon_deg, 2);
  std::remove(path.c_str());
}

// A FIFO is read once as delimited text, whatever its name (GDAL would open it twice and wait).
TEST(SiteSource, FifoIsReadOnceAsText) {
  for (const std::string name : {"site_source_fifo", "site_source_fifo.geojson"}) {
    const std::string path = testing::TempDir() + name;
    std::remove(path.c_str());
    ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
    EXPECT_TRUE(is_stream_path(path));
    EXPECT_TRUE(is_csv_site_path(path)) << path;
    std::thread writer([&] { std::ofstream(path) << "id,lat,lon\nA,10,20\nB,30,40\n"; });
    const SiteTable t = read_sites(path);
    writer.join();
    ASSERT_EQ(t.sites.size(), 2u);
    EXPECT_EQ(t.sites[1].id, "B");
    EXPECT_EQ(t.sites[1].line, 3u);
    std::remove(path.c_str());
  }
  EXPECT_TRUE(is_stream_path("-"));
  EXPECT_TRUE(is_stream_path("/dev/null"));
  EXPECT_FALSE(is_stream_path("/vsistdin/"));
  EXPECT_FALSE(is_stream_path(testing::TempDir()));
}

// A stream whose head is JSON is refused as bad data, naming it and saying what to do.
TEST(SiteSource, FifoOfJsonRefused) {
  const std::string path = testing::TempDir() + "site_source_json_fifo";
  std::remove(path.c_str());
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(path) << "\xEF\xBB\xBF [{\"a\": 1}]\n"; });
  try {
    read_sites(path);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadData);
    EXPECT_EQ(std::string(e.what()), path + ": not delimited text: it starts with '[' (JSON?); a pipe, FIFO, device or "
                                            "standard input is read as delimited text only (GDAL needs a file it can "
                                            "reopen): save the data to a file and give that");
  }
  writer.join();
  std::remove(path.c_str());
}

TEST(SiteSource, ReadsCsvWithTheCsvReader) {
  const std::string path = testing::TempDir() + "site_source_test.TXT";
  std::ofstream(path) << "id,lat,lon\nA,10,20\nB,x,30\n";
  const SiteTable via_source = read_sites(path);
  const SiteTable direct = read_sites_csv_file(path);
  ASSERT_EQ(via_source.sites.size(), 1u);
  EXPECT_EQ(via_source.sites[0].id, "A");
  EXPECT_EQ(via_source.sites[0].line, direct.sites[0].line);  // CSV rows have lines; OGR's have 0
  EXPECT_EQ(via_source.sites[0].line, 2u);
  ASSERT_EQ(via_source.rejected.size(), 1u);
  EXPECT_EQ(via_source.rejected[0].reason, direct.rejected[0].reason);
  std::remove(path.c_str());
}

TEST(SiteSource, OtherPathsGoToOgr) {
  // GeoJSON text, which the CSV reader would reject (no latitude column), read by GDAL: one
  // feature, and line 0 as for every OGR feature.
  const std::string path = testing::TempDir() + "site_source_test.json";
  std::ofstream(path) << R"({"type":"FeatureCollection","features":[{"type":"Feature","properties":{"id":"A"},)"
                         R"("geometry":{"type":"Point","coordinates":[20,10]}}]})";
  const SiteTable t = read_sites(path);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].id, "A");
  EXPECT_EQ(t.sites[0].line, 0u);
  EXPECT_DOUBLE_EQ(t.sites[0].lat_deg, 10);
  EXPECT_DOUBLE_EQ(t.sites[0].lon_deg, 20);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace geovor
