/// \file column_types.hpp
/// \brief The types of a CSV table's columns, told by their values as GDAL's CSV driver tells
/// them with AUTODETECT_TYPE=YES, except that nothing of a value's text may be lost by typing it.
///
/// A non-empty value is (value_type()):
/// - Integer: a JSON integer (RFC 8259: an optional '-', then "0" or digits not starting with 0)
///   that fits 32 bits; Integer64 when it fits 64 bits only;
/// - Real: any other JSON number ('.', an exponent, or an integer beyond 64 bits is String), finite;
/// - Date: YYYY-MM-DD, a day of the calendar;
/// - DateTime: a Date, 'T' or ' ', HH:MM, optionally :SS and up to 3 decimals of the second, then
///   optionally Z or an offset +HH, +HHMM or +HH:MM (minutes 00, 15, 30 or 45);
/// - String: anything else. So a leading zero ("007", "00.5"), a leading '+' ("+33"), spaces,
///   ".5", "1." and "1,5" keep a value text, as do "NaN" and "inf".
/// A column's type is the narrowest holding all its non-empty values (Integer < Integer64 < Real;
/// Date < DateTime; numbers and dates together: String); a column whose values are all empty is
/// String, and so is the id column (an identifier stays text). An empty value of a typed column
/// is null.
///
/// Invariant this gives SiteTable::column_types (the OGR reader keeps it too): every non-empty
/// value of an Integer, Integer64 or Real column is a JSON number of that type, which the GeoJSON
/// writer copies as it stands.
#pragma once

#include <string_view>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/geo/site_reader.hpp"

namespace geovor {

/// The type of one non-empty value (the file comment); String for "".
FieldType value_type(std::string_view text);

/// The narrowest type holding values of types a and b (the file comment).
FieldType wider_type(FieldType a, FieldType b);

/// The type of every column of `table` from its accepted rows' fields (the file comment), in
/// column order; the id column (table.id_column) String. One pass over the rows, each column
/// dropped once it is String.
std::vector<FieldType> detect_column_types(const SiteTable& table);

}  // namespace geovor
