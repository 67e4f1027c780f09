#include "geovor/layers/input_columns.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace geovor {
namespace {

SiteTable typed_table() {
  SiteTable t;
  t.columns = {"name", "pop", "lat", "day", "fid", "GEOM", "src_fid", "area_m2"};
  t.column_types = {FieldType::String, FieldType::Integer64, FieldType::Real, FieldType::Date,
                    FieldType::Integer, FieldType::String, FieldType::String, FieldType::Real};
  InputSite s;
  s.fields = {"Zürich \"Z\"", "", "47.5", "2024-02-29", "7", "", "x", "1e3"};
  t.sites.push_back(s);
  InputSite short_row;
  short_row.fields = {"short"};
  t.sites.push_back(short_row);
  return t;
}

TEST(InputColumns, ReservedAndOwnNamesAreRenamedUniquely) {
  const SiteTable t = typed_table();
  const std::vector<std::size_t> columns = {0, 1, 2, 3, 4, 5, 6, 7};
  const std::vector<Field> own = {{"site_index", FieldType::Integer64}, {"area_m2", FieldType::Real}};
  const std::vector<Field> fields = input_column_fields(t, columns, own);
  const std::vector<std::string> names = {"name", "pop", "lat", "day", "src_src_fid", "src_GEOM", "src_fid",
                                          "src_area_m2"};
  ASSERT_EQ(fields.size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    EXPECT_EQ(fields[i].name, names[i]);
    EXPECT_EQ(fields[i].type, t.column_types[i]) << names[i];
  }
}

TEST(InputColumns, ValuesTypedEmptyIsNull) {
  const SiteTable t = typed_table();
  const InputSite& s = t.sites[0];
  EXPECT_EQ(std::get<std::string>(input_value(t, s, 0)), "Zürich \"Z\"");
  EXPECT_TRUE(std::holds_alternative<std::monostate>(input_value(t, s, 1)));  // empty Integer64
  EXPECT_EQ(std::get<double>(input_value(t, s, 2)), 47.5);
  EXPECT_EQ(std::get<std::string>(input_value(t, s, 3)), "2024-02-29");
  EXPECT_EQ(std::get<std::int64_t>(input_value(t, s, 4)), 7);
  EXPECT_EQ(std::get<std::string>(input_value(t, s, 5)), "");  // an empty String stays text
  EXPECT_EQ(std::get<double>(input_value(t, s, 7)), 1000.0);
  EXPECT_TRUE(std::holds_alternative<std::monostate>(input_value(t, t.sites[1], 2)));  // short row
}

TEST(InputColumns, JsonNumbersUnquoted) {
  const SiteTable t = typed_table();
  std::string out;
  for (std::size_t c = 0; c < t.columns.size(); ++c) {
    if (c) out += ',';
    append_input_json(out, t, t.sites[0], c);
  }
  EXPECT_EQ(out, R"("Zürich \"Z\"",null,47.5,"2024-02-29",7,"","x",1e3)");
  out.clear();
  append_input_json(out, t, t.sites[1], 2);
  EXPECT_EQ(out, "null");
}

TEST(InputColumns, WithoutTypesEveryColumnIsText) {
  SiteTable t = typed_table();
  t.column_types.clear();
  EXPECT_EQ(std::get<std::string>(input_value(t, t.sites[0], 2)), "47.5");
  EXPECT_EQ(std::get<std::string>(input_value(t, t.sites[0], 1)), "");
}

}  // namespace
}  // namespace geovor
