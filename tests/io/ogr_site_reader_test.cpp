/// \file ogr_site_reader_test.cpp
/// \brief Tests of read_sites_ogr / read_sites: point layers created here with GDAL (GeoPackage,
/// Shapefile in EPSG:3857, GeoJSON with a LineString, FlatGeobuf, a geometry-less table) read
/// into the CSV reader's SiteTable: every feature a site or a rejected row with its reason,
/// positions reprojected (checked against the spherical Mercator formulas), attributes as text.
#include "geovor/io/ogr_site_reader.hpp"

#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <chrono>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "support/file_text.hpp"
#include "support/temp_dir.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor {
namespace {

namespace fs = std::filesystem;

// A temporary directory named for this test file.
class TempDir : public testing::TempDir {
 public:
  TempDir() : testing::TempDir("geovor_ogr") {}
};

using testing::error_of;

// One feature to create: a geometry as WKT ("" for none) and its attribute values ("" = null).
struct Row {
  std::string wkt;
  std::vector<std::string> values;
};

struct Column {
  std::string name;
  OGRFieldType type;
};

// Creates a one-layer dataset with GDAL.
void create_layer(const std::string& path, const char* driver, int epsg, OGRwkbGeometryType type,
                  const std::vector<Column>& columns, const std::vector<Row>& rows,
                  const std::string& layer_name = "sites") {
  GDALAllRegister();
  GDALDriver* drv = GetGDALDriverManager()->GetDriverByName(driver);
  ASSERT_NE(drv, nullptr);
  GDALDatasetUniquePtr ds(drv->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  ASSERT_TRUE(ds);
  OGRSpatialReference srs;
  if (epsg != 0) {
    srs.importFromEPSG(epsg);
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  }
  OGRLayer* layer = ds->CreateLayer(layer_name.c_str(), epsg != 0 ? &srs : nullptr, type, nullptr);
  ASSERT_NE(layer, nullptr);
  for (const Column& c : columns) {
    OGRFieldDefn defn(c.name.c_str(), c.type);
    ASSERT_EQ(layer->CreateField(&defn), OGRERR_NONE);
  }
  for (const Row& r : rows) {
    OGRFeatureUniquePtr f(OGRFeature::CreateFeature(layer->GetLayerDefn()));
    for (std::size_t i = 0; i < r.values.size(); ++i) {
      if (!r.values[i].empty()) f->SetField(static_cast<int>(i), r.values[i].c_str());
    }
    if (!r.wkt.empty()) {
      OGRGeometry* g = nullptr;
      ASSERT_EQ(OGRGeometryFactory::createFromWkt(r.wkt.c_str(), nullptr, &g), OGRERR_NONE) << r.wkt;
      f->SetGeometryDirectly(g);
    }
    ASSERT_EQ(layer->CreateFeature(f.get()), OGRERR_NONE) << r.wkt;
  }
}

void expect_accounted(const SiteTable& t) {
  EXPECT_EQ(t.rows_read, t.sites.size() + t.rejected.size());
}

const std::vector<Column> kColumns = {
    {"icao", OFTString}, {"elev_m", OFTInteger}, {"value", OFTReal}, {"note", OFTString}};

TEST(OgrSiteReader, GeoPackagePointsWithNullAndEmptyGeometries) {
  TempDir dir;
  const std::string path = dir / "sites.gpkg";
  create_layer(path, "GPKG", 4326, wkbPoint, kColumns,
               {{"POINT (2.5479 49.0097)", {"LFPG", "119", "0.1", "Paris, CDG"}},
                {"", {"NULL", "", "", ""}},
                {"POINT EMPTY", {"EMPT", "1", "", ""}},
                {"POINT (160.0500018 -9.4166645)", {"AGGH", "9", "1e-300", ""}},
                {"POINT (180 0)", {"ANTI", "", "", "lon 180 becomes -180"}},
                {"POINT (10 95)", {"POLE", "", "", "beyond the pole"}}});
  const SiteTable t = read_sites(path);
  expect_accounted(t);
  EXPECT_EQ(t.source, path);
  EXPECT_EQ(t.columns, (std::vector<std::string>{"icao", "elev_m", "value", "note"}));
  EXPECT_EQ(t.lat_column, -1);
  EXPECT_EQ(t.lon_column, -1);
  EXPECT_EQ(t.id_column, 0);  // "icao"
  EXPECT_TRUE(t.ecef_columns.empty());
  EXPECT_EQ(t.rows_read, 6u);
  ASSERT_EQ(t.sites.size(), 3u);
  ASSERT_EQ(t.rejected.size(), 3u);

  const InputSite& s = t.sites[0];
  EXPECT_EQ(s.row, 1u);
  EXPECT_EQ(s.line, 0u);
  EXPECT_EQ(s.id, "LFPG");
  EXPECT_EQ(s.lat_deg, 49.0097);
  EXPECT_EQ(s.lon_deg, 2.5479);
  EXPECT_EQ(s.height_m, 0.0);
  EXPECT_EQ(s.unit, SiteEncoder::from_lat_lon(49.0097, 2.5479));
  EXPECT_EQ(s.fields, (std::vector<std::string>{"LFPG", "119", "0.1", "Paris, CDG"}));
  EXPECT_EQ(t.sites[1].row, 4u);
  EXPECT_EQ(t.sites[1].fields, (std::vector<std::string>{"AGGH", "9", "1e-300", ""}));
  EXPECT_EQ(t.sites[2].id, "ANTI");
  EXPECT_EQ(t.sites[2].lon_deg, -180.0);  // normalize_lat_lon as for CSV

  EXPECT_EQ(t.rejected[0].row, 2u);
  EXPECT_EQ(t.rejected[0].reason, "feature 2 (FID 2): geometry is null");
  EXPECT_EQ(t.rejected[1].row, 3u);
  EXPECT_EQ(t.rejected[1].reason, "feature 3 (FID 3): geometry is empty (Point)");
  EXPECT_EQ(t.rejected[2].row, 6u);
  EXPECT_EQ(t.rejected[2].reason.rfind("feature 6 (FID 6): latitude 95", 0), 0u) << t.rejected[2].reason;
}

TEST(OgrSiteReader, ShapefileInWebMercatorIsReprojected) {
  TempDir dir;
  const std::string path = dir / "merc.shp";
  // Spherical Mercator (EPSG:3857) on R = 6378137 m, inverted by the textbook formulas.
  constexpr double R = 6378137.0;
  const std::vector<std::pair<double, double>> xy = {
      {261845.7, 6250566.7}, {-13627361.0, 4544761.6}, {17000000.0, -4000000.0}, {0.0, 0.0}};
  std::vector<Row> rows;
  for (std::size_t i = 0; i < xy.size(); ++i) {
    char wkt[100];
    std::snprintf(wkt, sizeof wkt, "POINT (%.17g %.17g)", xy[i].first, xy[i].second);
    rows.push_back({wkt, {"S" + std::to_string(i)}});
  }
  create_layer(path, "ESRI Shapefile", 3857, wkbPoint, {{"name", OFTString}}, rows);
  const SiteTable t = read_sites(path);
  expect_accounted(t);
  ASSERT_EQ(t.sites.size(), xy.size());
  for (std::size_t i = 0; i < xy.size(); ++i) {
    const double lon = xy[i].first / R * 180 / std::numbers::pi;
    const double lat = std::atan(std::sinh(xy[i].second / R)) * 180 / std::numbers::pi;
    EXPECT_NEAR(t.sites[i].lon_deg, lon, 1e-9) << i;
    EXPECT_NEAR(t.sites[i].lat_deg, lat, 1e-9) << i;
    EXPECT_EQ(t.sites[i].id, "S" + std::to_string(i));  // "name" is an id column
    EXPECT_EQ(t.sites[i].unit, SiteEncoder::from_lat_lon(t.sites[i].lat_deg, t.sites[i].lon_deg));
  }
}

// Points that PROJ would stall on (time growing with the magnitude) or wrap around the Earth are
// rejected before the transformation; the edge of the area of use stays in.
TEST(OgrSiteReader, PointsOutsideTheCrsDomainAreRejected) {
  TempDir dir;
  const std::string path = dir / "far.geojson";
  create_layer(path, "GeoJSON", 3857, wkbPoint, {{"name", OFTString}},
               {{"POINT (1e25 1e25)", {"huge"}},
                {"POINT (30000000 0)", {"wrapped"}},
                {"POINT (20037508.342789244 0)", {"edge"}},
                {"POINT (10000000 0)", {"inside"}}});
  const auto t0 = std::chrono::steady_clock::now();
  const SiteTable t = read_sites(path);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  expect_accounted(t);
  ASSERT_EQ(t.sites.size(), 2u);
  EXPECT_EQ(t.sites[0].id, "edge");
  EXPECT_EQ(t.sites[0].lon_deg, -180.0);  // 180 reduced to [-180, 180)
  EXPECT_EQ(t.sites[1].id, "inside");
  EXPECT_NEAR(t.sites[1].lon_deg, 89.83152841195214, 1e-12);  // x / R in degrees, R = 6378137 m
  ASSERT_EQ(t.rejected.size(), 2u);
  EXPECT_EQ(t.rejected[0].reason,
            "feature 1 (FID 0): point (1e+25, 1e+25) is far outside WGS 84 / Pseudo-Mercator (EPSG:3857) (a "
            "coordinate beyond 1e9)");
  EXPECT_EQ(t.rejected[1].reason.rfind("feature 2 (FID 1): point (30000000, 0) is outside the area of use of WGS 84 / "
                                       "Pseudo-Mercator (EPSG:3857) (x from -20037508.34 to 20037508.34",
                                       0),
            0u)
      << t.rejected[1].reason;
}

// --s-srs: CSV x/y columns in Lambert-93 (EPSG:2154), transformed as gdaltransform does
// (echo "652469 6862035" | gdaltransform -s_srs EPSG:2154 -t_srs EPSG:4326 -output_xy).
TEST(OgrSiteReader, CsvInAProjectedCrs) {
  TempDir dir;
  const std::string path = dir / "lambert93.csv";
  std::ofstream(path) << "name;X;Y\nParis;652469;6862035\nfar;1e12;0\nTokyo?;-9000000;6862035\n";
  SiteReaderOptions o;
  o.s_srs = "EPSG:2154";
  const SiteTable t = read_sites(path, o);
  expect_accounted(t);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_NEAR(t.sites[0].lon_deg, 2.3521997195163, 1e-12);
  EXPECT_NEAR(t.sites[0].lat_deg, 48.8565976653841, 1e-12);
  EXPECT_EQ(t.sites[0].line, 2u);
  EXPECT_EQ(t.sites[0].unit, SiteEncoder::from_lat_lon(t.sites[0].lat_deg, t.sites[0].lon_deg));
  ASSERT_EQ(t.rejected.size(), 2u);
  EXPECT_EQ(t.rejected[0].row, 2u);
  EXPECT_EQ(t.rejected[0].reason.rfind("X, Y: point (1e+12, 0) is far outside RGF93 v1 / Lambert-93 (EPSG:2154)", 0), 0u)
      << t.rejected[0].reason;
  EXPECT_EQ(t.rejected[1].row, 3u);
  EXPECT_NE(t.rejected[1].reason.find("is outside the area of use of RGF93 v1 / Lambert-93 (EPSG:2154)"), std::string::npos)
      << t.rejected[1].reason;
  o.s_srs = "EPSG:999999";
  EXPECT_EQ(error_of([&] { read_sites(path, o); }).code(), ErrorCode::InvalidArgument);
}

TEST(OgrSiteReader, GeoJsonWithALineStringAndAMultiPoint) {
  TempDir dir;
  const std::string path = dir / "mixed.geojson";
  create_layer(path, "GeoJSON", 4326, wkbUnknown, {{"code", OFTString}},
               {{"POINT (-73.7781 40.6413)", {"KJFK"}},
                {"LINESTRING (0 0,1 1)", {"LINE"}},
                {"MULTIPOINT ((5 6))", {"ONE"}},
                {"MULTIPOINT ((5 6),(7 8))", {"TWO"}},
                {"POLYGON ((0 0,1 0,1 1,0 0))", {"POLY"}}});
  const SiteTable t = read_sites(path);
  expect_accounted(t);
  ASSERT_EQ(t.sites.size(), 2u);
  EXPECT_EQ(t.sites[0].id, "KJFK");
  EXPECT_EQ(t.sites[0].lat_deg, 40.6413);
  EXPECT_EQ(t.sites[0].lon_deg, -73.7781);
  EXPECT_EQ(t.sites[1].id, "ONE");
  EXPECT_EQ(t.sites[1].lon_deg, 5.0);
  ASSERT_EQ(t.rejected.size(), 3u);
  EXPECT_EQ(t.rejected[0].row, 2u);
  EXPECT_EQ(t.rejected[0].reason, "feature 2 (FID 1): geometry is a Line String, not a Point");
  EXPECT_EQ(t.rejected[1].reason, "feature 4 (FID 3): geometry is a MultiPoint of 2 points, not a Point");
  EXPECT_EQ(t.rejected[2].reason, "feature 5 (FID 4): geometry is a Polygon, not a Point");
}

TEST(OgrSiteReader, FlatGeobufAndIdField) {
  TempDir dir;
  const std::string path = dir / "sites.fgb";
  create_layer(path, "FlatGeobuf", 4326, wkbPoint, {{"station", OFTString}, {"id", OFTInteger64}},
               {{"POINT (-0.4543 51.47)", {"London", "7"}}, {"POINT (139.78 35.55)", {"Tokyo", "8"}}});
  // FlatGeobuf returns features in the order of its spatial index: find Tokyo by name.
  auto tokyo = [](const SiteTable& t) -> const InputSite& {
    for (const InputSite& s : t.sites) {
      if (s.fields[0] == "Tokyo") return s;
    }
    ADD_FAILURE() << "no Tokyo";
    return t.sites.at(0);
  };
  SiteTable t = read_sites(path);
  expect_accounted(t);
  ASSERT_EQ(t.sites.size(), 2u);
  EXPECT_EQ(t.id_column, 1);
  EXPECT_EQ(tokyo(t).id, "8");
  EXPECT_EQ(tokyo(t).lat_deg, 35.55);
  EXPECT_EQ(tokyo(t).lon_deg, 139.78);
  SiteReaderOptions options;
  options.id_field = "STATION";  // case-insensitive, as for CSV
  t = read_sites(path, options);
  EXPECT_EQ(t.id_column, 0);
  EXPECT_EQ(tokyo(t).id, "Tokyo");
  options.id_field = "nope";
  const Error e = error_of([&] { read_sites(path, options); });
  EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
  EXPECT_NE(std::string(e.what()).find("station, id"), std::string::npos) << e.what();
}

TEST(OgrSiteReader, AttributeColumnsWhenNamedOrWithoutGeometry) {
  TempDir dir;
  // A GeoPackage table without geometry: latitude/longitude columns found as in CSV.
  const std::string table = dir / "table.gpkg";
  create_layer(table, "GPKG", 0, wkbNone,
               {{"name", OFTString}, {"Latitude", OFTReal}, {"Longitude", OFTReal}},
               {{"", {"A", "10.5", "20.25"}}, {"", {"B", "", "1"}}, {"", {"C", "-91", "1"}}});
  SiteTable t = read_sites(table);
  expect_accounted(t);
  EXPECT_EQ(t.lat_column, 1);
  EXPECT_EQ(t.lon_column, 2);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].id, "A");
  EXPECT_EQ(t.sites[0].lat_deg, 10.5);
  EXPECT_EQ(t.sites[0].lon_deg, 20.25);
  EXPECT_EQ(t.sites[0].line, 0u);
  ASSERT_EQ(t.rejected.size(), 2u);
  EXPECT_EQ(t.rejected[0].reason, "feature 2 (FID 2): Latitude: empty value");
  EXPECT_EQ(t.rejected[1].reason, "feature 3 (FID 3): Latitude: latitude -91 is beyond +-90");

