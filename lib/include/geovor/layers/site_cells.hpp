/// \file site_cells.hpp
/// \brief SiteCells: the cells of a job's sites written to a file with their row report, what
/// `geovor cells` does. The triangulation starts on the sites' positions while another core
/// makes the rows' strings and the ids' GeoJSON text (StagedSiteInput); with overwrite, an
/// existing GeoJSON output is removed on another core meanwhile (freeing a large file's blocks
/// takes tens of milliseconds that the final rename over it would otherwise spend); the Voronoi
/// diagram is built while the table is finished; then the cell file (cell_file.hpp) and the row
/// report (row_report.hpp), which is opened first, so that an existing one is refused before any
/// work, and moved into place last.
///
/// An object rather than a function, so that the data it made (the table, the triangulation,
/// the diagram) live as long as the caller wants: the geovor command exits without freeing them.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "geovor/core/output_file.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/layers/cell_file.hpp"
#include "geovor/layers/id_lists.hpp"
#include "geovor/layers/site_input.hpp"
#include "geovor/layers/staged_site_input.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace geovor {

/// Options of SiteCells; every default is documented.
struct SiteCellsOptions {
  /// The cells' file: its writer options (id_field set to site_index when ids repeat), layer
  /// options (densify_m; threads, id texts and diagram are set here), log and quiet (no progress,
  /// no summary), the names of the options in messages. DEFAULT: CellFileOptions{}.
  CellFileOptions file;
  /// The row report (row_report.hpp), written with file.writer.overwrite; "" (DEFAULT): none.
  std::string report_path;
  /// Threads reading the input, building the diagram and the cells (0: one per core); 1 runs
  /// everything on the calling thread. DEFAULT: 0. The outputs do not depend on it.
  unsigned threads = 0;
};

class SiteCells {
 public:
  /// Reads `input`'s sites (their rows accounted for on input.log, the merges unless input.quiet),
  /// builds their cells and writes them to `output` (write_cell_file()) and the row report to
  /// options.report_path; unless options.file.quiet, says the counts on the log ("SOURCE: rows N,
  /// sites S, merged M, rejected R; C cells written to OUTPUT").
  /// @exception Error as StagedSiteInput, OutputFile and write_cell_file().
  SiteCells(const SiteInput& input, const std::string& output, const SiteCellsOptions& options);

  const SiteTable& table() { return staged_->table(); }
  const BuildReport& build() const { return build_; }
  const SphericalDelaunay& triangulation() const { return *dt_; }
  const CellLayerReport& cells() const { return cells_; }

 private:
  // Starts removing an existing GeoJSON output when it is to be overwritten (the file comment).
  void remove_old_output(const std::string& output, const CellFileOptions& file);
  // The cell file, with the row report written before the cells are moved into place.
  void write(const std::string& output, const SiteCellsOptions& options);

  SiteInput input_;
  std::unique_ptr<OutputFile> report_file_;
  bool geojson_ = false;  // the output is GeoJSON text (it uses the ids' texts)
  CellIdTexts ids_;
  std::optional<StagedSiteInput> staged_;
  TaskGroup removal_;
  BuildReport build_;
  std::optional<SphericalDelaunay> dt_;
  std::optional<VoronoiDiagram> diagram_;
  CellLayerReport cells_;
};

}  // namespace geovor
