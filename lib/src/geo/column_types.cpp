#include "geovor/geo/column_types.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "geo/trim.hpp"
#include "geovor/core/ascii.hpp"
#include "geovor/core/error.hpp"

namespace geovor {
namespace {

bool digit(char c) { return c >= '0' && c <= '9'; }

// The number of leading digits of s from `at`.
std::size_t digits(std::string_view s, std::size_t at) {
  std::size_t n = at;
  while (n < s.size() && digit(s[n])) ++n;
  return n - at;
}

// The two-digit number at s[at] (both digits checked by the caller's length test), or -1.
int two(std::string_view s, std::size_t at) {
  if (!digit(s[at]) || !digit(s[at + 1])) return -1;
  return (s[at] - '0') * 10 + (s[at + 1] - '0');
}

// YYYY-MM-DD, a real day of the (proleptic Gregorian) calendar.
bool is_date(std::string_view s) {
  if (s.size() < 10 || s[4] != '-' || s[7] != '-' || digits(s, 0) != 4) return false;
  const int year = (s[0] - '0') * 1000 + (s[1] - '0') * 100 + (s[2] - '0') * 10 + (s[3] - '0');
  const int month = two(s, 5), day = two(s, 8);
  if (month < 1 || month > 12 || day < 1) return false;
  static constexpr int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  return day <= kDays[month - 1] + (month == 2 && leap ? 1 : 0);
}

// What follows a date in a DateTime: [T ]HH:MM[:SS[.s{1,3}]][Z|+HH|+HHMM|+HH:MM].
bool is_time_part(std::string_view s) {
  if (s.size() < 6 || (s[0] != 'T' && s[0] != ' ') || s[3] != ':') return false;
  const int hour = two(s, 1), minute = two(s, 4);
  if (hour < 0 || hour > 23 || minute < 0 || minute > 59) return false;
  std::size_t at = 6;
  if (at < s.size() && s[at] == ':') {
    if (s.size() < at + 3) return false;
    const int second = two(s, at + 1);
    if (second < 0 || second > 60) return false;  // 60: a leap second
    at += 3;
    if (at < s.size() && s[at] == '.') {
      const std::size_t n = digits(s, at + 1);
      if (n < 1 || n > 3) return false;  // GDAL keeps milliseconds: more would be cut
      at += 1 + n;
    }
  }
  if (at == s.size()) return true;
  if (s[at] == 'Z') return at + 1 == s.size();
  if (s[at] != '+' && s[at] != '-') return false;
  const std::string_view zone = s.substr(at + 1);
  int zone_minutes = 0;
  if (zone.size() == 2) {
    zone_minutes = 0;
  } else if (zone.size() == 4) {
    zone_minutes = two(zone, 2);
  } else if (zone.size() == 5 && zone[2] == ':') {
    zone_minutes = two(zone, 3);
  } else {
    return false;
  }
  const int zone_hours = two(zone, 0);
  // GDAL holds an offset in quarters of an hour.
  return zone_hours >= 0 && zone_hours <= 14 && zone_minutes >= 0 && zone_minutes % 15 == 0;
}

// Whether the integer text t (digits, an optional '-' before) fits the bounds of 32 or 64 bits.
bool fits(std::string_view t, const char* max_positive, const char* max_negative) {
  const bool negative = t[0] == '-';
  const std::string_view d = negative ? t.substr(1) : t;
  const std::string_view max = negative ? max_negative : max_positive;
  if (d.size() != max.size()) return d.size() < max.size();
  return d <= max;
}

// "an Integer", "a Real".
std::string with_article(FieldType t) {
  const std::string name = to_string(t);
  return (name[0] == 'I' ? "an " : "a ") + name;
}

}  // namespace

FieldType value_type(std::string_view s) {
  if (s.empty()) return FieldType::String;
  const char c = s[0];
  if (c == '-' || digit(c)) {
    std::size_t at = c == '-' ? 1 : 0;
    const std::size_t whole = digits(s, at);
    if (whole == 0) return FieldType::String;
    if (whole == 4 && at == 0 && s.size() >= 10 && s[4] == '-') {
      if (!is_date(s)) return FieldType::String;
      if (s.size() == 10) return FieldType::Date;
      return is_time_part(s.substr(10)) ? FieldType::DateTime : FieldType::String;
    }
    if (s[at] == '0' && whole > 1) return FieldType::String;  // a leading zero: an identifier
    at += whole;
    if (at == s.size()) {
      if (fits(s, "2147483647", "2147483648")) return FieldType::Integer;
      return fits(s, "9223372036854775807", "9223372036854775808") ? FieldType::Integer64 : FieldType::String;
    }
    if (s[at] == '.') {
      const std::size_t n = digits(s, at + 1);
      if (n == 0) return FieldType::String;
      at += 1 + n;
    }
    bool exponent = false;
    if (at < s.size() && (s[at] == 'e' || s[at] == 'E')) {
      ++at;
      if (at < s.size() && (s[at] == '+' || s[at] == '-')) ++at;
      const std::size_t n = digits(s, at);
      if (n == 0) return FieldType::String;
      at += n;
      exponent = true;
    }
    if (at != s.size()) return FieldType::String;
    if (exponent) {  // 1e999 is no double
      double v = 0;
      const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
      if (r.ec != std::errc() || !std::isfinite(v)) return FieldType::String;
    }
    return FieldType::Real;
  }
  return FieldType::String;
}

FieldType wider_type(FieldType a, FieldType b) {
  if (a == b) return a;
  auto number = [](FieldType t) {
    return t == FieldType::Integer || t == FieldType::Integer64 || t == FieldType::Real;
  };
  auto date = [](FieldType t) { return t == FieldType::Date || t == FieldType::DateTime; };
  if (number(a) && number(b)) {
    if (a == FieldType::Real || b == FieldType::Real) return FieldType::Real;
    return FieldType::Integer64;
  }
  if (date(a) && date(b)) return FieldType::DateTime;
  return FieldType::String;
}

ColumnTypeDetector::ColumnTypeDetector(std::size_t columns, int id_column)
    : types_(columns, FieldType::String), seen_(columns, false) {
  for (std::size_t c = 0; c < columns; ++c)
    if (static_cast<int>(c) != id_column) open_.push_back(c);
}

void ColumnTypeDetector::add(const std::vector<std::string>& fields) {
  for (std::size_t k = 0; k < open_.size();) {
    const std::size_t c = open_[k];
    if (c >= fields.size() || fields[c].empty()) {
      ++k;
      continue;
    }
    const FieldType t = value_type(fields[c]);
    types_[c] = seen_[c] ? wider_type(types_[c], t) : t;
    seen_[c] = true;
    if (types_[c] == FieldType::String) {
      open_[k] = open_.back();
      open_.pop_back();
    } else {
      ++k;
    }
  }
}

std::vector<FieldType> ColumnTypeDetector::types() const {
  std::vector<FieldType> types = types_;
  for (std::size_t c = 0; c < types.size(); ++c)
    if (!seen_[c]) types[c] = FieldType::String;
  return types;
}

std::vector<FieldType> detect_column_types(const SiteTable& table) {
  ColumnTypeDetector detector(table.columns.size(), table.id_column);
  for (const InputSite& site : table.sites) detector.add(site.fields);
  return detector.types();
}

std::optional<FieldType> field_type_named(std::string_view name) {
  for (const FieldType t : {FieldType::String, FieldType::Integer, FieldType::Integer64, FieldType::Real,
                            FieldType::Date, FieldType::DateTime})
    if (ascii_iequals(name, to_string(t))) return t;
  return std::nullopt;
}

void parse_field_types(std::string_view spec, std::vector<FieldTypeOverride>& out) {
  std::size_t at = 0;
  for (;;) {
    const std::size_t comma = spec.find(',', at);
    const std::string_view item = spec.substr(at, comma == std::string_view::npos ? std::string_view::npos : comma - at);
    const std::size_t eq = item.rfind('=');
    if (eq == std::string_view::npos || trim(item.substr(0, eq)).empty())
      throw Error(ErrorCode::InvalidArgument, "field type '" + std::string(item) +
                                                  "': expected NAME=TYPE (TYPE: String, Integer, Integer64, Real, Date, DateTime)");
    const std::string_view type_name = trim(item.substr(eq + 1));
    const std::optional<FieldType> type = field_type_named(type_name);
    if (!type)
      throw Error(ErrorCode::InvalidArgument, "field type '" + std::string(item) + "': unknown type '" +
                                                  std::string(type_name) +
                                                  "'; the types are String, Integer, Integer64, Real, Date, DateTime");
    out.push_back({std::string(trim(item.substr(0, eq))), *type});
    if (comma == std::string_view::npos) return;
    at = comma + 1;
  }
}

std::optional<std::string> declared_value(FieldType type, std::string_view text) {
  if (type == FieldType::String) return std::string(text);
  const std::string_view t = trim(text);
  if (t.empty()) return std::string();
  switch (type) {
    case FieldType::Integer:
    case FieldType::Integer64: {
      const std::size_t sign = t[0] == '+' || t[0] == '-' ? 1 : 0;
      if (t.size() == sign || digits(t, sign) != t.size() - sign) return std::nullopt;
      std::string_view d = t.substr(sign);
      while (d.size() > 1 && d[0] == '0') d.remove_prefix(1);  // "007": the user says it is a number
      const std::string canonical = (t[0] == '-' && d != "0" ? "-" : "") + std::string(d);
      const bool fit = type == FieldType::Integer ? fits(canonical, "2147483647", "2147483648")
                                                  : fits(canonical, "9223372036854775807", "9223372036854775808");
      if (!fit) return std::nullopt;
      return canonical;
    }
    case FieldType::Real: {
      std::size_t at = t[0] == '+' || t[0] == '-' ? 1 : 0;
      const std::size_t whole = digits(t, at);
      at += whole;
      std::size_t fraction = 0;
      if (at < t.size() && t[at] == '.') {
        fraction = digits(t, at + 1);
        at += 1 + fraction;
      }
      if (whole + fraction == 0) return std::nullopt;
      if (at < t.size() && (t[at] == 'e' || t[at] == 'E')) {
        ++at;
        if (at < t.size() && (t[at] == '+' || t[at] == '-')) ++at;
        const std::size_t n = digits(t, at);
        if (n == 0) return std::nullopt;
        at += n;
      }
      if (at != t.size()) return std::nullopt;
      const std::string_view unsigned_text = t[0] == '+' ? t.substr(1) : t;
      double v = 0;
      const auto r = std::from_chars(unsigned_text.data(), unsigned_text.data() + unsigned_text.size(), v);
      if (r.ec != std::errc() || !std::isfinite(v)) return std::nullopt;
      // A JSON number stays as written; ".5", "1.", "007.5" become the shortest text of their double.
      if (value_type(unsigned_text) != FieldType::String) return std::string(unsigned_text);
      char buf[32];
      return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
    }
    case FieldType::Date:
      if (value_type(t) != FieldType::Date) return std::nullopt;
      return std::string(t);
    case FieldType::DateTime: {
      const FieldType found = value_type(t);
      if (found != FieldType::Date && found != FieldType::DateTime) return std::nullopt;
      return std::string(t);
    }
    case FieldType::String:
      break;
  }
  return std::string(text);
}

std::string did_you_mean(const std::vector<std::string>& columns, std::string_view name) {
  std::string best;
  std::size_t best_distance = 3;  // closer than this: a likely typo
  for (const std::string& column : columns) {
    const std::size_t distance = edit_distance(ascii_lower(trim(name)), ascii_lower(trim(column)));
    if (distance < best_distance) {
      best_distance = distance;
      best = column;
    }
  }
  return best.empty() ? "" : "; did you mean '" + best + "'?";
}

std::string not_of_declared_type(FieldType type, std::string_view text) {
  return "'" + std::string(text) + "' is not " + with_article(type) + " (declared " + to_string(type) + ")" +
         (type == FieldType::Integer && declared_value(FieldType::Integer64, text) ? "; it needs 64 bits: declare Integer64"
                                                                                  : "");
}

void apply_field_types(SiteTable& table, std::span<const FieldTypeOverride> declared) {
  if (declared.empty()) return;
  if (table.column_types.size() != table.columns.size()) table.column_types.resize(table.columns.size(), FieldType::String);
  std::vector<std::pair<std::size_t, FieldType>> columns;  // in the order given; a later one wins
  for (const FieldTypeOverride& d : declared) {
    const int c = find_column(table.columns, d.column);
    if (c < 0) {
      std::string list;
      for (const std::string& name : table.columns) list += (list.empty() ? "" : ", ") + name;
      throw Error(ErrorCode::InvalidArgument, table.source + ": --field-type names '" + d.column + "', which is no column" +
                                                  did_you_mean(table.columns, d.column) + " (columns: " + list + ")");
    }
    columns.emplace_back(static_cast<std::size_t>(c), d.type);
  }
  for (const auto& [c, type] : columns) table.column_types[c] = type;
  for (InputSite& site : table.sites) {
    for (const auto& [c, type] : columns) {
      if (c >= site.fields.size() || table.column_types[c] != type) continue;  // a later declaration wins
      std::string& field = site.fields[c];
      std::optional<std::string> value = declared_value(type, field);
      if (!value) {
        const std::string where = site.line > 0 ? "row " + std::to_string(site.row) + " (line " + std::to_string(site.line) + ")"
                                                : "feature " + std::to_string(site.row);
        throw Error(ErrorCode::BadData,
                    table.source + ": " + where + ", column '" + table.columns[c] + "': " + not_of_declared_type(type, field));
      }
      field = std::move(*value);
    }
  }
}

}  // namespace geovor
