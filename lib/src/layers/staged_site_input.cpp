#include "geovor/layers/staged_site_input.hpp"

#include "geovor/geo/site_weights.hpp"
#include "geovor/io/ogr_site_reader.hpp"
#include "geovor/layers/row_accounting.hpp"

namespace geovor {

StagedSiteInput::StagedSiteInput(const SiteInput& input, bool in_background,
                                 std::function<void(const SiteTable&)> then)
    : input_(input) {
  check_site_input(input);
  if (!site_input_needs_gdal(input)) {  // needs GDAL: with s_srs, read_sites() reprojects
    scan_ = std::make_unique<CsvSiteScan>(CsvSiteScan::open(input.input, input.reader));
    positions_ = scan_->positions();
  } else {
    table_ = input.layer.empty() ? read_sites(input.input, input.reader)
                                 : read_sites_ogr(input.input, input.reader, input.layer);
    points_ = site_points(table_);
    positions_ = points_;
  }
  const bool weighted = !input.weight_field.empty();
  if (weighted) in_background = false;  // rows may yet be rejected: the positions come after them
  // No site: the rows are listed, and the caller stops before it creates any output.
  if (weighted || positions_.empty()) {
    finish(in_background, then);
    if (positions_.empty()) {
      list_rejected_rows(input.log, table_);
      require_sites(table_);
    }
    if (weighted) return;
  }
  if (in_background) {
    pending_ = std::make_unique<TaskGroup>();
    pending_->run([this, then = std::move(then)] { finish(true, then); });
  } else {
    finish(false, then);
  }
}

void StagedSiteInput::finish(bool in_background, const std::function<void(const SiteTable&)>& then) {
  SiteTable table = scan_ ? std::move(*scan_).finish() : std::move(table_);
  if (!input_.weight_field.empty()) {
    read_site_weights(table, input_.weight_field);
    points_ = site_points(table);
    positions_ = points_;
    lifts_ = site_lifts(table);
  }
  // The duplicate ids beside `then` (both only read the table; in the background, the caller's
  // thread waits for them once its own work is done, and they then share the cores).
  TaskGroup duplicates;
  auto find = [&] { duplicates_ = find_duplicate_ids(table); };
  if (in_background && then)
    duplicates.run(find);
  else
    find();
  if (then) then(table);
  duplicates.wait();
  table_ = std::move(table);
}

const SiteTable& StagedSiteInput::table() {
  if (pending_) {
    const std::unique_ptr<TaskGroup> pending = std::move(pending_);
    pending->wait();
  }
  if (!listed_) {
    list_rejected_rows(input_.log, table_);
    warn_duplicate_ids(input_.log, table_, duplicates_, input_.id_field_name);
  }
  listed_ = true;
  return table_;
}

}  // namespace geovor
