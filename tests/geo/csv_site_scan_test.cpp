/// \file csv_site_scan_test.cpp
/// \brief Tests of CsvSiteScan: the two-stage, multi-threaded reader against the streaming reader
/// it replaced (tests/support/reference_site_reader.cpp), member by member, on generated inputs
/// with every CSV oddity, chunk boundaries at every byte, read errors, and files.
#include "geovor/geo/csv_site_scan.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <sstream>
#include <streambuf>
#include <string>
#include <thread>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_reader.hpp"
#include "support/reference_site_reader.hpp"
#include "support/temp_dir.hpp"

namespace geovor {
namespace {

using testing::reference_read_sites_csv;
using testing::reference_read_sites_csv_file;

// A table, or the error that reading threw.
struct Outcome {
  std::optional<SiteTable> table;
  ErrorCode code = ErrorCode::Internal;
  std::string what;
};

template <typename Read>
Outcome outcome_of(Read read) {
  Outcome o;
  try {
    o.table = read();
  } catch (const Error& e) {
    o.code = e.code();
    o.what = e.what();
  }
  return o;
}

// Every member of both tables; `where` says which run differs.
void expect_same(const Outcome& got, const Outcome& want, const std::string& where) {
  ASSERT_EQ(got.table.has_value(), want.table.has_value()) << where << ": " << got.what << " | " << want.what;
  if (!want.table) {
    EXPECT_EQ(got.code, want.code) << where;
    EXPECT_EQ(got.what, want.what) << where;
    return;
  }
  const SiteTable& a = *got.table;
  const SiteTable& b = *want.table;
  EXPECT_EQ(a.source, b.source) << where;
  EXPECT_EQ(a.columns, b.columns) << where;
  EXPECT_EQ(a.lat_column, b.lat_column) << where;
  EXPECT_EQ(a.lon_column, b.lon_column) << where;
  EXPECT_EQ(a.id_column, b.id_column) << where;
  EXPECT_EQ(a.ecef_columns, b.ecef_columns) << where;
  EXPECT_EQ(a.rows_read, b.rows_read) << where;
  ASSERT_EQ(a.sites.size(), b.sites.size()) << where;
  for (std::size_t i = 0; i < a.sites.size(); ++i) {
    const InputSite& s = a.sites[i];
    const InputSite& t = b.sites[i];
    ASSERT_EQ(s.row, t.row) << where << " site " << i;
    ASSERT_EQ(s.line, t.line) << where << " site " << i;
    ASSERT_EQ(s.id, t.id) << where << " site " << i;
    // Bit for bit: the same parse and the same arithmetic.
    ASSERT_EQ(std::bit_cast<std::uint64_t>(s.lat_deg), std::bit_cast<std::uint64_t>(t.lat_deg)) << where << " site " << i;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(s.lon_deg), std::bit_cast<std::uint64_t>(t.lon_deg)) << where << " site " << i;
    ASSERT_EQ(std::bit_cast<std::uint64_t>(s.height_m), std::bit_cast<std::uint64_t>(t.height_m)) << where << " site " << i;
    ASSERT_EQ(s.unit, t.unit) << where << " site " << i;
    ASSERT_EQ(s.fields, t.fields) << where << " site " << i;
  }
  ASSERT_EQ(a.rejected.size(), b.rejected.size()) << where;
  for (std::size_t i = 0; i < a.rejected.size(); ++i) {
    ASSERT_EQ(a.rejected[i].row, b.rejected[i].row) << where << " rejected " << i;
    ASSERT_EQ(a.rejected[i].line, b.rejected[i].line) << where << " rejected " << i;
    ASSERT_EQ(a.rejected[i].reason, b.rejected[i].reason) << where << " rejected " << i;
  }
}

Outcome reference(const std::string& text, const SiteReaderOptions& options) {
  return outcome_of([&] {
    std::istringstream in(text);
    return reference_read_sites_csv(in, "t.csv", options);
  });
}

// Reads text with CsvSiteScan; positions() must be the sites' units.
Outcome scanned(const std::string& text, const SiteReaderOptions& options, const CsvScanTuning& tuning) {
  return outcome_of([&] {
    std::istringstream in(text);
    CsvSiteScan scan = CsvSiteScan::read(in, "t.csv", options, tuning);
    const std::vector<Vec3> positions(scan.positions().begin(), scan.positions().end());
    const std::uint64_t rows = scan.rows_read();
    SiteTable t = std::move(scan).finish();
    EXPECT_EQ(rows, t.rows_read);
    EXPECT_EQ(positions.size(), t.sites.size());
    for (std::size_t i = 0; i < positions.size() && i < t.sites.size(); ++i) EXPECT_EQ(positions[i], t.sites[i].unit);
    return t;
  });
}

// The threads and chunk sizes every comparison runs with: 1 thread, and small inputs forced to
// split into 2, 3 and 7 chunks.
void expect_matches_reference(const std::string& text, const SiteReaderOptions& base, const std::string& name) {
  const Outcome want = reference(text, base);
  for (const unsigned threads : {1u, 2u, 3u, 7u}) {
    SiteReaderOptions options = base;
    options.threads = threads;
    CsvScanTuning tuning;
    tuning.min_chunk_bytes = 1;
    expect_same(scanned(text, options, tuning), want, name + ", threads " + std::to_string(threads));
  }
  std::istringstream in(text);
  expect_same(outcome_of([&] { return read_sites_csv(in, "t.csv", base); }), want, name + ", read_sites_csv");
}

// Random CSV text with every feature the dialect has: good and bad rows, quotes, line ends.
class CsvGenerator {
 public:
  explicit CsvGenerator(std::uint32_t seed) : rng_(seed) {}

