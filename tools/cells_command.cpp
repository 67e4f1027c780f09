// geovor cells INPUT -o OUTPUT: the Voronoi cell of every site, as GIS polygons with the site's
// attributes, its areas and its neighbours.
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cell_output.hpp"
#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/output_file.hpp"
#include "geovor/core/output_target.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/layers/row_report.hpp"
#include "numeric_options.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct CellsArgs {
  SiteInputArgs sites;
  CellOutputArgs out;
  std::string report;
};

int run(CellsArgs& args) {
  // Two outputs that are one file (a path, an alias, a link; `-` twice): refused before any work.
  check_distinct_outputs({{"--output", args.out.output}, {"--report", args.report}});
  check_writer_options(args.out.output, GeometryType::MultiPolygon, cell_writer_options(args.out));  // --update or --lco with GeoJSON: before any work
  // Opened first, so that an existing report is refused before any work; renamed into place last.
  std::unique_ptr<OutputFile> report_file;
  if (!args.report.empty()) report_file = std::make_unique<OutputFile>(args.report, args.out.overwrite);
  args.sites.reader.threads = static_cast<unsigned>(args.out.threads);  // 0: one per core
  // The triangulation (one thread) starts on the positions while another core makes the rows'
  // strings (CSV input) and then the ids' GeoJSON text.
  CellIdTexts ids;
  StagedSiteInput input(args.sites, args.out.threads != 1, [&, geojson = writes_geojson(args.out)](const SiteTable& table) {
    if (geojson) ids = make_cell_id_texts(table, 1);
  });
  const std::span<const Vec3> points = input.positions();
  // A value not of its --field-type fails the rows' stage: before an old output is removed below.
  if (!args.sites.reader.field_types.empty()) input.table();
  // With --overwrite, an existing GeoJSON output (one regular file; the input is read by now) is
  // removed on another core while the triangulation is built: freeing a large file's blocks
  // takes tens of milliseconds that the final rename over it would otherwise spend.
  TaskGroup removal;
  struct stat st;
  if (args.out.overwrite && args.out.output != "-" && writes_geojson(args.out) &&
      ::lstat(args.out.output.c_str(), &st) == 0 && S_ISREG(st.st_mode))
    removal.run([path = args.out.output] { ::unlink(path.c_str()); });
  BuildReport report;
  const SphericalDelaunay dt = build_sites(points, input.lifts(), args.sites, report);
  removal.wait();
  // The diagram while the rows' strings and ids are finished on the other core.
  const VoronoiDiagram diagram(dt, static_cast<unsigned>(args.out.threads));
  const SiteTable& table = input.table();
  args.out.ids_repeat = input.ids_repeat();
  if (!args.out.quiet) list_merges(stderr, table, report);  // merged rows stay in the cells' ids and the report
  list_hidden(stderr, table, report);  // listed even with --quiet: an empty cell must not pass unseen
  const std::string at = writes_geojson(args.out) ? "at --precision " + std::to_string(args.out.precision) : "at full precision";
  const std::size_t written = write_cells(
      args.out, table, report, dt,
      [&](const CellLayerReport& cells) {
        if (!report_file) return;
        write_row_report(report_file->get(), table, report, cells.unwritten, at);
        report_file->flush();  // a full disk fails here, before the cells are renamed into place
      },
      &ids, &diagram).cells_written;
  if (report_file) report_file->commit();
  if (!args.out.quiet)
    std::fprintf(stderr, "%s; %zu cells written to %s\n", row_counts(table, dt.num_sites(), report.merges.size()).c_str(),
                 written, args.out.output.c_str());
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
  cmd->add_flag("-q,--quiet", args->out.quiet, "No progress, no summary and no list of merged rows on stderr (they stay in the cells' ids and --report); rejected rows and cells written with an empty geometry are still listed");
  cmd->add_option("--threads", args->out.threads, "Threads converting the coordinates and computing and formatting the cells (default: one per core); the output is the same")
      ->check(integer_in(0, kMaxThreads));
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
      "  geovor cells stations.gpkg -o stations.gpkg --update --nln voronoi   (a layer beside the stations)");
  return {[args] { return run(*args); },
          [args] {
            return site_input_needs_gdal(args->sites) ||
                   output_needs_gdal(args->out.output, args->out.format);
          }};
}

}  // namespace geovor::tools
