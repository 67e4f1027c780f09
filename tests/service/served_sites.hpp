// Test data of the service tests: `n` sites s0..s(n-1) spread over the sphere, served whole.
#pragma once

#include <memory>
#include <string>

#include "geovor/geo/site_encoder.hpp"
#include "live_data.hpp"

namespace geovor::service {

inline std::shared_ptr<const ServedData> served_sites(std::size_t n) {
  SiteTable t;
  t.source = "served.csv";
  for (std::size_t i = 0; i < n; ++i) {
    InputSite s;
    s.row = i + 1;
    s.id = "s" + std::to_string(i);
    s.lat_deg = -60.0 + 120.0 * static_cast<double>(i) / static_cast<double>(n);
    s.lon_deg = static_cast<double>(i * 53 % 360) - 180;
    s.unit = SiteEncoder::from_lat_lon(s.lat_deg, s.lon_deg);
    t.sites.push_back(s);
  }
  t.rows_read = t.sites.size();
  return make_served_data(build_site_index(t), "", {});
}

}  // namespace geovor::service