  std::string table(bool ecef) {
    std::string out;
    if (pick(8) == 0) out += "\xEF\xBB\xBF";
    const int layout = ecef ? 3 : pick(3);
    switch (layout) {
      case 0: out += "id,lat,lon,name"; columns_ = 4; break;
      case 1: out += "lat_deg,\"lon_deg\""; columns_ = 2; break;  // no id column: ids are rows
      case 2: out += "name,country,lat_deg,lon_deg"; columns_ = 4; break;
      default: out += "X,Y,Z,name"; columns_ = 4; break;
    }
    ecef_ = layout == 3;
    const int rows = pick(40);
    for (int r = 0; r < rows; ++r) {
      out += line_end();
      while (pick(6) == 0) out += line_end();  // empty lines
      out += row();
    }
    const int tail = pick(6);
    if (tail == 0) {
      out += line_end();
      out += "\"unterminated, with ";
      out += line_end();
      out += " a line end";
    } else if (tail < 4) {
      out += line_end();
      if (pick(3) == 0) out += line_end();
    }
    return out;
  }

 private:
  int pick(int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng_); }

  std::string line_end() {
    static const char* const kEnds[] = {"\n", "\r\n", "\r"};
    return kEnds[pick(3)];
  }

  std::string number(double lo, double hi) {
    switch (pick(14)) {
      case 0: return "abc";
      case 1: return "";
      case 2: return " ";
      case 3: return "1e999";
      case 4: return "nan";
      case 5: return "95";
      case 6: return "+12.5";
      case 7: return " -33.25 ";
      case 8: return "\"4" + std::string(pick(2) ? "," : ".") + "5\"";  // quoted, maybe a comma
      default: {
        std::ostringstream s;
        s.precision(pick(2) ? 17 : 6);
        s << std::uniform_real_distribution<double>(lo, hi)(rng_);
        return s.str();
      }
    }
  }

  std::string text() {
    switch (pick(10)) {
      case 0: return "\"with, comma\"";
      case 1: return "\"two" + line_end() + "lines\"";
      case 2: return "\"doubled \"\"quote\"\"\"";
      case 3: return "\"ab\"cd";  // text after the closing quote
      case 4: return "a\"b\"";    // quotes inside an unquoted field are kept
      case 5: return "";
      case 6: return "\"\"";
      case 7: return "\"cr\r\"\"\nlf\"";
      default: {
        std::string s = "n";
        for (int k = pick(20); k > 0; --k) s += static_cast<char>('a' + pick(26));
        return s;
      }
    }
  }

