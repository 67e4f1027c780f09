#include "geovor/layers/site_layer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "geovor/layers/input_columns.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor {
namespace {

// The input columns kept: all but the positions.
std::vector<std::size_t> kept_columns(const SiteTable& table) {
  std::vector<std::size_t> columns;
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    const int ci = static_cast<int>(c);
    if (ci == table.lat_column || ci == table.lon_column ||
        std::find(table.ecef_columns.begin(), table.ecef_columns.end(), ci) != table.ecef_columns.end())
      continue;
    columns.push_back(c);
  }
  return columns;
}

}  // namespace

std::vector<Field> site_layer_schema(const SiteTable& table) {
  std::vector<Field> schema = {{"site_index", FieldType::Integer64}, {"site_id", FieldType::String},
                               {"lat_deg", FieldType::Real},         {"lon_deg", FieldType::Real},
                               {"moved_m", FieldType::Real}};
  const std::vector<Field> inputs = input_column_fields(table, kept_columns(table), schema);
  schema.insert(schema.end(), inputs.begin(), inputs.end());
  return schema;
}

std::unique_ptr<FeatureWriter> open_site_layer_writer(const std::string& path, const SiteTable& table,
                                                      WriterOptions options) {
  if (options.id_field.empty()) options.id_field = "site_id";
  return open_feature_writer(path, GeometryType::Point, site_layer_schema(table), options);
}

std::size_t write_site_layer(FeatureWriter& writer, const SiteTable& table, const SiteRows& rows,
                             const SphericalDelaunay& dt, std::span<const Vec3> start) {
  const std::vector<std::size_t> columns = kept_columns(table);
  std::vector<FieldValue> values(5 + columns.size());
  std::size_t written = 0;
  for (SiteId s = 0; s < dt.site_capacity(); ++s) {
    if (!dt.is_live(s)) continue;
    const InputSite& first = table.sites[rows.first(s)];
    const LatLon ll = SiteEncoder::to_lat_lon(dt.site(s));
    const Vec3 d = cross(start[s], dt.site(s));
    values[0] = static_cast<std::int64_t>(s);
    values[1] = first.id;
    values[2] = ll.lat_deg;
    values[3] = ll.lon_deg;
    values[4] = std::atan2(std::sqrt(norm2(d)), dot(start[s], dt.site(s))) * SiteEncoder::kEarthRadiusM;
    for (std::size_t k = 0; k < columns.size(); ++k)
      values[5 + k] = input_value(table, first, columns[k]);
    writer.write(LonLat{ll.lon_deg, ll.lat_deg}, values);
    ++written;
  }
  return written;
}

}  // namespace geovor
