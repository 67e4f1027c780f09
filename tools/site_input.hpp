// Shared by the subcommands that read sites: the options naming the input columns, reading the
// table (CSV or any OGR point layer), the row accounting on stderr, and building the
// triangulation.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdio>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "geovor/core/parallel.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/csv_site_scan.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/geo/site_weights.hpp"

namespace geovor::tools {

struct SiteInputArgs {
  std::string input;
  SiteReaderOptions reader;
  std::string ecef_fields;  // "X,Y,Z"
  std::string layer;        // OGR layer; "" for the only one
  double merge_m = 0;       // 0: the minimum separation
  std::string weight_field; // the radius column of weighted sites; "" for none
  bool quiet = false;       // -q where the command has no other output options: no list of merged rows
};

/// Adds INPUT and the column options to a subcommand.
void add_site_input_options(CLI::App* cmd, SiteInputArgs& args);

/// Adds a repeatable option `name` NAME=TYPE[,NAME2=TYPE2] (parse_field_types) filling `out`; a
/// malformed one or an unknown type is a usage error.
CLI::Option* add_field_type_option(CLI::App* cmd, const std::string& name, std::vector<FieldTypeOverride>& out,
                                   const std::string& help);

/// Adds the options that say how to read a site table (columns, encoding, CRS); returns them.
std::vector<CLI::Option*> add_site_table_options(CLI::App* cmd, SiteInputArgs& args);

/// Whether reading the sites needs GDAL: an OGR source (any path but CSV/TXT and "-") or --layer.
bool site_input_needs_gdal(const SiteInputArgs& args);

/// Reads the sites; rejected rows go to stderr (file, row, line, reason), then a warning when
/// ids repeat. Throws Error(BadData) when no site remains (require_sites).
SiteTable read_site_input(SiteInputArgs& args, DuplicateIds* duplicates = nullptr);

/// The sites in two stages, so that the triangulation can start on the positions while the rest
/// is done: the rows' strings of CSV input (CsvSiteScan; OGR input is read whole at once), then
/// `then(table)`, on another thread when `in_background`. table() waits for them and lists the
/// rejected rows on stderr, as read_site_input does. Errors of the first stage are thrown by the
/// constructor, those of the second by table(); so is no site at all (require_sites), by the
/// constructor, after the rejected rows are listed.
class StagedSiteInput {
 public:
  StagedSiteInput(SiteInputArgs& args, bool in_background, std::function<void(const SiteTable&)> then = {});
  /// The accepted rows' unit vectors, in row order (valid while this object lives).
  std::span<const Vec3> positions() const { return positions_; }
  /// With --weight-field, the sites' lifts (site_lifts); empty otherwise. With weights, the table
  /// is read whole before the positions (a row may be rejected for its radius).
  std::span<const double> lifts() const { return lifts_; }
  const SiteTable& table();
  /// Whether two accepted rows share an id (known once table() returned).
  bool ids_repeat() const { return duplicates_.rows > 0; }

 private:
  std::unique_ptr<CsvSiteScan> scan_;
  std::vector<Vec3> points_;
  std::span<const Vec3> positions_;
  std::vector<double> lifts_;
  SiteTable table_;
  DuplicateIds duplicates_;
  bool listed_ = false;
  std::unique_ptr<TaskGroup> pending_;  // the second stage in the background (joined first)
};

/// The unit vectors of the accepted rows, in order.
std::vector<Vec3> site_points(const SiteTable& table);

/// The triangulation of the sites, weighted when lifts are given (SphericalDelaunay::build).
SphericalDelaunay build_sites(std::span<const Vec3> points, std::span<const double> lifts, const SiteInputArgs& args,
                              BuildReport& report);

/// Lists each hidden weighted site on stderr with its row and the row of a site that hides it.
void report_hidden(const SiteTable& table, const BuildReport& report);

/// DelaunayOptions with the --merge-m distance.
DelaunayOptions delaunay_options(const SiteInputArgs& args);

/// Lists each merge on stderr with the merged row and the row its site was built from.
void report_merges(const SiteTable& table, const BuildReport& report);

/// GDAL-style progress on stderr ("0...10...20...", "100 - done.") when stderr is a terminal and
/// not quiet.
class Progress {
 public:
  Progress(std::size_t total, bool quiet);
  void advance(std::size_t done);
  void finish();

 private:
  std::size_t total_;
  bool on_;
  int printed_ = -1;
};

}  // namespace geovor::tools
