/// \file copy_short_test.cpp
/// \brief copy_short() against memcpy: every length up to 40, nothing written outside the copy.
#include "geovor/core/copy_short.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

namespace geovor {
namespace {

TEST(CopyShort, CopiesEveryLengthAndNothingElse) {
  std::string source;
  for (int i = 0; i < 48; ++i) source += static_cast<char>('a' + i % 26);
  for (std::size_t n = 0; n <= 40; ++n)
    for (std::size_t offset = 0; offset < 8; ++offset) {  // any alignment of the source
      char out[64];
      std::memset(out, '#', sizeof out);
      const std::string_view text(source.data() + offset, n);
      char* end = copy_short(out + 8, text);
      ASSERT_EQ(end, out + 8 + n);
      ASSERT_EQ(std::string_view(out + 8, n), text) << n;
      for (std::size_t k = 0; k < sizeof out; ++k) {
        if (k < 8 || k >= 8 + n) {
          ASSERT_EQ(out[k], '#') << "length " << n << ", byte " << k;
        }
      }
    }
}

}  // namespace
}  // namespace geovor
