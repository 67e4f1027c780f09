/// \file json_text_test.cpp
/// \brief JSON string escaping: every byte value at every position, invalid UTF-8 replaced,
/// long strings as their pieces.
#include "geovor/io/json_text.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace geovor {
namespace {

const std::string kTricky =
    "quote \" backslash \\ newline \n tab \t cr \r ctrl \x01\x1f del \x7f slash / "
    "\xC3\xA9t\xC3\xA9 \xE6\xBC\xA2\xE5\xAD\x97 \xF0\x9F\x98\x80";

TEST(JsonString, Escapes) {
  std::string s;
  append_json_string(s, std::string("a\"b\\c\x01\x1f\b\f\n\r\t\x7f/", 14));
  EXPECT_EQ(s, R"("a\"b\\c\u0001\u001f\b\f\n\r\t)" "\x7f" R"(/")");
  s.clear();
  append_json_string(s, std::string("\0", 1));
  EXPECT_EQ(s, R"("\u0000")");
  // Invalid UTF-8: overlong, surrogate, beyond U+10FFFF, truncated, stray continuation.
  for (const std::string bad : {"\xC0\xAF", "\xED\xA0\x80", "\xF4\x90\x80\x80", "\xE2\x82", "\x80"}) {
    s.clear();
    append_json_string(s, bad);
    EXPECT_EQ(s.find_first_not_of("\"\xEF\xBF\xBD"), std::string::npos) << s;
  }
  s.clear();
  append_json_string(s, "\xF4\x8F\xBF\xBF \xEE\x80\x80");  // U+10FFFF, U+E000: valid
  EXPECT_EQ(s, "\"\xF4\x8F\xBF\xBF \xEE\x80\x80\"");
}

// Every byte value at every position of a 17-byte ASCII string (the escaping skips plain runs
// 8 bytes at a time): the one byte is escaped, passed or replaced as alone, the rest is copied.
TEST(JsonString, EveryByteAtEveryPosition) {
  auto expected_byte = [](unsigned char c) -> std::string {
    switch (c) {
      case '"': return "\\\"";
      case '\\': return "\\\\";
      case '\b': return "\\b";
      case '\f': return "\\f";
      case '\n': return "\\n";
      case '\r': return "\\r";
      case '\t': return "\\t";
    }
    if (c < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x", c);
      return buf;
    }
    if (c >= 0x80) return "\xEF\xBF\xBD";  // a lone byte from 0x80 is never valid UTF-8
    return std::string(1, static_cast<char>(c));
  };
  for (int c = 0; c < 256; ++c)
    for (std::size_t at = 0; at < 17; ++at) {
      std::string text(17, 'a');
      for (std::size_t k = 0; k < text.size(); ++k) text[k] = static_cast<char>('a' + k);
      text[at] = static_cast<char>(c);
      std::string got;
      append_json_string(got, text);
      std::string want = "\"";  // (appended piece by piece: GCC 12 warns wrongly on "x" + s, -Wrestrict)
      want += text.substr(0, at);
      want += expected_byte(static_cast<unsigned char>(c));
      want += text.substr(at + 1);
      want += '"';
      ASSERT_EQ(got, want) << "byte " << c << " at " << at;
    }
}

// A long string (escaped in place rather than through the short strings' buffer) is the
// concatenation of its pieces' escapes.
TEST(JsonString, LongStringsEscapeLikeTheirPieces) {
  std::string piece;
  append_json_string(piece, kTricky);
  piece = piece.substr(1, piece.size() - 2);
  std::string text, want = "\"";
  for (int k = 0; k < 40; ++k) text += kTricky, want += piece;
  want += '"';
  ASSERT_GT(text.size(), 1000u);
  std::string got = "prefix";
  append_json_string(got, text);
  std::string expected = "prefix";  // (not "prefix" + want: GCC 12 warns wrongly, -Wrestrict)
  expected += want;
  EXPECT_EQ(got, expected);
}

// put_json_string() writes what append_json_string() appends.
TEST(JsonString, PutWritesWhatAppendAppends) {
  for (const std::string& text : {std::string(), kTricky, std::string(300, '\x01')}) {
    std::string want;
    append_json_string(want, text);
    std::string got(6 * text.size() + 2, '?');
    got.resize(static_cast<std::size_t>(put_json_string(got.data(), text) - got.data()));
    EXPECT_EQ(got, want);
  }
}

}  // namespace
}  // namespace geovor
