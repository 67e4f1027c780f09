#include "geovor/layers/input_columns.hpp"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <set>

#include "geovor/core/ascii.hpp"
#include "geovor/core/assert.hpp"
#include "geovor/io/json_text.hpp"

namespace geovor {
namespace {

bool is_number(FieldType t) { return t == FieldType::Integer || t == FieldType::Integer64 || t == FieldType::Real; }

}  // namespace

std::vector<Field> input_column_fields(const SiteTable& table, std::span<const std::size_t> columns,
                                       const std::vector<Field>& own) {
  std::set<std::string> taken;  // lower case
  for (const Field& f : own) taken.insert(ascii_lower(f.name));
  for (const std::string_view name : kReservedFieldNames) taken.insert(std::string(name));
  // A renamed column must not take the name of another input column either.
  std::set<std::string> inputs;
  for (const std::size_t c : columns) inputs.insert(ascii_lower(table.columns[c]));
  std::vector<Field> fields;
  for (const std::size_t c : columns) {
    std::string name = table.columns[c];
    if (taken.count(ascii_lower(name)) != 0) {
      do name = "src_" + name;
      while (taken.count(ascii_lower(name)) != 0 || inputs.count(ascii_lower(name)) != 0);
    }
    taken.insert(ascii_lower(name));
    fields.push_back({name, table.column_type(c)});
  }
  return fields;
}

FieldValue typed_value(FieldType type, const std::string& text) {
  if (type == FieldType::String) return text;
  if (text.empty()) return {};
  if (type == FieldType::Integer || type == FieldType::Integer64) {
    std::int64_t v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    GEOVOR_ASSERT(r.ec == std::errc() && r.ptr == text.data() + text.size());
    return v;
  }
  if (type == FieldType::Real) {
    double v = 0;
    const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
    GEOVOR_ASSERT(r.ec == std::errc() && r.ptr == text.data() + text.size());
    return v;
  }
  return text;  // Date, DateTime: ISO 8601 text
}

FieldValue input_value(const SiteTable& table, const InputSite& site, std::size_t c) {
  if (c >= site.fields.size()) return {};
  return typed_value(table.column_type(c), site.fields[c]);
}

void append_input_json(std::string& out, const SiteTable& table, const InputSite& site, std::size_t c) {
  if (c >= site.fields.size()) {
    out += "null";
    return;
  }
  const std::string& text = site.fields[c];
  const FieldType type = table.column_type(c);
  if (type == FieldType::String) {
    append_json_string(out, text);
  } else if (text.empty()) {
    out += "null";
  } else if (is_number(type)) {
    out += text;
  } else {
    append_json_string(out, text);
  }
}

}  // namespace geovor
