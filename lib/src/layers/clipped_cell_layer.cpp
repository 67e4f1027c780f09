#include "geovor/layers/clipped_cell_layer.hpp"

#include <algorithm>
#include <numeric>
#include <string>

#include "geovor/core/ascii.hpp"
#include "geovor/io/number_format.hpp"
#include "geovor/layers/input_columns.hpp"

namespace geovor {
namespace {

constexpr const char* kKeys[] = {"site_index", "site_id", "region_index", "region_id", "area_m2", "region_share"};
constexpr FieldType kKeyTypes[] = {FieldType::Integer, FieldType::String, FieldType::Integer,
                                   FieldType::String,  FieldType::Real,   FieldType::Real};
constexpr const char* kWeightField = "weight_m";

bool taken(const std::vector<Field>& fields, const std::string& name) {
  return std::any_of(fields.begin(), fields.end(), [&](const Field& f) { return ascii_iequals(f.name, name); });
}

std::string site_id(const SiteTable& table, const SiteRows& rows, SiteId s) {
  const std::uint32_t row = rows.first(s);
  return row == kNoIndex ? std::to_string(s) : table.sites[row].id;
}

void append_csv(std::string& out, std::string_view field) {
  if (field.find_first_of(",\"\r\n") == std::string_view::npos) {
    out += field;
    return;
  }
  out += '"';
  for (const char c : field) out += c == '"' ? std::string_view("\"\"") : std::string_view(&c, 1);
  out += '"';
}

std::string real(double v) {
  std::string out;
  append_real(out, v);
  return out;
}

}  // namespace

std::vector<Field> clipped_cell_layer_schema(const SiteTable& table, const RegionTable& regions) {
  std::vector<Field> schema;
  for (std::size_t i = 0; i < std::size(kKeys); ++i) schema.push_back({kKeys[i], kKeyTypes[i], false});
  if (table.weighted) schema.push_back({kWeightField, FieldType::Real, false});
  std::vector<std::size_t> columns(table.columns.size());
  std::iota(columns.begin(), columns.end(), std::size_t{0});
  const std::vector<Field> inputs = input_column_fields(table, columns, schema);
  schema.insert(schema.end(), inputs.begin(), inputs.end());
  for (const Field& f : regions.fields) {
    std::string name = "region_" + f.name;
    while (taken(schema, name)) name = "src_" + name;
    schema.push_back({name, f.type, false});
  }
  return schema;
}

void write_clipped_cells(FeatureWriter& writer, const SiteTable& table, const SiteRows& rows, const RegionTable& regions,
                         const std::vector<ClipPiece>& pieces) {
  std::vector<FieldValue> values;
  for (const ClipPiece& p : pieces) {
    const Region& region = regions.regions[p.region];
    const std::uint32_t row = rows.first(p.site);
    values.clear();
    values.emplace_back(static_cast<std::int64_t>(p.site));
    values.emplace_back(site_id(table, rows, p.site));
    values.emplace_back(static_cast<std::int64_t>(p.region));
    values.emplace_back(region.id);
    values.emplace_back(p.area_m2);
    values.emplace_back(p.region_share);
    if (table.weighted) values.emplace_back(row == kNoIndex ? FieldValue{} : FieldValue{table.sites[row].weight_m});
    for (std::size_t c = 0; c < table.columns.size(); ++c)
      values.push_back(row == kNoIndex ? FieldValue{} : input_value(table, table.sites[row], c));
    values.insert(values.end(), region.values.begin(), region.values.end());
    writer.write(p.geometry, values);
  }
}

void write_clip_weights_csv(const std::function<void(std::string_view)>& write, const SiteTable& table,
                            const SiteRows& rows, const RegionTable& regions, const std::vector<ClipPiece>& pieces) {
  std::vector<const ClipPiece*> order(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) order[i] = &pieces[i];
  std::stable_sort(order.begin(), order.end(), [](const ClipPiece* a, const ClipPiece* b) {
    return a->region != b->region ? a->region < b->region : a->site < b->site;
  });
  std::string out = "region_index,region_id,site_index,site_id,region_share,area_m2\n";
  for (const ClipPiece* p : order) {
    out += std::to_string(p->region) + ",";
    append_csv(out, regions.regions[p->region].id);
    out += "," + std::to_string(p->site) + ",";
    append_csv(out, site_id(table, rows, p->site));
    out += "," + real(p->region_share) + "," + real(p->area_m2) + "\n";
    if (out.size() > (std::size_t{1} << 16)) {
      write(out);
      out.clear();
    }
  }
  write(out);
}

}  // namespace geovor
