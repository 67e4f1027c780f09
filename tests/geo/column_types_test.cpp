#include "geovor/geo/column_types.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"

namespace geovor {
namespace {

TEST(ColumnTypes, IntegersBy32And64Bits) {
  EXPECT_EQ(value_type("0"), FieldType::Integer);
  EXPECT_EQ(value_type("-17"), FieldType::Integer);
  EXPECT_EQ(value_type("2147483647"), FieldType::Integer);
  EXPECT_EQ(value_type("-2147483648"), FieldType::Integer);
  EXPECT_EQ(value_type("2147483648"), FieldType::Integer64);
  EXPECT_EQ(value_type("-2147483649"), FieldType::Integer64);
  EXPECT_EQ(value_type("9223372036854775807"), FieldType::Integer64);
  EXPECT_EQ(value_type("-9223372036854775808"), FieldType::Integer64);
  // Beyond 64 bits a Real would lose digits of an identifier.
  EXPECT_EQ(value_type("9223372036854775808"), FieldType::String);
  EXPECT_EQ(value_type("12345678901234567890123"), FieldType::String);
}

TEST(ColumnTypes, RealsAreJsonNumbers) {
  EXPECT_EQ(value_type("47.4489"), FieldType::Real);
  EXPECT_EQ(value_type("-0.5"), FieldType::Real);
  EXPECT_EQ(value_type("1e5"), FieldType::Real);
  EXPECT_EQ(value_type("6.02E+23"), FieldType::Real);
  EXPECT_EQ(value_type("1.5e-300"), FieldType::Real);
  EXPECT_EQ(value_type("1e999"), FieldType::String);  // no double
  EXPECT_EQ(value_type(".5"), FieldType::String);
  EXPECT_EQ(value_type("1."), FieldType::String);
  EXPECT_EQ(value_type("1,5"), FieldType::String);
  EXPECT_EQ(value_type("1e"), FieldType::String);
  EXPECT_EQ(value_type("NaN"), FieldType::String);
  EXPECT_EQ(value_type("inf"), FieldType::String);
  EXPECT_EQ(value_type("-"), FieldType::String);
}

TEST(ColumnTypes, IdentifiersStayText) {
  EXPECT_EQ(value_type("007"), FieldType::String);
  EXPECT_EQ(value_type("00.5"), FieldType::String);
  EXPECT_EQ(value_type("-007"), FieldType::String);
  EXPECT_EQ(value_type("+33"), FieldType::String);
  EXPECT_EQ(value_type(" 12"), FieldType::String);
  EXPECT_EQ(value_type("12 "), FieldType::String);
  EXPECT_EQ(value_type("KSEA"), FieldType::String);
  EXPECT_EQ(value_type(""), FieldType::String);
}

TEST(ColumnTypes, DatesAndDateTimes) {
  EXPECT_EQ(value_type("2024-02-29"), FieldType::Date);
  EXPECT_EQ(value_type("2023-02-29"), FieldType::String);  // not a day
  EXPECT_EQ(value_type("1900-02-29"), FieldType::String);
  EXPECT_EQ(value_type("2000-02-29"), FieldType::Date);
  EXPECT_EQ(value_type("2024-13-01"), FieldType::String);
  EXPECT_EQ(value_type("2024-04-31"), FieldType::String);
  EXPECT_EQ(value_type("2024/02/29"), FieldType::String);
  EXPECT_EQ(value_type("2024-02-29T13:05"), FieldType::DateTime);
  EXPECT_EQ(value_type("2024-02-29 13:05:59"), FieldType::DateTime);
  EXPECT_EQ(value_type("2024-02-29T13:05:59.125Z"), FieldType::DateTime);
  EXPECT_EQ(value_type("2024-02-29T13:05:59+02:00"), FieldType::DateTime);
  EXPECT_EQ(value_type("2024-02-29T13:05:59-0530"), FieldType::DateTime);
  EXPECT_EQ(value_type("2024-02-29T13:05:59+05"), FieldType::DateTime);
  EXPECT_EQ(value_type("2024-02-29T13:05:59.1234"), FieldType::String);  // GDAL keeps milliseconds
  EXPECT_EQ(value_type("2024-02-29T13:05:59+05:20"), FieldType::String);  // not in quarters
  EXPECT_EQ(value_type("2024-02-29T24:00"), FieldType::String);
  EXPECT_EQ(value_type("2024-02-29T13"), FieldType::String);
  EXPECT_EQ(value_type("2024-02-29Z"), FieldType::String);
}

TEST(ColumnTypes, WiderType) {
  EXPECT_EQ(wider_type(FieldType::Integer, FieldType::Integer64), FieldType::Integer64);
  EXPECT_EQ(wider_type(FieldType::Integer64, FieldType::Real), FieldType::Real);
  EXPECT_EQ(wider_type(FieldType::Integer, FieldType::Real), FieldType::Real);
  EXPECT_EQ(wider_type(FieldType::Date, FieldType::DateTime), FieldType::DateTime);
  EXPECT_EQ(wider_type(FieldType::Date, FieldType::Integer), FieldType::String);
  EXPECT_EQ(wider_type(FieldType::Real, FieldType::String), FieldType::String);
}

SiteTable table(const std::vector<std::string>& columns, const std::vector<std::vector<std::string>>& rows,
                int id_column) {
  SiteTable t;
  t.columns = columns;
  t.id_column = id_column;
  for (const auto& r : rows) t.sites.push_back(InputSite{.fields = r});
  return t;
}

TEST(ColumnTypes, ColumnsTakeTheNarrowestTypeOfTheirValues) {
  const SiteTable t = table({"code", "lat", "pop", "big", "mixed", "day", "when", "empty", "zip", "short"},
                            {{"A1", "47.5", "12", "1", "1", "2024-01-01", "2024-01-01", "", "02134", "1"},
                             {"A2", "-3", "", "3000000000", "x", "", "2024-01-01T10:00Z", "", "90210"},
                             {"A3", "1e2", "7", "2", "2", "2024-12-31", "2024-01-02", "", "10001", "2"}},
                            0);
  const std::vector<FieldType> expected = {FieldType::String,  FieldType::Real,   FieldType::Integer,
                                           FieldType::Integer64, FieldType::String, FieldType::Date,
                                           FieldType::DateTime, FieldType::String, FieldType::String,
                                           FieldType::Integer};
  EXPECT_EQ(detect_column_types(t), expected);
}

TEST(ColumnTypes, TheIdColumnStaysText) {
  const SiteTable t = table({"id", "n"}, {{"1", "1"}, {"2", "2"}}, 0);
  EXPECT_EQ(detect_column_types(t), (std::vector<FieldType>{FieldType::String, FieldType::Integer}));
  const SiteTable no_id = table({"id", "n"}, {{"1", "1"}, {"2", "2"}}, -1);
  EXPECT_EQ(detect_column_types(no_id), (std::vector<FieldType>{FieldType::Integer, FieldType::Integer}));
}

TEST(ColumnTypes, TypeNamesAreCaseInsensitive) {
  EXPECT_EQ(field_type_named("integer64"), FieldType::Integer64);
  EXPECT_EQ(field_type_named("DATETIME"), FieldType::DateTime);
  EXPECT_EQ(field_type_named("string"), FieldType::String);
  EXPECT_EQ(field_type_named("int"), std::nullopt);
  EXPECT_EQ(field_type_named(""), std::nullopt);
}

TEST(ColumnTypes, FieldTypeSpecsAreGdalsColumnTypes) {
  std::vector<FieldTypeOverride> out;
  parse_field_types("zip=Integer, when = datetime", out);
  parse_field_types("code=String", out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].column, "zip");
  EXPECT_EQ(out[0].type, FieldType::Integer);
  EXPECT_EQ(out[1].column, "when");
  EXPECT_EQ(out[1].type, FieldType::DateTime);
  EXPECT_EQ(out[2].column, "code");
  EXPECT_EQ(out[2].type, FieldType::String);
  for (const char* bad : {"zip", "=Integer", "zip=int", "zip=Integer,", "zip=Integer,pop"}) {
    std::vector<FieldTypeOverride> v;
    try {
      parse_field_types(bad, v);
      ADD_FAILURE() << bad << " accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << bad;
    }
  }
}

TEST(ColumnTypes, DeclaredValuesAreReadLeniently) {
  // Integers: a sign, leading zeros and spaces are the user's choice to read as numbers.
  EXPECT_EQ(declared_value(FieldType::Integer, "007"), "7");
  EXPECT_EQ(declared_value(FieldType::Integer, "+33"), "33");
  EXPECT_EQ(declared_value(FieldType::Integer, " -12 "), "-12");
  EXPECT_EQ(declared_value(FieldType::Integer, "-000"), "0");
  EXPECT_EQ(declared_value(FieldType::Integer, "2147483647"), "2147483647");
  EXPECT_EQ(declared_value(FieldType::Integer, "2147483648"), std::nullopt);
  EXPECT_EQ(declared_value(FieldType::Integer64, "2147483648"), "2147483648");
  EXPECT_EQ(declared_value(FieldType::Integer64, "9223372036854775808"), std::nullopt);
  EXPECT_EQ(declared_value(FieldType::Integer, "1.5"), std::nullopt);
  EXPECT_EQ(declared_value(FieldType::Integer, "abc"), std::nullopt);
  EXPECT_EQ(declared_value(FieldType::Integer, "+"), std::nullopt);
  // Reals: a JSON number stays as written, the others become their double's shortest text.
  EXPECT_EQ(declared_value(FieldType::Real, "47.5"), "47.5");
  EXPECT_EQ(declared_value(FieldType::Real, "12"), "12");
  EXPECT_EQ(declared_value(FieldType::Real, ".5"), "0.5");
  EXPECT_EQ(declared_value(FieldType::Real, "1."), "1");
  EXPECT_EQ(declared_value(FieldType::Real, "+2.25"), "2.25");
  EXPECT_EQ(declared_value(FieldType::Real, "007.5"), "7.5");
  EXPECT_EQ(declared_value(FieldType::Real, "1e999"), std::nullopt);
  EXPECT_EQ(declared_value(FieldType::Real, "nan"), std::nullopt);
  EXPECT_EQ(declared_value(FieldType::Real, "1,5"), std::nullopt);
  EXPECT_EQ(declared_value(FieldType::Real, "."), std::nullopt);
  // Dates: ISO 8601; a DateTime column takes a Date.
  EXPECT_EQ(declared_value(FieldType::Date, "2024-02-29"), "2024-02-29");
  EXPECT_EQ(declared_value(FieldType::Date, "2023-02-29"), std::nullopt);
  EXPECT_EQ(declared_value(FieldType::Date, "2024-02-29T10:00Z"), std::nullopt);
  EXPECT_EQ(declared_value(FieldType::DateTime, "2024-02-29T10:00Z"), "2024-02-29T10:00Z");
  EXPECT_EQ(declared_value(FieldType::DateTime, "2024-02-29"), "2024-02-29");
  EXPECT_EQ(declared_value(FieldType::DateTime, "29/02/2024"), std::nullopt);
  // Empty is null; a String keeps its text, spaces included.
  EXPECT_EQ(declared_value(FieldType::Integer, ""), "");
  EXPECT_EQ(declared_value(FieldType::Integer, "  "), "");
  EXPECT_EQ(declared_value(FieldType::String, " 007 "), " 007 ");
}

TEST(ColumnTypes, DeclaredTypesReplaceDetectedOnesTheIdColumnsToo) {
  SiteTable t = table({"id", "zip", "pop", "note"}, {{"007", "02134", "12", "x"}, {"10", "90210", "", "y"}}, 0);
  t.source = "t.csv";
  t.column_types = detect_column_types(t);
  const std::vector<FieldTypeOverride> declared = {{"ID", FieldType::Integer}, {"zip", FieldType::Integer},
                                                   {"pop", FieldType::String}};
  apply_field_types(t, declared);
  EXPECT_EQ(t.column_types, (std::vector<FieldType>{FieldType::Integer, FieldType::Integer, FieldType::String,
                                                     FieldType::String}));
  EXPECT_EQ(t.sites[0].fields, (std::vector<std::string>{"7", "2134", "12", "x"}));
  EXPECT_EQ(t.sites[1].fields, (std::vector<std::string>{"10", "90210", "", "y"}));
}

TEST(ColumnTypes, AValueNotOfItsDeclaredTypeIsBadDataNamingRowColumnValueAndType) {
  SiteTable t = table({"id", "pop"}, {{"a", "12"}, {"b", "3000000000"}}, 0);
  t.source = "t.csv";
  t.sites[1].row = 2;
  t.sites[1].line = 3;
  const std::vector<FieldTypeOverride> declared = {{"pop", FieldType::Integer}};
  try {
    apply_field_types(t, declared);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadData);
    EXPECT_EQ(std::string(e.what()),
              "t.csv: row 2 (line 3), column 'pop': '3000000000' is not an Integer (declared Integer); it needs 64 "
              "bits: declare Integer64");
  }
}

TEST(ColumnTypes, AnUnknownColumnIsAUsageErrorWithTheNearestName) {
  SiteTable t = table({"id", "population"}, {{"a", "12"}}, 0);
  t.source = "t.csv";
  const std::vector<FieldTypeOverride> declared = {{"popluation", FieldType::Integer}};
  try {
    apply_field_types(t, declared);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
    EXPECT_EQ(std::string(e.what()),
              "t.csv: --field-type names 'popluation', which is no column; did you mean 'population'? (columns: id, "
              "population)");
  }
}

}  // namespace
}  // namespace geovor