  std::string row() {
    std::vector<std::string> fields;
    if (ecef_) {
      for (int k = 0; k < 3; ++k) fields.push_back(pick(20) == 0 ? "0" : number(-7e6, 7e6));
      fields.push_back(text());
    } else if (columns_ == 2) {
      fields = {number(-90, 90), number(-540, 540)};
    } else if (pick(2)) {
      fields = {text(), number(-90, 90), number(-200, 200), text()};
    } else {
      fields = {text(), text(), number(-90, 90), number(-200, 200)};
    }
    const int odd = pick(12);
    if (odd == 0) fields.pop_back();
    if (odd == 1) fields.push_back(text());
    std::string out;
    for (std::size_t k = 0; k < fields.size(); ++k) out += (k ? "," : "") + fields[k];
    return out;
  }

  std::mt19937 rng_;
  int columns_ = 0;
  bool ecef_ = false;
};

TEST(CsvSiteScan, RandomTablesMatchTheStreamingReader) {
  for (std::uint32_t seed = 1; seed <= 400; ++seed) {
    CsvGenerator gen(seed);
    const bool ecef = seed % 4 == 0;
    const std::string text = gen.table(ecef);
    SiteReaderOptions options;
    if (ecef) options.ecef_fields = {"X", "Y", "Z"};
    expect_matches_reference(text, options, "seed " + std::to_string(seed));
    if (HasFatalFailure()) return;
  }
}

// Texts where a chunk boundary can fall on every awkward byte: inside quoted fields holding line
// ends, between a CR and its LF, on empty lines, in a last record without a line end.
TEST(CsvSiteScan, ChunkBoundaryAtEveryByte) {
  const std::vector<std::string> texts = {
      "name,lat,lon\r\na,1,2\r\n\r\n\"b\r\n,c\",3,4\r\"x\"\"y\",5,6\n\nz,7,8",
      "\xEF\xBB\xBFlat,lon,id\n1,2,\"q\n\"\"\n\"\r\n3,4,\"ab\"c\r\r5,x,e\n6,7,\"open\n,8",
      "id,lat,lon\n\"a\"\"\",1,2\n\"\"\"\",3,4\nb\"\",5,6\r\n\"c\r\n\"\r\nd,9\n",
      "lat,lon\r1,2\r3,4\r\r\n5,6\n\r7,8\r",
  };
  for (std::size_t t = 0; t < texts.size(); ++t) {
    const std::string& text = texts[t];
    const Outcome want = reference(text, {});
    ASSERT_TRUE(want.table.has_value()) << want.what;
    for (std::size_t cut = 0; cut <= text.size(); ++cut) {
      CsvScanTuning one;
      one.cuts = {cut};
      expect_same(scanned(text, {}, one), want, "text " + std::to_string(t) + ", cut " + std::to_string(cut));
      CsvScanTuning three;
      three.cuts = {cut, cut + 1, cut + 3};
      expect_same(scanned(text, {}, three), want, "text " + std::to_string(t) + ", cuts " + std::to_string(cut) + "+");
      if (HasFatalFailure()) return;
    }
  }
}

// The header rules that came after the streaming reader (no column found, names repeated, ranks)
// are site_reader_test's and coordinate_columns_test's.
TEST(CsvSiteScan, HeaderAndOptionErrorsMatch) {
  SiteReaderOptions two_ecef;
  two_ecef.ecef_fields = {"X", "Y"};
  SiteReaderOptions both;
  both.ecef_fields = {"X", "Y", "Z"};
  both.lat_field = "lat";
  SiteReaderOptions missing;
  missing.id_field = "nope";
  const std::vector<std::pair<std::string, SiteReaderOptions>> cases = {
      {"", {}},
      {"\xEF\xBB\xBF", {}},
      {"\n\r\n\r", {}},
      {"\x1f\x8b\x08\x00,lat,lon\n1,2", {}},
      {"\"lat,lon\n1,2\n", {}},
      {"lat,x\n1,2\n", {}},
      {"lat,b\n1,2\n", SiteReaderOptions{"lat", "lat", "", {}, 1}},
      {"lat,lon\n1,2\n", two_ecef},
      {"lat,lon\n1,2\n", both},
      {"lat,lon\n1,2\n", missing},
      {"lat,lon", {}},
      {"lat,lon\r", {}},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    expect_matches_reference(cases[i].first, cases[i].second, "case " + std::to_string(i));
  }
}

