// geovor cells INPUT -o OUTPUT: the Voronoi cell of every site, as GIS polygons with the site's
// attributes, its areas and its neighbours.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <future>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/io/feature_writer.hpp"
#include "geovor/voronoi/cell_geometry.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"
#include "output_file.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct CellsArgs {
  SiteInputArgs sites;
  std::string output;
  std::string format;
  double densify_m = 100;
  int precision = 7;
  std::string report;
  bool overwrite = false;
  bool quiet = false;
  int threads = 0;  // 0: one per core
};

// A block of consecutive cells, computed in parallel and then written in order.
struct CellBlock {
  std::vector<SiteId> sites;
  std::vector<MultiPolygon> polygons;
  std::vector<std::vector<FieldValue>> values;
};

// Appends s as a JSON string.
void append_json(std::string& out, const std::string& s) {
  out += '"';
  std::size_t plain = 0;  // copy runs of ordinary characters at once
  for (std::size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c != '"' && c != '\\' && c >= 0x20) continue;
    out.append(s, plain, i - plain);
    if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      out += buf;
    } else {
      out += '\\';
      out += static_cast<char>(c);
    }
    plain = i + 1;
  }
  out.append(s, plain, std::string::npos);
  out += '"';
}

// A JSON array of strings, portable in every format (no list field types needed), built in a
// reused buffer. id(k) gives the k-th string.
template <class Id>
const std::string& json_array(std::string& out, std::size_t n, Id id) {
  out.assign(1, '[');
  for (std::size_t k = 0; k < n; ++k) {
    if (k) out += ',';
    append_json(out, id(k));
  }
  out += ']';
  return out;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Every input row and what became of it, for --report.
void write_report(OutputFile& out, const SiteTable& table, const BuildReport& report) {
  std::FILE* f = out.get();
  std::fprintf(f, "row,line,id,status,site_index,detail\n");
  auto quoted = [](const std::string& s) {
    std::string q = "\"";
    for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
  };
  std::vector<char> merged(table.sites.size(), 0);
  for (const Merge& m : report.merges) merged[m.input] = 1;
  for (std::size_t i = 0; i < table.sites.size(); ++i) {
    const InputSite& row = table.sites[i];
    std::fprintf(f, "%llu,%llu,%s,%s,%u,\n", static_cast<unsigned long long>(row.row),
                 static_cast<unsigned long long>(row.line), quoted(row.id).c_str(), merged[i] ? "merged" : "site",
                 report.site_of_input[i]);
  }
  for (const RejectedRow& r : table.rejected)
    std::fprintf(f, "%llu,%llu,,rejected,,%s\n", static_cast<unsigned long long>(r.row),
                 static_cast<unsigned long long>(r.line), quoted(r.reason).c_str());
  out.flush();  // a full disk fails here, before the cells are renamed into place
}

int run(CellsArgs& args) {
  // Opened first, so that an existing report is refused before any work; renamed into place last.
  std::unique_ptr<OutputFile> report_file;
  if (!args.report.empty()) report_file = std::make_unique<OutputFile>(args.report, args.overwrite);
  const SiteTable table = read_site_input(args.sites);
  const std::vector<Vec3> points = site_points(table);
  BuildReport report;
  const SphericalDelaunay dt = SphericalDelaunay::build(points, delaunay_options(args.sites), &report);
  report_merges(table, report);
  const VoronoiDiagram diagram(dt);
  CellGeometryOptions geometry_options;
  geometry_options.densify_m = args.densify_m;
  const CellGeometry cells(diagram, geometry_options);
  const auto rows = rows_of_sites(report, dt.site_capacity());

  // Schema: our fields, then every input column (renamed src_<name> if it clashes with ours).
  const std::vector<std::string> ours = {"site_index", "site_id", "ids",        "n_rows",
                                         "area_m2",    "area_sr", "n_vertices", "neighbors"};
  std::vector<Field> schema = {{"site_index", FieldType::Integer}, {"site_id", FieldType::String},
                               {"ids", FieldType::String},         {"n_rows", FieldType::Integer},
                               {"area_m2", FieldType::Real},       {"area_sr", FieldType::Real},
                               {"n_vertices", FieldType::Integer}, {"neighbors", FieldType::String}};
  for (const std::string& column : table.columns) {
    const bool clash = std::any_of(ours.begin(), ours.end(), [&](const std::string& o) { return lower(o) == lower(column); });
    schema.push_back({clash ? "src_" + column : column, FieldType::String});
  }
  WriterOptions writer_options;
  writer_options.format = args.format;
  writer_options.layer = "cells";
  writer_options.precision = args.precision;
  writer_options.overwrite = args.overwrite;
  writer_options.id_field = "site_id";
  const auto writer = open_feature_writer(args.output, GeometryType::MultiPolygon, schema, writer_options);

  // One cell's geometry and properties (thread-safe: only reads shared state).
  auto make_cell = [&](SiteId s, MultiPolygon& polygon, std::vector<FieldValue>& values, std::string& buffer) {
    cells.polygon(s, polygon);
    const std::vector<std::uint32_t>& site_rows = rows[s];
    const InputSite& first = table.sites[site_rows.front()];
    const auto neighbours = diagram.cell_neighbors(s);
    values.resize(schema.size());
    values[0] = static_cast<std::int64_t>(s);
    values[1] = first.id;
    values[2] = json_array(buffer, site_rows.size(), [&](std::size_t k) -> const std::string& {
      return table.sites[site_rows[k]].id;
    });
    values[3] = static_cast<std::int64_t>(site_rows.size());
    values[4] = ellipsoid_area_m2(polygon);
    values[5] = diagram.cell_area_sr(s);
    values[6] = static_cast<std::int64_t>(diagram.cell_vertices(s).size());
    values[7] = json_array(buffer, neighbours.size(), [&](std::size_t k) -> const std::string& {
      return table.sites[rows[neighbours[k]].front()].id;
    });
    for (std::size_t c = 0; c < table.columns.size(); ++c)
      values[8 + c] = c < first.fields.size() ? FieldValue(first.fields[c]) : FieldValue();
  };
  const unsigned threads = args.threads > 0 ? static_cast<unsigned>(args.threads)
                                            : std::max(1u, std::thread::hardware_concurrency());
  auto compute = [&](CellBlock& block) {
    block.polygons.resize(block.sites.size());
    block.values.resize(block.sites.size());
    auto work = [&](std::size_t begin, std::size_t step) {
      std::string buffer;
      for (std::size_t i = begin; i < block.sites.size(); i += step)
        make_cell(block.sites[i], block.polygons[i], block.values[i], buffer);
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(work, t, threads);
    work(0, threads);
    for (auto& th : pool) th.join();
  };
  // Cells in site order, in blocks: the next block is computed while this one is written.
  constexpr std::size_t kBlock = 4096;
  std::vector<SiteId> order;
  for (SiteId s = 0; s < dt.site_capacity(); ++s)
    if (diagram.has_cell(s)) order.push_back(s);
  auto fill = [&](CellBlock& block, std::size_t begin) {
    block.sites.assign(order.begin() + static_cast<std::ptrdiff_t>(begin),
                       order.begin() + static_cast<std::ptrdiff_t>(std::min(order.size(), begin + kBlock)));
  };
  Progress progress(order.size(), args.quiet);
  std::size_t written = 0;
  CellBlock current, next;
  fill(current, 0);
  compute(current);
  for (std::size_t begin = 0; begin < order.size(); begin += kBlock) {
    std::future<void> ahead;
    if (begin + kBlock < order.size()) {
      fill(next, begin + kBlock);
      ahead = std::async(std::launch::async, [&] { compute(next); });
    }
    for (std::size_t i = 0; i < current.sites.size(); ++i) writer->write(current.polygons[i], current.values[i]);
    written += current.sites.size();
    progress.advance(written);
    if (ahead.valid()) ahead.get();
    std::swap(current, next);
  }
  if (report_file) write_report(*report_file, table, report);
  writer->finish();
  progress.finish();
  if (report_file) report_file->commit();
  if (!args.quiet)
    std::fprintf(stderr, "%s: rows %llu, sites %zu, merged %zu, rejected %zu; %zu cells written to %s\n",
                 table.source.c_str(), static_cast<unsigned long long>(table.rows_read), dt.num_sites(),
                 report.merges.size(), table.rejected.size(), written, args.output.c_str());
  return kOk;
}

}  // namespace

std::function<int()> add_cells_command(CLI::App& app) {
  auto args = std::make_shared<CellsArgs>();
  CLI::App* cmd = app.add_subcommand("cells", "Write the Voronoi cell of every site as GIS polygons");
  add_site_input_options(cmd, args->sites);
  cmd->add_option("-o,--output", args->output,
                  "Output file (- for GeoJSON on stdout); the format follows the extension: .geojson, "
                  ".geojsons/.geojsonl, .gpkg, .fgb, .shp, .csv")
      ->required();
  cmd->add_option("--format", args->format, "OGR driver name, overriding the extension (GeoJSON, GeoJSONSeq, GPKG, FlatGeobuf, \"ESRI Shapefile\", CSV, ...)");
  cmd->add_option("--densify-m", args->densify_m, "Largest distance in metres between a written edge and the true great-circle arc (default 100)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--precision", args->precision, "Decimals of coordinates in text formats (default 7, about 1 cm)")
      ->check(CLI::Range(1, 17));
  cmd->add_option("--report", args->report, "CSV file listing every input row: site, merged (with its site) or rejected (with the reason)");
  cmd->add_flag("--overwrite", args->overwrite, "Replace existing output files");
  cmd->add_flag("-q,--quiet", args->quiet, "No progress and no summary on stderr");
  cmd->add_option("--threads", args->threads, "Threads computing the cells (default: one per core); the output is the same")
      ->check(CLI::NonNegativeNumber);
  cmd->footer(
      "Each cell carries: site_index, site_id (also the feature id), ids (JSON array of the ids of every\n"
      "row merged into the site), n_rows, area_m2 (WGS84 ellipsoid), area_sr (sphere), n_vertices,\n"
      "neighbors (JSON array of the neighbours' ids), then every input column.\n"
      "Examples:\n"
      "  geovor cells datasets/weather_stations.csv -o cells.geojson\n"
      "  geovor cells stations.gpkg -o cells.fgb --densify-m 10 --report rows.csv");
  return [args] { return run(*args); };
}

}  // namespace geovor::tools
