/// \file staged_site_input.hpp
/// \brief StagedSiteInput: the sites of a SiteInput read in two stages, so that the triangulation
/// can start on the positions while the rest of the table is made (`geovor cells`).
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "geovor/core/parallel.hpp"
#include "geovor/core/types.hpp"
#include "geovor/geo/csv_site_scan.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/layers/site_input.hpp"

namespace geovor {

/// The sites in two stages: the positions of a CSV input's rows first (CsvSiteScan; an OGR input,
/// or one with a coordinate system, is read whole at once), then the rows' strings and
/// `then(table)`, on another thread when `in_background`. With a weight_field the table is read
/// whole before the positions (a row may be rejected for its radius). table() waits for the second
/// stage, then accounts for the rows on input.log as read_site_input() does (the rejected rows,
/// the repeated ids). Errors of the first stage are thrown by the constructor, those of the second
/// by table(); so is no site at all (require_sites()), by the constructor, after the rejected rows
/// are listed.
class StagedSiteInput {
 public:
  /// Starts reading `input` (which must outlive this object).
  StagedSiteInput(const SiteInput& input, bool in_background, std::function<void(const SiteTable&)> then = {});
  /// The accepted rows' unit vectors, in row order (valid while this object lives).
  std::span<const Vec3> positions() const { return positions_; }
  /// With a weight_field, the sites' lifts (site_lifts()); empty otherwise.
  std::span<const double> lifts() const { return lifts_; }
  /// The whole table, once the second stage is done; the rows are accounted for at the first call.
  const SiteTable& table();
  /// Whether two accepted rows share an id (known once table() returned).
  bool ids_repeat() const { return duplicates_.rows > 0; }

 private:
  // The second stage: the table's strings, the weights, the duplicate ids, then `then`.
  void finish(bool in_background, const std::function<void(const SiteTable&)>& then);

  const SiteInput& input_;
  std::unique_ptr<CsvSiteScan> scan_;
  std::vector<Vec3> points_;
  std::span<const Vec3> positions_;
  std::vector<double> lifts_;
  SiteTable table_;
  DuplicateIds duplicates_;
  bool listed_ = false;
  std::unique_ptr<TaskGroup> pending_;  // the second stage in the background (joined first)
};

}  // namespace geovor
