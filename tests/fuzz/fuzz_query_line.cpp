// Fuzz target: arbitrary bytes as a query stream of `geovor nearest` (split at '\n' as the
// command does). The first line gives the format (detect_query_format: a format or
// Error(BadData)); every other non-empty line must parse to a valid position or give a reason.
// Where a line has no CR and its quotes close, its fields must equal CsvReader's.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_check.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/csv_reader.hpp"
#include "geovor/geo/query_line.hpp"

namespace {

using namespace geovor;

bool within(std::string_view inner, std::string_view outer) {
  const std::less_equal<const char*> le;
  return le(outer.data(), inner.data()) && le(inner.data() + inner.size(), outer.data() + outer.size());
}

// Checks the fields of a line against CsvReader; returns their number.
std::size_t check_fields(std::string_view line) {
  std::vector<std::string_view> ours;
  std::string scratch;
  const char* why = split_query_fields(line, ours, scratch);
  FUZZ_CHECK(!ours.empty() || *why, "no field and no reason");
  if (*why || line.empty() || line.find('\r') != std::string_view::npos || line.starts_with("\xEF\xBB\xBF"))
    return ours.size();
  std::istringstream in{std::string(line)};
  CsvReader reader(in);
  std::vector<std::string> theirs;
  FUZZ_CHECK(reader.next(theirs), "CsvReader found no record");
  FUZZ_CHECK(ours.size() == theirs.size(), "%zu fields, CsvReader %zu", ours.size(), theirs.size());
  for (std::size_t i = 0; i < ours.size(); ++i) FUZZ_CHECK(ours[i] == theirs[i], "field %zu differs from CsvReader's", i);
  return ours.size();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  if (rest.starts_with("\xEF\xBB\xBF")) rest.remove_prefix(3);
  auto next_line = [&rest] {
    const std::size_t nl = rest.find('\n');
    const std::string_view line = rest.substr(0, nl);
    rest.remove_prefix(nl == std::string_view::npos ? rest.size() : nl + 1);
    return line;
  };
  const std::string_view first = next_line();
  check_fields(first);
  QueryFormat format;
  try {
    format = detect_query_format(first, "fuzz.csv");
  } catch (const Error& e) {
    FUZZ_CHECK(e.code() == ErrorCode::BadData, "%s", e.what());
    return 0;
  }
  FUZZ_CHECK(format.lat >= 0 && format.lon >= 0 && format.lat != format.lon, "lat %d lon %d", format.lat, format.lon);
  if (format.header) {
    FUZZ_CHECK(format.fields == format.columns.size() && static_cast<std::size_t>(format.lat) < format.fields &&
                   static_cast<std::size_t>(format.lon) < format.fields && format.id < static_cast<int>(format.fields),
               "format out of range");
  }
  QueryLineParser parser(format);
  QueryLine q;
  std::string reason;
  // Without a header the first line is a query too.
  bool first_line = !format.header;
  while (first_line || !rest.empty()) {
    std::string_view line = first_line ? first : next_line();
    first_line = false;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) continue;
    const std::size_t fields = check_fields(line);
    reason.clear();
    if (!parser.parse(line, q, reason)) {
      FUZZ_CHECK(!reason.empty(), "rejected without a reason");
      continue;
    }
    FUZZ_CHECK(reason.empty(), "accepted with a reason");
    FUZZ_CHECK(std::isfinite(q.lat_deg) && std::fabs(q.lat_deg) <= 90, "latitude %.17g", q.lat_deg);
    FUZZ_CHECK(std::isfinite(q.lon_deg) && q.lon_deg >= -180 && q.lon_deg < 180, "longitude %.17g", q.lon_deg);
    const bool has_id = format.header ? format.id >= 0 : fields == 3;
    FUZZ_CHECK((q.id.data() != nullptr) == has_id, "id presence");
    if (has_id && !q.id_quoted) FUZZ_CHECK(within(q.id, line), "an unquoted id outside its line");
    if (q.id_quoted) FUZZ_CHECK(q.id.size() <= line.size(), "a quoted id longer than its line");
  }
  return 0;
}
