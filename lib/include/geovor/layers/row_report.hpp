/// \file row_report.hpp
/// \brief The row report of a cell layer (`geovor cells --report`): every row of the site table
/// and what became of it, as CSV.
///
/// Columns: row, line, id, status, site_index, detail. One line per accepted row, in row order:
/// status site (the row a site was built from), merged (a row merged into another row's site,
/// site_index that site) or hidden (a weighted site whose power cell is empty; detail "power cell
/// empty: site S holds its position"); a site whose cell was written with an empty geometry has
/// the detail "cell STATUS AT: empty geometry". Then one line per rejected row: status rejected,
/// site_index empty, detail the reason. Text values are quoted, control characters escaped
/// (printable()), so that a row is one line.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/layers/cell_layer.hpp"

namespace geovor {

/// Writes the report of `table` (built with `report`; `unwritten`: CellLayerReport::unwritten of
/// its cells) to `out`. `at` says at which precision the cells were written, e.g. "at precision 7"
/// or "at full precision" (the geovor command: "at --precision 7").
void write_row_report(std::FILE* out, const SiteTable& table, const BuildReport& report,
                      const std::vector<UnwrittenCell>& unwritten, const std::string& at);

}  // namespace geovor
