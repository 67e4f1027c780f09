#include "geovor/layers/clipped_cells_file.hpp"

#include "geovor/core/error.hpp"
#include "geovor/core/output_file.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "geovor/geo/site_weights.hpp"
#include "geovor/io/ogr_region_reader.hpp"
#include "geovor/layers/clipped_cell_layer.hpp"
#include "geovor/layers/region_clip.hpp"
#include "geovor/lonlat/cell_geometry.hpp"

namespace geovor {
namespace {

// The regions' rejected features, problems and the sites outside every region, on the log.
void say_problems(std::FILE* log, const RegionTable& regions, const RegionClipReport& report, const SiteTable& table,
                  const SiteRows& rows) {
  if (log == nullptr) return;
  for (const RejectedRow& r : regions.rejected)
    std::fprintf(log, "%s: %s (left out)\n", regions.source.c_str(), r.reason.c_str());
  for (const RegionProblem& p : report.problems) {
    const Region& region = regions.regions[p.region];
    std::fprintf(log, "%s: region %s (feature %llu): %s\n", regions.source.c_str(), region.id.c_str(),
                 static_cast<unsigned long long>(region.row), p.reason.c_str());
  }
  if (report.sites_outside.empty()) return;
  std::string listed;
  for (std::size_t i = 0; i < report.sites_outside.size() && i < 20; ++i) {
    const std::uint32_t row = rows.first(report.sites_outside[i]);
    listed += (i ? ", " : "") + (row == kNoIndex ? std::to_string(report.sites_outside[i]) : table.sites[row].id);
  }
  std::fprintf(log, "%zu sites' cells meet no region (not in the output): %s%s\n", report.sites_outside.size(),
               listed.c_str(), report.sites_outside.size() > 20 ? ", ..." : "");
}

}  // namespace

ClippedCellsReport clip_cells_to_file(const SiteInput& input, const std::string& output, const ClippedCellsOptions& options) {
  const SiteTable table = read_site_input(input);
  RegionTable regions = read_regions_ogr(options.regions_path, options.regions_layer, options.region_id_field);
  if (regions.regions.empty())
    throw Error(ErrorCode::BadData, options.regions_path + ": no feature is a polygon (" +
                                        std::to_string(regions.rejected.size()) + " features left out)");
  BuildReport build;
  const std::vector<double> lifts = table.weighted ? site_lifts(table) : std::vector<double>();
  const SphericalDelaunay dt = build_sites(site_points(table), lifts, input, build);
  list_build(input, table, build);
  const SiteRows rows = rows_of_sites(build, dt.site_capacity());
  const VoronoiDiagram diagram(dt, options.threads);
  // Cut and measured as written: GeoJSON text at its precision, binary formats and CSV as doubles.
  const bool text = !options.no_geometry && output_kind(output, options.writer.format, false) == OutputKind::Native;
  CellGeometryOptions geometry;
  geometry.densify_m = options.densify_m;
  geometry.threads = options.threads;
  geometry.precision = text ? options.writer.precision : kFullPrecision;
  const CellGeometry cells(diagram, geometry);
  RegionClipReport clip;
  const std::vector<ClipPiece> pieces = clip_cells_to_regions(diagram, cells, regions, {.threads = options.threads}, clip);
  say_problems(options.log, regions, clip, table, rows);

  if (options.no_geometry) {
    OutputFile out(output, options.writer.overwrite);
    write_clip_weights_csv([&](std::string_view s) { out.write(s.data(), s.size()); }, table, rows, regions, pieces);
    out.commit();
  } else {
    std::unique_ptr<FeatureWriter> writer =
        open_feature_writer(output, GeometryType::MultiPolygon, clipped_cell_layer_schema(table, regions), options.writer);
    write_clipped_cells(*writer, table, rows, regions, pieces);
    writer->finish();
  }
  ClippedCellsReport report{dt.num_sites(), regions.regions.size(), pieces.size(), regions.rejected.size(),
                            clip.problems.size(), clip.sites_outside.size()};
  if (!options.quiet && options.log != nullptr)
    std::fprintf(options.log, "%s: sites %zu, regions %zu: %zu pieces written to %s\n", table.source.c_str(), report.sites,
                 report.regions, report.pieces, output.c_str());
  return report;
}

}  // namespace geovor
