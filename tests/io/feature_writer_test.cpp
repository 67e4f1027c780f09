/// \file feature_writer_test.cpp
/// \brief Tests of the feature writers: every format is written, then read back by GDAL (an
/// independent reader) and checked for feature count, geometry type, coordinates, attributes,
/// validity and ring orientation; GeoJSON text is checked for its bbox members (against GDAL's
/// own RFC 7946 writer), RFC 8142 record separators, escaping and number formatting; the output
/// is checked to appear only when finish() succeeds (overwrite refusal, abandoned writers,
/// failures, a full file system).
#include "geovor/io/feature_writer.hpp"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_geometry.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <csignal>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "geovor/core/error.hpp"
#include "support/file_text.hpp"
#include "support/temp_dir.hpp"
#include "geovor/io/geojson_writer.hpp"
#include "geovor/core/output_target.hpp"

namespace geovor {
namespace {

namespace fs = std::filesystem;
using testing::slurp;
using testing::spit;
using testing::error_of;
using testing::contains;

// ---------------------------------------------------------------------------------------------
// Helpers

// A temporary directory named for this test file.
class TempDir : public testing::TempDir {
 public:
  TempDir() : testing::TempDir("geovor_io") {}
};

// Counter-clockwise rectangle.
Ring box(double w, double s, double e, double n) { return {{w, s}, {e, s}, {e, n}, {w, n}, {w, s}}; }

// ---------------------------------------------------------------------------------------------
// The test data: four cells and their attributes

const std::string kTricky =
    "quote \" backslash \\ newline \n tab \t cr \r ctrl \x01\x1f del \x7f slash / "
    "\xC3\xA9t\xC3\xA9 \xE6\xBC\xA2\xE5\xAD\x97 \xF0\x9F\x98\x80";

std::vector<Field> cell_schema() {
  return {{"site_id", FieldType::Integer64},
          {"name", FieldType::String},
          {"area_km2", FieldType::Real},
          {"population_2020", FieldType::Integer64},
          {"population_2021", FieldType::Integer64}};
}

struct Cell {
  MultiPolygon geometry;
  std::vector<FieldValue> values;
  BBox bbox;  // expected RFC 7946 bbox
};

const std::vector<Cell>& cells() {
  static const std::vector<Cell> kCells = [] {
  std::vector<Cell> out;
  // 0: a square with a (clockwise) hole, coordinates that need rounding.
  Polygon square{box(0.12345678912, 0, 10, 10), {{{2, 2}, {2, 4}, {4, 4}, {4, 2}, {2, 2}}}};
  out.push_back({{square},
                 {std::int64_t{1}, std::string("plain"), 510065621724088.5, std::int64_t{123456},
                  std::int64_t{-7}},
                 {0.12345678912, 0, 10, 10}});
  // 1: a cell cut at the antimeridian.
  out.push_back({{Polygon{box(170, -10, 180, 10), {}}, Polygon{box(-180, -10, -170, 10), {}}},
                 {std::int64_t{2}, kTricky, 0.1, std::monostate{}, std::int64_t{0}},
                 {170, -10, -170, 10}});
  // 2: the north polar cap, closed through (180, 90) and (-180, 90).
  out.push_back({{Polygon{{{-180, 70},
                            {-90, 72.25},
                            {0, 70.5},
                            {90, 71},
                            {180, 70},
                            {180, 90},
                            {-180, 90},
                            {-180, 70}},
                           {}}},
                 {std::int64_t{3}, std::string(""), 2.0,
                  std::int64_t{9007199254740993},  // 2^53 + 1: not a double
                  std::int64_t{-9223372036854775807}},
                 {-180, 70, 180, 90}});
  // 3: the south polar cap, running west along its boundary, then through (-180, -90), (180, -90).
  out.push_back({{Polygon{{{180, -75},
                            {90, -76},
                            {0, -75},
                            {-90, -74},
                            {-180, -75},
                            {-180, -90},
                            {180, -90},
                            {180, -75}},
                           {}}},
                 {std::int64_t{4}, std::monostate{}, -1e-300, std::int64_t{1},
                  std::int64_t{std::numeric_limits<std::int64_t>::max()}},
                 {-180, -90, 180, -74}});
  return out;
  }();
  return kCells;
}

const std::vector<LonLat>& points() {
  static const std::vector<LonLat> kPoints{{2.3522, 48.8566}, {-180, 0}, {179.9999999, -89.5}, {0, 90}};
  return kPoints;
}

const MultiLineString& lines() {
  static const MultiLineString kLines{{{170, 1}, {180, 2}}, {{-180, 2}, {-170, 3}, {-160, 3.5}}};
  return kLines;
}

void write_cells(const std::string& path, const WriterOptions& options = {}) {
  auto writer = open_feature_writer(path, GeometryType::MultiPolygon, cell_schema(), options);
  for (const Cell& c : cells()) writer->write(c.geometry, c.values);
  writer->finish();
}

// ---------------------------------------------------------------------------------------------
// Reading back with GDAL

struct ReadBack {
  std::string driver;
  OGRwkbGeometryType layer_type = wkbUnknown;
  std::vector<std::string> field_names;
  std::vector<OGRFieldType> field_types;
  std::vector<OGRFeatureUniquePtr> features;
};

ReadBack read_back(const std::string& path, const char* driver) {
  GDALAllRegister();
  const char* allowed[] = {driver, nullptr};
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY,
                                            driver != nullptr ? allowed : nullptr));
  ReadBack r;
  if (!ds) {
    ADD_FAILURE() << "GDAL cannot open " << path << ": " << CPLGetLastErrorMsg();
    return r;
  }
  EXPECT_EQ(ds->GetLayerCount(), 1);
  r.driver = ds->GetDriver()->GetDescription();
  OGRLayer* layer = ds->GetLayer(0);
  r.layer_type = wkbFlatten(layer->GetGeomType());
  OGRFeatureDefn* defn = layer->GetLayerDefn();
  for (int i = 0; i < defn->GetFieldCount(); ++i) {
    r.field_names.emplace_back(defn->GetFieldDefn(i)->GetNameRef());
    r.field_types.push_back(defn->GetFieldDefn(i)->GetType());
  }
  // The SRS, where the format stores one, is WGS 84 longitude/latitude.
  if (const OGRSpatialReference* srs = layer->GetSpatialRef()) {
    OGRSpatialReference wgs84;
    wgs84.importFromEPSG(4326);
    const char* opts[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES",
                          "CRITERION=EQUIVALENT_EXCEPT_AXIS_ORDER_GEOGCRS", nullptr};
    EXPECT_TRUE(srs->IsSame(&wgs84, opts)) << path;
  }
  for (auto& f : *layer) r.features.push_back(std::move(f));
  return r;
}

int field_index(const ReadBack& r, const std::string& name) {
  const auto it = std::find(r.field_names.begin(), r.field_names.end(), name);
  return it == r.field_names.end() ? -1 : static_cast<int>(it - r.field_names.begin());
}

std::vector<LonLat> ring_points(const OGRSimpleCurve& curve) {
  std::vector<LonLat> out;
  for (int i = 0; i < curve.getNumPoints(); ++i) out.push_back({curve.getX(i), curve.getY(i)});
  return out;
}

::testing::AssertionResult same_points(const std::vector<LonLat>& got,
                                       const std::vector<LonLat>& want, double tol = 1e-7) {
  if (got.size() != want.size()) {
    return ::testing::AssertionFailure() << got.size() << " points, expected " << want.size();
  }
  for (std::size_t i = 0; i < got.size(); ++i) {
    if (std::abs(got[i].lon_deg - want[i].lon_deg) > tol ||
        std::abs(got[i].lat_deg - want[i].lat_deg) > tol) {
      return ::testing::AssertionFailure()
             << "point " << i << ": (" << got[i].lon_deg << ", " << got[i].lat_deg
             << "), expected (" << want[i].lon_deg << ", " << want[i].lat_deg << ")";
    }
  }
  return ::testing::AssertionSuccess();
}

struct FormatCase {
  std::string file;
  const char* driver;
  bool clockwise_shells;  // Shapefile stores exterior rings clockwise
  bool typed_fields;      // false: CSV reads every field back as a string
};

void PrintTo(const FormatCase& fc, std::ostream* os) { *os << fc.file; }

std::string case_name(const ::testing::TestParamInfo<FormatCase>& info) {
  std::string s = info.param.file;
  for (char& c : s) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return s;
}

