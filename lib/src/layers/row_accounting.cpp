#include "geovor/layers/row_accounting.hpp"

#include "geovor/core/ascii.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor {

void list_rejected_rows(std::FILE* log, const SiteTable& table) {
  if (log == nullptr) return;
  const std::string source = printable(table.source);
  for (const RejectedRow& r : table.rejected) {
    if (r.line > 0)
      std::fprintf(log, "%s: row %llu (line %llu) rejected: %s\n", source.c_str(), static_cast<unsigned long long>(r.row),
                   static_cast<unsigned long long>(r.line), printable(r.reason).c_str());
    else
      std::fprintf(log, "%s: row %llu rejected: %s\n", source.c_str(), static_cast<unsigned long long>(r.row),
                   printable(r.reason).c_str());
  }
}

void warn_duplicate_ids(std::FILE* log, const SiteTable& table, const DuplicateIds& duplicates,
                        std::string_view id_field) {
  if (log == nullptr || duplicates.rows == 0) return;
  std::string examples;
  for (const DuplicateIds::Example& e : duplicates.examples) {
    if (!examples.empty()) examples += "; ";
    examples += "'" + printable(e.id) + "' rows";
    for (const std::uint64_t row : e.rows) examples += " " + std::to_string(row);
  }
  const std::string column =
      table.id_column >= 0 ? printable(table.columns[static_cast<std::size_t>(table.id_column)]) : "";
  std::fprintf(log, "%s: warning: %llu rows have the id of an earlier row (id column '%s'; e.g. %s); %s '#row' makes the row number the id\n",
               printable(table.source).c_str(), static_cast<unsigned long long>(duplicates.rows), column.c_str(),
               examples.c_str(), std::string(id_field).c_str());
}

void list_merges(std::FILE* log, const SiteTable& table, const BuildReport& report) {
  if (log == nullptr || report.merges.empty()) return;
  // The row each site was built from comes first among its rows.
  const SiteRows rows = rows_of_sites(report, report.site_of_input.size());
  for (const Merge& m : report.merges) {
    const InputSite& row = table.sites[m.input];
    const InputSite& kept = table.sites[rows.first(m.site)];
    char why[96];
    if (m.chord == 0)
      std::snprintf(why, sizeof why, "same position");
    else
      std::snprintf(why, sizeof why, "%.3g m apart, closer than the merge distance%s",
                    m.chord * SiteEncoder::kEarthRadiusM, m.hidden ? " (hidden)" : "");
    std::fprintf(log, "%s: row %llu (id %s) merged into the site of row %llu (id %s): %s\n",
                 printable(table.source).c_str(), static_cast<unsigned long long>(row.row), printable(row.id).c_str(),
                 static_cast<unsigned long long>(kept.row), printable(kept.id).c_str(), why);
  }
}

void list_hidden(std::FILE* log, const SiteTable& table, const BuildReport& report) {
  if (log == nullptr || report.hidden.empty()) return;
  const SiteRows rows = rows_of_sites(report, report.site_of_input.size());
  for (const Hidden& h : report.hidden) {
    const InputSite& site = table.sites[rows.first(h.site)];
    const InputSite& by = table.sites[rows.first(h.by)];
    std::fprintf(log, "%s: row %llu (id '%s', radius %.17g m) is hidden: its power cell is empty (row %llu, id '%s', radius %.17g m, holds its position)\n",
                 printable(table.source).c_str(), static_cast<unsigned long long>(site.row), printable(site.id).c_str(),
                 site.weight_m, static_cast<unsigned long long>(by.row), printable(by.id).c_str(), by.weight_m);
  }
}

std::string row_counts(const SiteTable& table, std::size_t sites, std::size_t merged) {
  return table.source + ": rows " + std::to_string(table.rows_read) + ", sites " + std::to_string(sites) +
         ", merged " + std::to_string(merged) + ", rejected " + std::to_string(table.rejected.size());
}

}  // namespace geovor
