/// \file balanced_cells.hpp
/// \brief balance_to_files(): the radii that give each of a job's sites its capacity's share of
/// the Earth's area (relax/balance.hpp), then the balanced power cells written to a file
/// (cell_file.hpp) and, optionally, the sites with their radii as CSV (relax/balanced_sites.hpp):
/// what `geovor balance` does, each Newton iteration said on the log.
#pragma once

#include <string>

#include "geovor/layers/cell_file.hpp"
#include "geovor/layers/site_input.hpp"
#include "geovor/relax/balance.hpp"

namespace geovor {

/// Options of balance_to_files(); every default is documented.
struct BalancedCellsOptions {
  /// The solve (tolerance, iterations, threads). DEFAULT: BalanceOptions{}.
  BalanceOptions balance;
  /// The column of the sites' capacities (relax/capacities.hpp); "" (DEFAULT): equal shares.
  std::string capacity_field;
  /// The cells' file: its writer options (id_field set to site_index when ids repeat), layer
  /// options, log and quiet (no progress, no lines per iteration, no summary). DEFAULT: CellFileOptions{}.
  CellFileOptions cells;
  /// The sites as CSV (write_balanced_sites(), with the cells' overwrite); "" (DEFAULT): none.
  std::string sites_path;
};

/// Reads `input`'s sites (read_site_input(); they must be unweighted: balance computes the radii),
/// their capacities (rows without one are listed on the log as the rejected rows are), and
/// balances them. Converged, writes the cells of the balanced sites, with their radii (weight_m)
/// and target areas (target_m2, unless the table has such a column: then said on the log), to
/// `cells_path` and the sites to options.sites_path; not converged, writes nothing (the caller
/// says so). On the log, unless options.cells.quiet: a header, a line per iteration (the largest
/// relative area error, the damping step, seconds) and a summary line; the merged rows unless
/// input.quiet, the hidden sites always.
/// @exception Error(BadData) when no row has a positive capacity; as read_site_input(),
///   read_capacities(), balance() and the writers.
BalanceReport balance_to_files(const SiteInput& input, const std::string& cells_path, const BalancedCellsOptions& options);

}  // namespace geovor