const std::vector<FormatCase> kFormats = {
    {"cells.geojson", "GeoJSON", false, true},     {"cells.geojsonl", "GeoJSONSeq", false, true},
    {"cells.geojsons", "GeoJSONSeq", false, true}, {"cells.gpkg", "GPKG", false, true},
    {"cells.fgb", "FlatGeobuf", false, true},      {"cells.shp", "ESRI Shapefile", true, true},
    {"cells.csv", "CSV", false, false},
};

class EveryFormat : public ::testing::TestWithParam<FormatCase> {};

TEST_P(EveryFormat, CellsRoundTripThroughGdal) {
  const FormatCase& fc = GetParam();
  TempDir dir;
  const std::string path = dir / fc.file;
  write_cells(path);
  const bool shapefile = std::string(fc.driver) == "ESRI Shapefile";
  const ReadBack r = read_back(path, fc.driver);
  EXPECT_EQ(r.driver, fc.driver);
  const bool csv = std::string(fc.driver) == "CSV";
  const bool flatgeobuf = std::string(fc.driver) == "FlatGeobuf";
  const std::vector<Cell>& want = cells();
  ASSERT_EQ(r.features.size(), want.size());
  if (fc.typed_fields) {
    EXPECT_EQ(r.layer_type, shapefile ? wkbPolygon : wkbMultiPolygon);
  }

  // Attributes. Shapefile field names are cut to 10 characters, deterministically.
  const std::vector<std::string> names =
      shapefile ? std::vector<std::string>{"site_id", "name", "area_km2", "population", "populati_1"}
                : std::vector<std::string>{"site_id", "name", "area_km2", "population_2020",
                                           "population_2021"};
  for (const std::string& n : names) EXPECT_GE(field_index(r, n), 0) << n;
  if (fc.typed_fields) {
    // GeoJSON has no schema (GDAL guesses Integer for small values); DBF sizes integers.
    const OGRFieldType id_type = r.field_types[field_index(r, names[0])];
    EXPECT_TRUE(id_type == OFTInteger64 || id_type == OFTInteger) << id_type;
    EXPECT_EQ(r.field_types[field_index(r, names[1])], OFTString);
    EXPECT_EQ(r.field_types[field_index(r, names[2])], OFTReal);
    EXPECT_EQ(r.field_types[field_index(r, names[3])], OFTInteger64);  // "population": 6 digits
  }
  for (std::size_t k = 0; k < want.size(); ++k) {
    // FlatGeobuf stores features in the order of its spatial index (a Hilbert sort); the other
    // formats keep the order written.
    const std::size_t at = [&] {
      if (!flatgeobuf) return k;
      for (std::size_t i = 0; i < r.features.size(); ++i) {
        if (r.features[i]->GetFieldAsInteger64(field_index(r, names[0])) ==
            std::get<std::int64_t>(want[k].values[0])) {
          return i;
        }
      }
      return r.features.size();
    }();
    ASSERT_LT(at, r.features.size());
    const OGRFeature& f = *r.features[at];
    const auto& v = want[k].values;
    SCOPED_TRACE("feature " + std::to_string(k));
    EXPECT_EQ(f.GetFieldAsInteger64(field_index(r, names[0])), std::get<std::int64_t>(v[0]));
    const int name_i = field_index(r, names[1]);
    if (const auto* s = std::get_if<std::string>(&v[1])) {
      std::string text = *s;
      // GDAL's CSV reader turns a CR inside a quoted field into LF (the file has the CR).
      if (csv) std::replace(text.begin(), text.end(), '\r', '\n');
      EXPECT_EQ(std::string(f.GetFieldAsString(name_i)), text);
    } else if (!shapefile && !csv) {
      EXPECT_FALSE(f.IsFieldSetAndNotNull(name_i));  // null (FlatGeobuf: unset) survives
    } else {
      EXPECT_EQ(std::string(f.GetFieldAsString(name_i)), "");
    }
    const double area = std::get<double>(v[2]);
    // DBF stores reals with 15 decimals.
    EXPECT_NEAR(f.GetFieldAsDouble(field_index(r, names[2])), area,
                shapefile ? 1e-15 + std::abs(area) * 1e-15 : std::abs(area) * 1e-15);
    for (int j : {3, 4}) {
      const int idx = field_index(r, names[j]);
      if (const auto* n = std::get_if<std::int64_t>(&v[j])) {
        if (shapefile && std::to_string(*n).size() > 18) {
          // The DBF holds every digit (width 20), but GDAL reads a field wider than 18 as Real.
          EXPECT_EQ(f.GetFieldAsDouble(idx), static_cast<double>(*n)) << names[j];
        } else {
          EXPECT_EQ(f.GetFieldAsInteger64(idx), *n) << names[j];
        }
      } else if (!shapefile && !csv) {
        EXPECT_FALSE(f.IsFieldSetAndNotNull(idx)) << names[j];
      } else {
        EXPECT_TRUE(f.IsFieldNull(idx) || std::string(f.GetFieldAsString(idx)).empty());
      }
    }

    // Geometry: a valid MultiPolygon with the same rings, exterior rings counter-clockwise
    // (clockwise in Shapefile, which rewinds them itself).
    const OGRGeometry* g = f.GetGeometryRef();
    ASSERT_NE(g, nullptr);
    if (!shapefile) {
      EXPECT_EQ(wkbFlatten(g->getGeometryType()), wkbMultiPolygon);
    }
    std::unique_ptr<OGRGeometry> multi(OGRGeometryFactory::forceToMultiPolygon(g->clone()));
    const OGRMultiPolygon* mp = multi->toMultiPolygon();
    EXPECT_TRUE(mp->IsValid());
    const MultiPolygon& wg = want[k].geometry;
    ASSERT_EQ(mp->getNumGeometries(), static_cast<int>(wg.size()));
    for (int p = 0; p < mp->getNumGeometries(); ++p) {
      const OGRPolygon* poly = mp->getGeometryRef(p);
      EXPECT_TRUE(poly->IsValid());
      ASSERT_EQ(poly->getNumInteriorRings(), static_cast<int>(wg[p].holes.size()));
      for (int ring = 0; ring <= poly->getNumInteriorRings(); ++ring) {
        const OGRLinearRing* lr = ring == 0 ? poly->getExteriorRing() : poly->getInteriorRing(ring - 1);
        std::vector<LonLat> expected = ring == 0 ? wg[p].exterior : wg[p].holes[ring - 1];
        const bool clockwise_expected = (ring == 0) == fc.clockwise_shells;
        EXPECT_EQ(static_cast<bool>(lr->isClockwise()), clockwise_expected) << "ring " << ring;
        if (shapefile) {
          // The driver reverses rings whose orientation it does not like; the start is kept.
          std::vector<LonLat> reversed(expected.rbegin(), expected.rend());
          const auto got = ring_points(*lr);
          EXPECT_TRUE(same_points(got, expected) || same_points(got, reversed)) << "ring " << ring;
        } else {
          EXPECT_TRUE(same_points(ring_points(*lr), expected)) << "ring " << ring;
        }
      }
    }
  }
  // Nothing but the output (and, for Shapefile, its sidecars) is left in the directory.
  for (const std::string& e : dir.entries()) {
    EXPECT_EQ(e.rfind("cells.", 0), 0u) << "left behind: " << e;
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, EveryFormat, ::testing::ValuesIn(kFormats), case_name);

class PointsAndLines : public ::testing::TestWithParam<FormatCase> {};

TEST_P(PointsAndLines, RoundTripThroughGdal) {
  const FormatCase& fc = GetParam();
  const bool shapefile = std::string(fc.driver) == "ESRI Shapefile";
  TempDir dir;
  const bool flatgeobuf = std::string(fc.driver) == "FlatGeobuf";
  const std::vector<Field> schema{{"id", FieldType::String}};
  // The feature whose "id" is `id` (FlatGeobuf reorders features along its spatial index).
  auto by_id = [](const ReadBack& r, const std::string& id) -> const OGRFeature* {
    const int idx = field_index(r, "id");
    for (const auto& f : r.features) {
      if (f->GetFieldAsString(idx) == id) return f.get();
    }
    return nullptr;
  };
  {
    const std::string path = dir / ("points." + fs::path(fc.file).extension().string().substr(1));
    auto w = open_feature_writer(path, GeometryType::Point, schema, {});
    for (std::size_t i = 0; i < points().size(); ++i) {
      w->write(points()[i], std::vector<FieldValue>{std::string("p") + std::to_string(i)});
    }
    w->finish();
    const ReadBack r = read_back(path, fc.driver);
    ASSERT_EQ(r.features.size(), points().size());
    if (fc.typed_fields) {
      EXPECT_EQ(r.layer_type, wkbPoint);
    }
    for (std::size_t i = 0; i < points().size(); ++i) {
      const std::string id = "p" + std::to_string(i);
      const OGRFeature* f = by_id(r, id);
      ASSERT_NE(f, nullptr) << id;
      if (!flatgeobuf) {
        EXPECT_EQ(f, r.features[i].get());
      }
      const OGRGeometry* g = f->GetGeometryRef();
      ASSERT_NE(g, nullptr);
      ASSERT_EQ(wkbFlatten(g->getGeometryType()), wkbPoint);
      EXPECT_TRUE(same_points({{g->toPoint()->getX(), g->toPoint()->getY()}}, {points()[i]}));
    }
  }
  {
    const std::string path = dir / ("lines." + fs::path(fc.file).extension().string().substr(1));
    auto w = open_feature_writer(path, GeometryType::MultiLineString, schema, {});
    w->write(lines(), std::vector<FieldValue>{std::string("edge")});
    w->write(MultiLineString{{{0, 0}, {1, 1}}}, std::vector<FieldValue>{std::monostate{}});
    w->finish();
    const ReadBack r = read_back(path, fc.driver);
    ASSERT_EQ(r.features.size(), 2u);
    if (fc.typed_fields) {
      EXPECT_EQ(r.layer_type, shapefile ? wkbLineString : wkbMultiLineString);
    }
    const OGRFeature* edge = by_id(r, "edge");
    ASSERT_NE(edge, nullptr);
    const OGRGeometry* g = edge->GetGeometryRef();
    ASSERT_NE(g, nullptr);
    ASSERT_EQ(wkbFlatten(g->getGeometryType()), wkbMultiLineString);
    const OGRMultiLineString* ml = g->toMultiLineString();
    ASSERT_EQ(ml->getNumGeometries(), 2);
    for (int i = 0; i < 2; ++i) {
      EXPECT_TRUE(same_points(ring_points(*ml->getGeometryRef(i)), lines()[i]));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, PointsAndLines, ::testing::ValuesIn(kFormats), case_name);

// ---------------------------------------------------------------------------------------------
// GeoJSON text

std::vector<std::vector<double>> bboxes_in(const std::string& text) {
  static const std::regex re(R"re("bbox":\s*\[([^\]]*)\])re");
  std::vector<std::vector<double>> out;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator();
       ++it) {
    std::vector<double> v;
    std::stringstream s((*it)[1].str());
    std::string item;
    while (std::getline(s, item, ',')) v.push_back(std::stod(item));
    out.push_back(v);
  }
  return out;
}

TEST(GeoJson, FeatureCollectionLayoutAndBoxes) {
  TempDir dir;
  const std::string path = dir / "cells.geojson";
  WriterOptions options;
  options.id_field = "site_id";
  options.layer = "voronoi \"cells\"";
  write_cells(path, options);
  const std::string text = slurp(path);
  EXPECT_EQ(text.rfind("{\"type\":\"FeatureCollection\",\"name\":\"voronoi \\\"cells\\\"\","
                       "\"features\":[\n",
                       0),
            0u)
      << text.substr(0, 100);
  EXPECT_FALSE(contains(text, "\"crs\""));
  EXPECT_FALSE(contains(text, "\"Polygon\""));  // always MultiPolygon
  EXPECT_TRUE(contains(text, "{\"type\":\"Feature\",\"id\":1,\"bbox\":[0.1234568,0,10,10],"));
  EXPECT_TRUE(contains(text, "[[[[0.1234568,0],[10,0],[10,10],[0.1234568,10],[0.1234568,0]],"
                             "[[2,2],[2,4],[4,4],[4,2],[2,2]]]]"));
  EXPECT_EQ(text.back(), '\n');
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 6);  // header, 4 features, trailer

  // Feature boxes per RFC 7946 §5.2/§5.3, then the collection's.
  const auto boxes = bboxes_in(text);
  const auto want = cells();
  ASSERT_EQ(boxes.size(), want.size() + 1);
  for (std::size_t k = 0; k < want.size(); ++k) {
    const BBox& b = want[k].bbox;
    const std::vector<double> wb{b.west, b.south, b.east, b.north};
    ASSERT_EQ(boxes[k].size(), 4u);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(boxes[k][i], wb[i], 5e-8) << k;
  }
  EXPECT_EQ(boxes.back(), (std::vector<double>{-180, -90, 180, 90}));
  EXPECT_TRUE(text.ends_with("}\n],\"bbox\":[-180,-90,180,90]}\n")) << text.substr(text.size() - 40);

  // GDAL's GeoJSON driver reads it, ids included.
  const ReadBack r = read_back(path, "GeoJSON");
  ASSERT_EQ(r.features.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(r.features[k]->GetFID(), static_cast<GIntBig>(k + 1));
  // The id field also stays a property.
  EXPECT_GE(field_index(r, "site_id"), 0);
}

// Our boxes against GDAL's own RFC 7946 writer (RFC7946=YES, WRITE_BBOX=YES).
TEST(GeoJson, BoxesAgreeWithGdalRfc7946Writer) {
  TempDir dir;
  const std::string ours = dir / "ours.geojson";
  const std::string theirs = dir / "theirs.geojson";
  std::vector<MultiPolygon> geoms;
  for (const Cell& c : cells()) geoms.push_back(c.geometry);
  // A cut cell whose parts have different extents.
  geoms.push_back({Polygon{box(175.5, -20, 180, -16), {}}, Polygon{box(-180, -18, -178, -17), {}}});
  {
    auto w = open_feature_writer(ours, GeometryType::MultiPolygon, {}, {});
    for (const auto& g : geoms) w->write(g, {});
    w->finish();
  }
  {
    GDALAllRegister();
    GDALDriver* drv = GetGDALDriverManager()->GetDriverByName("GeoJSON");
    GDALDatasetUniquePtr ds(drv->Create(theirs.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    ASSERT_TRUE(ds);
    OGRSpatialReference srs;
    srs.importFromEPSG(4326);
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    const char* lco[] = {"RFC7946=YES", "WRITE_BBOX=YES", "WRAPDATELINE=NO", nullptr};
    OGRLayer* layer = ds->CreateLayer("cells", &srs, wkbMultiPolygon, const_cast<char**>(lco));
    ASSERT_NE(layer, nullptr);
    for (const auto& g : geoms) {
      OGRMultiPolygon mp;
      for (const Polygon& p : g) {
        OGRPolygon poly;
        OGRLinearRing ring;
        for (const LonLat& q : p.exterior) ring.addPoint(q.lon_deg, q.lat_deg);
        poly.addRing(&ring);
        for (const Ring& h : p.holes) {
          OGRLinearRing hr;
          for (const LonLat& q : h) hr.addPoint(q.lon_deg, q.lat_deg);
          poly.addRing(&hr);
        }
        mp.addGeometry(&poly);
      }
      OGRFeatureUniquePtr f(OGRFeature::CreateFeature(layer->GetLayerDefn()));
      f->SetGeometry(&mp);
      ASSERT_EQ(layer->CreateFeature(f.get()), OGRERR_NONE);
    }
  }
  const auto a = bboxes_in(slurp(ours));
  const auto b = bboxes_in(slurp(theirs));
  ASSERT_EQ(a.size(), geoms.size() + 1);
  ASSERT_EQ(b.size(), a.size());
  // GDAL writes the collection bbox first, we write it last.
  for (std::size_t k = 0; k < geoms.size(); ++k) {
    ASSERT_EQ(a[k].size(), 4u);
    ASSERT_EQ(b[k + 1].size(), 4u);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(a[k][i], b[k + 1][i], 1e-7) << "feature " << k;
  }
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(a.back()[i], b.front()[i], 1e-7) << "collection";
}

TEST(GeoJson, Rfc8142RecordSeparatorsForGeojsons) {
  TempDir dir;
  const std::string path = dir / "cells.geojsons";
  write_cells(path);
  const std::string text = slurp(path);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.front(), '\x1e');
  EXPECT_EQ(text.back(), '\n');
  // Each record is RS, one JSON text without RS or LF inside, LF.
  std::vector<std::string> records;
  std::size_t pos = 0;
  while (pos < text.size()) {
    ASSERT_EQ(text[pos], '\x1e') << "at " << pos;
    const std::size_t lf = text.find('\n', pos);
    ASSERT_NE(lf, std::string::npos);
    records.push_back(text.substr(pos + 1, lf - pos - 1));
    pos = lf + 1;
  }
  ASSERT_EQ(records.size(), 4u);
  for (const std::string& r : records) {
    EXPECT_EQ(r.find('\x1e'), std::string::npos);
    EXPECT_EQ(r.rfind("{\"type\":\"Feature\",\"bbox\":[", 0), 0u) << r.substr(0, 40);
    EXPECT_EQ(r.back(), '}');
  }
  EXPECT_FALSE(contains(text, "FeatureCollection"));
  // Each record alone is a GeoJSON Feature that GDAL's GeoJSON driver reads.
  for (std::size_t k = 0; k < records.size(); ++k) {
    const std::string one = dir / ("one" + std::to_string(k) + ".geojson");
    spit(one, records[k]);
    const ReadBack r = read_back(one, "GeoJSON");
    ASSERT_EQ(r.features.size(), 1u);
    EXPECT_EQ(r.features[0]->GetFieldAsInteger64(0), static_cast<GIntBig>(k + 1));
  }
}

TEST(GeoJson, NewlineDelimitedForGeojsonlAndSeqFormat) {
  TempDir dir;
  for (const std::string name : {"cells.geojsonl", "cells.txt"}) {
    const std::string path = dir / name;
    WriterOptions options;
    options.format = "GeoJSONSeq";
    write_cells(path, options);
    const std::string text = slurp(path);
    EXPECT_EQ(text.find('\x1e'), std::string::npos);
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 4);
    std::istringstream in(text);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
      EXPECT_EQ(line.rfind("{\"type\":\"Feature\",", 0), 0u);
      ++n;
    }
    EXPECT_EQ(n, 4);
  }
}

// Features encoded on other threads and written in blocks give the bytes write() gives, in
// every framing, with a block that starts the file, an empty block and a one-feature block; a
// feature the encoder refuses names its number and leaves the block and the writer usable.
TEST(GeoJson, EncodedBlocksWriteTheSameBytesAsWrite) {
  TempDir dir;
  for (const std::string name : {"cells.geojson", "cells.geojsons", "cells.geojsonl"}) {
    const std::string plain = dir / ("plain_" + name), encoded = dir / ("encoded_" + name);
    WriterOptions options;
    options.id_field = "site_id";
    write_cells(plain, options);
    auto writer = open_feature_writer(encoded, GeometryType::MultiPolygon, cell_schema(), options);
    const FeatureEncoder* encoder = writer->encoder();
    ASSERT_NE(encoder, nullptr);
    const std::vector<Cell>& cs = cells();
    // Blocks {0, 1}, {}, {2}, {3}, each encoded on its own thread.
    const std::vector<std::pair<std::size_t, std::size_t>> blocks = {{0, 2}, {2, 2}, {2, 3}, {3, 4}};
    std::vector<EncodedFeatures> texts(blocks.size());
    std::vector<std::thread> threads;
    for (std::size_t b = 0; b < blocks.size(); ++b)
      threads.emplace_back([&, b] {
        for (std::size_t i = blocks[b].first; i < blocks[b].second; ++i)
          encoder->encode(cs[i].geometry, cs[i].values, i + 1, texts[b]);
      });
    for (std::thread& t : threads) t.join();
    // A bad feature (an unclosed ring) is refused by number, and nothing is appended.
    const std::size_t before = texts[2].text.size();
    const MultiPolygon open_ring{Polygon{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {}}};
    const Error e = error_of([&] { encoder->encode(open_ring, cs[0].values, 3, texts[2]); });
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_TRUE(contains(e.what(), "feature 3")) << e.what();
    EXPECT_EQ(texts[2].text.size(), before);
    EXPECT_EQ(texts[2].boxes.size(), 1u);
    for (const EncodedFeatures& t : texts) writer->write_encoded(t);
    writer->finish();
    EXPECT_EQ(slurp(encoded), slurp(plain)) << name;
  }
  // GDAL formats have no encoder and refuse encoded text.
  auto gpkg = open_feature_writer(dir / "cells.gpkg", GeometryType::MultiPolygon, cell_schema(), {});
  EXPECT_EQ(gpkg->encoder(), nullptr);
  EXPECT_EQ(error_of([&] { gpkg->write_encoded(EncodedFeatures{}); }).code(), ErrorCode::InvalidArgument);
}

// encode_json() with each value's text from append_json_value() gives encode()'s bytes in every
// framing, a null id field (text "null") leaves the feature without "id", and a wrong number of
// values is refused by feature number with nothing appended.
TEST(GeoJson, EncodeJsonWritesTheSameBytesAsEncode) {
  TempDir dir;
  for (const std::string name : {"cells.geojson", "cells.geojsons", "cells.geojsonl"}) {
    WriterOptions options;
    options.id_field = "name";  // null in cell 3
    auto writer = open_feature_writer(dir / name, GeometryType::MultiPolygon, cell_schema(), options);
    const FeatureEncoder* encoder = writer->encoder();
    ASSERT_NE(encoder, nullptr);
    EncodedFeatures by_values, by_texts;
    for (std::size_t i = 0; i < cells().size(); ++i) {
      const Cell& cell = cells()[i];
      encoder->encode(cell.geometry, cell.values, i + 1, by_values);
      std::vector<std::string> texts;
      for (const FieldValue& v : cell.values) {
        texts.emplace_back();
        append_json_value(texts.back(), v);
      }
      const std::vector<std::string_view> views(texts.begin(), texts.end());
      encoder->encode_json(cell.geometry, views, i + 1, by_texts);
    }
    EXPECT_EQ(by_texts.text, by_values.text) << name;
    EXPECT_EQ(by_texts.boxes.size(), cells().size());
    EXPECT_TRUE(contains(by_texts.text, "{\"type\":\"Feature\",\"id\":\"plain\","));
    EXPECT_TRUE(contains(by_texts.text, "{\"type\":\"Feature\",\"bbox\":[-180,-90,180,-74],"));
    const std::vector<std::string_view> too_few = {"1", "\"x\""};
    const std::size_t before = by_texts.text.size();
    const Error e = error_of([&] { encoder->encode_json(cells()[0].geometry, too_few, 7, by_texts); });
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_TRUE(contains(e.what(), "feature 7")) << e.what();
    EXPECT_EQ(by_texts.text.size(), before);
  }
}

TEST(GeoJson, AppendJsonValueWritesEachKindAsTheWriter) {
  auto text = [](const FieldValue& v) {
    std::string s = "<";
    append_json_value(s, v);
    return s;
  };
  EXPECT_EQ(text(std::monostate{}), "<null");
  EXPECT_EQ(text(std::int64_t{-9223372036854775807 - 1}), "<-9223372036854775808");
  EXPECT_EQ(text(2.0), "<2.0");
  EXPECT_EQ(text(1e-300), "<1e-300");
  EXPECT_EQ(text(std::numeric_limits<double>::quiet_NaN()), "<null");
  EXPECT_EQ(text(-std::numeric_limits<double>::infinity()), "<null");
  EXPECT_EQ(text(std::string("a\"b\n")), "<\"a\\\"b\\n\"");
}

// A file of several MB (the writer stages the temporary file in 4 MB aligned blocks for direct
// I/O, then writes the partial last block normally) holds exactly the encoded text, in the
// test's temporary directory and on tmpfs.
TEST(GeoJson, LargeFilesHoldExactlyTheEncodedText) {
  TempDir dir;
  std::vector<std::string> paths = {dir / "big.geojsonl"};
  std::unique_ptr<TempDir> shm;
  if (std::filesystem::is_directory("/dev/shm")) {
    shm = std::make_unique<TempDir>();
    paths.push_back(*shm / "big.geojsonl");
  }
  Ring ring;
  for (int k = 0; k < 1000; ++k) ring.push_back({-180 + 0.3 * k, std::sin(k * 0.01) * 10});
  ring.push_back({120, 50});
  ring.push_back(ring.front());
  const MultiPolygon geometry{Polygon{ring, {}}};
  for (const std::string& path : paths) {
    SCOPED_TRACE(path);
    auto writer = open_feature_writer(path, GeometryType::MultiPolygon, cell_schema(), {});
    EncodedFeatures expected;
    for (int i = 0; i < 400; ++i) {
      std::vector<FieldValue> values = cells()[i % 4].values;
      values[0] = std::int64_t{i};
      writer->encoder()->encode(geometry, values, static_cast<std::uint64_t>(i + 1), expected);
      if (i % 3 == 0) {
        writer->write(geometry, values);
      } else {
        EncodedFeatures one;
        writer->encoder()->encode(geometry, values, static_cast<std::uint64_t>(i + 1), one);
        writer->write_encoded(one);
      }
    }
    writer->finish();
    ASSERT_GT(expected.text.size(), std::size_t{5} << 20);  // more than one 4 MB stage
    const std::string text = slurp(path);
    EXPECT_EQ(text.size(), expected.text.size());
    EXPECT_TRUE(text == expected.text);
  }
}

TEST(GeoJson, StringsEscapedAndReadBackExactly) {
  TempDir dir;
  const std::string path = dir / "strings.geojson";
  auto w = open_feature_writer(path, GeometryType::Point, {{"s", FieldType::String}}, {});
  w->write(LonLat{1, 2}, std::vector<FieldValue>{kTricky});
  w->write(LonLat{1, 2}, std::vector<FieldValue>{std::string("bad \xff utf-8 \xC3")});
  w->finish();
  const std::string text = slurp(path);
  EXPECT_TRUE(contains(text, R"("quote \" backslash \\ newline \n tab \t cr \r ctrl \u0001\u001f del )" "\x7f"))
      << text;
  EXPECT_TRUE(contains(text, "\xE6\xBC\xA2\xE5\xAD\x97 \xF0\x9F\x98\x80"));  // UTF-8 as it is
  EXPECT_TRUE(contains(text, "bad \xEF\xBF\xBD utf-8 \xEF\xBF\xBD"));         // U+FFFD
  const ReadBack r = read_back(path, "GeoJSON");
  ASSERT_EQ(r.features.size(), 2u);
  EXPECT_EQ(std::string(r.features[0]->GetFieldAsString(0)), kTricky);
}

TEST(GeoJson, NumbersIntegersExactRealsRoundTripAndStayReal) {
  TempDir dir;
  const std::string path = dir / "numbers.geojson";
  const std::vector<Field> schema{{"i", FieldType::Integer64}, {"r", FieldType::Real}};
  const std::vector<double> reals = {2.0, 0.1, -1e-300, 1e300, 123456789.123456789, 5e-324,
                                     std::nextafter(1.0, 2.0)};
  auto w = open_feature_writer(path, GeometryType::Point, schema, {});
  for (double v : reals) {
    w->write(LonLat{0, 0}, std::vector<FieldValue>{std::int64_t{9007199254740993}, v});
  }
  w->write(LonLat{0, 0}, std::vector<FieldValue>{std::numeric_limits<std::int64_t>::min(),
                                                 std::numeric_limits<double>::quiet_NaN()});
  w->finish();
  const std::string text = slurp(path);
  EXPECT_TRUE(contains(text, "\"i\":9007199254740993,\"r\":2.0}"));
  EXPECT_TRUE(contains(text, "\"r\":0.1}"));
  EXPECT_TRUE(contains(text, "\"r\":1e+300}"));
  EXPECT_TRUE(contains(text, "\"i\":-9223372036854775808,\"r\":null}"));
  const ReadBack r = read_back(path, "GeoJSON");
  ASSERT_EQ(r.features.size(), reals.size() + 1);
  EXPECT_EQ(r.field_types[0], OFTInteger64);
  EXPECT_EQ(r.field_types[1], OFTReal);
  for (std::size_t k = 0; k < reals.size(); ++k) {
    EXPECT_EQ(r.features[k]->GetFieldAsInteger64(0), 9007199254740993);
    EXPECT_EQ(r.features[k]->GetFieldAsDouble(1), reals[k]) << k;  // bit-exact
  }
  EXPECT_TRUE(r.features.back()->IsFieldNull(1));
}

TEST(GeoJson, PrecisionOption) {
  TempDir dir;
  const std::string path = dir / "p.geojsonl";
  WriterOptions options;
  options.precision = 3;
  auto w = open_feature_writer(path, GeometryType::Point, {}, options);
  w->write(LonLat{1.23456, -0.0004}, {});
  w->finish();
  EXPECT_EQ(slurp(path),
            "{\"type\":\"Feature\",\"bbox\":[1.235,0,1.235,0],\"properties\":{},"
            "\"geometry\":{\"type\":\"Point\",\"coordinates\":[1.235,0]}}\n");
  options.precision = 18;
  EXPECT_EQ(error_of([&] { open_feature_writer(dir / "q.geojson", GeometryType::Point, {}, options); })
                .code(),
            ErrorCode::InvalidArgument);
}

TEST(GeoJson, StdoutForDash) {
  TempDir dir;
  const std::string capture = dir / "stdout.txt";
  std::fflush(stdout);
  const int saved = ::dup(STDOUT_FILENO);
  ASSERT_GE(saved, 0);
  FILE* f = std::fopen(capture.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  ::dup2(::fileno(f), STDOUT_FILENO);
  {
    WriterOptions options;
    options.format = "GeoJSONSeq";
    auto w = open_feature_writer("-", GeometryType::Point, {{"n", FieldType::Integer64}}, options);
    w->write(LonLat{10, 20}, std::vector<FieldValue>{std::int64_t{5}});
    w->finish();
  }
  std::fflush(stdout);
  ::dup2(saved, STDOUT_FILENO);
  ::close(saved);
  std::fclose(f);
  EXPECT_EQ(slurp(capture),
            "{\"type\":\"Feature\",\"bbox\":[10,20,10,20],\"properties\":{\"n\":5},"
            "\"geometry\":{\"type\":\"Point\",\"coordinates\":[10,20]}}\n");
  // Only GeoJSON goes to stdout.
  WriterOptions gpkg;
  gpkg.format = "GPKG";
  EXPECT_EQ(error_of([&] { open_feature_writer("-", GeometryType::Point, {}, gpkg); }).code(),
            ErrorCode::InvalidArgument);
}

// ---------------------------------------------------------------------------------------------
// Arguments

TEST(FeatureWriter, FormatFromExtension) {
  EXPECT_EQ(format_from_extension("a/b.geojson"), "GeoJSON");
  EXPECT_EQ(format_from_extension("b.GeoJSON"), "GeoJSON");
  EXPECT_EQ(format_from_extension("b.json"), "GeoJSON");
  EXPECT_EQ(format_from_extension("b.geojsons"), "GeoJSONSeq");
  EXPECT_EQ(format_from_extension("b.geojsonl"), "GeoJSONSeq");
  EXPECT_EQ(format_from_extension("b.gpkg"), "GPKG");
  EXPECT_EQ(format_from_extension("b.fgb"), "FlatGeobuf");
  EXPECT_EQ(format_from_extension("b.SHP"), "ESRI Shapefile");
  EXPECT_EQ(format_from_extension("b.csv"), "CSV");
  EXPECT_EQ(format_from_extension("b.xyz"), "");
  EXPECT_EQ(format_from_extension("b"), "");
}

// The one rule of what an output is, for every command, Python and the service.
TEST(FeatureWriter, OutputKind) {
  EXPECT_EQ(output_kind("-", ""), OutputKind::Native);
  EXPECT_EQ(output_kind("a/b.geojson", ""), OutputKind::Native);
  EXPECT_EQ(output_kind("b.JSON", ""), OutputKind::Native);
  EXPECT_EQ(output_kind("b.geojsonl", ""), OutputKind::Native);
  EXPECT_EQ(output_kind("b.gpkg", ""), OutputKind::Gdal);
  EXPECT_EQ(output_kind("b.csv", ""), OutputKind::Gdal);  // CSV points through GDAL
  EXPECT_EQ(output_kind("b.xyz", ""), OutputKind::Gdal);
  EXPECT_EQ(output_kind("b.gpkg", "GeoJSONSeq"), OutputKind::Native);
  EXPECT_EQ(output_kind("b.geojson", "FlatGeobuf"), OutputKind::Gdal);
  EXPECT_FALSE(output_needs_gdal("-", ""));
  EXPECT_FALSE(output_needs_gdal("b.gpkg", "GeoJSON"));
  EXPECT_TRUE(output_needs_gdal("b.gpkg", ""));
  EXPECT_TRUE(output_needs_gdal("b.csv", ""));
  // Where the caller has its own CSV text (the nearest join).
  EXPECT_EQ(output_kind("-", "", true), OutputKind::Text);
  EXPECT_EQ(output_kind("d/b.CSV", "", true), OutputKind::Text);
  EXPECT_EQ(output_kind("b.txt", "", true), OutputKind::Text);
  EXPECT_EQ(output_kind("/dev/null", "", true), OutputKind::Text);
  EXPECT_EQ(output_kind(".hidden", "", true), OutputKind::Text);
  EXPECT_EQ(output_kind("b.gpkg", "csv", true), OutputKind::Text);
  EXPECT_EQ(output_kind("b.csv", "GPKG", true), OutputKind::Gdal);
  EXPECT_EQ(output_kind("-", "GeoJSON", true), OutputKind::Native);
  EXPECT_EQ(output_kind("b.geojson", "", true), OutputKind::Native);
}

TEST(FeatureWriter, InvalidArguments) {
  TempDir dir;
  auto code = [](const std::function<void()>& f) { return error_of(f).code(); };
  const auto bad = ErrorCode::InvalidArgument;
  EXPECT_EQ(code([&] { open_feature_writer(dir / "a.nope", GeometryType::Point, {}, {}); }), bad);
  WriterOptions unknown;
  unknown.format = "NoSuchDriver";
  EXPECT_EQ(code([&] { open_feature_writer(dir / "a.x", GeometryType::Point, {}, unknown); }), bad);
  EXPECT_EQ(code([&] {
              open_feature_writer(dir / "a.geojson", GeometryType::Point,
                                  {{"a", FieldType::String}, {"A", FieldType::Integer64}}, {});
            }),
            bad);
  EXPECT_EQ(code([&] { open_feature_writer(dir / "a.gpkg", GeometryType::Point, {{"", FieldType::String}}, {}); }),
            bad);
  WriterOptions id;
  id.id_field = "nope";
  EXPECT_EQ(code([&] { open_feature_writer(dir / "a.geojson", GeometryType::Point, {}, id); }), bad);
  EXPECT_TRUE(dir.entries().empty());

  // A bad feature is refused before anything is written: the writer goes on.
  for (const std::string name : {"w.geojson", "w.gpkg"}) {
    auto w = open_feature_writer(dir / name, GeometryType::MultiPolygon, {{"n", FieldType::Integer64}}, {});
    const std::vector<FieldValue> one{std::int64_t{1}};
    MultiPolygon open_ring{{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {}}};
    EXPECT_EQ(code([&] { w->write(open_ring, one); }), bad);
    MultiPolygon out_of_range{{box(0, 0, 190, 1), {}}};
    EXPECT_EQ(code([&] { w->write(out_of_range, one); }), bad);
    MultiPolygon nan{{box(0, 0, std::nan(""), 1), {}}};
    EXPECT_EQ(code([&] { w->write(nan, one); }), bad);
    EXPECT_EQ(code([&] { w->write(LonLat{0, 0}, one); }), bad);                   // wrong type
    EXPECT_EQ(code([&] { w->write(cells()[0].geometry, std::vector<FieldValue>{}); }), bad);  // count
    w->write(cells()[0].geometry, one);
    w->finish();
    EXPECT_EQ(read_back(dir / name, nullptr).features.size(), 1u);
  }
}

TEST(FeatureWriter, FormatByGdalExtensionOrName) {
  TempDir dir;
  // .sqlite is not in our table: GDAL's extension metadata names the SQLite driver.
  write_cells(dir / "cells.sqlite");
  const ReadBack r = read_back(dir / "cells.sqlite", "SQLite");
  EXPECT_EQ(r.features.size(), 4u);
  // Any driver by name, e.g. GML.
  WriterOptions gml;
  gml.format = "GML";
  write_cells(dir / "cells.gml", gml);
  EXPECT_EQ(read_back(dir / "cells.gml", "GML").features.size(), 4u);
  // The GML driver writes an .xsd sidecar, moved into place with it.
  EXPECT_TRUE(fs::exists(dir / "cells.xsd"));
  for (const std::string& e : dir.entries()) EXPECT_NE(e.front(), '.') << e;
}

// ---------------------------------------------------------------------------------------------
// Safe output

TEST(SafeOutput, RefusesExistingOutputUnlessOverwrite) {
  for (const std::string name : {"out.geojson", "out.gpkg", "out.fgb", "out.shp", "out.csv"}) {
    SCOPED_TRACE(name);
    TempDir dir;
    const std::string path = dir / name;
    spit(path, "old");
    const Error e = error_of([&] { write_cells(path); });
    EXPECT_EQ(e.code(), ErrorCode::Io);
    EXPECT_TRUE(contains(e.what(), "exists; use --overwrite")) << e.what();
    EXPECT_EQ(slurp(path), "old");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{name});

    WriterOptions overwrite;
    overwrite.overwrite = true;
    auto w = open_feature_writer(path, GeometryType::MultiPolygon, cell_schema(), overwrite);
    for (const Cell& c : cells()) w->write(c.geometry, c.values);
    EXPECT_EQ(slurp(path), "old");  // replaced only by finish()
    w->finish();
    EXPECT_EQ(read_back(path, nullptr).features.size(), 4u);
    for (const std::string& entry : dir.entries()) EXPECT_NE(entry.front(), '.') << entry;
  }
}

TEST(SafeOutput, ShapefileSidecarsCountAsTheOutput) {
  TempDir dir;
  spit(dir / "cells.dbf", "old");
  const Error e = error_of([&] { write_cells(dir / "cells.shp"); });
  EXPECT_EQ(e.code(), ErrorCode::Io);
  EXPECT_TRUE(contains(e.what(), "cells.dbf: exists")) << e.what();
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"cells.dbf"});
  // Overwriting removes sidecars the new output does not have (a stale spatial index).
  spit(dir / "cells.qix", "stale");
  WriterOptions overwrite;
  overwrite.overwrite = true;
  write_cells(dir / "cells.shp", overwrite);
  EXPECT_EQ(dir.entries(),
            (std::vector<std::string>{"cells.cpg", "cells.dbf", "cells.prj", "cells.shp", "cells.shx"}));
}

