/// \file ascii_test.cpp
/// \brief Tests of ASCII case folding and of printable(), which keeps messages on one line.
#include "geovor/core/ascii.hpp"

#include <gtest/gtest.h>

#include <string>

#include "geovor/core/error.hpp"

namespace geovor {
namespace {

using namespace std::string_literals;

TEST(Ascii, FoldsOnlyAsciiLetters) {
  EXPECT_EQ(ascii_lower("LAT_Deg \xC3\x89"), "lat_deg \xC3\x89");
  EXPECT_TRUE(ascii_iequals("Latitude", "LATITUDE"));
  EXPECT_FALSE(ascii_iequals("lat", "lat "));
}

// Hand-counted edits: the classic kitten/sitting (3), a missing letter, a swap (2 substitutions).
TEST(Ascii, EditDistanceCountsEdits) {
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
  EXPECT_EQ(edit_distance("cels", "cells"), 1u);
  EXPECT_EQ(edit_distance("lat", "alt"), 2u);
  EXPECT_EQ(edit_distance("", "pop"), 3u);
  EXPECT_EQ(edit_distance("pop", ""), 3u);
  EXPECT_EQ(edit_distance("same", "same"), 0u);
  EXPECT_EQ(edit_distance("Pop", "pop"), 1u);  // bytes: fold the case first to ignore it
}

TEST(Ascii, PrintableEscapesControlCharacters) {
  const std::string raw = "a\0b\tc\nd\re\x01" "f\x7Fg\xC3\xA9"s;
  EXPECT_EQ(printable(raw), "a\\0b\\tc\\nd\\re\\x01f\\x7Fg\xC3\xA9");
  EXPECT_EQ(printable("plain, \"quoted\""), "plain, \"quoted\"");
}

TEST(Ascii, ErrorMessagesAreOneLineAndWhole) {
  const Error e(ErrorCode::BadData, "f.csv: 'x\0y\nz' is bad"s);
  EXPECT_STREQ(e.what(), "f.csv: 'x\\0y\\nz' is bad");
}

}  // namespace
}  // namespace geovor
