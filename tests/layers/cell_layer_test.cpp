#include "geovor/layers/cell_layer.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/io/geojson_writer.hpp"
#include "support/recording_writer.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

using testing::RecordingWriter;
using testing::TempDir;

// Eight sites at the cube's corners, whose cells are the eight octants (bounded by the equator
// and the meridians 0, 90, 180 and -90), and a ninth row at the first corner (merged into it).
// Input i has x < 0 when bit 0 is set, y < 0 for bit 1, z < 0 for bit 2; ids "a".."h", "dup".
struct Octants {
  SiteTable table;
  BuildReport report;
  SphericalDelaunay dt;
  std::vector<SiteId> site;  // of each input

  Octants() : dt(build(table, report)) { site = report.site_of_input; }

  static SphericalDelaunay build(SiteTable& table, BuildReport& report) {
    table.source = "octants";
    table.columns = {"id", "name", "Area_M2"};
    table.id_column = 0;
    std::vector<Vec3> points;
    for (int i = 0; i < 9; ++i) {
      const int corner = i % 8;
      const double k = 1 / std::sqrt(3.0);
      InputSite row;
      row.row = static_cast<std::uint64_t>(i + 1);
      row.id = i == 8 ? "dup" : std::string(1, static_cast<char>('a' + i));
      row.unit = {corner & 1 ? -k : k, corner & 2 ? -k : k, corner & 4 ? -k : k};
      row.fields = {row.id, "name " + row.id, "x"};
      if (i == 7) row.fields = {row.id};  // a short row: the other columns are null
      points.push_back(row.unit);
      table.sites.push_back(row);
    }
    return SphericalDelaunay::build(points, {}, &report);
  }
};

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

const std::string& string_of(const FieldValue& v) { return std::get<std::string>(v); }
std::int64_t integer_of(const FieldValue& v) { return std::get<std::int64_t>(v); }
double real_of(const FieldValue& v) { return std::get<double>(v); }

TEST(CellLayer, SchemaOursThenTheInputColumnsRenamedOnAClash) {
  SiteTable table;
  table.columns = {"id", "name", "Area_M2", "SITE_ID", "fid", "pop"};
  table.column_types = {FieldType::String, FieldType::String, FieldType::Real,
                        FieldType::String, FieldType::Integer, FieldType::Integer64};
  const std::vector<Field> schema = cell_layer_schema(table);
  const std::vector<std::string> names = {"site_index", "site_id",   "ids",  "n_rows", "area_m2",     "area_sr",
                                          "n_vertices", "neighbors", "id",   "name",   "src_Area_M2", "src_SITE_ID",
                                          "src_fid",    "pop"};
  const std::vector<FieldType> types = {FieldType::Integer64, FieldType::String, FieldType::String, FieldType::Integer64,
                                        FieldType::Real,      FieldType::Real,   FieldType::Integer64, FieldType::String,
                                        FieldType::String,    FieldType::String, FieldType::Real,   FieldType::String,
                                        FieldType::Integer,   FieldType::Integer64};
  ASSERT_EQ(schema.size(), names.size());
  for (std::size_t i = 0; i < schema.size(); ++i) {
    EXPECT_EQ(schema[i].name, names[i]);
    EXPECT_EQ(schema[i].type, types[i]) << names[i];
    EXPECT_EQ(schema[i].json, names[i] == "ids" || names[i] == "neighbors") << names[i];
  }
}