TEST(SafeOutput, NothingLeftWhenNotFinished) {
  for (const std::string name :
       {"a.geojson", "a.geojsons", "a.gpkg", "a.fgb", "a.shp", "a.csv"}) {
    SCOPED_TRACE(name);
    TempDir dir;
    {
      auto w = open_feature_writer(dir / name, GeometryType::MultiPolygon, cell_schema(), {});
      for (const Cell& c : cells()) w->write(c.geometry, c.values);
      EXPECT_FALSE(dir.entries().empty());  // the temporary file or directory
    }
    EXPECT_TRUE(dir.entries().empty()) << dir.entries().front();
  }
}

// ---------------------------------------------------------------------------------------------
// ogr2ogr's output model: layers of one data source, update, overwrite of one layer

// The layers of a data source and their feature counts, as GDAL reads them back.
std::vector<std::pair<std::string, GIntBig>> layers_of(const std::string& path) {
  std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  std::vector<std::pair<std::string, GIntBig>> out;
  if (!ds) return out;
  for (int i = 0; i < ds->GetLayerCount(); ++i) out.emplace_back(ds->GetLayer(i)->GetName(), ds->GetLayer(i)->GetFeatureCount());
  return out;
}

WriterOptions layer_named(const std::string& name, bool update, bool overwrite) {
  WriterOptions o;
  o.layer = name;
  o.update = update;
  o.overwrite = overwrite;
  return o;
}

