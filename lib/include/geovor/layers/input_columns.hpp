/// \file input_columns.hpp
/// \brief The input columns of a SiteTable as fields of a layer (the cell and site layers carry
/// them after their own fields): names, types and each row's values.
///
/// Names: a column keeps its name unless it equals, ASCII case-insensitively, a field of the
/// layer's own or a name an output format reserves for itself (kReservedFieldNames: GeoPackage's
/// `fid` and `geom`, SQLite's and PostGIS' `ogc_fid` and `wkb_geometry`, the CSV driver's `wkt`,
/// ...); then it becomes `src_NAME` (`src_src_NAME` if that is taken too, and so on). The rule is
/// the same for every output format, so a column has one name in all of them.
///
/// Types: the table's column types (SiteTable::column_types, column_types.hpp). Values: an
/// Integer or Integer64 column's text as std::int64_t, a Real's as double, the others' text; an
/// empty value of a column that is not String, and a field missing from a short row, are null.
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "geovor/geo/site_reader.hpp"
#include "geovor/io/feature_writer.hpp"

namespace geovor {

/// Names some output format gives its own columns (the file comment), lower case.
inline constexpr std::array<std::string_view, 9> kReservedFieldNames = {
    "fid", "ogc_fid", "geom", "geometry", "the_geom", "wkb_geometry", "wkt", "gml_id", "shape"};

/// The fields of `columns` (indices into table.columns, in that order) after the layer's `own`
/// fields (the file comment).
std::vector<Field> input_column_fields(const SiteTable& table, std::span<const std::size_t> columns,
                                       const std::vector<Field>& own);

/// `text` as a value of a column of type `type` (column_types.hpp): a number column's text
/// parsed (the type guarantees it parses: a bug otherwise), empty text null; other types as text.
FieldValue typed_value(FieldType type, const std::string& text);

/// The value of column c of `site` (the file comment).
FieldValue input_value(const SiteTable& table, const InputSite& site, std::size_t c);

/// Appends the JSON text of input_value(table, site, c) as the GeoJSON writer writes it: a
/// number column's text as it stands (a JSON number: column_types.hpp), null, or a string.
void append_input_json(std::string& out, const SiteTable& table, const InputSite& site, std::size_t c);

}  // namespace geovor
