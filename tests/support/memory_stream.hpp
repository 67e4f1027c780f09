/// \file memory_stream.hpp
/// \brief A stdio stream in memory (open_memstream), for the tests of functions that write on a
/// std::FILE* (logs, reports).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace geovor::testing {

class MemoryStream {
 public:
  MemoryStream() : file_(open_memstream(&text_, &size_)) {}
  ~MemoryStream() {
    std::fclose(file_);
    std::free(text_);
  }
  MemoryStream(const MemoryStream&) = delete;
  MemoryStream& operator=(const MemoryStream&) = delete;

  std::FILE* get() const { return file_; }
  /// Everything written so far.
  std::string text() {
    std::fflush(file_);
    return std::string(text_, size_);
  }

 private:
  char* text_ = nullptr;
  std::size_t size_ = 0;
  std::FILE* file_;
};

}  // namespace geovor::testing