  // A point layer whose attributes are preferred when named.
  const std::string points = dir / "points.gpkg";
  create_layer(points, "GPKG", 4326, wkbPoint, {{"ylat", OFTReal}, {"xlon", OFTReal}},
               {{"POINT (1 2)", {"30", "40"}}});
  SiteReaderOptions options;
  options.lat_field = "ylat";
  options.lon_field = "xlon";
  t = read_sites(points, options);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].lat_deg, 30.0);
  EXPECT_EQ(t.sites[0].lon_deg, 40.0);
  t = read_sites(points);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_EQ(t.sites[0].lat_deg, 2.0);
}

TEST(OgrSiteReader, LayersAndErrors) {
  TempDir dir;
  const std::string path = dir / "two.gpkg";
  create_layer(path, "GPKG", 4326, wkbPoint, {}, {{"POINT (1 2)", {}}}, "first");
  {
    GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_UPDATE));
    ASSERT_TRUE(ds);
    OGRLayer* second = ds->CreateLayer("second", nullptr, wkbPoint, nullptr);
    ASSERT_NE(second, nullptr);
  }
  Error e = error_of([&] { read_sites(path); });
  EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
  EXPECT_NE(std::string(e.what()).find("first, second"), std::string::npos) << e.what();
  EXPECT_EQ(read_sites_ogr(path, {}, "first").sites.size(), 1u);
  EXPECT_EQ(read_sites_ogr(path, {}, "second").rows_read, 0u);
  EXPECT_EQ(error_of([&] { read_sites_ogr(path, {}, "third"); }).code(), ErrorCode::InvalidArgument);

  e = error_of([&] { read_sites(dir / "missing.gpkg"); });
  EXPECT_EQ(e.code(), ErrorCode::Io);
  EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos) << e.what();

  const std::string junk = dir / "junk.dat";
  std::ofstream(junk) << "\x01\x02 not a vector format\n";
  EXPECT_EQ(error_of([&] { read_sites(junk); }).code(), ErrorCode::BadData);
}

}  // namespace
}  // namespace geovor
