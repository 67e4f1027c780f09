#include "geovor/geo/csv_reader.hpp"

#include <cstring>

#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"

namespace geovor {
namespace {

// Large enough that refills are rare, small enough to be cheap for tiny inputs.
constexpr std::size_t kBlockSize = 1 << 16;

}  // namespace

CsvReader::CsvReader(std::istream& in, char delimiter) : in_(in), delim_(delimiter), buf_(kBlockSize) {
  GEOVOR_ASSERT(delimiter != '"' && delimiter != '\n' && delimiter != '\r');
}

bool CsvReader::fill() {
  if (pos_ < end_) return true;
  pos_ = end_ = 0;
  if (!in_.good()) {
    if (in_.bad()) throw Error(ErrorCode::Io, "read error near line " + std::to_string(next_line_));
    return false;
  }
  in_.read(buf_.data(), static_cast<std::streamsize>(buf_.size()));
  end_ = static_cast<std::size_t>(in_.gcount());
  if (in_.bad()) throw Error(ErrorCode::Io, "read error near line " + std::to_string(next_line_));
  if (!started_) {
    started_ = true;
    // One read() fills the whole block unless the stream ends, so a BOM cannot be split.
    if (end_ >= 3 && std::memcmp(buf_.data(), "\xEF\xBB\xBF", 3) == 0) pos_ = 3;
  }
  return pos_ < end_;
}

bool CsvReader::at_char() { return pos_ < end_ || fill(); }

void CsvReader::consume_line_end() {
  const char c = buf_[pos_++];
  if (c == '\r' && at_char() && buf_[pos_] == '\n') ++pos_;
  ++next_line_;
}

bool CsvReader::next(std::vector<std::string>& fields) {
  error_.clear();
  // Skip empty lines; see the header for why they are not records.
  for (;;) {
    if (!at_char()) {
      fields.clear();
      return false;
    }
    const char c = buf_[pos_];
    if (c != '\n' && c != '\r') break;
    consume_line_end();
  }
  line_ = next_line_;
  ++record_;

  std::size_t count = 0;
  // Reuse the strings already in fields, so their capacity survives from record to record.
  auto start_field = [&]() -> std::string& {
    if (count < fields.size()) {
      fields[count].clear();
    } else {
      fields.emplace_back();
    }
    return fields[count++];
  };
  std::string* field = &start_field();
  enum class State { Start, Unquoted, Quoted, AfterQuote };
  State state = State::Start;
  std::uint64_t quote_line = 0;

  for (;;) {
    if (!at_char()) {
      if (state == State::Quoted) {
        error_ = "unterminated quoted field starting on line " + std::to_string(quote_line);
      }
      fields.resize(count);
      return true;
    }
    switch (state) {
      case State::Start:
        if (buf_[pos_] == '"') {
          ++pos_;
          state = State::Quoted;
          quote_line = next_line_;
          prev_cr_ = false;
          break;
        }
        state = State::Unquoted;
        [[fallthrough]];
      case State::Unquoted: {
        // Copy the whole run of ordinary characters at once: this is the hot loop.
        const char* const first = buf_.data() + pos_;
        const char* const last = buf_.data() + end_;
        const char* p = first;
        while (p != last && *p != delim_ && *p != '\n' && *p != '\r') ++p;
        field->append(first, p);
        pos_ += static_cast<std::size_t>(p - first);
        if (p == last) break;
        if (*p == delim_) {
          ++pos_;
          field = &start_field();
          state = State::Start;
          break;
        }
        consume_line_end();
        fields.resize(count);
        return true;
      }
      case State::Quoted: {
        const char* const first = buf_.data() + pos_;
        const char* const last = buf_.data() + end_;
        const char* p = first;
        for (; p != last && *p != '"'; ++p) {
          // CRLF, LF and lone CR each count as one line, even across a block boundary.
          if (*p == '\n') {
            if (!prev_cr_) ++next_line_;
            prev_cr_ = false;
          } else if (*p == '\r') {
            ++next_line_;
            prev_cr_ = true;
          } else {
            prev_cr_ = false;
          }
        }
        field->append(first, p);
        pos_ += static_cast<std::size_t>(p - first);
        if (p == last) break;
        ++pos_;
        prev_cr_ = false;
        state = State::AfterQuote;
        break;
      }
      case State::AfterQuote: {
        const char c = buf_[pos_];
        if (c == '"') {
          field->push_back('"');
          ++pos_;
          state = State::Quoted;
        } else if (c == delim_) {
          ++pos_;
          field = &start_field();
          state = State::Start;
        } else if (c == '\n' || c == '\r') {
          consume_line_end();
          fields.resize(count);
          return true;
        } else {
          state = State::Unquoted;
        }
        break;
      }
    }
  }
}

}  // namespace geovor
