/// \file relaxed_cells.hpp
/// \brief relax_to_files(): Lloyd's iterations on a job's sites (relax/lloyd.hpp), then the final
/// cells written to a file (cell_file.hpp) and, optionally, the final sites as points
/// (site_layer.hpp): what `geovor relax` does, each iteration said on the log.
///
/// The sites' file is a file of its own, or the second layer ("sites") of the cells' data source
/// when both paths name one file of a format that holds several layers (GPKG, ...): it is then
/// added once the cells are in place.
#pragma once

#include <string>

#include "geovor/layers/cell_file.hpp"
#include "geovor/layers/site_input.hpp"
#include "geovor/relax/lloyd.hpp"

namespace geovor {

/// Options of relax_to_files(); every default is documented.
struct RelaxedCellsOptions {
  /// The iterations. DEFAULT: LloydOptions{}.
  LloydOptions lloyd;
  /// The cells' file: its writer options (id_field set to site_index when ids repeat), layer
  /// options, log and quiet (no progress, no lines per iteration, no summary). DEFAULT: CellFileOptions{}.
  CellFileOptions cells;
  /// The final sites (site_layer.hpp), written with the cells' precision and overwrite; "" (DEFAULT): none.
  std::string sites_path;
};

/// Whether the sites go into the cells' data source (the file comment).
/// @exception Error(InvalidArgument) as format_holds_layers() for a format it does not know.
bool sites_in_cells_source(const std::string& cells_path, const RelaxedCellsOptions& options);

/// Refuses, before any work: the two outputs as one file (check_distinct_outputs(), naming them
/// `cells_name` and `sites_name`) unless the sites go into the cells' data source; writer options
/// the outputs cannot take (check_writer_options()); existing outputs without overwrite (update
/// of a format that holds several layers: the layer is added) (refuse_existing_output()).
/// @exception Error as those.
void check_relaxed_outputs(const std::string& cells_path, const RelaxedCellsOptions& options,
                           const std::string& cells_name = "cells_path", const std::string& sites_name = "sites_path");

/// Reads `input`'s sites (read_site_input(); they must be unweighted), builds them, runs lloyd()
/// and writes the final cells to `cells_path` and the sites to options.sites_path. On the log:
/// the merged rows (unless input.quiet), and unless options.cells.quiet a header, a line per
/// iteration (energy, largest and mean move in metres, moves the filter certified, seconds), the
/// final energy with the moves refused and the sites without a centroid, and a summary line.
/// @exception Error as read_site_input(), lloyd() and the writers.
LloydReport relax_to_files(const SiteInput& input, const std::string& cells_path, const RelaxedCellsOptions& options);

}  // namespace geovor
