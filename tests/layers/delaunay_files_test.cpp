// The Delaunay layers written to files: one set of options for both outputs, the checks before any
// work, the precision of the text outputs, and what could not be written on the log.
#include "geovor/layers/delaunay_files.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/io/ogr_site_reader.hpp"
#include "geovor/layers/site_input.hpp"
#include "support/file_text.hpp"
#include "support/memory_stream.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

using testing::contains;
using testing::error_of;
using testing::MemoryStream;

WriterOptions gdal_options() {
  WriterOptions o;
  o.layer = "tin";
  o.update = true;
  o.layer_options = {"SPATIAL_INDEX=NO"};
  o.dataset_options = {"VERSION=1.2"};
  return o;
}

TEST(DelaunayFiles, TheEdgesTakeTheOptionsTheirFormatCanTake) {
  DelaunayOutput out = delaunay_output("t.gpkg", "e.geojson", gdal_options(), "", "edges");
  EXPECT_EQ(out.triangles.layer, "tin");
  EXPECT_EQ(out.triangles.layer_options.size(), 1u);
  EXPECT_TRUE(out.triangles.update);
  EXPECT_EQ(out.edges.layer, "edges");
  EXPECT_TRUE(out.edges.layer_options.empty());  // GeoJSON: written natively
  EXPECT_TRUE(out.edges.dataset_options.empty());
  EXPECT_FALSE(out.edges.update);  // one layer per file
  out = delaunay_output("t.gpkg", "e.sqlite", gdal_options(), "", "edges");
  EXPECT_EQ(out.edges.layer_options.size(), 1u);
  EXPECT_TRUE(out.edges.update);
  out = delaunay_output("t.gpkg", "e.fgb", gdal_options(), "", "edges");
  EXPECT_EQ(out.edges.layer_options.size(), 1u);  // GDAL writes it
  EXPECT_FALSE(out.edges.update);
  out = delaunay_output("t.gpkg", "t.gpkg", gdal_options(), "", "e");  // one data source: all of them
  EXPECT_TRUE(one_data_source(out));
  EXPECT_TRUE(out.edges.update);
  EXPECT_EQ(out.edges.dataset_options.size(), 1u);
  out = delaunay_output("", "e.geojsons", WriterOptions{}, "GeoJSONSeq", "e");
  EXPECT_EQ(out.edges.format, "GeoJSONSeq");
}

TEST(DelaunayFiles, OutputsAreCheckedBeforeAnyWork) {
  testing::TempDir dir("geovor_delaunay_files");
  const std::string one = dir / "a.geojson";
  Error e = error_of([&] { check_delaunay_output(delaunay_output(one, one, {}, "", "edges")); });
  EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
  EXPECT_TRUE(contains(e.what(), "triangles_path " + one + " and edges_path " + one)) << e.what();
  e = error_of([&] { check_delaunay_output(delaunay_output(one, one, {}, "", "edges"), "--output", "--edges"); });
  EXPECT_TRUE(contains(e.what(), "--output " + one + " and --edges " + one)) << e.what();
  check_delaunay_output(delaunay_output(dir / "t.gpkg", dir / "t.gpkg", {}, "", "edges"));  // two layers of one
  WriterOptions lco;
  lco.layer_options = {"A=B"};
  EXPECT_EQ(error_of([&] { check_delaunay_output(delaunay_output(one, "", lco, "", "edges")); }).code(),
            ErrorCode::InvalidArgument);  // GeoJSON takes no creation option
}

TEST(DelaunayFiles, WritesAtTheTextPrecisionAndListsWhatCouldNotBeWritten) {
  SiteTable table = read_sites(std::string(GEOVOR_SOURCE_DIR) + "/datasets/fixtures/thin_triangles.csv");
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(site_points(table), {}, &report);
  testing::TempDir dir("geovor_delaunay_files");
  WriterOptions options;
  options.precision = 1;
  MemoryStream log;
  DelaunayFilesOptions files;
  files.log = log.get();
  const DelaunayLayersReport written =
      write_delaunay_files(delaunay_output(dir / "t.geojson", dir / "e.geojson", options, "", "edges"), table, report, dt, files);
  ASSERT_FALSE(written.triangles.unwritten.empty());
  const std::string text = log.text();
  EXPECT_TRUE(contains(text, std::to_string(written.triangles.unwritten.size()) +
                                 " triangle(s) written with an empty geometry: at precision 1 they collapse or would "
                                 "not be valid polygons (raise precision):\n  triangle "))
      << text;
  EXPECT_EQ(written.triangles.triangles_written, dt.num_triangles());
  EXPECT_GT(written.edges.edges_written, 0u);
  // Binary outputs alone store doubles: nothing collapses.
  MemoryStream quiet;
  files.log = quiet.get();
  const DelaunayLayersReport binary =
      write_delaunay_files(delaunay_output(dir / "t.gpkg", "", options, "", "edges"), table, report, dt, files);
  EXPECT_TRUE(binary.triangles.unwritten.empty());
  EXPECT_EQ(quiet.text(), "");
}

TEST(DelaunayFiles, TheLayersOfAJobsSites) {
  testing::TempDir dir("geovor_delaunay_files");
  MemoryStream log;
  SiteInput input;
  input.input = std::string(GEOVOR_SOURCE_DIR) + "/datasets/fixtures/weighted_hidden.csv";
  input.weight_field = "radius_m";
  input.log = log.get();
  DelaunayFilesOptions files;
  files.log = log.get();
  const DelaunayOutput output = delaunay_output(dir / "t.geojson", dir / "e.geojson", {}, "", "edges");
  const DelaunayLayersReport written = delaunay_to_files(input, output, files);
  EXPECT_EQ(written.triangles.triangles_written, 8u);  // 6 live sites: G is hidden
  const std::string text = log.text();
  EXPECT_TRUE(contains(text, "row 7 (id 'G', radius 0 m) is hidden")) << text;
  EXPECT_TRUE(contains(text, input.input + ": rows 7, sites 6, merged 0, rejected 0; triangles 8 (ghost 0), 8 written to " +
                                 dir / "t.geojson" + "; edges " + std::to_string(written.edges.edges_written) +
                                 " written to " + dir / "e.geojson" + "\n"))
      << text;
  MemoryStream quiet;
  input.log = files.log = quiet.get();
  files.quiet = true;
  delaunay_to_files(input, delaunay_output(dir / "t2.geojson", "", {}, "", "edges"), files);
  EXPECT_EQ(quiet.text(), input.input + ": row 7 (id 'G', radius 0 m) is hidden: its power cell is empty (row 1, id "
                                        "'A', radius 600000 m, holds its position)\n");
}

}  // namespace
}  // namespace geovor
