// geovor cells INPUT -o OUTPUT: the Voronoi cell of every site, as GIS polygons with the site's
// attributes, its areas and its neighbours.
#include <memory>
#include <string>

#include "cell_output.hpp"
#include "commands.hpp"
#include "geovor/core/output_target.hpp"
#include "geovor/core/error.hpp"
#include "geovor/layers/clipped_cells_file.hpp"
#include "geovor/layers/site_cells.hpp"
#include "numeric_options.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct CellsArgs {
  SiteInputArgs sites;
  CellOutputArgs out;
  std::string report;
  ClippedCellsOptions clip;  // --clip, --clip-layer, --region-id-field, --no-geometry
};

// geovor cells --clip: the pieces of the cells in each region (layers/clipped_cells_file.hpp).
int run_clipped(CellsArgs& args) {
  if (!args.report.empty()) throw Error(ErrorCode::InvalidArgument, "--report lists the rows of the cells; not with --clip");
  args.sites.quiet = args.out.quiet;
  args.clip.writer = cell_writer_options(args.out);
  args.clip.densify_m = args.out.densify_m;
  args.clip.threads = static_cast<unsigned>(args.out.threads);
  args.clip.quiet = args.out.quiet;
  clip_cells_to_file(args.sites, args.out.output, args.clip);
  return kOk;
}

int run(CellsArgs& args) {
  args.sites.reader.threads = static_cast<unsigned>(args.out.threads);
  if (!args.clip.regions_path.empty()) return run_clipped(args);
  if (args.clip.no_geometry) throw Error(ErrorCode::InvalidArgument, "--no-geometry is the weights table of --clip; give --clip REGIONS");
  // Two outputs that are one file (a path, an alias, a link; `-` twice): refused before any work.
  check_distinct_outputs({{"--output", args.out.output}, {"--report", args.report}});
  check_writer_options(args.out.output, GeometryType::MultiPolygon, cell_writer_options(args.out));  // --update or --lco with GeoJSON: before any work
  args.sites.quiet = args.out.quiet;  // merged rows stay in the cells' ids and the report
  SiteCellsOptions options;
  options.file = cell_file_options(args.out);
  options.report_path = args.report;
  options.threads = static_cast<unsigned>(args.out.threads);  // 0: one per core
  const SiteCells cells(args.sites, args.out.output, options);
  return finish_command(kOk);  // every output is complete: no need to free the data
}

}  // namespace

Command add_cells_command(CLI::App& app) {
  auto args = std::make_shared<CellsArgs>();
  CLI::App* cmd = app.add_subcommand("cells", "Write the Voronoi cell of every site as GIS polygons");
  add_site_input_options(cmd, args->sites);
  cmd->add_option("-o,--output", args->out.output,
                  "Output file (- for GeoJSON on stdout); the format follows the extension: .geojson, "
                  ".geojsons/.geojsonl, .gpkg, .fgb, .shp, .csv")
      ->required();
  add_output_model_options(cmd, args->out.format, args->out.overwrite, args->out.model, "cells");
  cmd->add_option("--densify-m", args->out.densify_m, "Largest distance in metres between a written edge and the true great-circle arc (default 100)")
      ->check(finite_above(0, false));
  cmd->add_option("--precision", args->out.precision, "Decimals of coordinates in GeoJSON (default 7, about 1 cm; binary formats store doubles): the cells are computed, checked valid and measured (area_m2) as written; a cell that collapses or cannot be written valid at this precision gets an empty geometry and is reported")
      ->check(integer_in(1, 17));
  cmd->add_option("--report", args->report, "CSV file listing every input row: site, merged (with its site), hidden (a weighted site whose power cell is empty, with a site that holds its position) or rejected (with the reason)");
  cmd->add_option("--clip", args->clip.regions_path, "Cut the cells by the regions of this polygon layer (any OGR format and CRS): one feature per (site, region) piece with region_share, its Thiessen weight");
  cmd->add_option("--clip-layer", args->clip.regions_layer, "The layer of a multi-layer --clip source");
  cmd->add_option("--region-id-field", args->clip.region_id_field, "The --clip field holding each region's id (default: its feature number)");
  cmd->add_flag("--no-geometry", args->clip.no_geometry, "With --clip: the weights table alone, as CSV (region_index, region_id, site_index, site_id, region_share, area_m2)");
  cmd->add_flag("-q,--quiet", args->out.quiet, "No progress, no summary and no list of merged rows on stderr (they stay in the cells' ids and --report); rejected rows and cells written with an empty geometry are still listed");
  add_threads_option(cmd, args->out.threads);
  cmd->footer(
      "Each cell carries: site_index, site_id (also the feature id; site_index is when ids repeat), ids (JSON array of the ids of every\n"
      "row merged into the site), n_rows, area_m2 (WGS84 ellipsoid, of the ring as written), area_sr\n"
      "(sphere, of the exact cell), n_vertices,\n"
      "neighbors (JSON array of the neighbours' ids), then every input column with its type (CSV columns\n"
      "typed by their values unless --all-text, or as --field-type NAME=TYPE declares; fid, geom, ... and our own\n"
      "names become src_NAME).\n"
      "A value a format cannot hold whole (Shapefile: 254 bytes) is refused (exit 3), never cut.\n"
      "Examples:\n"
      "  geovor cells datasets/weather_stations.csv -o cells.geojson\n"
      "  geovor cells stations.gpkg -o cells.fgb --densify-m 10 --report rows.csv\n"
      "  geovor cells stations.gpkg -o stations.gpkg --update --nln voronoi   (a layer beside the stations)\n"
      "  geovor cells stations.csv --clip basins.gpkg --region-id-field name -o pieces.gpkg   (Thiessen pieces)\n"
      "  geovor cells stations.csv --clip basins.gpkg --no-geometry -o weights.csv");
  return {[args] { return run(*args); },
          [args] {
            return !args->clip.regions_path.empty() || site_input_needs_gdal(args->sites) ||
                   output_needs_gdal(args->out.output, args->out.format);
          }};
}

}  // namespace geovor::tools
