#include "request_target.hpp"

namespace geovor::service {
namespace {

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// `text` percent-decoded ('+' a space when `plus_is_space`); false on a malformed escape.
bool decode(std::string_view text, bool plus_is_space, std::string& out) {
  out.clear();
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '+' && plus_is_space) {
      out += ' ';
    } else if (c != '%') {
      out += c;
    } else {
      if (i + 2 >= text.size()) return false;
      const int high = hex_digit(text[i + 1]), low = hex_digit(text[i + 2]);
      if (high < 0 || low < 0) return false;
      out += static_cast<char>(high * 16 + low);
      i += 2;
    }
  }
  return true;
}

}  // namespace

std::optional<RequestTarget> parse_request_target(std::string_view target) {
  if (target.empty() || target[0] != '/' || target.find('#') != std::string_view::npos) return std::nullopt;
  const std::size_t mark = target.find('?');
  RequestTarget out;
  if (!decode(target.substr(0, mark), false, out.path)) return std::nullopt;
  if (mark == std::string_view::npos) return out;
  std::string_view query = target.substr(mark + 1);
  std::string name, value;
  while (!query.empty()) {
    const std::size_t amp = query.find('&');
    const std::string_view pair = query.substr(0, amp);
    query = amp == std::string_view::npos ? std::string_view{} : query.substr(amp + 1);
    if (pair.empty()) continue;  // "a=1&&b=2"
    const std::size_t eq = pair.find('=');
    if (!decode(pair.substr(0, eq), true, name)) return std::nullopt;
    if (!decode(eq == std::string_view::npos ? std::string_view{} : pair.substr(eq + 1), true, value)) return std::nullopt;
    out.query.emplace(name, value);
  }
  return out;
}

}  // namespace geovor::service
