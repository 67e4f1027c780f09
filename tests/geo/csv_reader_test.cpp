/// \file csv_reader_test.cpp
/// \brief Tests of CsvReader: RFC 4180 quoting, line ends, BOM, huge lines, block boundaries.
#include "geovor/geo/csv_reader.hpp"

#include <gtest/gtest.h>

#include <random>
#include <sstream>
#include <streambuf>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"

namespace geovor {
namespace {

using Record = std::vector<std::string>;

struct Read {
  std::vector<Record> records;
  std::vector<std::uint64_t> lines;
  std::vector<std::string> errors;
};

Read read_all(const std::string& text, char delimiter = ',') {
  std::istringstream in(text);
  CsvReader reader(in, delimiter);
  Read out;
  Record fields;
  while (reader.next(fields)) {
    out.records.push_back(fields);
    out.lines.push_back(reader.line());
    out.errors.push_back(reader.error());
    EXPECT_EQ(reader.record(), out.records.size());
  }
  EXPECT_TRUE(fields.empty());
  return out;
}

TEST(CsvReader, EmptyInputHasNoRecords) {
  EXPECT_TRUE(read_all("").records.empty());
  EXPECT_TRUE(read_all("\xEF\xBB\xBF").records.empty());
  EXPECT_TRUE(read_all("\n\r\n\n").records.empty());
}

TEST(CsvReader, SimpleRecords) {
  const Read r = read_all("a,b,c\n1,2,3\n");
  ASSERT_EQ(r.records.size(), 2u);
  EXPECT_EQ(r.records[0], (Record{"a", "b", "c"}));
  EXPECT_EQ(r.records[1], (Record{"1", "2", "3"}));
  EXPECT_EQ(r.lines, (std::vector<std::uint64_t>{1, 2}));
  EXPECT_EQ(r.errors, (std::vector<std::string>{"", ""}));
}

TEST(CsvReader, LastRecordWithoutLineEnd) {
  const Read r = read_all("a,b\n1,2");
  ASSERT_EQ(r.records.size(), 2u);
  EXPECT_EQ(r.records[1], (Record{"1", "2"}));
}

TEST(CsvReader, ByteOrderMarkIsSkipped) {
  const Read r = read_all("\xEF\xBB\xBFlat,lon\n1,2\n");
  ASSERT_EQ(r.records.size(), 2u);
  EXPECT_EQ(r.records[0], (Record{"lat", "lon"}));
  // A BOM-like sequence later in the file is data.
  const Read s = read_all("x\n\xEF\xBB\xBFy\n");
  EXPECT_EQ(s.records[1][0], "\xEF\xBB\xBFy");
}

TEST(CsvReader, CrLfAndLoneCrAndLfLineEnds) {
  const Read r = read_all("a,b\r\n1,2\r\n3,4\n5,6\r7,8\r\n");
  ASSERT_EQ(r.records.size(), 5u);
  EXPECT_EQ(r.records[1], (Record{"1", "2"}));
  EXPECT_EQ(r.records[2], (Record{"3", "4"}));
  EXPECT_EQ(r.records[3], (Record{"5", "6"}));
  EXPECT_EQ(r.records[4], (Record{"7", "8"}));
  EXPECT_EQ(r.lines, (std::vector<std::uint64_t>{1, 2, 3, 4, 5}));
}

TEST(CsvReader, EmptyFields) {
  const Read r = read_all(",,\na,,\n,\"\",b\n");
  ASSERT_EQ(r.records.size(), 3u);
  EXPECT_EQ(r.records[0], (Record{"", "", ""}));
  EXPECT_EQ(r.records[1], (Record{"a", "", ""}));
  EXPECT_EQ(r.records[2], (Record{"", "", "b"}));
}

TEST(CsvReader, QuotedFieldsWithCommasQuotesAndNewlines) {
  const std::string text =
      "id,name,note\n"
      "1,\"Honiara / Henderson, Solomon Islands\",x\n"
      "2,\"say \"\"hi\"\"\",\"\"\"\"\n"
      "3,\"two\nlines\",\"crlf\r\ninside\"\n"
      "4,last,\"\"\n";
  const Read r = read_all(text);
  ASSERT_EQ(r.records.size(), 5u);
  EXPECT_EQ(r.records[1], (Record{"1", "Honiara / Henderson, Solomon Islands", "x"}));
  EXPECT_EQ(r.records[2], (Record{"2", "say \"hi\"", "\""}));
  EXPECT_EQ(r.records[3], (Record{"3", "two\nlines", "crlf\r\ninside"}));
  EXPECT_EQ(r.records[4], (Record{"4", "last", ""}));
  // Record 4 holds two line breaks (LF, then CRLF): it spans lines 4-6, record 5 is on line 7.
  EXPECT_EQ(r.lines, (std::vector<std::uint64_t>{1, 2, 3, 4, 7}));
  for (const auto& e : r.errors) EXPECT_EQ(e, "");
}

TEST(CsvReader, LenientAboutStrayQuotes) {
  const Read r = read_all("ab\"c,\"de\"f,\" g\" \n");
  ASSERT_EQ(r.records.size(), 1u);
  EXPECT_EQ(r.records[0], (Record{"ab\"c", "def", " g "}));
  EXPECT_EQ(r.errors[0], "");
}

TEST(CsvReader, OtherDelimiters) {
  for (const char d : {';', '\t', '|'}) {
    const std::string s(1, d);
    // Commas are text; a quote opens a field only right after the delimiter or a line end.
    const Read r = read_all("a" + s + "b,c\n1,\"2" + s + "\"3" + s + "x\n\"\n4" + s + "\"\"" + s + "\n", d);
    ASSERT_EQ(r.records.size(), 3u) << d;
    EXPECT_EQ(r.records[0], (Record{"a", "b,c"}));
    EXPECT_EQ(r.records[1], (Record{"1,\"2", "3" + s + "x\n"}));
    EXPECT_EQ(r.records[2], (Record{"4", "", ""}));
    EXPECT_EQ(r.lines, (std::vector<std::uint64_t>{1, 2, 4}));
  }
}

TEST(CsvReader, EmptyLinesAreSkippedButCounted) {
  const Read r = read_all("a\n\n1\r\n\r\n\r\n2\n\n");
  ASSERT_EQ(r.records.size(), 3u);
  EXPECT_EQ(r.records[1], (Record{"1"}));
  EXPECT_EQ(r.records[2], (Record{"2"}));
  EXPECT_EQ(r.lines, (std::vector<std::uint64_t>{1, 3, 6}));
}

TEST(CsvReader, UnterminatedQuoteReturnsRecordWithError) {
  std::istringstream in("a,b\n1,\"open\n2,3\n");
  CsvReader reader(in);
  Record f;
  ASSERT_TRUE(reader.next(f));
  EXPECT_EQ(reader.error(), "");
  ASSERT_TRUE(reader.next(f));
  EXPECT_EQ(f, (Record{"1", "open\n2,3\n"}));
  EXPECT_EQ(reader.line(), 2u);
  EXPECT_EQ(reader.error(), "unterminated quoted field starting on line 2");
  EXPECT_FALSE(reader.next(f));
  EXPECT_EQ(reader.error(), "");  // cleared by next()
}

TEST(CsvReader, ErrorIsClearedAtNextRecord) {
  // The quote never closes, so the rest of the input is one record, read with an error.
  std::istringstream in("\"x\n1\n");
  CsvReader reader(in);
  Record f;
  ASSERT_TRUE(reader.next(f));
  EXPECT_NE(reader.error(), "");
  EXPECT_FALSE(reader.next(f));
  EXPECT_EQ(reader.error(), "");
}

TEST(CsvReader, TenMegabyteLine) {
  const std::string big(10 * 1024 * 1024 + 17, 'z');
  const Read r =
      read_all("h1,h2,h3\r\n1," + big + ",3\r\n\"" + big + "\",\"a,\"\"" + big + "\",x\r\n");
  ASSERT_EQ(r.records.size(), 3u);
  ASSERT_EQ(r.records[1].size(), 3u);
  EXPECT_EQ(r.records[1][1].size(), big.size());
  EXPECT_EQ(r.records[1][1], big);
  EXPECT_EQ(r.records[1][2], "3");
  ASSERT_EQ(r.records[2].size(), 3u);
  EXPECT_EQ(r.records[2][0], big);
  EXPECT_EQ(r.records[2][1], "a,\"" + big);
  EXPECT_EQ(r.records[2][2], "x");
  EXPECT_EQ(r.lines, (std::vector<std::uint64_t>{1, 2, 3}));
}

// Put `tail` so that its first character is the last byte of the reader's first 64 KiB block.
std::string straddling(const std::string& head, const std::string& tail) {
  constexpr std::size_t kBlock = 1 << 16;
  std::string text = head;
  text += std::string(kBlock - 1 - text.size(), 'p');
  return text + tail;
}

TEST(CsvReader, LineEndAndDoubledQuoteAcrossBlockBoundary) {
  {
    const Read r = read_all(straddling("a\n", "\r\nb\n"));
    ASSERT_EQ(r.records.size(), 3u);
    EXPECT_EQ(r.records[2], (Record{"b"}));
    EXPECT_EQ(r.lines, (std::vector<std::uint64_t>{1, 2, 3}));
  }
  {
    const Read r = read_all(straddling("a\n\"", "\"\"q\"\nb\n"));
    ASSERT_EQ(r.records.size(), 3u);
    EXPECT_EQ(r.records[1][0].back(), 'q');
    EXPECT_EQ(r.records[1][0][r.records[1][0].size() - 2], '"');
    EXPECT_EQ(r.lines, (std::vector<std::uint64_t>{1, 2, 3}));
  }
  {
    const Read r = read_all(straddling("a\n\"", "\r\n\"\nb\n"));
    ASSERT_EQ(r.records.size(), 3u);
    EXPECT_EQ(r.lines, (std::vector<std::uint64_t>{1, 2, 4}));
  }
}

std::string quote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

TEST(CsvReader, RandomRoundTrip) {
  std::mt19937_64 rng(20240611);
  const std::string alphabet = "abc ,\"\n\r;xyz019.-";
  std::vector<Record> written;
  std::string text;
  std::uint64_t line = 1;
  std::vector<std::uint64_t> lines;
  const char* const ends[] = {"\n", "\r\n", "\r"};
  for (int r = 0; r < 3000; ++r) {
    Record rec(1 + rng() % 6);
    for (auto& f : rec) {
      const std::size_t n = rng() % 40;
      for (std::size_t i = 0; i < n; ++i) f += alphabet[rng() % alphabet.size()];
    }
    if (rec.size() == 1 && rec[0].empty()) rec[0].push_back('e');  // an empty line is not a record
    lines.push_back(line);
    for (std::size_t i = 0; i < rec.size(); ++i) {
      if (i) text += ',';
      const auto& f = rec[i];
      const bool needs_quotes = f.find_first_of(",\"\r\n") != std::string::npos || rng() % 4 == 0;
      text += needs_quotes ? quote(f) : f;
      for (std::size_t k = 0; k < f.size(); ++k) {
        if (f[k] == '\n' && (k == 0 || f[k - 1] != '\r')) ++line;
        if (f[k] == '\r') ++line;
      }
    }
    text += ends[rng() % 3];
    ++line;
    written.push_back(rec);
  }
  ASSERT_GT(text.size(), 3u << 16);  // several block boundaries
  const Read r = read_all(text);
  ASSERT_EQ(r.records.size(), written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    ASSERT_EQ(r.records[i], written[i]) << "record " << i + 1;
    ASSERT_EQ(r.lines[i], lines[i]) << "record " << i + 1;
    ASSERT_EQ(r.errors[i], "");
  }
}

// A stream buffer whose device fails after some bytes, like a disk error.
class FailingBuf : public std::streambuf {
 public:
  explicit FailingBuf(std::string data) : data_(std::move(data)) {
    setg(data_.data(), data_.data(), data_.data() + data_.size());
  }

 protected:
  int_type underflow() override { throw std::runtime_error("device error"); }

 private:
  std::string data_;
};

TEST(CsvReader, ReadErrorThrowsIo) {
  FailingBuf buf("a,b\n1,2\n");
  std::istream in(&buf);
  CsvReader reader(in);
  Record f;
  try {
    reader.next(f);
    FAIL() << "expected geovor::Error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Io);
  }
}

}  // namespace
}  // namespace geovor