using Layers = std::vector<std::pair<std::string, GIntBig>>;

TEST(OutputModel, UpdateAddsALayerAndOverwriteReplacesOnlyItsLayer) {
  TempDir dir;
  const std::string path = dir / "two.gpkg";
  write_cells(path, layer_named("a", false, false));
  write_cells(path, layer_named("b", true, false));
  EXPECT_EQ(layers_of(path), (Layers{{"a", 4}, {"b", 4}}));
  // A layer of the same name needs overwrite; the file is left as it was.
  const std::string before = slurp(path);
  const Error e = error_of([&] { write_cells(path, layer_named("a", true, false)); });
  EXPECT_EQ(e.code(), ErrorCode::Io);
  EXPECT_TRUE(contains(e.what(), "has a layer 'a'; use --overwrite")) << e.what();
  EXPECT_EQ(slurp(path), before);
  // overwrite alone (ogr2ogr -overwrite) replaces layer a, with 1 feature now; b is kept.
  auto w = open_feature_writer(path, GeometryType::MultiPolygon, cell_schema(), layer_named("a", false, true));
  w->write(cells()[0].geometry, cells()[0].values);
  w->finish();
  EXPECT_EQ(layers_of(path), (Layers{{"b", 4}, {"a", 1}}));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"two.gpkg"});
}

