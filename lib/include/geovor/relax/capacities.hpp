/// \file capacities.hpp
/// \brief The capacity of each site of a table, read from one of its columns: the shares of the
/// Earth's area that balance() gives the sites' cells (`geovor balance --capacity-field`).
///
/// A capacity is a positive finite number, written as the table's coordinates are (spaces and tabs
/// around it ignored, a leading '+', a decimal comma when the delimiter is not a comma). A row
/// whose value is empty, not a number, zero or negative is not a site to balance: it moves to the
/// table's rejected rows, with the reason naming the column.
#pragma once

#include <string>
#include <vector>

#include "geovor/geo/site_reader.hpp"

namespace geovor {

/// What read_capacities() read.
struct CapacityReport {
  std::vector<double> capacities;     ///< one per site left in table.sites, in order
  std::vector<RejectedRow> rejected;  ///< the rows moved to table.rejected for their capacity, in row order
};

/// Reads the capacity of each site of `table` from `column` (name compared trimmed and
/// case-insensitively; "" gives every site the capacity 1) and moves the rows without one from
/// table.sites to table.rejected (kept in row order; rows_read unchanged). No site may be left:
/// the caller decides what that means (balance() needs one).
/// @exception Error(InvalidArgument) naming the columns when none is `column`.
CapacityReport read_capacities(SiteTable& table, const std::string& column);

/// Why `text` is no capacity ("empty: a site needs a positive capacity", "\"abc\" is not a number",
/// "capacity -1 is not positive"), or "" with `value` set when it is one.
std::string parse_capacity(const std::string& text, bool decimal_comma, double& value);

}  // namespace geovor
