// The CSV site reader as it was before the two-stage CsvSiteScan (read_csv_table over the
// streaming CsvReader, coordinates converted afterwards), kept unchanged as the oracle that the
// new reader is compared with field by field. Do not optimise it: its worth is being the old code.
#include "support/reference_site_reader.hpp"

#include "geovor/geo/site_reader.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <span>
#include <string_view>
#include <system_error>
#include <thread>
#include <utility>

#include "geovor/core/error.hpp"
#include "geovor/geo/csv_reader.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor::testing {
namespace {

constexpr std::array<std::string_view, 4> kLatNames = {"lat", "latitude", "lat_deg", "y"};
constexpr std::array<std::string_view, 6> kLonNames = {"lon",       "lng",     "long",
                                                       "longitude", "lon_deg", "x"};
constexpr std::array<std::string_view, 4> kIdNames = {"id", "icao", "code", "name"};

// A value longer than this is cut in messages: a reason must stay one readable line.
constexpr std::size_t kMaxQuotedValue = 40;

std::string_view trim(std::string_view s) {
  constexpr std::string_view kSpace = " \t\r\n\v\f";
  const auto first = s.find_first_not_of(kSpace);
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(kSpace) - first + 1);
}

bool same_name(std::string_view column, std::string_view name) {
  column = trim(column);
  name = trim(name);
  if (column.size() != name.size()) return false;
  for (std::size_t i = 0; i < column.size(); ++i) {
    auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c; };
    if (lower(column[i]) != lower(name[i])) return false;
  }
  return true;
}

// The oracle keeps its own copy of find_column too.
int find_column(const std::vector<std::string>& columns, std::string_view name) {
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (same_name(columns[i], name)) return static_cast<int>(i);
  }
  return -1;
}

int find_column(const std::vector<std::string>& columns, std::span<const std::string_view> names) {
  for (const auto name : names) {
    if (const int c = find_column(columns, name); c >= 0) return c;
  }
  return -1;
}

template <std::size_t N>
int detect_column(const std::vector<std::string>& columns,
                  const std::array<std::string_view, N>& names) {
  return find_column(columns, std::span<const std::string_view>(names.data(), N));
}

template <typename Range>
std::string join(const Range& names) {
  std::string out;
  for (const auto& name : names) {
    if (!out.empty()) out += ", ";
    out += name;
  }
  return out;
}

std::string quoted(std::string_view value) {
  if (value.size() <= kMaxQuotedValue) return "'" + std::string(value) + "'";
  return "'" + std::string(value.substr(0, kMaxQuotedValue)) + "...' (" +
         std::to_string(value.size()) + " characters)";
}

// Parse one number; "" on success, else the reason (without the column name).
std::string parse_double(std::string_view text, double& value) {
  const std::string_view s = trim(text);
  if (s.empty()) return "empty value";
  std::string_view digits = s;
  // std::from_chars refuses a leading '+', which spreadsheets and printf("%+f") do write.
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-' && digits[1] != '+') {
    digits.remove_prefix(1);
  }
  const char* const last = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(digits.data(), last, value);
  if (ec == std::errc::result_out_of_range) return quoted(s) + " is out of the range of a double";
  if (ec != std::errc() || ptr != last) return quoted(s) + " is not a number";
  return "";
}

// The header's names for a message: long names cut, and at most kMaxListedColumns of them.
std::string column_list(const std::vector<std::string>& columns) {
  constexpr std::size_t kMaxListedColumns = 50;
  std::string out;
  for (std::size_t i = 0; i < columns.size() && i < kMaxListedColumns; ++i) {
    if (i > 0) out += ", ";
    const std::string_view name = columns[i];
    out += name.size() <= kMaxQuotedValue ? std::string(name)
                                          : std::string(name.substr(0, kMaxQuotedValue)) + "...";
  }
  if (columns.size() > kMaxListedColumns) {
    out += ", ... (" + std::to_string(columns.size()) + " columns)";
  }
  return out;
}

Error named_field_error(const std::string& source, const char* what, const std::string& name,
                        const std::vector<std::string>& columns) {
  return Error(ErrorCode::InvalidArgument,
               source + ": " + what + " field '" + name +
                   "' is not a column; found columns: " + column_list(columns));
}

int named_column(const std::string& source, const char* what, const std::string& name,
                 const std::vector<std::string>& columns) {
  const int c = find_column(columns, name);
  if (c < 0) throw named_field_error(source, what, name, columns);
  return c;
}