TEST(CellLayer, OctantsAsValues) {
  const Octants o;
  RecordingWriter writer;
  std::vector<std::size_t> progress;
  CellLayerOptions options;
  options.threads = 2;
  options.progress = [&](std::size_t n) { progress.push_back(n); };
  const CellLayerReport report = write_cell_layer(writer, o.table, o.report, o.dt, options);
  EXPECT_FALSE(writer.finished);  // the caller finishes
  EXPECT_EQ(report.cells_written, 8u);
  EXPECT_TRUE(report.unwritten.empty());
  EXPECT_EQ(progress, std::vector<std::size_t>{8});
  ASSERT_EQ(writer.features.size(), 8u);
  const double octant_m2 = GeographicLib::Geodesic::WGS84().EllipsoidArea() / 8;
  for (std::size_t f = 0; f < 8; ++f) {
    const std::vector<FieldValue>& v = writer.features[f].values;
    ASSERT_EQ(v.size(), 11u);
    const SiteId s = static_cast<SiteId>(integer_of(v[0]));
    if (f > 0) {
      EXPECT_GT(s, integer_of(writer.features[f - 1].values[0]));  // in site order
    }
    const std::size_t corner = static_cast<std::size_t>(std::find(o.site.begin(), o.site.end(), s) - o.site.begin());
    ASSERT_LT(corner, 8u);
    const std::string id(1, static_cast<char>('a' + corner));
    EXPECT_EQ(string_of(v[1]), id);
    EXPECT_EQ(string_of(v[2]), corner == 0 ? R"(["a","dup"])" : "[\"" + id + "\"]");
    EXPECT_EQ(integer_of(v[3]), corner == 0 ? 2 : 1);
    EXPECT_NEAR(real_of(v[4]), octant_m2, 1e-9 * octant_m2);
    EXPECT_NEAR(real_of(v[5]), std::numbers::pi / 2, 1e-12);
    // The cube's faces are co-circular: each is split into two Delaunay triangles with one
    // circumcentre, so a cell has a Voronoi vertex per incident triangle (some coincide) and a
    // neighbour across each of its edges (the face diagonals' edges have length zero).
    std::int64_t incident = 0;
    for (TriId t = 0; t < o.dt.num_triangles(); ++t)
      for (int k = 0; k < 3; ++k) incident += o.dt.tri_site(t, k) == s;
    EXPECT_EQ(integer_of(v[6]), incident);
    EXPECT_GE(incident, 3);
    const std::string& neighbours = string_of(v[7]);
    EXPECT_EQ(static_cast<std::int64_t>(std::count(neighbours.begin(), neighbours.end(), ',')) + 1, incident);
    for (const std::size_t bit : {1u, 2u, 4u}) {  // the corners across the octant's three sides
      const std::string across(1, static_cast<char>('a' + (corner ^ bit)));
      EXPECT_NE(neighbours.find("\"" + across + "\""), std::string::npos) << neighbours;
    }
    const std::string antipode(1, static_cast<char>('a' + (corner ^ 7)));
    EXPECT_EQ(neighbours.find("\"" + antipode + "\""), std::string::npos) << neighbours;
    // The list starts at the smallest neighbour (VoronoiDiagram's order).
    const std::string first_neighbour = neighbours.substr(2, 1);
    for (std::size_t n = 0; n < 8; ++n)
      if (neighbours.find("\"" + std::string(1, static_cast<char>('a' + n)) + "\"") != std::string::npos) {
        EXPECT_LE(o.site[static_cast<std::size_t>(first_neighbour[0] - 'a')], o.site[n]) << neighbours;
      }
    EXPECT_EQ(string_of(v[8]), id);
    if (corner == 7) {
      EXPECT_TRUE(std::holds_alternative<std::monostate>(v[9]));
      EXPECT_TRUE(std::holds_alternative<std::monostate>(v[10]));
    } else {
      EXPECT_EQ(string_of(v[9]), "name " + id);
      EXPECT_EQ(string_of(v[10]), "x");
    }
    const MultiPolygon& cell = std::get<MultiPolygon>(writer.features[f].geometry);
    ASSERT_FALSE(cell.empty());
  }
}

TEST(CellLayer, OctantsAsGeoJsonInSiteOrderWithTheValuesText) {
  const Octants o;
  TempDir dir("geovor_cell_layer");
  RecordingWriter values;
  write_cell_layer(values, o.table, o.report, o.dt);
  for (const unsigned threads : {1u, 3u}) {
    const std::string path = dir / ("cells" + std::to_string(threads) + ".geojson");
    const auto writer = open_cell_layer_writer(path, o.table, {});
    CellLayerOptions options;
    options.threads = threads;
    const CellLayerReport report = write_cell_layer(*writer, o.table, o.report, o.dt, options);
    writer->finish();
    EXPECT_EQ(report.cells_written, 8u);
  }
  const std::string text = read_file(dir / "cells1.geojson");
  EXPECT_EQ(text, read_file(dir / "cells3.geojson"));  // the threads change nothing
  std::size_t at = 0;
  for (const RecordingWriter::Feature& f : values.features) {
    // Feature by feature in site order, with the feature id and the same property values.
    const std::string site_index = "\"site_index\":" + std::to_string(integer_of(f.values[0])) + ",";
    const std::size_t next = text.find(site_index, at);
    ASSERT_NE(next, std::string::npos) << site_index;
    const std::size_t line_begin = text.rfind('\n', next) + 1;
    const std::string line = text.substr(line_begin, text.find('\n', next) - line_begin);
    std::string id;
    append_json_string(id, string_of(f.values[1]));
    const std::string& ids = string_of(f.values[2]);  // JSON arrays, written as such
    const std::string& neighbours = string_of(f.values[7]);
    EXPECT_EQ(line.rfind("{\"type\":\"Feature\",\"id\":" + id + ",", 0), 0u) << line;
    EXPECT_NE(line.find("\"ids\":" + ids + ",\"n_rows\":" + std::to_string(integer_of(f.values[3]))), std::string::npos)
        << line;
    EXPECT_NE(line.find("\"neighbors\":" + neighbours + ",\"id\":" + id), std::string::npos) << line;
    if (string_of(f.values[1]) == "h") {
      EXPECT_NE(line.find("\"name\":null,\"src_Area_M2\":null"), std::string::npos) << line;
    }
    at = next + 1;
  }
  EXPECT_NE(text.find(R"("ids":["a","dup"])"), std::string::npos);
}

