/// \file direct_output_test.cpp
/// \brief DirectOutput writes exactly the bytes given, in pieces of every size across its 4 MiB
/// stage, with direct I/O (where the file system allows it) and without; the file's bytes read
/// back are the oracle. A full device fails with ENOSPC.
#include "io/direct_output.hpp"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdio>
#include <random>
#include <string>

#include "support/file_text.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

using testing::slurp;

// 11 MB of random bytes written in pieces of random sizes (1 byte to 3 MB), then finish().
void write_and_check(const std::string& path, bool direct) {
  std::mt19937_64 rng(direct ? 3 : 4);
  std::string text(11'000'000, '\0');
  for (char& c : text) c = static_cast<char>(rng());
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  DirectOutput out;
  out.attach(f, true);
  if (direct) out.enable_direct();
  std::size_t at = 0;
  std::uniform_int_distribution<int> digits(0, 6);
  while (at < text.size()) {
    std::size_t n = std::uniform_int_distribution<std::size_t>(1, 3)(rng);
    for (int d = digits(rng); d > 0; --d) n *= 10;
    n = std::min(n, text.size() - at);
    out.write(text.data() + at, n);
    at += n;
  }
  out.finish();
  ASSERT_EQ(std::fclose(f), 0);
  EXPECT_TRUE(slurp(path) == text) << path << (direct ? " direct" : "");
}

TEST(DirectOutput, WritesExactlyTheBytes) {
  testing::TempDir dir("geovor_direct_output");
  write_and_check(dir / "plain", false);
  write_and_check(dir / "direct", true);
  // A disk-backed directory too (the temporary directory may be a tmpfs, which refuses O_DIRECT).
  testing::TempDir here(GEOVOR_BINARY_DIR "/direct_output_test");
  write_and_check(here / "direct", true);
}

TEST(DirectOutput, FullDeviceFails) {
  std::FILE* f = std::fopen("/dev/full", "wb");
  if (f == nullptr) GTEST_SKIP() << "no /dev/full";
  DirectOutput out;
  out.attach(f, false);
  const std::string block(1 << 20, 'x');
  int err = 0;
  try {
    for (int i = 0; i < 64; ++i) out.write(block.data(), block.size());
  } catch (const DirectOutput::Failure& failure) {
    err = failure.err;
  }
  std::fclose(f);
  EXPECT_EQ(err, ENOSPC);
}

}  // namespace
}  // namespace geovor
