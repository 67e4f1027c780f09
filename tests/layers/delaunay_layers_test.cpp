#include "geovor/layers/delaunay_layers.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <gdal_priv.h>
#include <ogrsf_frmts.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "geovor/geo/site_encoder.hpp"
#include "geovor/core/error.hpp"
#include "support/recording_writer.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

using testing::RecordingWriter;

const std::string& string_of(const FieldValue& v) { return std::get<std::string>(v); }
std::int64_t integer_of(const FieldValue& v) { return std::get<std::int64_t>(v); }
double real_of(const FieldValue& v) { return std::get<double>(v); }

// "p<row>" (appended: GCC 12 warns wrongly on "p" + std::to_string(i)).
std::string id_of(std::size_t row) {
  std::string id(1, 'p');
  return id += std::to_string(row);
}

SiteTable table_of(const std::vector<Vec3>& points) {
  SiteTable table;
  for (std::size_t i = 0; i < points.size(); ++i) {
    InputSite row;
    row.id = id_of(i);
    row.unit = points[i];
    table.sites.push_back(row);
  }
  return table;
}

TEST(DelaunayLayers, Schemas) {
  std::vector<std::string> names;
  for (const Field& f : triangle_layer_schema()) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"tri_index", "kind", "ghost", "site_a", "site_b", "site_c", "id_a", "id_b",
                                             "id_c", "area_m2", "area_sr", "circumradius_m"}));
  names.clear();
  for (const Field& f : edge_layer_schema()) names.push_back(f.name);
  EXPECT_EQ(names, (std::vector<std::string>{"edge_index", "site_a", "site_b", "id_a", "id_b", "length_m", "geodesic_m",
                                             "hull", "ghost"}));
}

// The octahedron (the six axis points, and a duplicate of the first merged into it): its eight
// triangles are the octants, its twelve edges quarter great circles, four on the equator.
TEST(DelaunayLayers, Octahedron) {
  const std::vector<Vec3> points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 0, 0}};
  const SiteTable table = table_of(points);
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(points, {}, &report);
  ASSERT_EQ(dt.num_triangles(), 8u);
  const SiteRows rows = rows_of_sites(report, dt.site_capacity());
  const DelaunayGeometry geometry(dt, {});
  const double R = SiteEncoder::kEarthRadiusM;
  const GeographicLib::Geodesic& wgs84 = GeographicLib::Geodesic::WGS84();

  RecordingWriter triangles;
  std::vector<std::size_t> progress;
  DelaunayLayerOptions options;
  options.progress = [&](std::size_t t) { progress.push_back(t); };
  const TriangleLayerReport tri = write_triangle_layer(triangles, table, rows, geometry, options);
  EXPECT_EQ(tri.triangles_written, 8u);
  EXPECT_TRUE(tri.unwritten.empty());
  EXPECT_EQ(progress, std::vector<std::size_t>{0});  // every 4,096 triangles, from the first
  ASSERT_EQ(triangles.features.size(), 8u);
  for (std::size_t t = 0; t < 8; ++t) {
    const std::vector<FieldValue>& v = triangles.features[t].values;
    EXPECT_EQ(integer_of(v[0]), static_cast<std::int64_t>(t));
    EXPECT_EQ(string_of(v[1]), "proper");
    EXPECT_EQ(integer_of(v[2]), 0);
    std::set<std::string> ids;
    for (int k = 0; k < 3; ++k) {
      const SiteId s = static_cast<SiteId>(integer_of(v[3 + k]));
      EXPECT_EQ(s, dt.tri_site(static_cast<TriId>(t), k));
      ids.insert(string_of(v[6 + k]));
    }
    EXPECT_EQ(ids.size(), 3u);
    EXPECT_EQ(ids.count("p6"), 0u);  // the merged row names no site
    EXPECT_NEAR(real_of(v[9]), wgs84.EllipsoidArea() / 8, 1e-9 * wgs84.EllipsoidArea() / 8);
    EXPECT_NEAR(real_of(v[10]), std::numbers::pi / 2, 1e-12);
    EXPECT_NEAR(real_of(v[11]), std::acos(1 / std::sqrt(3.0)) * R, 1e-9 * R);
  }

  RecordingWriter edges;
  const EdgeLayerReport edge = write_edge_layer(edges, table, rows, geometry);
  EXPECT_EQ(edge.edges_written, 12u);
  EXPECT_EQ(edge.collapsed, 0u);
  std::size_t on_equator = 0;
  for (std::size_t e = 0; e < edges.features.size(); ++e) {
    const std::vector<FieldValue>& v = edges.features[e].values;
    EXPECT_EQ(integer_of(v[0]), static_cast<std::int64_t>(e));
    EXPECT_EQ(string_of(v[3]), id_of(rows.first(static_cast<SiteId>(integer_of(v[1])))));
    EXPECT_EQ(string_of(v[4]), id_of(rows.first(static_cast<SiteId>(integer_of(v[2])))));
    EXPECT_NEAR(real_of(v[5]), std::numbers::pi / 2 * R, 1e-9 * R);
    // A quarter of the equator (pi a / 2) or of a meridian.
    const double quarter_equator = std::numbers::pi / 2 * wgs84.EquatorialRadius();
    double quarter_meridian = 0;
    wgs84.Inverse(0, 0, 90, 0, quarter_meridian);
    const double g = real_of(v[6]);
    EXPECT_TRUE(std::abs(g - quarter_equator) < 1e-6 || std::abs(g - quarter_meridian) < 1e-6) << g;
    on_equator += std::abs(g - quarter_equator) < 1e-6;
    EXPECT_EQ(integer_of(v[7]), 0);  // no hull: the sites lie in no hemisphere
    EXPECT_EQ(integer_of(v[8]), 0);
  }
  EXPECT_EQ(on_equator, 4u);
}

