/// \file row_accounting.hpp
/// \brief What became of the rows of a site table, said on a log stream (the geovor command's
/// stderr): each rejected row and why, the ids that repeat, each row merged into another row's
/// site, each hidden weighted site, and the counts a run ends with. Every function says nothing
/// when the log is null. Values from the input are made printable (core/ascii.hpp), so that a row
/// is said on one line whatever its bytes.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_reader.hpp"

namespace geovor {

/// Lists table.rejected in row order: "SOURCE: row R (line L) rejected: REASON", or "SOURCE: row R
/// rejected: REASON" for a row without a line (an OGR feature: its reason names the feature).
void list_rejected_rows(std::FILE* log, const SiteTable& table);

/// Says once that ids repeat (nothing when duplicates.rows is 0): "SOURCE: warning: N rows have the
/// id of an earlier row (id column 'C'; e.g. 'X' rows 1 2; 'Y' rows 3 5); ID_FIELD '#row' makes the
/// row number the id", where ID_FIELD is what the caller's users call SiteReaderOptions::id_field
/// (the geovor command: --id-field).
void warn_duplicate_ids(std::FILE* log, const SiteTable& table, const DuplicateIds& duplicates,
                        std::string_view id_field = "id_field");

/// Lists each merge of `report` (a build of table.sites' positions): "SOURCE: row R (id X) merged
/// into the site of row K (id Y): same position" (or "D m apart, closer than the merge distance").
void list_merges(std::FILE* log, const SiteTable& table, const BuildReport& report);

/// Lists each hidden weighted site of `report` with its row and radius, and the row and radius of
/// a site whose power cell holds its position.
void list_hidden(std::FILE* log, const SiteTable& table, const BuildReport& report);

/// "SOURCE: rows N, sites S, merged M, rejected R": the counts that a run's summary line starts with
/// (the source as named, not made printable).
std::string row_counts(const SiteTable& table, std::size_t sites, std::size_t merged);

}  // namespace geovor
