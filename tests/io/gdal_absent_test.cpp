// The library without GDAL (geovor_without_gdal, linked by the geovor tool): GeoJSON and CSV
// work; every GDAL entry point throws Error(Internal) naming the path, instead of a link error
// or a crash (the tool never reaches them: it hands such jobs to geovor-gdal).
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <vector>
#include <string>

#include "geovor/core/error.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/io/ogr_site_reader.hpp"

namespace geovor {
namespace {

void expect_absent(const std::function<void()>& call, const std::string& path) {
  try {
    call();
    ADD_FAILURE() << path << ": no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Internal) << e.what();
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find("needs GDAL"), std::string::npos) << what;
  }
}

TEST(GdalAbsent, GdalFormatsThrowInternal) {
  const std::string dir = testing::TempDir();
  const std::vector<Field> schema = {{"name", FieldType::String}};
  expect_absent([&] { open_feature_writer(dir + "a.gpkg", GeometryType::Point, schema); }, dir + "a.gpkg");
  expect_absent([&] { open_feature_writer(dir + "a.unknown_ext", GeometryType::Point, schema); }, dir + "a.unknown_ext");
  WriterOptions csv;
  csv.format = "CSV";
  expect_absent([&] { open_feature_writer(dir + "a.txt", GeometryType::Point, schema, csv); }, dir + "a.txt");
  expect_absent([&] { read_sites(dir + "a.gpkg"); }, dir + "a.gpkg");
  expect_absent([&] { read_sites_ogr(dir + "a.csv"); }, dir + "a.csv");
}

TEST(GdalAbsent, GeoJsonAndCsvWork) {
  const std::string out = testing::TempDir() + "gdal_absent_test.geojson";
  std::remove(out.c_str());
  auto writer = open_feature_writer(out, GeometryType::Point, {{"name", FieldType::String}});
  const std::vector<FieldValue> values = {std::string("A")};
  writer->write(LonLat{20, 10}, values);
  writer->finish();
  std::FILE* f = std::fopen(out.c_str(), "rb");
  ASSERT_NE(f, nullptr);
  char text[256] = {};
  const std::size_t n = std::fread(text, 1, sizeof text - 1, f);
  std::fclose(f);
  EXPECT_NE(std::string(text, n).find("\"name\":\"A\""), std::string::npos) << std::string(text, n);
  std::remove(out.c_str());

  const std::string csv = testing::TempDir() + "gdal_absent_test.csv";
  if (std::FILE* c = std::fopen(csv.c_str(), "wb")) {
    std::fputs("id,lat,lon\nA,10,20\n", c);
    std::fclose(c);
  }
  const SiteTable t = read_sites(csv);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].id, "A");
  std::remove(csv.c_str());
}

}  // namespace
}  // namespace geovor
