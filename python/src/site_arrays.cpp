#include "site_arrays.hpp"

#include "geovor/core/error.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_weights.hpp"

namespace geovor::python {

const double* column_data(const Doubles& a, const char* name, std::size_t& n) {
  if (a.ndim() != 1) throw Error(ErrorCode::InvalidArgument, std::string(name) + " must be one-dimensional");
  const std::size_t size = static_cast<std::size_t>(a.shape(0));
  if (n == static_cast<std::size_t>(-1)) n = size;
  if (size != n)
    throw Error(ErrorCode::InvalidArgument,
                std::string(name) + " has " + std::to_string(size) + " values, lat has " + std::to_string(n));
  return a.data();
}

SiteTable site_table_from_arrays(const Doubles& lat, const Doubles& lon, std::optional<std::vector<std::string>> ids) {
  std::size_t n = static_cast<std::size_t>(-1);
  const double* la = column_data(lat, "lat", n);
  const double* lo = column_data(lon, "lon", n);
  if (ids && ids->size() != n)
    throw Error(ErrorCode::InvalidArgument, "ids has " + std::to_string(ids->size()) + " values, lat has " + std::to_string(n));
  SiteTable table;
  table.source = "<arrays>";
  table.rows_read = n;
  table.sites.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    InputSite& s = table.sites[i];
    s.row = i + 1;
    s.lat_deg = la[i], s.lon_deg = lo[i];
    const std::string problem = normalize_lat_lon(s.lat_deg, s.lon_deg);
    if (!problem.empty()) throw Error(ErrorCode::BadData, "site " + std::to_string(i) + ": " + problem);
    s.unit = SiteEncoder::from_lat_lon(s.lat_deg, s.lon_deg);
    s.id = ids ? std::move((*ids)[i]) : std::to_string(i);
  }
  return table;
}

void set_radii(SiteTable& table, const Doubles& radii_m) {
  std::size_t n = table.sites.size();
  const double* r = column_data(radii_m, "weights", n);
  for (std::size_t i = 0; i < n; ++i) {
    if (std::string why = radius_problem(r[i]); !why.empty())
      throw Error(ErrorCode::InvalidArgument, "weights[" + std::to_string(i) + "]: " + why);
    table.sites[i].weight_m = r[i] + 0.0;  // -0 as 0
  }
  table.weighted = true;
}

}  // namespace geovor::python
