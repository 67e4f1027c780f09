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
/// Declared types (SiteReaderOptions::field_types, the CLI's --field-type NAME=TYPE, as GDAL's
/// COLUMN_TYPES and ogr2ogr's -mapFieldType) replace the detected ones, the id column's too. A
/// declared value is read leniently, as the user asked for that type, and written as the type's
/// own text (declared_value()): spaces around it dropped; Integer and Integer64 an optional '+' or
/// '-' and decimal digits, leading zeros allowed ("007" -> 7), within 32 or 64 bits; Real a
/// decimal number (optional sign, digits with an optional '.', ".5" and "1." included, an optional
/// exponent), finite; Date and DateTime as above (DateTime takes a Date); String any text, kept
/// as it is. An empty (or blank) value of a typed column is null. Any other value is bad data:
/// never nulled, never dropped.
///
/// Invariant this gives SiteTable::column_types (the OGR reader keeps it too): every non-empty
/// value of an Integer, Integer64 or Real column is a JSON number of that type, which the GeoJSON
/// writer copies as it stands.
#pragma once

#include <optional>
#include <span>
#include <string>
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

/// detect_column_types one row at a time, for a reader that types the rows as it makes them
/// (while their text is in cache): add() every accepted row's fields in order, then types().
class ColumnTypeDetector {
 public:
  ColumnTypeDetector(std::size_t columns, int id_column);
  void add(const std::vector<std::string>& fields);
  std::vector<FieldType> types() const;

 private:
  std::vector<FieldType> types_;
  std::vector<bool> seen_;         // a non-empty value was met
  std::vector<std::size_t> open_;  // columns not yet String
};

/// The type named `name` (String, Integer, Integer64, Real, Date, DateTime; ASCII
/// case-insensitive), or nullopt.
std::optional<FieldType> field_type_named(std::string_view name);

/// "NAME=TYPE" or a comma list "NAME=TYPE,NAME2=TYPE2" (GDAL's COLUMN_TYPES syntax), appended
/// to `out`. The last '=' of an item splits it, so a name may hold '=' but not ','.
/// @exception Error(InvalidArgument) for an item without '=', an empty name, or an unknown type
///   (naming the types).
void parse_field_types(std::string_view spec, std::vector<FieldTypeOverride>& out);

/// `text` as a value of declared type `type` (the file comment): its text as written for that
/// type ("" for null), or nullopt when it is not a value of that type.
std::optional<std::string> declared_value(FieldType type, std::string_view text);

/// "; did you mean 'pop'?" naming the column of `columns` nearest to `name` (edit distance below
/// 3, case-insensitive), or "" when none is that close.
std::string did_you_mean(const std::vector<std::string>& columns, std::string_view name);

/// Why `text` is not a value of declared type `type`: "'abc' is not an Integer (declared
/// Integer)", with "; it needs 64 bits: declare Integer64" for an integer beyond 32 bits.
std::string not_of_declared_type(FieldType type, std::string_view text);

/// Applies `declared` to `table` after its types were set (detected, the OGR layer's, or String):
/// each named column gets its declared type and every accepted row's value of it becomes
/// declared_value() (the same column named twice: the last wins).
/// @exception Error(InvalidArgument) for a name that is no column of the table (naming the
///   nearest column and the columns).
/// @exception Error(BadData) for a value that is not of the declared type: "FILE: row R (line
///   L), column 'pop': 'abc' is not an Integer (declared Integer)".
void apply_field_types(SiteTable& table, std::span<const FieldTypeOverride> declared);

}  // namespace geovor