// Which columns of the header hold what; throws when the table cannot be used at all.
void choose_columns(SiteTable& table, const SiteReaderOptions& options) {
  const auto& columns = table.columns;
  const std::string& source = table.source;
  if (!options.ecef_fields.empty()) {
    for (const auto& name : options.ecef_fields) {
      table.ecef_columns.push_back(named_column(source, "ECEF", name, columns));
    }
  } else {
    table.lat_column = options.lat_field.empty()
                           ? detect_column(columns, kLatNames)
                           : named_column(source, "latitude", options.lat_field, columns);
    table.lon_column = options.lon_field.empty()
                           ? detect_column(columns, kLonNames)
                           : named_column(source, "longitude", options.lon_field, columns);
    if (table.lat_column < 0 || table.lon_column < 0) {
      std::string which;
      if (table.lat_column >= 0) which = " (found latitude '" + columns[table.lat_column] + "')";
      if (table.lon_column >= 0) which = " (found longitude '" + columns[table.lon_column] + "')";
      throw Error(ErrorCode::BadData,
                  source + ": no latitude/longitude columns" + which + "; looked for " +
                      join(kLatNames) + " and " + join(kLonNames) +
                      "; found columns: " + column_list(columns) + "; use --lat-field/--lon-field");
    }
    if (table.lat_column == table.lon_column) {
      throw Error(
          ErrorCode::InvalidArgument,
          source + ": latitude and longitude are both column '" + columns[table.lat_column] + "'");
    }
  }
  table.id_column = options.id_field.empty()
                        ? detect_column(columns, kIdNames)
                        : named_column(source, "id", options.id_field, columns);
}

// Fill site's position from the row; "" on success, else the reason naming the column.
std::string locate_site(const SiteTable& table, const std::vector<std::string>& fields,
                        InputSite& site) {
  const auto& columns = table.columns;
  if (!table.ecef_columns.empty()) {
    std::array<double, 3> xyz{};
    for (std::size_t k = 0; k < 3; ++k) {
      const auto c = static_cast<std::size_t>(table.ecef_columns[k]);
      if (auto reason = parse_double(fields[c], xyz[k]); !reason.empty()) {
        return columns[c] + ": " + reason;
      }
      if (!std::isfinite(xyz[k])) {
        return columns[c] + ": " + quoted(trim(fields[c])) + " is not a finite number";
      }
    }
    const std::string names = columns[table.ecef_columns[0]] + ", " +
                              columns[table.ecef_columns[1]] + ", " +
                              columns[table.ecef_columns[2]];
    // The centre of the Earth has no direction, so no latitude/longitude to give it.
    if (xyz[0] == 0 && xyz[1] == 0 && xyz[2] == 0) {
      return names + ": (0, 0, 0) is the centre of the Earth, not a position on it";
    }
    const auto g = SiteEncoder::from_ecef(xyz[0], xyz[1], xyz[2]);
    site.lat_deg = g.lat_deg;
    site.lon_deg = g.lon_deg;
    site.height_m = g.height_m;
    if (auto reason = normalize_lat_lon(site.lat_deg, site.lon_deg); !reason.empty()) {
      return names + ": " + reason;
    }
  } else {
    const auto lat_c = static_cast<std::size_t>(table.lat_column);
    const auto lon_c = static_cast<std::size_t>(table.lon_column);
    if (auto reason = parse_double(fields[lat_c], site.lat_deg); !reason.empty()) {
      return columns[lat_c] + ": " + reason;
    }
    if (auto reason = parse_double(fields[lon_c], site.lon_deg); !reason.empty()) {
      return columns[lon_c] + ": " + reason;
    }
    if (auto reason = normalize_lat_lon(site.lat_deg, site.lon_deg); !reason.empty()) {
      // normalize_lat_lon's reasons start with the coordinate they are about.
      const bool about_lat = reason.rfind("latitude", 0) == 0;
      return columns[about_lat ? lat_c : lon_c] + ": " + reason;
    }
  }
  site.unit = SiteEncoder::from_lat_lon(site.lat_deg, site.lon_deg);
  return "";
}

}  // namespace

