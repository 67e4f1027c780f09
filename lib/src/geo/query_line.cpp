// One line of a query stream: fields, numbers, format detection (see query_line.hpp).
#include "geovor/geo/query_line.hpp"

#include <charconv>
#include <cstring>
#include <functional>
#include <span>
#include <system_error>

#include "geovor/core/error.hpp"
#include "geovor/geo/coordinate_columns.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geo/trim.hpp"

namespace geovor {
namespace {

constexpr std::string_view kIdNames[] = {"query_id", "id", "icao", "code", "name"};

template <std::size_t N>
int detect(const std::vector<std::string>& columns, const std::string_view (&names)[N]) {
  return find_column(columns, std::span<const std::string_view>(names, N));
}

std::string quoted(std::string_view v) {
  constexpr std::size_t kMax = 40;
  if (v.size() <= kMax) return "'" + std::string(v) + "'";
  return "'" + std::string(v.substr(0, kMax)) + "...' (" + std::to_string(v.size()) + " characters)";
}

}  // namespace

const char* parse_query_number(std::string_view text, double& value) {
  std::string_view s = text;
  if (!s.empty() && (s.front() == ' ' || s.back() == ' ' || s.front() == '\t' || s.back() == '\t')) s = trim(s);
  if (s.empty()) return "empty value";
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec == std::errc::result_out_of_range) return "is out of the range of a double";
  if (ec != std::errc() || ptr != s.data() + s.size()) return "is not a number";
  return "";
}

