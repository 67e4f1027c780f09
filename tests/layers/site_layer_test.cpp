#include "geovor/layers/site_layer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "geovor/geo/site_encoder.hpp"
#include "support/recording_writer.hpp"

namespace geovor {
namespace {

using testing::RecordingWriter;

// "s<row>" (appended: GCC 12 warns wrongly on "s" + std::to_string(i)).
std::string id_of(std::size_t row) {
  std::string id(1, 's');
  return id += std::to_string(row);
}

TEST(SiteLayer, SchemaDropsThePositionsAndRenamesClashes) {
  SiteTable table;
  table.columns = {"id", "lat", "lon", "Name", "name", "MOVED_M"};
  table.lat_column = 1;
  table.lon_column = 2;
  std::vector<std::string> names;
  for (const Field& f : site_layer_schema(table)) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"site_index", "site_id", "lat_deg", "lon_deg", "moved_m", "id", "Name",
                                             "src_name", "src_MOVED_M"}));
  table.lat_column = table.lon_column = -1;
  table.ecef_columns = {3, 4, 5};  // X, Y, Z columns are positions too
  names.clear();
  for (const Field& f : site_layer_schema(table)) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"site_index", "site_id", "lat_deg", "lon_deg", "moved_m", "id", "lat", "lon"}));
}

TEST(SiteLayer, PositionsDistancesAndAttributes) {
  // The six axis points (and a duplicate, merged); each started 0.01 rad from where it is.
  const std::vector<Vec3> points = {{1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, 1, 0}};
  SiteTable table;
  table.columns = {"id", "lat", "lon", "note"};
  table.lat_column = 1;
  table.lon_column = 2;
  for (std::size_t i = 0; i < points.size(); ++i) {
    InputSite row;
    row.id = id_of(i);
    row.fields = {row.id, "?", "?", "note " + row.id};
    table.sites.push_back(row);
  }
  table.sites[3].fields.resize(2);  // a short row: note is null
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(points, {}, &report);
  std::vector<Vec3> start(dt.site_capacity());
  const double a = 0.01, c = std::cos(a), s = std::sin(a);
  for (SiteId site = 0; site < dt.site_capacity(); ++site) {
    const Vec3 p = dt.site(site);
    // Equator points turned by -a about the axis, the poles tilted by a toward x.
    start[site] = p.z == 0 ? Vec3{c * p.x + s * p.y, -s * p.x + c * p.y, 0} : Vec3{s, 0, p.z > 0 ? c : -c};
  }
  RecordingWriter writer;
  EXPECT_EQ(write_site_layer(writer, table, rows_of_sites(report, dt.site_capacity()), dt, start), 6u);
  ASSERT_EQ(writer.features.size(), 6u);
  for (std::size_t f = 0; f < 6; ++f) {
    const std::vector<FieldValue>& v = writer.features[f].values;
    ASSERT_EQ(v.size(), 7u);
    const SiteId site = static_cast<SiteId>(std::get<std::int64_t>(v[0]));
    const std::size_t row = std::find(report.site_of_input.begin(), report.site_of_input.end(), site) -
                            report.site_of_input.begin();  // the first row of the site
    EXPECT_EQ(std::get<std::string>(v[1]), id_of(row));
    const Vec3 p = points[row];
    const double lat = p.z > 0 ? 90 : p.z < 0 ? -90 : 0;
    EXPECT_DOUBLE_EQ(std::get<double>(v[2]), lat);
    if (p.z == 0) {  // -180 and 180 are one meridian
      EXPECT_NEAR(std::remainder(std::get<double>(v[3]) - std::atan2(p.y, p.x) * 180 / std::numbers::pi, 360.0), 0, 1e-12);
    }
    EXPECT_NEAR(std::get<double>(v[4]), a * SiteEncoder::kEarthRadiusM, 1e-6);
    EXPECT_EQ(std::get<std::string>(v[5]), id_of(row));
    if (row == 3)
      EXPECT_TRUE(std::holds_alternative<std::monostate>(v[6]));
    else
      EXPECT_EQ(std::get<std::string>(v[6]), "note " + id_of(row));
    const LonLat& point = std::get<LonLat>(writer.features[f].geometry);
    EXPECT_EQ(point.lat_deg, std::get<double>(v[2]));
    EXPECT_EQ(point.lon_deg, std::get<double>(v[3]));
  }
}

}  // namespace
}  // namespace geovor
