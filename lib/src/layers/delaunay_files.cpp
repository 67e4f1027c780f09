#include "geovor/layers/delaunay_files.hpp"

#include "geovor/core/output_target.hpp"
#include "geovor/core/progress.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "geovor/geo/site_weights.hpp"
#include "geovor/layers/row_accounting.hpp"
#include "geovor/lonlat/cell_geometry.hpp"

namespace geovor {
namespace {

// Whether `path` is given and written as text (GeoJSON, GeoJSONSeq) rather than by GDAL.
bool writes_text(const std::string& path, const std::string& format) {
  return !path.empty() && output_kind(path, format) != OutputKind::Gdal;
}

// Listed even when quiet, as rejected rows are: a feature without geometry must not pass unseen.
void list_unwritten(const DelaunayLayersReport& written, const SphericalDelaunay& dt, int precision,
                    const DelaunayFilesOptions& options) {
  if (options.log == nullptr) return;
  const std::string where =
      precision >= 0 ? options.precision_name + " " + std::to_string(precision) : "full precision";
  const std::vector<UnwrittenTriangle>& unwritten = written.triangles.unwritten;
  if (!unwritten.empty()) {
    std::fprintf(options.log, "%zu triangle(s) written with an empty geometry: at %s they collapse or would not be valid polygons (raise %s):\n",
                 unwritten.size(), where.c_str(), options.precision_name.c_str());
    for (std::size_t i = 0; i < unwritten.size() && i < 20; ++i) {
      const TriId t = unwritten[i].triangle;
      std::fprintf(options.log, "  triangle %u (sites %u, %u, %u): %s\n", t, dt.tri_site(t, 0), dt.tri_site(t, 1),
                   dt.tri_site(t, 2), to_string(unwritten[i].status));
    }
    if (unwritten.size() > 20) std::fprintf(options.log, "  ... (%zu more)\n", unwritten.size() - 20);
  }
  if (written.edges.collapsed > 0)
    std::fprintf(options.log, "%zu edge(s) written with an empty geometry: their ends are one position at %s\n",
                 written.edges.collapsed, where.c_str());
}

// The counts of the run (delaunay_to_files()).
void say_counts(std::FILE* log, const SiteTable& table, const BuildReport& report, const SphericalDelaunay& dt,
                const DelaunayOutput& output, const DelaunayLayersReport& written) {
  std::fprintf(log, "%s; triangles %zu (ghost %zu)", row_counts(table, dt.num_sites(), report.merges.size()).c_str(),
               dt.num_triangles(), dt.num_ghost_triangles());
  if (!output.triangles_path.empty())
    std::fprintf(log, ", %zu written to %s", written.triangles.triangles_written, output.triangles_path.c_str());
  if (!output.edges_path.empty())
    std::fprintf(log, "; edges %zu written to %s", written.edges.edges_written, output.edges_path.c_str());
  std::fprintf(log, "\n");
}

}  // namespace

DelaunayOutput delaunay_output(const std::string& triangles_path, const std::string& edges_path,
                               const WriterOptions& options, const std::string& edges_format,
                               const std::string& edges_layer) {
  DelaunayOutput output;
  output.triangles_path = triangles_path;
  output.triangles = options;
  output.edges_path = edges_path;
  output.edges = options;
  output.edges.format = edges_format;
  output.edges.layer = edges_layer;
  // Update concerns the outputs whose format holds several layers, creation options those GDAL
  // writes; an edges file of another format is created as it would be without them.
  if (!edges_path.empty() && !one_data_source(output)) {
    if (output_kind(edges_path, edges_format) != OutputKind::Gdal) {
      output.edges.layer_options.clear();
      output.edges.dataset_options.clear();
    }
    if (!format_holds_layers(edges_path, edges_format)) output.edges.update = false;
  }
  return output;
}

void check_delaunay_output(const DelaunayOutput& output, const std::string& triangles_name,
                           const std::string& edges_name) {
  if (!(one_data_source(output) && format_holds_layers(output.triangles_path, output.triangles.format)))
    check_distinct_outputs({{triangles_name, output.triangles_path}, {edges_name, output.edges_path}});
  if (!output.triangles_path.empty())
    check_writer_options(output.triangles_path, GeometryType::MultiPolygon, output.triangles);
  if (!output.edges_path.empty()) check_writer_options(output.edges_path, GeometryType::MultiLineString, output.edges);
}

DelaunayLayersReport write_delaunay_files(const DelaunayOutput& output, const SiteTable& table, const BuildReport& report,
                                          const SphericalDelaunay& dt, const DelaunayFilesOptions& options) {
  DelaunayGeometryOptions geometry_options;
  geometry_options.densify_m = options.densify_m;
  const bool text = writes_text(output.triangles_path, output.triangles.format) ||
                    writes_text(output.edges_path, output.edges.format);
  geometry_options.precision = text ? output.triangles.precision : kFullPrecision;
  const DelaunayGeometry geometry(dt, geometry_options);
  const std::size_t total = (output.triangles_path.empty() ? 0 : dt.num_triangles()) +
                            (output.edges_path.empty() ? 0 : dt.halfedges().size() / 2);
  Progress progress(total, Progress::on_terminal(options.log, options.quiet));
  DelaunayLayerOptions layer_options;
  layer_options.no_ghosts = options.no_ghosts;
  layer_options.progress = [&](std::size_t done) { progress.advance(done); };
  const DelaunayLayersReport written = write_delaunay_layers(output, table, rows_of_sites(report, dt.site_capacity()),
                                                             geometry, layer_options);
  progress.finish();
  list_unwritten(written, dt, geometry_options.precision, options);
  return written;
}

DelaunayLayersReport delaunay_to_files(const SiteInput& input, const DelaunayOutput& output,
                                       const DelaunayFilesOptions& options) {
  const SiteTable table = read_site_input(input);
  BuildReport report;
  const SphericalDelaunay dt =
      build_sites(site_points(table), table.weighted ? site_lifts(table) : std::vector<double>(), input, report);
  list_build(input, table, report);  // merged rows stay in the counts
  const DelaunayLayersReport written = write_delaunay_files(output, table, report, dt, options);
  if (!options.quiet && options.log != nullptr) say_counts(options.log, table, report, dt, output, written);
  return written;
}

}  // namespace geovor