// A stream whose device gives its bytes a few at a time and then fails, like a disk error.
class FailingBuf : public std::streambuf {
 public:
  explicit FailingBuf(std::string data) : data_(std::move(data)) {}

 protected:
  int_type underflow() override {
    if (pos_ >= data_.size()) throw std::runtime_error("device error");
    const std::size_t n = std::min<std::size_t>(4096, data_.size() - pos_);
    setg(data_.data() + pos_, data_.data() + pos_, data_.data() + pos_ + n);
    pos_ += n;
    return traits_type::to_int_type(data_[pos_ - n]);
  }

 private:
  std::string data_;
  std::size_t pos_ = 0;
};

// CsvReader read in blocks of 64 KiB and met the error after the last whole block: the line in
// the message, or an error of the header instead, must be the same.
TEST(CsvSiteScan, ReadErrorsMatch) {
  const std::size_t block = std::size_t{1} << 16;
  auto padded = [&](const std::string& head, const std::string& last) {
    std::string s = head;
    while (s.size() + 20 < block - last.size()) s += "1,2\n";
    s += std::string(block - last.size() - s.size(), 'x');
    return s + last + "tail,3\n";
  };
  const std::vector<std::string> texts = {
      "lat,lon\n1,2\n",
      padded("lat,lon\n", "\r"),
      padded("lat,lon\n", "\n"),
      padded("lat,lon\n\"", "\r"),      // the CR inside a quoted field
      padded("lat,lon\n\"", "\r\n\""),  // closed again before the end
      padded("lat,", "\r"),             // the header is the whole first block
      padded("a,b\n", "\r"),            // no latitude column: that error comes first
      std::string(block, '\n') + "lat,lon\n",
      padded("\"lat\",lon\n\"a\"\"", ","),
  };
  for (std::size_t i = 0; i < texts.size(); ++i) {
    const Outcome want = outcome_of([&] {
      FailingBuf buf(texts[i]);
      std::istream in(&buf);
      return reference_read_sites_csv(in, "t.csv");
    });
    ASSERT_FALSE(want.table.has_value()) << i;
    for (const unsigned threads : {1u, 2u}) {
      SiteReaderOptions options;
      options.threads = threads;
      const Outcome got = outcome_of([&] {
        FailingBuf buf(texts[i]);
        std::istream in(&buf);
        return std::move(CsvSiteScan::read(in, "t.csv", options)).finish();
      });
      // The columns' error comes first; its list of names looked for is newer than the oracle.
      const std::size_t looked = want.what.find("; looked for");
      if (looked != std::string::npos) {
        EXPECT_EQ(got.code, want.code) << i;
        EXPECT_EQ(got.what.substr(0, looked + 1), want.what.substr(0, looked + 1)) << i;
        continue;
      }
      expect_same(got, want, "text " + std::to_string(i));
    }
  }
}

// Enough rows that the default chunk size splits them: ~2 MB with quoted fields here and there.
TEST(CsvSiteScan, LargeTableWithDefaultChunks) {
  std::mt19937 rng(7);
  std::string text = "name,country,lat_deg,lon_deg\r\n";
  std::uniform_real_distribution<double> lat(-90, 90), lon(-180, 180);
  for (int i = 0; text.size() < (std::size_t{2} << 20); ++i) {
    std::ostringstream row;
    row.precision(7);
    if (i % 997 == 0) {
      row << "\"Town " << i << ", quoted\r\nover two lines\"";
    } else {
      row << "Town " << i;
    }
    row << ",C" << i % 50 << ',' << (i % 4999 == 0 ? "bad" : "") << lat(rng) << ',' << lon(rng) << "\r\n";
    text += row.str();
  }
  const Outcome want = reference(text, {});
  ASSERT_TRUE(want.table.has_value());
  for (const unsigned threads : {0u, 1u, 2u, 3u, 7u}) {
    SiteReaderOptions options;
    options.threads = threads;
    expect_same(scanned(text, options, {}), want, "threads " + std::to_string(threads));
  }
}

