// Progress: GDAL's terminal progress, and only for a terminal.
#include "geovor/core/progress.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "support/memory_stream.hpp"

namespace geovor {
namespace {

using testing::MemoryStream;

constexpr const char* kAll = "0...10...20...30...40...50...60...70...80...90...100 - done.\n";

TEST(Progress, PrintsGdalsTicks) {
  MemoryStream out;
  Progress p(200, out.get());
  p.advance(0);
  EXPECT_EQ(out.text(), "0");
  p.advance(50);  // 25 %: 10 ticks of 2.5 %
  EXPECT_EQ(out.text(), "0...10...20..");
  p.advance(50);
  p.advance(20);  // never backwards
  EXPECT_EQ(out.text(), "0...10...20..");
  p.advance(199);
  p.finish();
  EXPECT_EQ(out.text(), kAll);
}

TEST(Progress, FinishPrintsWhatIsLeft) {
  MemoryStream out;
  Progress p(3, out.get());
  p.finish();
  EXPECT_EQ(out.text(), kAll);
}

TEST(Progress, NothingWithoutAStreamOrSteps) {
  Progress off(10, nullptr);
  off.advance(5);
  off.finish();
  MemoryStream out;
  Progress empty(0, out.get());
  empty.advance(0);
  EXPECT_EQ(out.text(), "");
}

TEST(Progress, OnlyOnATerminal) {
  std::FILE* file = std::tmpfile();
  EXPECT_EQ(Progress::on_terminal(file, false), nullptr);  // a file is no terminal
  EXPECT_EQ(Progress::on_terminal(nullptr, false), nullptr);
  std::fclose(file);
  std::FILE* tty = std::fopen("/dev/tty", "w");
  if (tty == nullptr) GTEST_SKIP() << "no terminal";
  EXPECT_EQ(Progress::on_terminal(tty, false), tty);
  EXPECT_EQ(Progress::on_terminal(tty, true), nullptr);  // quiet
  std::fclose(tty);
}

}  // namespace
}  // namespace geovor
