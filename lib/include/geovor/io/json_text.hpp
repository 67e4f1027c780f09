/// \file json_text.hpp
/// \brief JSON text as the GeoJSON writers write it: strings escaped (always valid UTF-8) and
/// property values.
#pragma once

#include <string>
#include <string_view>

#include "geovor/io/feature_writer.hpp"

namespace geovor {

/// Appends `text` as a JSON string with its quotes: '"' and '\\' escaped, control characters as
/// \b \f \n \r \t or \u00XX, valid UTF-8 passed through, and each byte that is not part of valid
/// UTF-8 replaced by U+FFFD (JSON text must be UTF-8, RFC 8259 §8.1).
void append_json_string(std::string& out, std::string_view text);

/// Writes `text` as append_json_string() does, quotes included, to p, which has room for
/// 6 * text.size() + 2 characters (the longest escape is \u00XX); returns the end.
char* put_json_string(char* p, std::string_view text);

/// Appends `value` as the GeoJSON writers write a property value: null for monostate and for a
/// non-finite double (JSON has neither NaN nor infinity), an integer in decimal, a double as
/// format_real(), a string as append_json_string().
void append_json_value(std::string& out, const FieldValue& value);

}  // namespace geovor
