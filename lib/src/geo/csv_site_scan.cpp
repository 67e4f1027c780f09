#include "geovor/geo/csv_site_scan.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iconv.h>
#include <fstream>
#include <iostream>
#include <limits>
#include <string_view>
#include <system_error>
#include <utility>

#include "geovor/core/ascii.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/geo/column_types.hpp"
#include "geovor/geo/coordinate_columns.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geo/trim.hpp"

namespace geovor {
namespace {

constexpr std::array<std::string_view, 4> kIdNames = {"id", "icao", "code", "name"};

// A value longer than this is cut in messages: a reason must stay one readable line.
constexpr std::size_t kMaxQuotedValue = 40;

// Streams are read in blocks of this size, as CsvReader did (a read error drops the whole block).
constexpr std::size_t kBlockSize = std::size_t{1} << 16;

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

// Degrees, minutes and seconds (40°26'46"N, 40 26 46 N): said so rather than "not a number".
bool looks_like_dms(std::string_view s) {
  const bool degree_sign = s.find("\xC2\xB0") != std::string_view::npos || s.find("\xBA") != std::string_view::npos;
  const bool hemisphere = !s.empty() && std::string_view("NSEWnsew").find(s.back()) != std::string_view::npos &&
                          s.size() > 1 && (std::isdigit(static_cast<unsigned char>(s[0])) != 0);
  return degree_sign || (hemisphere && (s.find('\'') != std::string_view::npos || s.find(' ') != std::string_view::npos ||
                                        std::isdigit(static_cast<unsigned char>(s[s.size() - 2])) != 0));
}

// Why `s` (its number part `digits`) did not parse, where from_chars stopped at `ptr` with `ec`;
// "" when it is a number with a decimal comma after all. Out of line: the hot path stays small.
[[gnu::noinline]] std::string parse_failure(std::string_view s, std::string_view digits, const char* ptr,
                                            std::errc ec, double& value, bool decimal_comma) {
  if (ec == std::errc::result_out_of_range) return quoted(s) + " is out of the range of a double";
  if (decimal_comma && *ptr == ',' && digits.size() < 64 && digits.find('.') == std::string_view::npos &&
      std::count(digits.begin(), digits.end(), ',') == 1) {
    char point[64];
    std::memcpy(point, digits.data(), digits.size());
    point[ptr - digits.data()] = '.';
    const auto [p2, ec2] = std::from_chars(point, point + digits.size(), value);
    if (ec2 == std::errc::result_out_of_range) return quoted(s) + " is out of the range of a double";
    if (ec2 == std::errc() && p2 == point + digits.size()) return "";
  }
  if (looks_like_dms(s)) return quoted(s) + " is in degrees, minutes and seconds; geovor reads decimal degrees";
  return quoted(s) + " is not a number";
}

// Parse one number; "" on success, else the reason (without the column name). `decimal_comma`:
// one ',' and no '.' is read as the decimal point ("48,85" in a semicolon-delimited file).
std::string parse_double(std::string_view text, double& value, bool decimal_comma = false) {
  const std::string_view s = trim(text);
  if (s.empty()) return "empty value";
  std::string_view digits = s;
  // std::from_chars refuses a leading '+', which spreadsheets and printf("%+f") do write.
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '-' && digits[1] != '+') {
    digits.remove_prefix(1);
  }
  const char* const last = digits.data() + digits.size();
  const auto [ptr, ec] = std::from_chars(digits.data(), last, value);
  if (ec != std::errc() || ptr != last) [[unlikely]] return parse_failure(s, digits, ptr, ec, value, decimal_comma);
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

void check_options(const SiteReaderOptions& options) {
  if (!options.ecef_fields.empty() && options.ecef_fields.size() != 3) {
    throw Error(ErrorCode::InvalidArgument, "ECEF input needs exactly 3 columns (X, Y, Z), got " +
                                                std::to_string(options.ecef_fields.size()) + ": " +
                                                join(options.ecef_fields));
  }
  if (!options.ecef_fields.empty() && (!options.lat_field.empty() || !options.lon_field.empty())) {
    throw Error(ErrorCode::InvalidArgument,
                "ECEF columns and latitude/longitude columns cannot both be given");
  }
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
    const bool projected = !options.s_srs.empty();
    table.lat_column = options.lat_field.empty()
                           ? detect_coordinate_column(columns, Axis::Latitude, projected, source)
                           : named_column(source, "latitude", options.lat_field, columns);
    table.lon_column = options.lon_field.empty()
                           ? detect_coordinate_column(columns, Axis::Longitude, projected, source)
                           : named_column(source, "longitude", options.lon_field, columns);
    if (table.lat_column < 0 || table.lon_column < 0) {
      std::string which;
      if (table.lat_column >= 0) which = " (found latitude '" + columns[table.lat_column] + "')";
      if (table.lon_column >= 0) which = " (found longitude '" + columns[table.lon_column] + "')";
      throw Error(ErrorCode::BadData,
                  source + ": no " + (projected ? "x/y" : "latitude/longitude") + " columns" + which +
                      "; looked for names such as lat, latitude, stop_lat, decimalLatitude, LATITUDE_DEG, "
                      "POINT_Y, y and lon, lng, long, longitude, stop_lon, decimalLongitude, POINT_X, x" +
                      (projected ? ", northing and easting" : "") + "; found columns: " + column_list(columns) +
                      "; use --lat-field/--lon-field");
    }
    if (table.lat_column == table.lon_column) {
      throw Error(
          ErrorCode::InvalidArgument,
          source + ": latitude and longitude are both column '" + columns[table.lat_column] + "'");
    }
  }
  table.id_column = options.id_field.empty()        ? detect_column(columns, kIdNames)
                    : options.id_field == kRowNumberId ? -1
                                                       : named_column(source, "id", options.id_field, columns);
}

// A row's position as InputSite holds it.
struct Located {
  double lat_deg = 0, lon_deg = 0, height_m = 0;
  Vec3 unit;
};

// How the rows are read, decided from the options and the header.
struct ScanRules {
  char delimiter = ',';
  bool decimal_comma = false;      // the delimiter is not ','
  bool projected = false;          // SiteReaderOptions::s_srs: x/y kept as read
  std::size_t named = 0;           // columns with a name; those after it must stay empty
  std::size_t total = 0;           // columns in the header
};

// The row's position; "" on success, else the reason naming the column.
std::string locate_site(const SiteTable& table, std::span<const std::string_view> fields,
                        Located& site, const ScanRules& rules) {
  const auto& columns = table.columns;
  if (!table.ecef_columns.empty()) {
    std::array<double, 3> xyz{};
    for (std::size_t k = 0; k < 3; ++k) {
      const auto c = static_cast<std::size_t>(table.ecef_columns[k]);
      if (auto reason = parse_double(fields[c], xyz[k], rules.decimal_comma); !reason.empty()) {
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
    if (auto reason = parse_double(fields[lat_c], site.lat_deg, rules.decimal_comma); !reason.empty()) {
      return columns[lat_c] + ": " + reason;
    }
    if (auto reason = parse_double(fields[lon_c], site.lon_deg, rules.decimal_comma); !reason.empty()) {
      return columns[lon_c] + ": " + reason;
    }
    if (rules.projected) {  // reproject_sites() checks the rest and makes the unit vector
      if (!std::isfinite(site.lat_deg)) return columns[lat_c] + ": " + quoted(trim(fields[lat_c])) + " is not a finite number";
      if (!std::isfinite(site.lon_deg)) return columns[lon_c] + ": " + quoted(trim(fields[lon_c])) + " is not a finite number";
      return "";
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

// The whole input in one buffer.
struct Text {
  std::unique_ptr<char[]> data;
  std::size_t size = 0;
  bool failed = false;  // the stream reported a read error after `size` good bytes
};

// Reads `in` to its end; `size_hint` (a regular file's size, or 0) is read first in one go.
// As CsvReader did: read in blocks while the stream is good; a block whose read fails is dropped.
Text read_text(std::istream& in, std::size_t size_hint) {
  Text text;
  std::size_t capacity = size_hint + kBlockSize;
  text.data = std::make_unique_for_overwrite<char[]>(capacity);
  bool first = size_hint > 0;
  for (;;) {
    if (!in.good()) {
      text.failed = in.bad();
      break;
    }
    const std::size_t want = first ? size_hint : kBlockSize;
    first = false;
    if (capacity - text.size < want) {
      const std::size_t grown = std::max(2 * capacity, text.size + want);
      auto bigger = std::make_unique_for_overwrite<char[]>(grown);
      std::memcpy(bigger.get(), text.data.get(), text.size);
      text.data = std::move(bigger);
      capacity = grown;
    }
    in.read(text.data.get() + text.size, static_cast<std::streamsize>(want));
    if (in.bad()) {
      text.failed = true;
      break;
    }
    text.size += static_cast<std::size_t>(in.gcount());
  }
  return text;
}

// One record of the text, its fields decoded in place: [begin, end) holds them separated by
// one delimiter each (the text after a record's end is not touched).
struct RawRecord {
  std::size_t begin = 0, end = 0;
  std::uint64_t line = 0;        // line where it starts, counted from the tokeniser's start (1)
  std::uint64_t quote_line = 0;  // an unterminated quoted field: its first line; else 0
  bool comma_in_field = false;   // a quoted field holds the delimiter: the fields cannot be split at it
  bool line_end = false;         // ended by a line end (not by the end of the text)
};

// CsvReader's state machine (csv_reader.hpp) over [pos, end) of a buffer, which it decodes in
// place: a record's decoded fields never run past its raw bytes, so they are written from its
// first byte on.
// The delimiter is a template argument: a constant in the hot loop, as ',' was.
template <char kDelimiter>
class Tokenizer {
 public:
  Tokenizer(char* buf, std::size_t pos, std::size_t end) : buf_(buf), pos_(pos), end_(end) {}

  // The next record, or false at the end of the range; fields point into the buffer.
  bool next(RawRecord& r, std::vector<std::string_view>& fields) {
    constexpr char delim = kDelimiter;
    fields.clear();
    // Empty lines are not records, but are counted.
    for (;;) {
      if (pos_ == end_) return false;
      const char c = buf_[pos_];
      if (c != '\n' && c != '\r') break;
      consume_line_end();
    }
    r.line = next_line_;
    r.begin = pos_;
    r.quote_line = 0;
    r.comma_in_field = false;
    r.line_end = false;
    std::size_t w = pos_;  // where the next decoded byte goes (w <= pos_)
    std::size_t field_begin = w;
    auto end_field = [&]() { fields.emplace_back(buf_ + field_begin, w - field_begin); };
    for (;;) {  // at the start of a field
      if (pos_ < end_ && buf_[pos_] == '"') {
        ++pos_;
        const std::uint64_t quote_line = next_line_;
        for (;;) {
          // CRLF, LF and lone CR each count as one line; the quotes around reset the pairing.
          const char* const first = buf_ + pos_;
          const char* const last = buf_ + end_;
          const char* p = first;
          bool prev_cr = false;
          for (; p != last && *p != '"'; ++p) {
            const char c = *p;
            if (c == '\n') {
              if (!prev_cr) ++next_line_;
              prev_cr = false;
            } else if (c == '\r') {
              ++next_line_;
              prev_cr = true;
            } else {
              prev_cr = false;
              if (c == delim) r.comma_in_field = true;
            }
          }
          move_run(w, static_cast<std::size_t>(p - first));
          if (pos_ == end_) {
            r.quote_line = quote_line;
            end_field();
            r.end = w;
            return true;
          }
          ++pos_;  // the closing quote, unless a second one follows: a quote in the field
          if (pos_ < end_ && buf_[pos_] == '"') {
            buf_[w++] = '"';
            ++pos_;
            continue;
          }
          break;
        }
        if (pos_ == end_) {
          end_field();
          r.end = w;
          return true;
        }
        const char c = buf_[pos_];
        if (c == delim) {
          end_field();
          buf_[w++] = delim;
          ++pos_;
          field_begin = w;
          continue;
        }
        if (c == '\n' || c == '\r') {
          end_field();
          consume_line_end();
          r.line_end = true;
          r.end = w;
          return true;
        }
        // Text after the closing quote: the field goes on unquoted.
      }
      // An unquoted run: this is the hot loop.
      const char* const first = buf_ + pos_;
      const char* const last = buf_ + end_;
      const char* p = first;
      while (p != last && *p != delim && *p != '\n' && *p != '\r') ++p;
      move_run(w, static_cast<std::size_t>(p - first));
      if (pos_ == end_) {
        end_field();
        r.end = w;
        return true;
      }
      end_field();
      if (buf_[pos_] == delim) {
        buf_[w++] = delim;
        ++pos_;
        field_begin = w;
        continue;
      }
      consume_line_end();
      r.line_end = true;
      r.end = w;
      return true;
    }
  }

  std::size_t pos() const { return pos_; }
  // Line of the next unread character, counted from 1 at the start.
  std::uint64_t next_line() const { return next_line_; }

 private:
  // The next n raw bytes become decoded bytes at w.
  void move_run(std::size_t& w, std::size_t n) {
    if (w != pos_) std::memmove(buf_ + w, buf_ + pos_, n);
    w += n;
    pos_ += n;
  }
  void consume_line_end() {
    const char c = buf_[pos_++];
    if (c == '\r' && pos_ < end_ && buf_[pos_] == '\n') ++pos_;
    ++next_line_;
  }

  char* buf_;
  std::size_t pos_, end_;
  std::uint64_t next_line_ = 1;
};

// Follows CsvReader's quoting over raw text from a record start, quote to quote (memchr), to
// tell whether a position is inside a quoted field. A quote opens one at a field start (at
// `begin`, or after the delimiter or a line end outside quotes) and right after a closing quote (a doubled
// quote); inside, any quote closes it; elsewhere a quote is text.
class QuoteWalker {
 public:
  QuoteWalker(const char* buf, std::size_t begin, std::size_t end, char delimiter)
      : buf_(buf), begin_(begin), end_(end), next_(begin), delim_(delimiter) {}

  // Whether position e (>= every earlier e) is inside a quoted field.
  bool inside_at(std::size_t e) {
    while (next_ < e) {
      const void* q = std::memchr(buf_ + next_, '"', e - next_);
      if (q == nullptr) {
        next_ = e;
        break;
      }
      step(static_cast<std::size_t>(static_cast<const char*>(q) - buf_));
    }
    return inside_;
  }

  // Inside a quoted field: the position after its closing quote (end if there is none).
  std::size_t skip_quoted() {
    const void* q = std::memchr(buf_ + next_, '"', end_ - next_);
    if (q == nullptr) {
      next_ = end_;
      return end_;
    }
    step(static_cast<std::size_t>(static_cast<const char*>(q) - buf_));
    return next_;
  }

 private:
  void step(std::size_t p) {
    if (inside_) {
      inside_ = false;
      after_close_ = p + 1;
    } else if (p == begin_ || p == after_close_ || buf_[p - 1] == delim_ || buf_[p - 1] == '\n' ||
               buf_[p - 1] == '\r') {
      inside_ = true;
    }
    next_ = p + 1;
  }

  const char* buf_;
  std::size_t begin_, end_, next_;
  char delim_;
  std::size_t after_close_ = std::numeric_limits<std::size_t>::max();
  bool inside_ = false;
};

// The line CsvReader was on when it met a read error after the good bytes [0, size): every line
// end before counted, except a CR outside quotes at the very end (it was looking for its LF).
std::uint64_t read_error_line(const char* buf, std::size_t begin, std::size_t size, char delimiter) {
  std::uint64_t line = 1;
  for (std::size_t i = 0; i < size; ++i) {
    if (buf[i] == '\r' || (buf[i] == '\n' && (i == 0 || buf[i - 1] != '\r'))) ++line;
  }
  if (size > begin && buf[size - 1] == '\r') {
    QuoteWalker quotes(buf, begin, size, delimiter);
    if (!quotes.inside_at(size - 1)) --line;
  }
  return line;
}

Error read_error(const std::string& source, std::uint64_t line) {
  return Error(ErrorCode::Io, source + ": read error near line " + std::to_string(line));
}

// An accepted row until finish(): its decoded fields are [begin, begin + size) of the buffer.
struct PendingSite {
  std::uint64_t row = 0;   // counted from 1 in its chunk
  std::uint64_t line = 0;  // counted from 1 in its chunk
  std::uint64_t begin = 0;
  std::uint32_t size = 0;
  std::uint32_t split = 0;  // 0: split at the delimiter; else 1 + index of its field ends in Chunk::field_ends
  double lat_deg = 0, lon_deg = 0;
};

constexpr std::uint64_t kNoUnterminated = std::numeric_limits<std::uint64_t>::max();

// One thread's share of the data rows, and what it found there.
struct Chunk {
  std::size_t begin = 0, end = 0;  // raw bytes; begins at a record start
  std::uint64_t records = 0;       // data rows
  std::uint64_t lines = 0;         // line ends
  std::vector<PendingSite> pending;
  std::vector<Vec3> units;          // of pending, same order
  std::vector<double> heights_m;    // of pending, ECEF input only
  std::vector<std::size_t> field_ends;
  std::vector<RejectedRow> rejected;  // row and line counted in the chunk
  // The last record's quoted field is unterminated: its index in rejected, the quote's line, the
  // field's column.
  std::uint64_t unterminated = kNoUnterminated, quote_line = 0;
  std::size_t quote_column = 0;
  // The first row with a value in a column without a name (row counted in the chunk; 0: none).
  std::uint64_t unnamed_row = 0, unnamed_line = 0;
  std::size_t unnamed_column = 0;
  std::string unnamed_value;
};

// The offset of the first byte of [p, p + n) that is not part of valid UTF-8 (no overlong form,
// no surrogate, nothing beyond U+10FFFF); n if there is none.
std::size_t invalid_utf8_at(const char* text, std::size_t n) {
  const auto* p = reinterpret_cast<const unsigned char*>(text);
  std::size_t i = 0;
  while (i < n) {
    while (i + 16 <= n) {  // ASCII runs, 16 bytes at a time
      std::uint64_t a, b;
      std::memcpy(&a, p + i, 8);
      std::memcpy(&b, p + i + 8, 8);
      if (((a | b) & 0x8080808080808080ULL) != 0) break;
      i += 16;
    }
    if (i + 8 <= n) {
      std::uint64_t word;
      std::memcpy(&word, p + i, 8);
      if ((word & 0x8080808080808080ULL) == 0) {
        i += 8;
        continue;
      }
    }
    const unsigned char c = p[i];
    if (c < 0x80) {
      ++i;
      continue;
    }
    std::size_t len = 0;
    unsigned char lo = 0x80, hi = 0xBF;  // the second byte's range
    if (c >= 0xC2 && c <= 0xDF) {
      len = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3;
      if (c == 0xE0) lo = 0xA0;
      if (c == 0xED) hi = 0x9F;
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4;
      if (c == 0xF0) lo = 0x90;
      if (c == 0xF4) hi = 0x8F;
    } else {
      return i;
    }
    if (i + len > n || p[i + 1] < lo || p[i + 1] > hi) return i;
    for (std::size_t k = 2; k < len; ++k)
      if ((p[i + k] & 0xC0) != 0x80) return i;
    i += len;
  }
  return n;
}

// The reason for bytes that are not UTF-8 at `at` in `field` (column `name`).
std::string utf8_reason(const std::string& name, std::string_view field, std::size_t at) {
  char byte[8];
  std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned>(static_cast<unsigned char>(field[at])));
  return name + ": not valid UTF-8 (byte " + byte + " at byte " + std::to_string(at + 1) +
         " of the field); give the file's encoding, e.g. --encoding ISO-8859-1";
}

// Tokenises and locates the chunk's rows.
template <char kDelimiter>
void scan_chunk(char* buf, const SiteTable& table, const ScanRules& rules, Chunk& chunk) {
  const std::size_t columns = rules.total;
  const std::size_t named = rules.named;
  const bool ecef = !table.ecef_columns.empty();
  // Lines bound the records: reserve once rather than grow.
  std::size_t lines = static_cast<std::size_t>(std::count(buf + chunk.begin, buf + chunk.end, '\n'));
  if (lines == 0) lines = static_cast<std::size_t>(std::count(buf + chunk.begin, buf + chunk.end, '\r'));
  chunk.pending.reserve(lines + 1);
  chunk.units.reserve(lines + 1);
  if (ecef) chunk.heights_m.reserve(lines + 1);

  Tokenizer<kDelimiter> tokens(buf, chunk.begin, chunk.end);
  RawRecord record;
  std::vector<std::string_view> fields;
  std::uint64_t row = 0;
  // The next byte that is not UTF-8, in the raw text ahead of the tokeniser (chunk.end: none);
  // only a record whose raw bytes hold it is checked field by field.
  std::size_t next_bad = chunk.begin + invalid_utf8_at(buf + chunk.begin, chunk.end - chunk.begin);
  while (tokens.next(record, fields)) {
    ++row;
    const bool maybe_bad = next_bad < tokens.pos();
    if (maybe_bad) next_bad = tokens.pos() + invalid_utf8_at(buf + tokens.pos(), chunk.end - tokens.pos());
    auto reject = [&](std::string reason) {
      chunk.rejected.push_back(RejectedRow{row, record.line, std::move(reason)});
    };
    if (record.quote_line != 0) {
      chunk.unterminated = chunk.rejected.size();
      chunk.quote_line = record.quote_line;
      chunk.quote_column = fields.size() - 1;
      reject("");  // the reason names the absolute line: made once lines are numbered
      continue;
    }
    if (const std::size_t bad = maybe_bad ? invalid_utf8_at(buf + record.begin, record.end - record.begin)
                                          : record.end - record.begin;
        bad != record.end - record.begin) {
      const char* at = buf + record.begin + bad;
      std::size_t c = 0;
      while (c + 1 < fields.size() && at >= fields[c].data() + fields[c].size()) ++c;
      const std::string name = c < named ? table.columns[c] : "field " + std::to_string(c + 1);
      reject(utf8_reason(name, fields[c], static_cast<std::size_t>(at - fields[c].data())));
      continue;
    }
    if (named < columns && fields.size() >= named && fields.size() <= columns) {
      // Columns without a name: the row may omit them, but must leave them empty.
      for (std::size_t c = named; c < fields.size(); ++c)
        if (!trim(fields[c]).empty() && chunk.unnamed_row == 0) {
          chunk.unnamed_row = row;
          chunk.unnamed_line = record.line;
          chunk.unnamed_column = c;
          chunk.unnamed_value = quoted(fields[c]);
        }
      fields.resize(named);
    } else if (fields.size() != columns) {
      std::string reason = "found " + std::to_string(fields.size()) + " fields, expected " +
                           std::to_string(columns) + " as in the header";
      if (fields.size() < named) {
        std::vector<std::string> missing(
            table.columns.begin() + static_cast<std::ptrdiff_t>(fields.size()),
            table.columns.end());
        reason += " (no value for " + join(missing) + ")";
      }
      reject(std::move(reason));
      continue;
    }
    Located site;
    if (std::string reason = locate_site(table, fields, site, rules); !reason.empty()) {
      reject(std::move(reason));
      continue;
    }
    PendingSite pending;
    pending.row = row;
    pending.line = record.line;
    pending.begin = record.begin;
    pending.lat_deg = site.lat_deg;
    pending.lon_deg = site.lon_deg;
    const std::size_t size = record.end - record.begin;
    if (record.comma_in_field || size > std::numeric_limits<std::uint32_t>::max()) {
      pending.split = static_cast<std::uint32_t>(chunk.field_ends.size() / named + 1);
      for (const std::string_view f : fields) {
        chunk.field_ends.push_back(static_cast<std::size_t>(f.data() + f.size() - buf));
      }
    } else {
      pending.size = static_cast<std::uint32_t>(size);
    }
    chunk.pending.push_back(pending);
    chunk.units.push_back(site.unit);
    if (ecef) chunk.heights_m.push_back(site.height_m);
  }
  chunk.records = row;
  chunk.lines = tokens.next_line() - 1;
}

// Where the chunks start: every target moved forward to the next record start (after a line end
// outside quotes, after the LF of a CRLF), found from the raw text before any thread decodes it.
std::vector<std::size_t> chunk_starts(const char* buf, std::size_t body, std::size_t size,
                                      std::vector<std::size_t> targets, char delimiter) {
  std::sort(targets.begin(), targets.end());
  std::vector<std::size_t> starts = {body};
  QuoteWalker quotes(buf, body, size, delimiter);
  for (const std::size_t target : targets) {
    std::size_t pos = std::max(target, starts.back());
    std::size_t start = size;
    while (pos < size) {
      std::size_t e = pos;
      while (e < size && buf[e] != '\n' && buf[e] != '\r') ++e;
      if (e == size) break;
      if (!quotes.inside_at(e)) {
        start = e + 1;
        if (buf[e] == '\r' && start < size && buf[start] == '\n') ++start;
        break;
      }
      pos = quotes.skip_quoted();
    }
    if (start >= size) break;  // so are all later targets'
    starts.push_back(start);
  }
  return starts;
}

// f(std::integral_constant<char, d>{}) for the delimiters the reader knows.
template <typename F>
decltype(auto) with_delimiter(char d, F&& f) {
  switch (d) {
    case ';': return f(std::integral_constant<char, ';'>{});
    case '\t': return f(std::integral_constant<char, '\t'>{});
    case '|': return f(std::integral_constant<char, '|'>{});
    default: return f(std::integral_constant<char, ','>{});
  }
}

// The delimiter of the header line starting at `begin`: the most frequent of ',', ';', TAB and
// '|' outside quotes, ties to the earlier in that order; ',' when there is none.
char sniff_delimiter(const char* buf, std::size_t begin, std::size_t size) {
  constexpr char kCandidates[] = {',', ';', '\t', '|'};
  std::size_t counts[4] = {};
  bool inside = false;
  for (std::size_t i = begin; i < size; ++i) {
    const char c = buf[i];
    if (c == '"') {
      inside = !inside;  // a doubled quote toggles twice
    } else if (!inside) {
      if (c == '\n' || c == '\r') break;
      for (int k = 0; k < 4; ++k)
        if (c == kCandidates[k]) ++counts[k];
    }
  }
  int best = 0;
  for (int k = 1; k < 4; ++k)
    if (counts[k] > counts[best]) best = k;
  return kCandidates[best];
}

// The text converted from `encoding` to UTF-8 by iconv.
Text to_utf8(const Text& text, const std::string& encoding, const std::string& source) {
  iconv_t cd = iconv_open("UTF-8", encoding.c_str());
  if (cd == reinterpret_cast<iconv_t>(-1))
    throw Error(ErrorCode::InvalidArgument, "--encoding " + encoding + ": not an encoding iconv knows (iconv -l lists them)");
  Text out;
  std::size_t capacity = 4 * text.size + 16;  // UTF-8 takes at most 4 bytes per input byte
  out.data = std::make_unique_for_overwrite<char[]>(capacity);
  char* in = text.data.get();
  std::size_t in_left = text.size;
  char* o = out.data.get();
  std::size_t out_left = capacity;
  const std::size_t rc = iconv(cd, &in, &in_left, &o, &out_left);
  const int err = errno;
  iconv_close(cd);
  if (rc == static_cast<std::size_t>(-1)) {
    const std::size_t at = text.size - in_left;
    const std::uint64_t line = 1 + static_cast<std::uint64_t>(std::count(text.data.get(), text.data.get() + at, '\n'));
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02X", at < text.size ? static_cast<unsigned>(static_cast<unsigned char>(text.data[at])) : 0u);
    throw Error(ErrorCode::BadData, source + ": line " + std::to_string(line) + ": " +
                                        (err == EINVAL ? std::string("text cut inside a character")
                                                       : "byte " + std::string(byte) + " (byte " + std::to_string(at + 1) +
                                                             " of the file) is not valid " + encoding));
  }
  out.size = capacity - out_left;
  out.failed = text.failed;
  return out;
}

// A stream (stdin, a pipe, a FIFO, a device) is read as delimited text without being sniffed
// first: one whose head is not text (a NUL byte, JSON or XML) is refused, naming the file.
void require_text_head(const char* buf, std::size_t size, const std::string& source) {
  const std::string_view head(buf, std::min<std::size_t>(size, 4096));
  std::string what;
  if (head.find('\0') != std::string_view::npos) {
    what = "a NUL byte in its first 4 KiB (a binary format?)";
  } else {
    std::size_t first = head.starts_with("\xEF\xBB\xBF") ? 3 : 0;
    first = head.find_first_not_of(" \t\r\n", first);
    if (first != std::string_view::npos && std::string_view("{[<").find(head[first]) != std::string_view::npos)
      what = std::string("it starts with '") + head[first] + (head[first] == '<' ? "' (XML?)" : "' (JSON?)");
  }
  if (!what.empty())
    throw Error(ErrorCode::BadData, source + ": not delimited text: " + what +
                                        "; a pipe, FIFO, device or standard input is read as delimited text only "
                                        "(GDAL needs a file it can reopen): save the data to a file and give that");
}

}  // namespace

struct CsvSiteScan::State {
  Text text;
  SiteTable table;  // everything but the sites
  std::vector<Chunk> chunks;
  std::vector<std::uint64_t> row_base, line_base;  // per chunk: its first row and first line - 1
  std::size_t sites = 0;
  bool detect_types = true;  // SiteReaderOptions::detect_types
  std::vector<FieldTypeOverride> field_types;  // SiteReaderOptions::field_types
  bool stream = false;       // read from a pipe, FIFO, device or stdin: its head not sniffed first
  ScanRules rules;
};

CsvSiteScan::CsvSiteScan(std::unique_ptr<State> state) : state_(std::move(state)) {}
CsvSiteScan::CsvSiteScan(CsvSiteScan&&) noexcept = default;
CsvSiteScan& CsvSiteScan::operator=(CsvSiteScan&&) noexcept = default;
CsvSiteScan::~CsvSiteScan() = default;

std::uint64_t CsvSiteScan::rows_read() const { return state_ ? state_->table.rows_read : 0; }

CsvSiteScan CsvSiteScan::read(std::istream& in, const std::string& source,
                              const SiteReaderOptions& options, const CsvScanTuning& tuning) {
  check_options(options);
  auto state = std::make_unique<State>();
  state->table.source = source;
  state->text = read_text(in, 0);
  CsvSiteScan scan(std::move(state));
  scan.scan(options, tuning);
  return scan;
}

CsvSiteScan CsvSiteScan::open(const std::string& path, const SiteReaderOptions& options,
                              const CsvScanTuning& tuning) {
  std::error_code ec;
  if (path == "-") {
    check_options(options);
    auto state = std::make_unique<State>();
    state->table.source = "<stdin>";
    state->stream = true;
    state->text = read_text(std::cin, 0);
    CsvSiteScan scan(std::move(state));
    scan.scan(options, tuning);
    return scan;
  }
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
  check_options(options);
  // A regular file is read in one go: its size is known.
  std::size_t size_hint = 0;
  if (std::filesystem::is_regular_file(path, ec)) {
    const auto size = std::filesystem::file_size(path, ec);
    if (!ec) size_hint = static_cast<std::size_t>(size);
  }
  auto state = std::make_unique<State>();
  state->table.source = path;
  state->stream = !std::filesystem::is_regular_file(path, ec);
  state->text = read_text(file, size_hint);
  CsvSiteScan scan(std::move(state));
  scan.scan(options, tuning);
  return scan;
}

void CsvSiteScan::scan(const SiteReaderOptions& options, const CsvScanTuning& tuning) {
  State& s = *state_;
  s.detect_types = options.detect_types;
  s.field_types = options.field_types;
  std::vector<Vec3>& positions = positions_;
  SiteTable& table = s.table;
  const std::string& source = table.source;
  if (!options.encoding.empty()) {
    const std::string e = ascii_lower(options.encoding);
    if (e != "utf-8" && e != "utf8") s.text = to_utf8(s.text, options.encoding, source);
  }
  char* const buf = s.text.data.get();
  const std::size_t size = s.text.size;
  if (s.stream) require_text_head(buf, size, source);
  const std::size_t start = size >= 3 && std::memcmp(buf, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
  ScanRules& rules = s.rules;
  rules.delimiter = options.delimiter != 0 ? options.delimiter : sniff_delimiter(buf, start, size);
  if (std::string_view(",;\t|").find(rules.delimiter) == std::string_view::npos)
    throw Error(ErrorCode::InvalidArgument, "the delimiter must be ',', ';', TAB or '|'");
  table.delimiter = rules.delimiter;
  rules.decimal_comma = rules.delimiter != ',';
  rules.projected = !options.s_srs.empty();
  // A read error: CsvReader would have met it when it needed the first byte after the good ones,
  // which is at the end of the header unless the header is cut short.
  const std::uint64_t error_line = s.text.failed ? read_error_line(buf, start, size, rules.delimiter) : 0;

  RawRecord record;
  std::vector<std::string_view> fields;
  std::size_t body = 0;                // where the rows start
  std::uint64_t header_next_line = 1;  // the line after the header
  const bool has_header = with_delimiter(rules.delimiter, [&](auto d) {
    Tokenizer<decltype(d)::value> header(buf, start, size);
    const bool found = header.next(record, fields);
    body = header.pos();
    header_next_line = header.next_line();
    return found;
  });
  if (s.text.failed && (!has_header || !record.line_end ||
                        (body == size && buf[size - 1] == '\r'))) {
    throw read_error(source, error_line);
  }
  if (!has_header) throw Error(ErrorCode::BadData, source + ": empty file, no header");
  // A compressed file would otherwise be reported as a header of binary garbage.
  if (fields[0].starts_with("\x1f\x8b")) {
    throw Error(ErrorCode::BadData,
                source + ": gzip-compressed data, not CSV; decompress it first");
  }
  if (record.quote_line != 0) {
    throw Error(ErrorCode::BadData, source + ": header: unterminated quoted field starting on line " +
                                        std::to_string(record.quote_line));
  }
  for (std::size_t c = 0; c < fields.size(); ++c)
    if (const std::size_t bad = invalid_utf8_at(fields[c].data(), fields[c].size()); bad != fields[c].size())
      throw Error(ErrorCode::BadData, source + ": header: " + utf8_reason("column " + std::to_string(c + 1), fields[c], bad));
  table.columns.assign(fields.begin(), fields.end());
  rules.named = table.columns.size() - check_header_names(table.columns, source);
  if (rules.named == 0) throw Error(ErrorCode::BadData, source + ": header: no column has a name");
  rules.total = table.columns.size();
  table.columns.resize(rules.named);  // the empty trailing ones are dropped
  choose_columns(table, options);
  if (s.text.failed) throw read_error(source, error_line);

  // One chunk per thread, each with at least min_chunk_bytes of rows.
  std::vector<std::size_t> targets = tuning.cuts;
  if (targets.empty()) {
    const std::size_t wanted = thread_count(options.threads);
    const std::size_t n = std::max<std::size_t>(
        1, std::min(wanted, (size - body) / std::max<std::size_t>(1, tuning.min_chunk_bytes)));
    for (std::size_t k = 1; k < n; ++k) targets.push_back(body + (size - body) * k / n);
  }
  const std::vector<std::size_t> starts = chunk_starts(buf, body, size, std::move(targets), rules.delimiter);
  s.chunks.resize(starts.size());
  for (std::size_t k = 0; k < starts.size(); ++k) {
    s.chunks[k].begin = starts[k];
    s.chunks[k].end = k + 1 < starts.size() ? starts[k + 1] : size;
  }

  // One slice per chunk (the first chunk's error, by chunk order, is rethrown).
  const std::size_t chunks = s.chunks.size();
  parallel_for(chunks, static_cast<unsigned>(chunks), [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k)
      with_delimiter(rules.delimiter, [&](auto d) { scan_chunk<decltype(d)::value>(buf, table, rules, s.chunks[k]); });
  });

  // Rows and lines numbered across chunks; rejected rows in row order, chunk after chunk.
  std::uint64_t rows = 0, line = header_next_line - 1;
  std::size_t sites = 0, rejected = 0;
  for (const Chunk& c : s.chunks) {
    s.row_base.push_back(rows);
    s.line_base.push_back(line);
    rows += c.records;
    line += c.lines;
    sites += c.pending.size();
    rejected += c.rejected.size();
  }
  table.rows_read = rows;
  s.sites = sites;
  table.rejected.reserve(rejected);
  for (std::size_t k = 0; k < s.chunks.size(); ++k) {
    Chunk& c = s.chunks[k];
    if (c.unterminated != kNoUnterminated) {
      const std::string error = "unterminated quoted field starting on line " +
                                std::to_string(s.line_base[k] + c.quote_line);
      c.rejected[c.unterminated].reason = c.quote_column < table.columns.size()
                                              ? table.columns[c.quote_column] + ": " + error
                                              : error;
    }
    for (RejectedRow& r : c.rejected) {
      table.rejected.push_back(
          RejectedRow{r.row + s.row_base[k], r.line + s.line_base[k], std::move(r.reason)});
    }
    c.rejected = {};
  }
  for (std::size_t k = 0; k < s.chunks.size(); ++k) {
    const Chunk& c = s.chunks[k];
    if (c.unnamed_row != 0)
      throw Error(ErrorCode::BadData, source + ": header: column " + std::to_string(c.unnamed_column + 1) +
                                          " has no name, but row " + std::to_string(c.unnamed_row + s.row_base[k]) +
                                          " (line " + std::to_string(c.unnamed_line + s.line_base[k]) +
                                          ") has a value there: " + c.unnamed_value + "; name the column");
  }
  if (s.chunks.size() == 1) {
    positions = std::move(s.chunks[0].units);
  } else {
    positions.reserve(sites);
    for (Chunk& c : s.chunks) {
      positions.insert(positions.end(), c.units.begin(), c.units.end());
      c.units = {};
    }
  }
}

SiteTable CsvSiteScan::finish() && {
  if (!state_) throw Error(ErrorCode::Internal, "CsvSiteScan::finish called twice");
  State& s = *state_;
  SiteTable table = std::move(s.table);
  const char* const buf = s.text.data.get();
  const std::size_t columns = table.columns.size();
  const int id_column = table.id_column;
  const char delimiter = s.rules.delimiter;
  table.sites.reserve(s.sites);
  // Typed row by row, while each row's fields are in cache.
  const bool detect = state_->detect_types;
  ColumnTypeDetector detector(columns, id_column);
  std::size_t i = 0;  // index into positions_
  for (std::size_t k = 0; k < s.chunks.size(); ++k) {
    const Chunk& c = s.chunks[k];
    for (std::size_t j = 0; j < c.pending.size(); ++j, ++i) {
      const PendingSite& p = c.pending[j];
      InputSite& site = table.sites.emplace_back();
      site.row = p.row + s.row_base[k];
      site.line = p.line + s.line_base[k];
      site.lat_deg = p.lat_deg;
      site.lon_deg = p.lon_deg;
      if (!c.heights_m.empty()) site.height_m = c.heights_m[j];
      site.unit = positions_[i];
      site.fields.reserve(columns);
      if (p.split == 0) {
        const char* f = buf + p.begin;
        const char* const last = f + p.size;
        for (;;) {
          const char* comma = static_cast<const char*>(std::memchr(f, delimiter, static_cast<std::size_t>(last - f)));
          if (comma == nullptr) {
            site.fields.emplace_back(f, last);
            break;
          }
          site.fields.emplace_back(f, comma);
          f = comma + 1;
        }
        if (site.fields.size() > columns) site.fields.resize(columns);  // empty columns without a name
      } else {
        const std::size_t* ends = c.field_ends.data() + (p.split - 1) * columns;
        std::size_t f = p.begin;
        for (std::size_t col = 0; col < columns; ++col) {
          site.fields.emplace_back(buf + f, buf + ends[col]);
          f = ends[col] + 1;
        }
      }
      site.id = id_column >= 0 ? site.fields[static_cast<std::size_t>(id_column)]
                               : std::to_string(site.row);
      if (detect) detector.add(site.fields);
    }
  }
  const std::vector<FieldTypeOverride> declared = std::move(state_->field_types);
  state_.reset();  // the buffer and the per-row data; positions_ stay
  table.column_types = detect ? detector.types() : std::vector<FieldType>(table.columns.size(), FieldType::String);
  apply_field_types(table, declared);
  return table;
}

}  // namespace geovor
