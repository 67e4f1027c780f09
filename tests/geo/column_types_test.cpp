#include "geovor/geo/column_types.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

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

}  // namespace
}  // namespace geovor
