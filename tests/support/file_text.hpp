/// \file file_text.hpp
/// \brief Small helpers of the tests that write and read files: a file's bytes, writing them, the
/// Error a call throws, substring search.
#pragma once

#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "geovor/core/error.hpp"

namespace geovor::testing {

/// The whole file as bytes ("" if it cannot be read).
inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Writes `text` as the whole file.
inline void spit(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

/// The Error that f throws, or an Internal one saying that nothing was thrown.
inline Error error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  return Error(ErrorCode::Internal, "no error thrown");
}

inline bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

}  // namespace geovor::testing
