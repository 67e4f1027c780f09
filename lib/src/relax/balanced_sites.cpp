#include "geovor/relax/balanced_sites.hpp"

#include <cstdio>
#include <vector>

#include "geovor/core/output_file.hpp"

namespace geovor {

bool apply_balance(SiteTable& table, const BalanceReport& result) {
  for (std::size_t i = 0; i < table.sites.size(); ++i) table.sites[i].weight_m = result.radii_m[i];
  table.weighted = true;
  if (find_column(table.columns, kTargetField) >= 0) return false;
  if (table.column_types.empty()) table.column_types.assign(table.columns.size(), FieldType::String);
  table.columns.push_back(kTargetField);
  table.column_types.push_back(FieldType::Real);
  char text[32];
  for (std::size_t i = 0; i < table.sites.size(); ++i) {
    std::vector<std::string>& fields = table.sites[i].fields;
    fields.resize(table.columns.size() - 1);  // a short row's missing values are empty
    std::snprintf(text, sizeof text, "%.17g", result.targets[i]);
    fields.push_back(text);
  }
  return true;
}

void write_balanced_sites(const std::string& path, bool overwrite, const SiteTable& table, const BuildReport& build,
                          const BalanceReport& result) {
  std::vector<char> merged(table.sites.size(), 0);
  for (const Merge& m : build.merges) merged[m.input] = 1;
  OutputFile out(path, overwrite);
  std::FILE* f = out.get();
  std::fprintf(f, "site_id,lat_deg,lon_deg,weight_m,target_m2\n");
  for (std::size_t i = 0; i < table.sites.size(); ++i) {
    if (merged[i]) continue;
    const InputSite& s = table.sites[i];
    std::string id = "\"";
    for (const char ch : s.id) id += ch == '"' ? std::string("\"\"") : std::string(1, ch);
    std::fprintf(f, "%s\",%.17g,%.17g,%.17g,%.17g\n", id.c_str(), s.lat_deg, s.lon_deg, result.radii_m[i],
                 result.targets[i]);
  }
  out.commit();
}

}  // namespace geovor