TEST(OutputModel, UpdateRefusedForOneLayerFormats) {
  TempDir dir;
  for (const std::string name : {"a.geojson", "a.geojsonl", "a.fgb", "a.shp", "a.csv"}) {
    SCOPED_TRACE(name);
    const Error e = error_of([&] { write_cells(dir / name, layer_named("cells", true, false)); });
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_TRUE(contains(e.what(), "holds one")) << e.what();
    EXPECT_FALSE(format_holds_layers(dir / name, ""));
  }
  EXPECT_TRUE(dir.entries().empty());
  EXPECT_TRUE(format_holds_layers(dir / "a.gpkg", ""));
  EXPECT_TRUE(format_holds_layers(dir / "a.db", "SQLite"));
}

// GDAL 3.6's drivers: the metadata rule (no geometry; no fields of the writer's choosing) and the
// listed ones, checked without creating anything; the formats that hold the layers pass.
TEST(OutputModel, FormatsThatCannotHoldTheLayerAreRefusedUpFront) {
  TempDir dir;
  auto refusal = [&](const std::string& file, GeometryType type, const WriterOptions& options) -> std::string {
    try {
      check_writer_options(dir / file, type, options);
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << file;
      return e.what();
    }
    return "";
  };
  WriterOptions none;
  EXPECT_TRUE(contains(refusal("a.ods", GeometryType::Point, none), "stores no geometry"));
  EXPECT_TRUE(contains(refusal("a.dxf", GeometryType::MultiLineString, none), "format DXF holds no attribute fields"));
  EXPECT_TRUE(contains(refusal("a.dgn", GeometryType::Point, none), "format DGN holds no attribute fields"));
  EXPECT_TRUE(contains(refusal("a.gpx", GeometryType::MultiPolygon, none), "no polygons; write GeoPackage, FlatGeobuf or GeoJSON"));
  EXPECT_TRUE(contains(refusal("a.gpx", GeometryType::Point, none), "--dsco GPX_USE_EXTENSIONS=YES"));
  WriterOptions extensions;
  extensions.dataset_options = {"GPX_USE_EXTENSIONS=YES"};
  EXPECT_EQ(refusal("a.gpx", GeometryType::Point, extensions), "");
  EXPECT_EQ(refusal("a.gpx", GeometryType::MultiLineString, extensions), "");
  EXPECT_TRUE(contains(refusal("a.pix", GeometryType::MultiPolygon, none), "drops multi-part geometries"));
  EXPECT_EQ(refusal("a.pix", GeometryType::Point, none), "");
  WriterOptions mvt;
  mvt.format = "MVT";
  EXPECT_TRUE(contains(refusal("tiles", GeometryType::MultiPolygon, mvt), "vector tiles snap coordinates"));
  WriterOptions unknown;
  unknown.format = "NoSuchDriver";
  EXPECT_TRUE(contains(refusal("a.x", GeometryType::Point, unknown), "unknown output format 'NoSuchDriver'"));
  // A refused format names others; a format is never told to write itself.
  EXPECT_FALSE(contains(refusal("a.gpx", GeometryType::MultiPolygon, none), "GPX or"));
  for (const char* ok : {"a.gpkg", "a.fgb", "a.shp", "a.csv", "a.tab", "a.sqlite", "a.gml"})
    EXPECT_EQ(refusal(ok, GeometryType::MultiPolygon, none), "") << ok;
  EXPECT_TRUE(dir.entries().empty());
}

