#include "geovor/layers/site_input.hpp"

#include <algorithm>
#include <chrono>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_weights.hpp"
#include "geovor/io/ogr_site_reader.hpp"
#include "geovor/layers/row_accounting.hpp"

namespace geovor {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

bool site_input_needs_gdal(const SiteInput& input) {
  return !input.layer.empty() || !input.reader.s_srs.empty() || !is_csv_site_path(input.input, input.reader.encoding);
}

void check_site_input(const SiteInput& input) {
  if (!input.layer.empty() && is_csv_site_path(input.input, input.reader.encoding))
    throw Error(ErrorCode::InvalidArgument,
                input.input + ": " + input.layer_name + " is for OGR sources; a CSV file has one table");
}

SiteTable read_site_input(const SiteInput& input, DuplicateIds* duplicates) {
  check_site_input(input);
  SiteTable table = input.layer.empty() ? read_sites(input.input, input.reader)
                                        : read_sites_ogr(input.input, input.reader, input.layer);
  if (!input.weight_field.empty()) read_site_weights(table, input.weight_field);
  list_rejected_rows(input.log, table);
  require_sites(table);
  const DuplicateIds found = find_duplicate_ids(table);
  warn_duplicate_ids(input.log, table, found, input.id_field_name);
  if (duplicates) *duplicates = found;
  return table;
}

DelaunayOptions delaunay_options(const SiteInput& input) {
  DelaunayOptions options;
  if (input.merge_m > 0)
    options.merge_distance = std::max(SphericalDelaunay::kMinSeparation, input.merge_m / SiteEncoder::kEarthRadiusM);
  return options;
}

SphericalDelaunay build_sites(std::span<const Vec3> points, std::span<const double> lifts, const SiteInput& input,
                              BuildReport& report) {
  if (lifts.empty()) return SphericalDelaunay::build(points, delaunay_options(input), &report);
  return SphericalDelaunay::build(points, lifts, delaunay_options(input), &report);
}

void list_build(const SiteInput& input, const SiteTable& table, const BuildReport& report) {
  if (!input.quiet) list_merges(input.log, table, report);
  list_hidden(input.log, table, report);
}

SiteIndex build_index_from_table(const SiteInput& input, TableBuild* summary) {
  auto t0 = std::chrono::steady_clock::now();
  const SiteTable table = read_site_input(input);
  const double read_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  BuildReport report;
  SiteIndex index = build_site_index(table, delaunay_options(input), {}, &report);
  const double build_s = seconds_since(t0);
  list_build(input, table, report);  // the merges stay in the index and its counts
  if (summary) {
    summary->source = table.source;
    summary->rows = table.rows_read;
    summary->sites = index.hierarchy.base().num_sites();
    summary->merged = report.merges.size();
    summary->hidden = table.weighted ? std::optional<std::uint64_t>(report.hidden.size()) : std::nullopt;
    summary->rejected = table.rejected.size();
    summary->read_seconds = read_s;
    summary->build_seconds = build_s;
  }
  return index;
}

SiteIndex load_site_index(const SiteInput& input, unsigned threads) {
  return is_index_path(input.input) ? load_index(input.input, threads) : build_index_from_table(input);
}

}  // namespace geovor
