/// \file error.hpp
/// \brief The one exception type of geovor, thrown only for I/O failures and invalid arguments.
/// Data problems (bad rows, merged sites) are values in a report; bugs are assertions.
#pragma once

#include <stdexcept>
#include <string>

#include "geovor/core/ascii.hpp"

namespace geovor {

/// What kind of failure an Error reports; the command maps it to an exit code.
enum class ErrorCode : int {
  InvalidArgument = 100,  ///< an option or argument the caller gave is invalid (exit 2)
  BadData = 200,          ///< the input cannot be used at all, e.g. no latitude column (exit 3)
  Io = 400,               ///< a file cannot be read or written (exit 4)
  Internal = 900,         ///< an invariant failed: a bug in geovor
};

class Error : public std::runtime_error {
 public:
  /// Control characters in `what` (a NUL or a line break from a file name or a value) are
  /// escaped (printable()): what() is one line, never cut.
  Error(ErrorCode code, const std::string& what) : std::runtime_error(printable(what)), code_(code) {}
  ErrorCode code() const noexcept { return code_; }

 private:
  ErrorCode code_;
};

}  // namespace geovor