TEST(OutputModel, CreationOptionsAreNameValueAndGdalOnly) {
  TempDir dir;
  WriterOptions bad;
  bad.layer_options = {"GEOMETRY_NAME"};
  EXPECT_EQ(error_of([&] { write_cells(dir / "a.gpkg", bad); }).code(), ErrorCode::InvalidArgument);
  WriterOptions lco;
  lco.layer_options = {"GEOMETRY_NAME=shape"};
  EXPECT_EQ(error_of([&] { write_cells(dir / "a.geojson", lco); }).code(), ErrorCode::InvalidArgument);
  // The same checks, without opening anything (callers refuse them before long work).
  EXPECT_EQ(error_of([&] { check_writer_options(dir / "a.geojson", GeometryType::MultiPolygon, lco); }).code(), ErrorCode::InvalidArgument);
  EXPECT_EQ(error_of([&] { check_writer_options(dir / "a.gpkg", GeometryType::MultiPolygon, bad); }).code(), ErrorCode::InvalidArgument);
  EXPECT_EQ(error_of([&] { check_writer_options(dir / "a.geojsonl", GeometryType::MultiPolygon, layer_named("x", true, false)); }).code(),
            ErrorCode::InvalidArgument);
  check_writer_options(dir / "a.gpkg", GeometryType::MultiPolygon, lco);
  EXPECT_TRUE(dir.entries().empty());
  write_cells(dir / "a.gpkg", lco);
  std::unique_ptr<GDALDataset> ds(GDALDataset::Open((dir / "a.gpkg").c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  ASSERT_TRUE(ds);
  EXPECT_STREQ(ds->GetLayer(0)->GetGeometryColumn(), "shape");
}

// An update abandoned (an error, a crash of the caller) or overtaken by another program leaves
// the data source as it is: the layer was written into a copy.
TEST(OutputModel, UpdateNeverLeavesAHalfUpdatedDataSource) {
  TempDir dir;
  const std::string path = dir / "d.gpkg";
  write_cells(path, layer_named("keep", false, false));
  const std::string before = slurp(path);
  {
    auto w = open_feature_writer(path, GeometryType::MultiPolygon, cell_schema(), layer_named("keep", true, true));
    for (const Cell& c : cells()) w->write(c.geometry, c.values);
  }  // not finished
  EXPECT_EQ(slurp(path), before);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"d.gpkg"});
  {
    auto w = open_feature_writer(path, GeometryType::MultiPolygon, cell_schema(), layer_named("new", true, false));
    for (const Cell& c : cells()) w->write(c.geometry, c.values);
    spit(path, "changed by another program");
    const Error e = error_of([&] { w->finish(); });
    EXPECT_EQ(e.code(), ErrorCode::Io);
    EXPECT_TRUE(contains(e.what(), "changed while geovor was updating it")) << e.what();
  }
  EXPECT_EQ(slurp(path), "changed by another program");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"d.gpkg"});
}