// read_sites_csv, with room reserved for `expected_rows` rows (0: unknown), so that the rows are
// not moved to ever larger fresh memory as they come.
namespace {

SiteTable read_csv_table(std::istream& in, const std::string& source, const SiteReaderOptions& options,
                         std::size_t expected_rows) {
  if (!options.ecef_fields.empty() && options.ecef_fields.size() != 3) {
    throw Error(ErrorCode::InvalidArgument, "ECEF input needs exactly 3 columns (X, Y, Z), got " +
                                                std::to_string(options.ecef_fields.size()) + ": " +
                                                join(options.ecef_fields));
  }
  if (!options.ecef_fields.empty() && (!options.lat_field.empty() || !options.lon_field.empty())) {
    throw Error(ErrorCode::InvalidArgument,
                "ECEF columns and latitude/longitude columns cannot both be given");
  }

  SiteTable table;
  table.source = source;
  CsvReader reader(in);
  std::vector<std::string> fields;
  // The reader does not know the source; name it here so the message says which input failed.
  auto next_record = [&]() {
    try {
      return reader.next(fields);
    } catch (const Error& e) {
      throw Error(e.code(), source + ": " + e.what());
    }
  };

  if (!next_record()) throw Error(ErrorCode::BadData, source + ": empty file, no header");
  // A compressed file would otherwise be reported as a header of binary garbage.
  if (fields[0].rfind("\x1f\x8b", 0) == 0) {
    throw Error(ErrorCode::BadData,
                source + ": gzip-compressed data, not CSV; decompress it first");
  }
  if (!reader.error().empty()) {
    throw Error(ErrorCode::BadData, source + ": header: " + reader.error());
  }
  table.columns = fields;
  choose_columns(table, options);
  std::vector<InputSite> rows;  // well-formed rows, located after reading
  rows.reserve(expected_rows);

  while (next_record()) {
    ++table.rows_read;
    const std::uint64_t row = table.rows_read;
    const std::uint64_t line = reader.line();
    auto reject = [&](std::string reason) {
      table.rejected.push_back(RejectedRow{row, line, std::move(reason)});
    };
    if (!reader.error().empty()) {
      const std::size_t c = fields.size() - 1;
      reject(c < table.columns.size() ? table.columns[c] + ": " + reader.error() : reader.error());
      continue;
    }
    if (fields.size() != table.columns.size()) {
      std::string reason = "found " + std::to_string(fields.size()) + " fields, expected " +
                           std::to_string(table.columns.size()) + " as in the header";
      if (fields.size() < table.columns.size()) {
        std::vector<std::string> missing(
            table.columns.begin() + static_cast<std::ptrdiff_t>(fields.size()),
            table.columns.end());
        reason += " (no value for " + join(missing) + ")";
      }
      reject(std::move(reason));
      continue;
    }
    InputSite site;
    site.row = row;
    site.line = line;
    site.id = table.id_column >= 0 ? fields[static_cast<std::size_t>(table.id_column)]
                                   : std::to_string(row);
    // Copied, not moved: `fields` keeps its strings and their capacity for the next record.
    site.fields.assign(fields.begin(), fields.end());
    rows.push_back(std::move(site));
  }

  // The coordinates of the well-formed rows, split over threads; then sites and rejected rows
  // in row order.
  std::vector<std::string> reasons(rows.size());
  auto locate = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) reasons[i] = locate_site(table, rows[i].fields, rows[i]);
  };
  const std::size_t n = rows.size();
  const unsigned threads = static_cast<unsigned>(std::min<std::size_t>(
      options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency()),
      std::max<std::size_t>(1, n / 16384)));
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(locate, n * t / threads, n * (t + 1) / threads);
  locate(0, n / threads);
  for (std::thread& th : pool) th.join();
  const bool early_rejects = !table.rejected.empty();
  bool late_rejects = false;
  std::size_t kept = 0;  // compacted in place: no second copy of the rows to allocate
  for (std::size_t i = 0; i < n; ++i) {
    if (reasons[i].empty()) {
      if (kept != i) rows[kept] = std::move(rows[i]);
      ++kept;
    } else {
      table.rejected.push_back(RejectedRow{rows[i].row, rows[i].line, std::move(reasons[i])});
      late_rejects = true;
    }
  }
  rows.resize(kept);
  table.sites = std::move(rows);
  if (early_rejects && late_rejects) {
    std::stable_sort(table.rejected.begin(), table.rejected.end(),
                     [](const RejectedRow& a, const RejectedRow& b) { return a.row < b.row; });
  }
  return table;
}

// Lines of a regular file (an upper bound of its records), or 0 if it cannot be counted.
std::size_t count_lines(std::istream& in) {
  std::vector<char> block(std::size_t{1} << 20);
  std::size_t lines = 0;
  while (in.read(block.data(), static_cast<std::streamsize>(block.size())) || in.gcount() > 0) {
    lines += static_cast<std::size_t>(std::count(block.data(), block.data() + in.gcount(), '\n'));
    if (!in) break;
  }
  in.clear();
  in.seekg(0);
  return in ? lines + 1 : 0;
}

}  // namespace

SiteTable reference_read_sites_csv(std::istream& in, const std::string& source, const SiteReaderOptions& options) {
  return read_csv_table(in, source, options, 0);
}

SiteTable reference_read_sites_csv_file(const std::string& path, const SiteReaderOptions& options) {
  if (path == "-") return reference_read_sites_csv(std::cin, "<stdin>", options);
  std::error_code ec;
  // Opening a directory succeeds on POSIX and only reading fails; say so up front instead.
  if (std::filesystem::is_directory(path, ec)) {
    throw Error(ErrorCode::Io, path + ": cannot read: " + std::strerror(EISDIR));
  }
  errno = 0;
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    const int err = errno;
    throw Error(ErrorCode::Io,
                path + ": cannot open: " + (err != 0 ? std::strerror(err) : "unknown error"));
  }
  // A regular file is counted first (from the page cache, a few ms) to reserve its rows.
  const std::size_t lines = std::filesystem::is_regular_file(path, ec) ? count_lines(file) : 0;
  if (!file) {
    throw Error(ErrorCode::Io, path + ": cannot read: " + std::strerror(errno != 0 ? errno : EIO));
  }
  return read_csv_table(file, path, options, lines);
}

}  // namespace geovor::testing
