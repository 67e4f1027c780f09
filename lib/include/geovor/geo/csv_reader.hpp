/// \file csv_reader.hpp
/// \brief CsvReader: a streaming RFC 4180 reader, one record at a time.
///
/// Accepts what spreadsheets and scripts actually write:
/// - a UTF-8 byte order mark at the start of the stream (skipped);
/// - CRLF, LF or lone CR line ends, mixed freely;
/// - quoted fields holding commas, line breaks (kept as written) and doubled quotes ("" -> ");
/// - empty fields, and a last record without a line end;
/// - text after a closing quote ("ab"c -> abc) and quotes inside an unquoted field (kept);
/// - a delimiter other than ',' (';', TAB, '|': what the site reader sniffs), given to the constructor.
///
/// Empty lines (no character at all before the line end) are not records: editors leave them,
/// most often at the end of a file, and reading them as a record of one empty field would only
/// produce a spurious bad row. line() still counts them, so positions stay true to the file.
///
/// A quote still open at the end of the stream ends the last record; that record is returned and
/// error() says why it is suspect. Field and line lengths are unbounded (no fixed buffer).
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace geovor {

class CsvReader {
 public:
  /// \param[in] in the stream to read; it must outlive the reader, which reads it in blocks.
  /// \param[in] delimiter the field delimiter; not '"', CR or LF (an assertion).
  explicit CsvReader(std::istream& in, char delimiter = ',');

  /// Read the next record.
  /// \param[out] fields the fields of the record (their storage is reused between calls).
  /// \return false at the end of the stream (fields is then empty).
  /// \throw Error (ErrorCode::Io) when the stream reports a read error.
  bool next(std::vector<std::string>& fields);

  /// 1-based line number where the last record returned by next() started.
  std::uint64_t line() const { return line_; }

  /// 1-based number of the last record returned by next(); a header is record 1.
  std::uint64_t record() const { return record_; }

  /// Why the last record is suspect ("" if it is not), e.g. an unterminated quoted field.
  /// Cleared at each next().
  const std::string& error() const { return error_; }

 private:
  bool fill();
  bool at_char();
  void consume_line_end();

  std::istream& in_;
  char delim_;
  std::vector<char> buf_;
  std::size_t pos_ = 0, end_ = 0;
  bool started_ = false;
  bool prev_cr_ = false;         // inside quotes: the last character consumed was a CR
  std::uint64_t next_line_ = 1;  // line number of the next unread character
  std::uint64_t line_ = 0, record_ = 0;
  std::string error_;
};

}  // namespace geovor