TEST(OutputModel, NextLayerWritesSeveralLayersIntoOneDataSource) {
  TempDir dir;
  const std::string path = dir / "both.gpkg";
  auto w = open_feature_writer(path, GeometryType::MultiPolygon, cell_schema(), layer_named("polygons", false, false));
  for (const Cell& c : cells()) w->write(c.geometry, c.values);
  const std::vector<Field> point_schema = {{"n", FieldType::Integer}};
  EXPECT_EQ(error_of([&] { w->next_layer("POLYGONS", GeometryType::Point, point_schema); }).code(),
            ErrorCode::InvalidArgument);  // one name per layer, case-insensitively
  w->next_layer("points", GeometryType::Point, point_schema);
  const std::vector<FieldValue> one = {std::int64_t{1}};
  w->write(LonLat{1, 2}, one);
  EXPECT_FALSE(fs::exists(path));  // both layers appear at once
  w->finish();
  EXPECT_EQ(layers_of(path), (Layers{{"polygons", 4}, {"points", 1}}));
  // One-layer formats refuse a second layer.
  for (const std::string name : {"one.fgb", "one.geojson"}) {
    auto single = open_feature_writer(dir / name, GeometryType::MultiPolygon, cell_schema(), {});
    EXPECT_EQ(error_of([&] { single->next_layer("points", GeometryType::Point, point_schema); }).code(),
              ErrorCode::InvalidArgument);
  }
}

// A file that appears at the target while the writer runs is never replaced without overwrite
// (the commit is renameat2(RENAME_NOREPLACE), not a plain rename); with overwrite it is.
TEST(SafeOutput, FileAppearingMeanwhileIsNotReplaced) {
  for (const std::string name : {"a.geojson", "a.geojsons", "a.gpkg", "a.fgb", "a.csv"}) {
    SCOPED_TRACE(name);
    TempDir dir;
    {
      auto w = open_feature_writer(dir / name, GeometryType::MultiPolygon, cell_schema(), {});
      for (const Cell& c : cells()) w->write(c.geometry, c.values);
      spit(dir / name, "precious");
      const Error e = error_of([&] { w->finish(); });
      EXPECT_EQ(e.code(), ErrorCode::Io) << e.what();
      EXPECT_TRUE(contains(e.what(), "exists; use --overwrite")) << e.what();
    }
    EXPECT_EQ(slurp(dir / name), "precious");
    EXPECT_EQ(dir.entries(), std::vector<std::string>{name});  // no temporary left
    WriterOptions overwrite;
    overwrite.overwrite = true;
    auto w = open_feature_writer(dir / name, GeometryType::MultiPolygon, cell_schema(), overwrite);
    for (const Cell& c : cells()) w->write(c.geometry, c.values);
    spit(dir / name, "replaced");
    w->finish();
    EXPECT_NE(slurp(dir / name), "replaced");
  }
}