const char* split_query_fields(std::string_view line, std::vector<std::string_view>& out, std::string& scratch) {
  out.clear();
  if (std::memchr(line.data(), '"', line.size()) == nullptr) {
    std::size_t start = 0;
    for (;;) {
      const void* comma = std::memchr(line.data() + start, ',', line.size() - start);
      if (!comma) {
        out.push_back(line.substr(start));
        return "";
      }
      const std::size_t at = static_cast<std::size_t>(static_cast<const char*>(comma) - line.data());
      out.push_back(line.substr(start, at - start));
      start = at + 1;
    }
  }
  scratch.clear();
  scratch.reserve(line.size());  // never reallocated below: the views into it stay valid
  std::size_t i = 0;
  for (;;) {
    if (i < line.size() && line[i] == '"') {
      const std::size_t begin = scratch.size();
      ++i;
      for (;;) {
        if (i >= line.size()) return "unterminated quoted field (a query cannot span lines)";
        if (line[i] == '"') {
          if (i + 1 < line.size() && line[i + 1] == '"') {
            scratch.push_back('"');
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        scratch.push_back(line[i++]);
      }
      while (i < line.size() && line[i] != ',') scratch.push_back(line[i++]);  // "ab"c -> abc
      out.push_back(std::string_view(scratch).substr(begin));
    } else {
      const std::size_t begin = i;
      while (i < line.size() && line[i] != ',') ++i;
      out.push_back(line.substr(begin, i - begin));
    }
    if (i >= line.size()) return "";
    ++i;  // the comma
  }
}

QueryFormat detect_query_format(std::string_view first, const std::string& source) {
  return detect_query_format(first, source, QueryColumns{});
}

QueryFormat detect_query_format(std::string_view first, const std::string& source, const QueryColumns& names) {
  if (!first.empty() && first.back() == '\r') first.remove_suffix(1);
  std::vector<std::string_view> fields;
  std::string scratch;
  QueryFormat fmt;
  double v;
  if (!names.any() && !*split_query_fields(first, fields, scratch) && fields.size() >= 2 &&
      !*parse_query_number(fields[0], v) && !*parse_query_number(fields[1], v))
    return fmt;  // headerless: lat,lon[,id]
  split_query_fields(first, fields, scratch);
  fmt.header = true;
  for (const std::string_view f : fields) fmt.columns.emplace_back(trim(f));
  fmt.fields = fmt.columns.size();
  check_header_names(fmt.columns, source);  // a name twice or an empty one: exit 3, as for sites
  // A named column must exist; an unnamed one is detected.
  auto column = [&](const std::string& name, const char* option, int detected) {
    if (name.empty()) return detected;
    const int c = find_column(fmt.columns, name);
    if (c >= 0) return c;
    std::string found;
    for (const auto& n : fmt.columns) found += (found.empty() ? "" : ", ") + n;
    throw Error(ErrorCode::InvalidArgument,
                source + ": " + option + " '" + name + "' is not a column of the header (" + found + ")");
  };
  // Unnamed coordinate columns are found as the sites' are (geo/coordinate_columns.hpp).
  auto coordinate = [&](Axis axis, const std::string& name) {
    return name.empty() ? detect_coordinate_column(fmt.columns, axis, false, source, "query-") : -1;
  };
  fmt.lat = column(names.lat_field, "--query-lat-field", coordinate(Axis::Latitude, names.lat_field));
  fmt.lon = column(names.lon_field, "--query-lon-field", coordinate(Axis::Longitude, names.lon_field));
  fmt.id = column(names.id_field, "--query-id-field", detect(fmt.columns, kIdNames));
  if (fmt.lat < 0 || fmt.lon < 0 || fmt.lat == fmt.lon) {
    std::string found;
    for (const auto& c : fmt.columns) found += (found.empty() ? "" : ", ") + c;
    throw Error(ErrorCode::BadData,
                source + ": no latitude/longitude columns in the header line (" + found +
                    "); looked for names such as lat, latitude, stop_lat, decimalLatitude, y and lon, lng, "
                    "longitude, stop_lon, x (docs/user-guide.md, Input); "
                    "name them with --query-lat-field and --query-lon-field, "
                    "or give lines of lat,lon[,id] without a header");
  }
  return fmt;
}

bool QueryLineParser::parse(std::string_view line, QueryLine& out, std::string& reason) {
  if (const char* why = split_query_fields(line, fields_, scratch_); *why) {
    reason = why;
    return false;
  }
  const std::size_t nf = fields_.size();
  if (fmt_.header ? nf != fmt_.fields : nf != 2 && nf != 3) {
    reason = "expected " + (fmt_.header ? std::to_string(fmt_.fields) : std::string("2 or 3 (lat,lon[,id])")) +
             " fields, found " + std::to_string(nf);
    return false;
  }
  double lat = 0, lon = 0;
  const char* why = parse_query_number(fields_[fmt_.lat], lat);
  int bad_column = fmt_.lat;
  if (!*why) why = parse_query_number(fields_[fmt_.lon], lon), bad_column = fmt_.lon;
  if (*why) {
    const std::string name = fmt_.header ? fmt_.columns[bad_column] : bad_column == 0 ? "lat" : "lon";
    reason = name + ": " +
             (std::strcmp(why, "empty value") == 0 ? std::string(why) : quoted(trim(fields_[bad_column])) + " " + why);
    return false;
  }
  if (std::string r = normalize_lat_lon(lat, lon); !r.empty()) {
    reason = std::move(r);
    return false;
  }
  out.lat_deg = lat;
  out.lon_deg = lon;
  out.id = {};
  out.id_quoted = false;
  const int id_col = fmt_.header ? fmt_.id : (nf == 3 ? 2 : -1);
  if (id_col >= 0) {
    out.id = fields_[id_col];
    // Never null (null means "no id"); an empty quoted id views the line, not the buffer.
    if (out.id.empty()) out.id = std::string_view(line.data(), 0);
    const std::less_equal<const char*> le;  // a total order, even between unrelated buffers
    out.id_quoted = !scratch_.empty() && le(scratch_.data(), out.id.data()) &&
                    le(out.id.data(), scratch_.data() + scratch_.size());
  }
  return true;
}

}  // namespace geovor
