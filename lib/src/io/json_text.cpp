#include "geovor/io/json_text.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "geovor/io/number_format.hpp"

namespace geovor {

namespace {

// The bytes of w (8 bytes of text, little-endian) that need escaping or UTF-8 checking, as their
// high bits: below 0x20, from 0x80, '"' and '\\' (the "has a byte less than n" and "has a zero
// byte" bit tricks; only the lowest flag is exact, which is the one used).
std::uint64_t special_bytes(std::uint64_t w) {
  constexpr std::uint64_t kOnes = 0x0101010101010101, kHigh = 0x8080808080808080;
  const std::uint64_t quote = w ^ (kOnes * '"'), backslash = w ^ (kOnes * '\\');
  const std::uint64_t below_space = (w - kOnes * 0x20) & ~w;
  const std::uint64_t is_quote = (quote - kOnes) & ~quote, is_backslash = (backslash - kOnes) & ~backslash;
  return (below_space | is_quote | is_backslash | w) & kHigh;
}

// Writes s[i] (and the rest of its UTF-8 sequence) escaped to p; advances i and returns the end.
char* escape_one(char* p, const unsigned char* s, std::size_t n, std::size_t& i) {
  static constexpr char kHex[] = "0123456789abcdef";
  const unsigned char c = s[i];
  if (c >= 0x20 && c != '"' && c != '\\' && c < 0x80) {
    *p++ = static_cast<char>(c);
    ++i;
    return p;
  }
  if (c >= 0x80) {
    // Length and validity of a UTF-8 sequence (RFC 3629: no overlongs, no surrogates,
    // nothing above U+10FFFF).
    std::size_t len = 0;
    if (c >= 0xC2 && c <= 0xDF) {
      len = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3;
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4;
    }
    bool ok = len != 0 && i + len <= n;
    for (std::size_t k = 1; ok && k < len; ++k) ok = (s[i + k] & 0xC0) == 0x80;
    if (ok && len == 3) {
      const unsigned char c1 = s[i + 1];
      ok = !(c == 0xE0 && c1 < 0xA0) && !(c == 0xED && c1 >= 0xA0);
    }
    if (ok && len == 4) {
      const unsigned char c1 = s[i + 1];
      ok = !(c == 0xF0 && c1 < 0x90) && !(c == 0xF4 && c1 >= 0x90);
    }
    if (ok) {
      std::memcpy(p, s + i, len);
      i += len;
      return p + len;
    }
    ++i;
    *p++ = '\xEF', *p++ = '\xBF', *p++ = '\xBD';  // U+FFFD
    return p;
  }
  ++i;
  *p++ = '\\';
  switch (c) {
    case '"':
      *p++ = '"';
      break;
    case '\\':
      *p++ = '\\';
      break;
    case '\b':
      *p++ = 'b';
      break;
    case '\f':
      *p++ = 'f';
      break;
    case '\n':
      *p++ = 'n';
      break;
    case '\r':
      *p++ = 'r';
      break;
    case '\t':
      *p++ = 't';
      break;
    default:
      *p++ = 'u', *p++ = '0', *p++ = '0', *p++ = kHex[c >> 4], *p++ = kHex[c & 15];
  }
  return p;
}

// Writes text escaped as append_json_string() does (without the quotes) to p, which has room for
// 6 characters per byte (the longest escape, \u00XX); returns the end. Plain runs are
// copied 8 bytes at a time, up to the first byte that needs attention.
char* escape_json(char* p, const unsigned char* s, std::size_t n) {
  static_assert(std::endian::native == std::endian::little);
  std::size_t i = 0;
  while (i + 8 <= n) {
    std::uint64_t w;
    std::memcpy(&w, s + i, 8);
    std::memcpy(p, &w, 8);  // the plain prefix stays, the rest is overwritten
    const std::uint64_t special = special_bytes(w);
    if (special == 0) {
      p += 8, i += 8;
      continue;
    }
    const std::size_t plain = static_cast<std::size_t>(std::countr_zero(special)) / 8;
    p += plain, i += plain;
    p = escape_one(p, s, n, i);
  }
  while (i < n) p = escape_one(p, s, n, i);
  return p;
}

}  // namespace

char* put_json_string(char* p, std::string_view text) {
  *p++ = '"';
  p = escape_json(p, reinterpret_cast<const unsigned char*>(text.data()), text.size());
  *p++ = '"';
  return p;
}

void append_json_string(std::string& out, std::string_view text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  // Short strings (nearly all) through a stack buffer: one append, no checks per character.
  constexpr std::size_t kShort = 256;
  if (n <= kShort) {
    char buf[6 * kShort + 2];
    buf[0] = '"';
    char* end = escape_json(buf + 1, s, n);
    *end++ = '"';
    out.append(buf, static_cast<std::size_t>(end - buf));
    return;
  }
  const std::size_t old = out.size();
  out.resize(old + 6 * n + 2);
  char* p = out.data() + old;
  *p++ = '"';
  p = escape_json(p, s, n);
  *p++ = '"';
  out.resize(static_cast<std::size_t>(p - out.data()));
}

void append_json_value(std::string& out, const FieldValue& value) {
  if (const auto* i = std::get_if<std::int64_t>(&value)) {
    char buf[24];
    out.append(buf, static_cast<std::size_t>(std::to_chars(buf, buf + sizeof buf, *i).ptr - buf));
  } else if (const auto* d = std::get_if<double>(&value)) {
    if (!std::isfinite(*d)) {
      out += "null";  // JSON has no NaN or infinity (GDAL writes null too by default)
      return;
    }
    char buf[kMaxRealChars];
    out.append(buf, static_cast<std::size_t>(format_real(buf, *d) - buf));
  } else if (const auto* s = std::get_if<std::string>(&value)) {
    append_json_string(out, *s);
  } else {
    out += "null";
  }
}

}  // namespace geovor