// Temporaries have short names in the target's folder: a 250-byte file name can be written.
TEST(SafeOutput, LongFileNames) {
  for (const std::string ext : {".geojson", ".fgb"}) {
    SCOPED_TRACE(ext);
    TempDir dir;
    const std::string name = std::string(250 - ext.size(), 'n') + ext;
    auto w = open_feature_writer(dir / name, GeometryType::MultiPolygon, cell_schema(), {});
    for (const Cell& c : cells()) w->write(c.geometry, c.values);
    for (const std::string& entry : dir.entries()) EXPECT_LE(entry.size(), 30u) << entry;  // the temporary
    w->finish();
    EXPECT_EQ(dir.entries(), std::vector<std::string>{name});
  }
}

// SIGTERM, SIGINT and SIGHUP (install_output_cleanup) remove the temporaries of the writers
// being written (a GeoJSON file, a GDAL driver's directory) and end the process by the signal.
TEST(SafeOutput, SignalsRemoveTemporaries) {
  for (const int sig : {SIGTERM, SIGINT, SIGHUP}) {
    SCOPED_TRACE(sig);
    TempDir dir;
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      install_output_cleanup();
      auto a = open_feature_writer(dir / "a.geojson", GeometryType::MultiPolygon, cell_schema(), {});
      auto b = open_feature_writer(dir / "b.gpkg", GeometryType::MultiPolygon, cell_schema(), {});
      for (const Cell& c : cells()) a->write(c.geometry, c.values), b->write(c.geometry, c.values);
      if (dir.entries().size() != 2) ::_exit(3);  // the two temporaries
      ::raise(sig);
      ::_exit(4);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
    EXPECT_TRUE(dir.entries().empty()) << dir.entries().front();
  }
}

TEST(SafeOutput, MissingDirectoryIsAnIoError) {
  TempDir dir;
  for (const std::string name : {"no/such/dir/a.geojson", "no/such/dir/a.gpkg"}) {
    const Error e = error_of([&] { write_cells(dir / name); });
    EXPECT_EQ(e.code(), ErrorCode::Io) << e.what();
    EXPECT_TRUE(contains(e.what(), dir / name)) << e.what();
  }
  EXPECT_TRUE(dir.entries().empty());
  // A directory is never replaced.
  fs::create_directory(dir / "d.geojson");
  WriterOptions overwrite;
  overwrite.overwrite = true;
  EXPECT_EQ(error_of([&] { write_cells(dir / "d.geojson", overwrite); }).code(), ErrorCode::Io);
}

// A 64 KiB tmpfs: every format fails cleanly (Error(Io)) and leaves nothing behind.
TEST(SafeOutput, FullFileSystem) {
  TempDir dir;
  const std::string mnt = dir / "tiny";
  fs::create_directory(mnt);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=64k") != 0) {
    GTEST_SKIP() << "cannot mount a tmpfs here (" << std::strerror(errno) << "); needs root";
  }
  struct Unmount {
    std::string at;
    ~Unmount() { ::umount2(at.c_str(), MNT_DETACH); }
  } unmount{mnt};
  for (const std::string name : {"a.geojson", "a.geojsons", "a.gpkg", "a.fgb", "a.shp", "a.csv"}) {
    SCOPED_TRACE(name);
    const Error e = error_of([&] {
      auto w = open_feature_writer(mnt + "/" + name, GeometryType::MultiPolygon, cell_schema(), {});
      // About 2 MB of features, far beyond 64 KiB.
      for (int i = 0; i < 5000; ++i) {
        const Cell& c = cells()[static_cast<std::size_t>(i % 4)];
        w->write(c.geometry, c.values);
      }
      w->finish();
    });
    EXPECT_EQ(e.code(), ErrorCode::Io) << e.what();
    EXPECT_TRUE(contains(e.what(), name)) << e.what();
    std::vector<std::string> left;
    for (const auto& entry : fs::directory_iterator(mnt)) left.push_back(entry.path().filename());
    EXPECT_TRUE(left.empty()) << left.front();
  }
}

}  // namespace
}  // namespace geovor

namespace geovor {
namespace {

// Each type in the driver's own type, the nearest it has otherwise (MapInfo: no Integer64).
TEST(GdalFieldTypes, OwnTypesOrTheNearest) {
  TempDir dir;
  const std::vector<Field> schema{{"i", FieldType::Integer},  {"l", FieldType::Integer64}, {"r", FieldType::Real},
                                  {"d", FieldType::Date},     {"t", FieldType::DateTime},  {"s", FieldType::String},
                                  {"j", FieldType::String, true}};
  const std::vector<FieldValue> values{std::int64_t{-7}, std::int64_t{5000000000}, 2.5, std::string("2024-02-29"),
                                       std::string("2024-02-29T13:05:00Z"), std::string("x"), std::string("[\"a\"]")};
  for (const char* name : {"t.gpkg", "t.tab"}) {
    auto w = open_feature_writer(dir / name, GeometryType::Point, schema, {});
    w->write(LonLat{1, 2}, values);
    w->finish();
  }
  const ReadBack g = read_back(dir / "t.gpkg", "GPKG");
  EXPECT_EQ(g.field_types, (std::vector<OGRFieldType>{OFTInteger, OFTInteger64, OFTReal, OFTDate, OFTDateTime,
                                                      OFTString, OFTString}));
  ASSERT_EQ(g.features.size(), 1u);
  EXPECT_EQ(g.features[0]->GetFieldAsInteger64(1), 5000000000);
  EXPECT_EQ(std::string(g.features[0]->GetFieldAsString(3)), "2024/02/29");
  EXPECT_EQ(g.features[0]->GetFieldDefnRef(6)->GetSubType(), OFSTJSON);
  const ReadBack m = read_back(dir / "t.tab", "MapInfo File");
  EXPECT_EQ(m.field_types[1], OFTReal);  // no Integer64 in MapInfo
  ASSERT_EQ(m.features.size(), 1u);
  EXPECT_EQ(m.features[0]->GetFieldAsDouble(1), 5e9);
}

// An integer a Real would round is refused, not rounded; a long text for a Shapefile too.
TEST(GdalFieldTypes, ValuesTheFormatCannotHoldAreRefused) {
  TempDir dir;
  auto tab = open_feature_writer(dir / "big.tab", GeometryType::Point, {{"l", FieldType::Integer64}}, {});
  const Error e = error_of([&] { tab->write(LonLat{1, 2}, std::vector<FieldValue>{(std::int64_t{1} << 53) + 1}); });
  EXPECT_EQ(e.code(), ErrorCode::BadData);
  EXPECT_NE(std::string(e.what()).find("9007199254740993 needs an Integer64 field"), std::string::npos) << e.what();
  auto shp = open_feature_writer(dir / "long.shp", GeometryType::Point, {{"s", FieldType::String}}, {});
  shp->write(LonLat{1, 2}, std::vector<FieldValue>{std::string(254, 'x')});  // fits
  const Error cut = error_of([&] { shp->write(LonLat{1, 2}, std::vector<FieldValue>{std::string(255, 'x')}); });
  EXPECT_EQ(cut.code(), ErrorCode::BadData);
  EXPECT_NE(std::string(cut.what()).find("feature 2, field 's': 255 bytes, but a field of format ESRI Shapefile holds at most 254"),
            std::string::npos)
      << cut.what();
  shp.reset();
  EXPECT_FALSE(std::filesystem::exists(dir / "long.shp"));
  EXPECT_FALSE(std::filesystem::exists(dir / "long.dbf"));
}

// A JSON field is its JSON value in GeoJSON, not a string.
TEST(GdalFieldTypes, GeoJsonWritesJsonFieldsAsValues) {
  TempDir dir;
  auto w = open_feature_writer(dir / "j.geojson", GeometryType::Point,
                               {{"j", FieldType::String, true}, {"s", FieldType::String}}, {});
  w->write(LonLat{1, 2}, std::vector<FieldValue>{std::string("[\"a\",\"b\"]"), std::string("[1]")});
  w->finish();
  EXPECT_TRUE(contains(slurp(dir / "j.geojson"), R"("properties":{"j":["a","b"],"s":"[1]"})"));
  const ReadBack r = read_back(dir / "j.geojson", "GeoJSON");
  EXPECT_EQ(r.field_types[0], OFTStringList);
}

}  // namespace
}  // namespace geovor
