/// \file balanced_sites.hpp
/// \brief The sites of a balance() solution as data (`geovor balance`): their radii and target
/// areas on the site table, so that the cell layer (layers/cell_layer.hpp) writes them, and a CSV
/// of the sites that reads back as the same weighted sites.
#pragma once

#include <string>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/relax/balance.hpp"

namespace geovor {

/// The column of each site's target area that apply_balance() adds.
inline constexpr const char* kTargetField = "target_m2";

/// Gives each site of `table` (the points balance() solved, in order) its radius (weight_m; the
/// table is then weighted) and adds the column target_m2 (Real: each site's target area, with 17
/// digits), after the table's own, so that the cells carry it. A table that has a column of that
/// name keeps it: the targets are then not added, and this returns false.
bool apply_balance(SiteTable& table, const BalanceReport& result);

/// Writes the sites to `path` as CSV (core/output_file.hpp: "-" is stdout; an existing file needs
/// `overwrite`), one row per site: the row each site was built from (rows merged into it in `build`,
/// balanced_triangulation()'s report, are not repeated), with the columns site_id, lat_deg,
/// lon_deg, weight_m (the radius) and target_m2, every number with 17 digits, so that reading the
/// file with the weight column weight_m gives the same doubles and the same cells.
/// @exception Error(Io) as OutputFile.
void write_balanced_sites(const std::string& path, bool overwrite, const SiteTable& table, const BuildReport& build,
                          const BalanceReport& result);

}  // namespace geovor