// Sites in the northern hemisphere: faces outside their convex hull are ghosts, left out with
// no_ghosts; the hull's edges are flagged.
TEST(DelaunayLayers, NoGhostsLeavesOutTheOuterFaces) {
  std::vector<Vec3> points;
  for (int i = 0; i < 5; ++i) points.push_back(SiteEncoder::from_lat_lon(40 + 3 * (i % 2), -100 + 7 * i));
  points.push_back(SiteEncoder::from_lat_lon(50, -85));
  const SiteTable table = table_of(points);
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(points, {}, &report);
  const SiteRows rows = rows_of_sites(report, dt.site_capacity());
  const DelaunayGeometry geometry(dt, {});
  RecordingWriter all, inner, inner_edges, all_edges;
  DelaunayLayerOptions no_ghosts;
  no_ghosts.no_ghosts = true;
  EXPECT_EQ(write_triangle_layer(all, table, rows, geometry).triangles_written, dt.num_triangles());
  const std::size_t kept = write_triangle_layer(inner, table, rows, geometry, no_ghosts).triangles_written;
  std::size_t outer = 0;
  for (const auto& f : all.features) outer += integer_of(f.values[2]);
  EXPECT_GT(outer, 0u);
  EXPECT_EQ(kept, dt.num_triangles() - outer);
  for (const auto& f : inner.features) EXPECT_EQ(integer_of(f.values[2]), 0);
  write_edge_layer(all_edges, table, rows, geometry);
  write_edge_layer(inner_edges, table, rows, geometry, no_ghosts);
  std::size_t hull = 0, ghost = 0;
  for (const auto& f : all_edges.features) {
    hull += integer_of(f.values[7]);
    ghost += integer_of(f.values[8]);
  }
  EXPECT_GE(hull, 3u);
  EXPECT_EQ(inner_edges.features.size(), all_edges.features.size() - ghost);
  EXPECT_EQ(all_edges.features.size(), dt.halfedges().size() / 2);
}

// The layers of a data source and their feature counts, as GDAL reads them back.
std::vector<std::pair<std::string, long long>> layers_of(const std::string& path) {
  std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  std::vector<std::pair<std::string, long long>> out;
  if (!ds) return out;
  for (int i = 0; i < ds->GetLayerCount(); ++i) out.emplace_back(ds->GetLayer(i)->GetName(), ds->GetLayer(i)->GetFeatureCount());
  return out;
}

// One GeoPackage named twice holds both layers (the octahedron: 8 triangles, 12 edges); a
// one-layer format named twice is refused before anything is written; two files get one each.
TEST(DelaunayLayers, TrianglesAndEdgesIntoOneDataSource) {
  const std::vector<Vec3> points = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  const SiteTable table = table_of(points);
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(points, {}, &report);
  const SiteRows rows = rows_of_sites(report, dt.site_capacity());
  const DelaunayGeometry geometry(dt, {});
  testing::TempDir dir("geovor_layers");
  using Layers = std::vector<std::pair<std::string, long long>>;

  DelaunayOutput one;
  one.triangles_path = one.edges_path = dir / "tin.gpkg";
  EXPECT_TRUE(one_data_source(one));
  const DelaunayLayersReport written = write_delaunay_layers(one, table, rows, geometry);
  EXPECT_EQ(written.triangles.triangles_written, 8u);
  EXPECT_EQ(written.edges.edges_written, 12u);
  EXPECT_EQ(layers_of(dir / "tin.gpkg"), (Layers{{"triangles", 8}, {"edges", 12}}));

  DelaunayOutput fgb;
  fgb.triangles_path = fgb.edges_path = dir / "tin.fgb";
  try {
    write_delaunay_layers(fgb, table, rows, geometry);
    ADD_FAILURE() << "a FlatGeobuf file cannot hold two layers";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"tin.gpkg"});

  DelaunayOutput two;
  two.triangles_path = dir / "t.gpkg";
  two.edges_path = dir / "e.fgb";
  two.edges.layer = "lines";
  EXPECT_FALSE(one_data_source(two));
  write_delaunay_layers(two, table, rows, geometry);
  EXPECT_EQ(layers_of(dir / "t.gpkg"), (Layers{{"triangles", 8}}));
  EXPECT_EQ(layers_of(dir / "e.fgb"), (Layers{{"lines", 12}}));
}

}  // namespace
}  // namespace geovor
