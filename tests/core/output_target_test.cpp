// The output primitive on its own: the commit that never clobbers, short temporaries in the
// target's folder, and the same-file test behind every command's outputs. (Writers through it:
// tests/io/feature_writer_test.cpp, SafeOutput.)
#include "geovor/core/output_target.hpp"

#include <gtest/gtest.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "support/file_text.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

namespace fs = std::filesystem;
using testing::slurp;
using testing::spit;
using testing::error_of;
using testing::contains;

class TempDir : public testing::TempDir {
 public:
  TempDir() : testing::TempDir("geovor_output_target") {}
};

// The commit: without overwrite an existing name is left alone (EEXIST), with overwrite replaced.
TEST(OutputTarget, OneMessageForAnExistingOutput) {
  EXPECT_EQ(output_exists("a/b.csv"), "a/b.csv: exists; use --overwrite to replace it");
  EXPECT_EQ(output_exists("x.gpkg", ", or --update"), "x.gpkg: exists; use --overwrite to replace it, or --update");
}

TEST(OutputTarget, AnExistingOutputIsRefusedBeforeALongJob) {
  TempDir dir;
  spit(dir / "old", "old");
  const Error e = error_of([&] { refuse_existing_output(dir / "old", false); });
  EXPECT_EQ(e.code(), ErrorCode::Io);
  EXPECT_EQ(std::string(e.what()), output_exists(dir / "old"));
  EXPECT_EQ(error_of([&] { refuse_existing_output("/dev/null", false); }).code(), ErrorCode::Io);  // a device too
  refuse_existing_output(dir / "old", true);
  refuse_existing_output(dir / "new", false);
  refuse_existing_output("-", false);
  refuse_existing_output("", false);
  EXPECT_EQ(slurp(dir / "old"), "old");
}

TEST(OutputTarget, RenameIntoPlace) {
  TempDir dir;
  spit(dir / "new", "new");
  spit(dir / "old", "old");
  EXPECT_EQ(rename_into_place(dir / "new", dir / "old", false), EEXIST);
  EXPECT_EQ(slurp(dir / "old"), "old");
  EXPECT_EQ(rename_into_place(dir / "new", dir / "fresh", false), 0);
  EXPECT_EQ(slurp(dir / "fresh"), "new");
  EXPECT_EQ(rename_into_place(dir / "fresh", dir / "old", true), 0);
  EXPECT_EQ(slurp(dir / "old"), "new");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"old"});
  // A temporary: short name in the target's folder, gone once committed or discarded.
  {
    TemporaryOutput t(dir / std::string(250, 'x'), TemporaryOutput::Kind::File);
    EXPECT_LE(fs::path(t.path()).filename().string().size(), 30u) << t.path();
    EXPECT_EQ(fs::path(t.path()).parent_path(), fs::path(dir / "old").parent_path());
    EXPECT_EQ(dir.entries().size(), 2u);
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"old"});
  TemporaryOutput t(dir / "old", TemporaryOutput::Kind::File);
  const Error e = error_of([&] { t.commit(dir / "old", false); });
  EXPECT_TRUE(contains(e.what(), "old: exists; use --overwrite to replace it")) << e.what();
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"old"});
}

// The same-file test behind every command's outputs.
TEST(OutputTarget, SameOutputFile) {
  TempDir dir;
  const std::string a = dir / "a.geojson";
  EXPECT_TRUE(same_output_file("-", "-"));
  EXPECT_TRUE(same_output_file(a, a));  // neither exists
  fs::create_directory(dir / "sub");
  EXPECT_TRUE(same_output_file(a, dir / "sub/../a.geojson"));
  EXPECT_FALSE(same_output_file(a, dir / "b.geojson"));
  EXPECT_FALSE(same_output_file(a, "-"));
  spit(a, "x");
  EXPECT_TRUE(same_output_file(a, dir / "./a.geojson"));
  fs::create_hard_link(a, dir / "hard");
  fs::create_symlink(a, dir / "soft");
  EXPECT_TRUE(same_output_file(a, dir / "hard"));
  EXPECT_TRUE(same_output_file(dir / "soft", a));
  EXPECT_FALSE(same_output_file("/dev/null", "/dev/null"));  // a device, written in place
  const Error e = error_of([&] { check_distinct_outputs({{"--output", a}, {"--report", ""}, {"--edges", dir / "hard"}}); });
  EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
  EXPECT_TRUE(contains(e.what(), "--output") && contains(e.what(), "--edges")) << e.what();
}

}  // namespace
}  // namespace geovor
