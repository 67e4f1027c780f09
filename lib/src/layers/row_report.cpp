#include "geovor/layers/row_report.hpp"

#include <algorithm>

#include "geovor/core/ascii.hpp"

namespace geovor {
namespace {

// A CSV text value: quoted, control characters escaped (printable), quotes doubled.
std::string quoted(const std::string& raw) {
  std::string q = "\"";
  for (const char c : printable(raw)) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// The status and detail of an accepted row whose site is `site`.
const char* row_status(SiteId site, bool merged, const BuildReport& report, const std::vector<UnwrittenCell>& unwritten,
                       const std::string& at, std::string& detail) {
  const auto it = std::lower_bound(unwritten.begin(), unwritten.end(), site,
                                   [](const UnwrittenCell& c, SiteId s) { return c.site < s; });
  const auto hidden = std::lower_bound(report.hidden.begin(), report.hidden.end(), site,
                                       [](const Hidden& h, SiteId s) { return h.site < s; });
  if (hidden != report.hidden.end() && hidden->site == site && !merged) {
    detail = quoted("power cell empty: site " + std::to_string(hidden->by) + " holds its position");
    return "hidden";
  }
  if (it != unwritten.end() && it->site == site)
    detail = quoted("cell " + std::string(to_string(it->status)) + " " + at + ": empty geometry");
  return merged ? "merged" : "site";
}

}  // namespace

void write_row_report(std::FILE* out, const SiteTable& table, const BuildReport& report,
                      const std::vector<UnwrittenCell>& unwritten, const std::string& at) {
  std::fprintf(out, "row,line,id,status,site_index,detail\n");
  std::vector<char> merged(table.sites.size(), 0);
  for (const Merge& m : report.merges) merged[m.input] = 1;
  for (std::size_t i = 0; i < table.sites.size(); ++i) {
    const InputSite& row = table.sites[i];
    const SiteId site = report.site_of_input[i];
    std::string detail;
    const char* status = row_status(site, merged[i], report, unwritten, at, detail);
    std::fprintf(out, "%llu,%llu,%s,%s,%u,%s\n", static_cast<unsigned long long>(row.row),
                 static_cast<unsigned long long>(row.line), quoted(row.id).c_str(), status, site, detail.c_str());
  }
  for (const RejectedRow& r : table.rejected)
    std::fprintf(out, "%llu,%llu,,rejected,,%s\n", static_cast<unsigned long long>(r.row),
                 static_cast<unsigned long long>(r.line), quoted(r.reason).c_str());
}

}  // namespace geovor