TEST(CellLayer, ADiagramBuiltEarlierWritesTheSameBytesAndAnotherIsRefused) {
  const Octants o;
  TempDir dir("geovor_cell_layer");
  const VoronoiDiagram diagram(o.dt, 2);
  for (const bool given : {false, true}) {
    const auto writer = open_cell_layer_writer(dir / (given ? "given.geojson" : "built.geojson"), o.table, {});
    CellLayerOptions options;
    if (given) options.diagram = &diagram;
    EXPECT_EQ(write_cell_layer(*writer, o.table, o.report, o.dt, options).cells_written, 8u);
    writer->finish();
  }
  EXPECT_EQ(read_file(dir / "given.geojson"), read_file(dir / "built.geojson"));
  // A diagram of other sites (here of four of them) is refused before anything is written.
  std::vector<Vec3> four;
  for (int i = 0; i < 4; ++i) four.push_back(o.table.sites[static_cast<std::size_t>(i)].unit);
  const SphericalDelaunay other_dt = SphericalDelaunay::build(four);
  const VoronoiDiagram other(other_dt);
  RecordingWriter values;
  CellLayerOptions options;
  options.diagram = &other;
  try {
    write_cell_layer(values, o.table, o.report, o.dt, options);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
  }
  EXPECT_TRUE(values.features.empty());
}

TEST(CellLayer, CellsThatCollapseAtThePrecisionAreWrittenEmptyAndReported) {
  // The octants, and a site with four others 200 m around it: its cell is about 100 m across,
  // which collapses at one decimal (about 11 km).
  SiteTable table;
  table.columns = {"id"};
  std::vector<Vec3> points;
  auto add = [&](const std::string& id, Vec3 unit) {
    InputSite row;
    row.id = id;
    row.fields = {id};
    row.unit = unit;
    table.sites.push_back(row);
    points.push_back(unit);
  };
  const double k = 1 / std::sqrt(3.0);
  for (int i = 0; i < 8; ++i) add(std::string(1, static_cast<char>('a' + i)), {i & 1 ? -k : k, i & 2 ? -k : k, i & 4 ? -k : k});
  const double d = 0.0018;  // degrees: 200 m
  add("centre", SiteEncoder::from_lat_lon(10, 10));
  add("n", SiteEncoder::from_lat_lon(10 + d, 10));
  add("s", SiteEncoder::from_lat_lon(10 - d, 10));
  add("e", SiteEncoder::from_lat_lon(10, 10 + d));
  add("w", SiteEncoder::from_lat_lon(10, 10 - d));
  BuildReport build;
  const SphericalDelaunay dt = SphericalDelaunay::build(points, {}, &build);
  TempDir dir("geovor_cell_layer");
  WriterOptions writer_options;
  writer_options.precision = 1;
  const auto writer = open_cell_layer_writer(dir / "cells.geojsonl", table, writer_options);
  CellLayerOptions options;
  options.precision = 1;
  const CellLayerReport report = write_cell_layer(*writer, table, build, dt, options);
  writer->finish();
  EXPECT_EQ(report.cells_written, 13u);  // every cell, the empty ones too
  ASSERT_FALSE(report.unwritten.empty());
  EXPECT_TRUE(std::is_sorted(report.unwritten.begin(), report.unwritten.end(),
                             [](const UnwrittenCell& a, const UnwrittenCell& b) { return a.site < b.site; }));
  EXPECT_TRUE(std::any_of(report.unwritten.begin(), report.unwritten.end(),
                          [&](const UnwrittenCell& c) { return c.site == build.site_of_input[8]; }));
  for (const UnwrittenCell& c : report.unwritten) EXPECT_NE(c.status, CellStatus::Written);
  std::size_t lines = 0;
  for (const char c : read_file(dir / "cells.geojsonl")) lines += c == '\n';
  EXPECT_EQ(lines, 13u);
}

}  // namespace
}  // namespace geovor
