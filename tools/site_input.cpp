#include "site_input.hpp"

#include <unistd.h>

#include <algorithm>

#include "geovor/core/ascii.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "geovor/geo/column_types.hpp"
#include "geovor/geo/csv_site_scan.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_weights.hpp"
#include "geovor/io/ogr_site_reader.hpp"
#include "numeric_options.hpp"

namespace geovor::tools {

void add_site_input_options(CLI::App* cmd, SiteInputArgs& args) {
  cmd->add_option("INPUT", args.input,
                  "Sites: CSV with a header (- for stdin; a pipe or FIFO is read as CSV) or any OGR point layer (GeoPackage, Shapefile, GeoJSON, FlatGeobuf)")
      ->required();
  add_site_table_options(cmd, args);
  cmd->add_option("--layer", args.layer, "Layer of a multi-layer OGR input (GeoPackage, ...); not for CSV");
  cmd->add_flag("--all-text", [&args](std::int64_t) { args.reader.detect_types = false; },
               "Keep every input column as text (String), as read; by default CSV columns are typed by their values "
               "(Integer, Integer64, Real, Date, DateTime) and OGR fields keep their types");
  add_field_type_option(cmd, "--field-type", args.reader.field_types,
                        "Declare an input column's type, over the typing by values, --all-text and the id rule: "
                        "NAME=TYPE (String, Integer, Integer64, Real, Date, DateTime; case-insensitive), repeatable or "
                        "NAME=TYPE,NAME2=TYPE2 (GDAL's COLUMN_TYPES); a value not of that type is bad data (exit 3)");
  cmd->add_option("--weight-field", args.weight_field,
                  "Weighted sites: the column holding each site's radius in metres (0 <= r < 10,007,557, a quarter "
                  "of the circumference); the cells are then power cells (docs/weighted.md). A row whose radius is "
                  "empty, not a number or out of range is rejected");
  cmd->add_option("--merge-m", args.merge_m,
                  "Merge sites closer than this many metres (default and minimum: 2^-24 R = 0.38 m)")
      ->check(finite_above(0, true));
}

CLI::Option* add_field_type_option(CLI::App* cmd, const std::string& name, std::vector<FieldTypeOverride>& out,
                                   const std::string& help) {
  return cmd
      ->add_option_function<std::vector<std::string>>(
          name,
          [&out, name](const std::vector<std::string>& specs) {
            out.clear();
            try {
              for (const std::string& spec : specs) parse_field_types(spec, out);
            } catch (const Error& e) {
              throw CLI::ValidationError(name, e.what());
            }
          },
          help)
      ->type_name("NAME=TYPE")
      ->allow_extra_args(false);
}

std::vector<CLI::Option*> add_site_table_options(CLI::App* cmd, SiteInputArgs& args) {
  return {
      cmd->add_option("--lat-field", args.reader.lat_field,
                      "Latitude (or y) column (default: found by name, case-insensitive: lat, Latitude (deg), "
                      "stop_lat, decimalLatitude, latitude_deg, POINT_Y, y...; several equally good ones are refused)"),
      cmd->add_option("--lon-field", args.reader.lon_field,
                      "Longitude (or x) column (default: found by name: lon, lng, long, Longitude, stop_lon, "
                      "decimalLongitude, longitude_deg, POINT_X, x...)"),
      cmd->add_option("--id-field", args.reader.id_field,
                      "Identifier column (default: id, icao, code or name; else the row number); '#row': the row number"),
      cmd->add_option("--ecef-fields", args.ecef_fields, "X,Y,Z columns of ECEF metres instead of latitude/longitude"),
      cmd->add_option("--encoding", args.reader.encoding,
                      "Encoding of a CSV input that is not UTF-8 (ISO-8859-1, CP1252, UTF-16...; iconv's names)"),
      cmd->add_option("--s-srs", args.reader.s_srs,
                      "Coordinate system of the input's coordinates (EPSG:2154, a WKT, a PROJ string): CSV x/y "
                      "columns are transformed to WGS84 (rows outside its area of use rejected); replaces an OGR layer's own"),
  };
}

namespace {

// --ecef-fields X,Y,Z into the reader's options; --layer refused for CSV.
void prepare(SiteInputArgs& args) {
  if (!args.ecef_fields.empty() && args.reader.ecef_fields.empty()) {
    std::string field;
    for (const char c : args.ecef_fields + ",") {
      if (c == ',') {
        args.reader.ecef_fields.push_back(field);
        field.clear();
      } else {
        field += c;
      }
    }
  }
  if (!args.layer.empty() && is_csv_site_path(args.input, args.reader.encoding))
    throw Error(ErrorCode::InvalidArgument, args.input + ": --layer is for OGR sources; a CSV file has one table");
}

// Control characters (a NUL, a line break in a value) escaped: one line per row, never cut.
void list_rejected(const SiteTable& table) {
  const std::string source = printable(table.source);
  for (const RejectedRow& r : table.rejected) {
    if (r.line > 0)  // CSV rows have a line; OGR features do not (their reason names the feature)
      std::fprintf(stderr, "%s: row %llu (line %llu) rejected: %s\n", source.c_str(),
                   static_cast<unsigned long long>(r.row), static_cast<unsigned long long>(r.line), printable(r.reason).c_str());
    else
      std::fprintf(stderr, "%s: row %llu rejected: %s\n", source.c_str(),
                   static_cast<unsigned long long>(r.row), printable(r.reason).c_str());
  }
}

// Ids that several sites share, said once (they stay as they are).
void warn_duplicate_ids(const SiteTable& table, const DuplicateIds& duplicates) {
  if (duplicates.rows == 0) return;
  std::string examples;
  for (const DuplicateIds::Example& e : duplicates.examples) {
    if (!examples.empty()) examples += "; ";
    examples += "'" + printable(e.id) + "' rows";
    for (const std::uint64_t row : e.rows) examples += " " + std::to_string(row);
  }
  std::fprintf(stderr, "%s: warning: %llu rows have the id of an earlier row (id column '%s'; e.g. %s); "
               "--id-field '#row' makes the row number the id\n",
               printable(table.source).c_str(), static_cast<unsigned long long>(duplicates.rows),
               table.id_column >= 0 ? printable(table.columns[static_cast<std::size_t>(table.id_column)]).c_str() : "",
               examples.c_str());
}

// The whole table at once, by the reader the path calls for (a --layer is OGR's).
SiteTable read_whole(const SiteInputArgs& args) {
  return args.layer.empty() ? read_sites(args.input, args.reader) : read_sites_ogr(args.input, args.reader, args.layer);
}

}  // namespace

bool site_input_needs_gdal(const SiteInputArgs& args) {
  return !args.layer.empty() || !args.reader.s_srs.empty() || !is_csv_site_path(args.input, args.reader.encoding);
}

SiteTable read_site_input(SiteInputArgs& args, DuplicateIds* duplicates) {
  prepare(args);
  SiteTable table = read_whole(args);
  if (!args.weight_field.empty()) read_site_weights(table, args.weight_field);
  list_rejected(table);
  require_sites(table);
  const DuplicateIds found = find_duplicate_ids(table);
  warn_duplicate_ids(table, found);
  if (duplicates) *duplicates = found;
  return table;
}

StagedSiteInput::StagedSiteInput(SiteInputArgs& args, bool in_background, std::function<void(const SiteTable&)> then) {
  prepare(args);
  if (!site_input_needs_gdal(args)) {  // needs GDAL: with --s-srs, read_sites() reprojects
    scan_ = std::make_unique<CsvSiteScan>(CsvSiteScan::open(args.input, args.reader));
    positions_ = scan_->positions();
  } else {
    table_ = read_whole(args);
    points_ = site_points(table_);
    positions_ = points_;
  }
  // The rest: a CSV table's strings, then the duplicate ids beside `then` (both only read the
  // table; in the background, the caller's thread waits for them once its own work is done, and
  // they then share the cores).
  const bool weighted = !args.weight_field.empty();
  if (weighted) in_background = false;  // rows may yet be rejected: the positions come after them
  auto rest = [this, in_background, weighted, field = args.weight_field, then = std::move(then)] {
    SiteTable table = scan_ ? std::move(*scan_).finish() : std::move(table_);
    if (weighted) {
      read_site_weights(table, field);
      points_ = site_points(table);
      positions_ = points_;
      lifts_ = site_lifts(table);
    }
    TaskGroup duplicates;
    auto find = [&] { duplicates_ = find_duplicate_ids(table); };
    if (in_background && then)
      duplicates.run(find);
    else
      find();
    if (then) then(table);
    duplicates.wait();
    table_ = std::move(table);
  };
  // No site: the rows are listed, and the command stops before it creates any output.
  if (weighted) {
    rest();
    if (positions_.empty()) {
      list_rejected(table_);
      require_sites(table_);
    }
    return;
  }
  if (positions_.empty()) {
    rest();
    list_rejected(table_);
    require_sites(table_);
  }
  if (in_background) {
    pending_ = std::make_unique<TaskGroup>();
    pending_->run(std::move(rest));
  } else {
    rest();
  }
}

const SiteTable& StagedSiteInput::table() {
  if (pending_) {
    const std::unique_ptr<TaskGroup> pending = std::move(pending_);
    pending->wait();
  }
  if (!listed_) {
    list_rejected(table_);
    warn_duplicate_ids(table_, duplicates_);
  }
  listed_ = true;
  return table_;
}

std::vector<Vec3> site_points(const SiteTable& table) {
  std::vector<Vec3> points;
  points.reserve(table.sites.size());
  for (const InputSite& s : table.sites) points.push_back(s.unit);
  return points;
}

SphericalDelaunay build_sites(std::span<const Vec3> points, std::span<const double> lifts, const SiteInputArgs& args,
                              BuildReport& report) {
  if (lifts.empty()) return SphericalDelaunay::build(points, delaunay_options(args), &report);
  return SphericalDelaunay::build(points, lifts, delaunay_options(args), &report);
}

void report_hidden(const SiteTable& table, const BuildReport& report) {
  if (report.hidden.empty()) return;
  const SiteRows rows = rows_of_sites(report, report.site_of_input.size());
  for (const Hidden& h : report.hidden) {
    const InputSite& site = table.sites[rows.first(h.site)];
    const InputSite& by = table.sites[rows.first(h.by)];
    std::fprintf(stderr, "%s: row %llu (id '%s', radius %.17g m) is hidden: its power cell is empty (row %llu, id '%s', radius %.17g m, holds its position)\n",
                 printable(table.source).c_str(), static_cast<unsigned long long>(site.row), printable(site.id).c_str(),
                 site.weight_m, static_cast<unsigned long long>(by.row), printable(by.id).c_str(), by.weight_m);
  }
}

DelaunayOptions delaunay_options(const SiteInputArgs& args) {
  DelaunayOptions options;
  if (args.merge_m > 0)
    options.merge_distance = std::max(SphericalDelaunay::kMinSeparation, args.merge_m / SiteEncoder::kEarthRadiusM);
  return options;
}

void report_merges(const SiteTable& table, const BuildReport& report) {
  if (report.merges.empty()) return;
  // The row each site was built from comes first among its rows.
  const SiteRows rows = rows_of_sites(report, report.site_of_input.size());
  for (const Merge& m : report.merges) {
    const InputSite& row = table.sites[m.input];
    const InputSite& kept = table.sites[rows.first(m.site)];
    char why[96];
    if (m.chord == 0)
      std::snprintf(why, sizeof why, "same position");
    else
      std::snprintf(why, sizeof why, "%.3g m apart, closer than the merge distance%s",
                    m.chord * SiteEncoder::kEarthRadiusM, m.hidden ? " (hidden)" : "");
    std::fprintf(stderr, "%s: row %llu (id %s) merged into the site of row %llu (id %s): %s\n",
                 printable(table.source).c_str(), static_cast<unsigned long long>(row.row), printable(row.id).c_str(),
                 static_cast<unsigned long long>(kept.row), printable(kept.id).c_str(), why);
  }
}

Progress::Progress(std::size_t total, bool quiet) : total_(total), on_(!quiet && isatty(STDERR_FILENO)) {}

void Progress::advance(std::size_t done) {
  if (!on_ || total_ == 0) return;
  const int step = static_cast<int>(done * 40 / total_);  // 40 ticks of 2.5 %, as GDAL prints
  while (printed_ < step) {
    ++printed_;
    if (printed_ % 4 == 0)
      std::fprintf(stderr, "%d", printed_ / 4 * 10);
    else
      std::fputc('.', stderr);
  }
}

void Progress::finish() {
  if (!on_) return;
  advance(total_);
  std::fprintf(stderr, " - done.\n");
}

}  // namespace geovor::tools
