// Sites from numpy arrays: a SiteTable as read_sites_csv would make it, with rows numbered
// from 1 (row r is input index r - 1), and the numpy arrays' access helpers.
#pragma once

#include <pybind11/numpy.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "geovor/geo/site_reader.hpp"

namespace geovor::python {

using Doubles = pybind11::array_t<double, pybind11::array::c_style | pybind11::array::forcecast>;

/// The data of a 1-D array of n values (n = lat's length when given -1), or Error naming it.
const double* column_data(const Doubles& a, const char* name, std::size_t& n);

/// The table of sites (lat[i], lon[i]) with ids[i] (default: "i"); no columns.
/// @exception Error(BadData) naming the first site whose position is invalid ("site 3: ...").
SiteTable site_table_from_arrays(const Doubles& lat, const Doubles& lon, std::optional<std::vector<std::string>> ids);

/// The sites' radii in metres (weights[i] of site i) into the table, which becomes weighted
/// (docs/weighted.md). @exception Error(InvalidArgument) naming the first bad radius ("weights[3]: ...").
void set_radii(SiteTable& table, const Doubles& radii_m);

}  // namespace geovor::python
