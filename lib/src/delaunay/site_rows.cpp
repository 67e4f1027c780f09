#include "geovor/delaunay/site_rows.hpp"

namespace geovor {

SiteRows rows_of_sites(const BuildReport& report, std::size_t site_capacity) {
  const std::vector<SiteId>& site_of = report.site_of_input;
  std::vector<char> merged(site_of.size(), 0);
  for (const Merge& m : report.merges)
    if (m.input < merged.size()) merged[m.input] = 1;
  SiteRows rows;
  rows.begin.assign(site_capacity + 1, 0);
  for (const SiteId s : site_of)
    if (s < site_capacity) ++rows.begin[s + 1];
  for (std::size_t s = 0; s < site_capacity; ++s) rows.begin[s + 1] += rows.begin[s];
  rows.inputs.resize(rows.begin[site_capacity]);
  std::vector<std::uint32_t> fill(rows.begin.begin(), rows.begin.end() - 1);
  // The point each site was built from is its one input not merged: a first pass puts it first.
  for (const char merged_pass : {0, 1})
    for (std::uint32_t i = 0; i < site_of.size(); ++i)
      if (site_of[i] < site_capacity && merged[i] == merged_pass) rows.inputs[fill[site_of[i]]++] = i;
  return rows;
}

}  // namespace geovor
