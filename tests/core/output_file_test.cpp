// OutputFile: a text output that appears whole or not at all (through output_target.hpp).
#include "geovor/core/output_file.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "support/file_text.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

using testing::contains;
using testing::error_of;
using testing::slurp;
using testing::spit;

class TempDir : public testing::TempDir {
 public:
  TempDir() : testing::TempDir("geovor_output_file") {}
};

TEST(OutputFile, AppearsOnlyWhenCommitted) {
  TempDir dir;
  const std::string path = dir / "out.csv";
  {
    OutputFile out(path, false);
    EXPECT_EQ(out.name(), path);
    out.write("a,b\n", 4);
    out.flush();
    EXPECT_EQ(dir.entries().size(), 1u);  // the temporary only
    EXPECT_NE(dir.entries()[0], "out.csv");
    out.commit();
  }
  EXPECT_EQ(slurp(path), "a,b\n");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.csv"});
}

// Past the write-back interval (8 MB: the write-back started, not waited for): the same bytes,
// and still nothing under the name before commit().
TEST(OutputFile, LargerThanTheWriteBackInterval) {
  TempDir dir;
  const std::string path = dir / "big.csv";
  std::string text;
  for (int i = 0; text.size() < (std::size_t{20} << 20); ++i) text += std::to_string(i) + ",row\n";
  {
    OutputFile out(path, false);
    for (std::size_t at = 0; at < text.size(); at += 100000) out.write(text.data() + at, std::min<std::size_t>(100000, text.size() - at));
    EXPECT_EQ(dir.entries().size(), 1u);
    EXPECT_NE(dir.entries()[0], "big.csv");
    out.commit();
  }
  EXPECT_EQ(slurp(path), text);
}

TEST(OutputFile, NotCommittedLeavesNothing) {
  TempDir dir;
  {
    OutputFile out(dir / "out.csv", false);
    std::fputs("partial", out.get());
  }
  EXPECT_TRUE(dir.entries().empty());
}

TEST(OutputFile, AnExistingFileNeedsOverwrite) {
  TempDir dir;
  const std::string path = dir / "out.csv";
  spit(path, "old");
  const Error e = error_of([&] { OutputFile out(path, false); });
  EXPECT_EQ(e.code(), ErrorCode::Io);
  EXPECT_EQ(std::string(e.what()), output_exists(path));
  OutputFile out(path, true);
  out.write("new", 3);
  EXPECT_EQ(slurp(path), "old");  // until the commit
  out.commit();
  EXPECT_EQ(slurp(path), "new");
}

TEST(OutputFile, AFileAppearingMeanwhileIsNotReplaced) {
  TempDir dir;
  const std::string path = dir / "out.csv";
  OutputFile out(path, false);
  out.write("mine", 4);
  spit(path, "theirs");
  const Error e = error_of([&] { out.commit(); });
  EXPECT_EQ(e.code(), ErrorCode::Io);
  EXPECT_TRUE(contains(e.what(), "exists")) << e.what();
  EXPECT_EQ(slurp(path), "theirs");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.csv"});
}

TEST(OutputFile, DevicesAndStdoutAreWrittenInPlace) {
  {
    OutputFile out("/dev/null", false);  // never renamed over
    out.write("x", 1);
    out.commit();
  }
  OutputFile out("-", false);
  EXPECT_EQ(out.get(), stdout);
  EXPECT_EQ(out.name(), "<stdout>");
}

TEST(OutputFile, AFolderThatDoesNotExistIsAnIoError) {
  TempDir dir;
  const Error e = error_of([&] { OutputFile out(dir / "no/such/out.csv", false); });
  EXPECT_EQ(e.code(), ErrorCode::Io);
  EXPECT_TRUE(contains(e.what(), "no/such/out.csv")) << e.what();
}

}  // namespace
}  // namespace geovor