TEST(CsvSiteScan, FilesMatch) {
  testing::TempDir dir("geovor_csv_site_scan_test");
  const std::string path = dir / "sites.csv";
  {
    CsvGenerator gen(99);
    std::ofstream out(path, std::ios::binary);
    out << gen.table(false);
  }
  const std::vector<std::string> paths = {
      path, std::string(GEOVOR_SOURCE_DIR) + "/datasets/weather_stations.csv", dir / "missing.csv",
      dir / ""};
  for (const std::string& p : paths) {
    const Outcome want = outcome_of([&] { return reference_read_sites_csv_file(p); });
    for (const unsigned threads : {1u, 2u}) {
      SiteReaderOptions options;
      options.threads = threads;
      CsvScanTuning tuning;
      tuning.min_chunk_bytes = 1000;
      expect_same(outcome_of([&] { return std::move(CsvSiteScan::open(p, options, tuning)).finish(); }), want, p);
    }
    expect_same(outcome_of([&] { return read_sites_csv_file(p); }), want, p + ", read_sites_csv_file");
  }
}

// finish() runs while another thread reads positions(), as geovor cells does with the
// triangulation; the positions stay valid after finish().
TEST(CsvSiteScan, FinishWhilePositionsAreRead) {
  std::string text = "lat,lon\n";
  for (int i = 0; i < 5000; ++i) text += std::to_string(i % 180 - 90) + "," + std::to_string(i % 360 - 180) + "\n";
  std::istringstream in(text);
  SiteReaderOptions options;
  options.threads = 2;
  CsvScanTuning tuning;
  tuning.min_chunk_bytes = 1;
  CsvSiteScan scan = CsvSiteScan::read(in, "t.csv", options, tuning);
  const std::span<const Vec3> positions = scan.positions();
  double sum = 0;
  std::thread reader([&] {
    for (const Vec3& p : positions) sum += p.x + p.y + p.z;
  });
  const SiteTable table = std::move(scan).finish();
  reader.join();
  ASSERT_EQ(positions.size(), table.sites.size());
  double want = 0;
  for (const InputSite& s : table.sites) want += s.unit.x + s.unit.y + s.unit.z;
  EXPECT_EQ(sum, want);
  EXPECT_EQ(positions.data(), scan.positions().data());
}

}  // namespace
}  // namespace geovor

namespace geovor {
namespace {

// A FIFO is read without a sniff: its head is checked once decoded (UTF-16 holds NUL bytes, and
// is text), and refused when it is not text.
TEST(CsvSiteScan, FifoHeadCheckedAfterDecoding) {
  const std::string path = ::testing::TempDir() + "csv_site_scan_fifo";
  auto through_fifo = [&](const std::string& bytes, const SiteReaderOptions& options) {
    std::remove(path.c_str());
    EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0);
    std::thread writer([&] { std::ofstream(path, std::ios::binary) << bytes; });
    struct Join {
      std::thread& t;
      ~Join() { t.join(); }
    } join{writer};
    return CsvSiteScan::open(path, options).finish();
  };
  SiteReaderOptions utf16;
  utf16.encoding = "UTF-16";
  const char text[] = "\xFF\xFEl\0a\0t\0,\0l\0o\0n\0\n\0\x31\0,\0\x32\0\n\0";
  const SiteTable t = through_fifo(std::string(text, sizeof text - 1), utf16);
  ASSERT_EQ(t.sites.size(), 1u);
  EXPECT_DOUBLE_EQ(t.sites[0].lat_deg, 1);
  try {
    through_fifo("  <?xml version=\"1.0\"?>\n", {});
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadData);
    EXPECT_NE(std::string(e.what()).find(path + ": not delimited text: it starts with '<' (XML?)"), std::string::npos)
        << e.what();
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace geovor
