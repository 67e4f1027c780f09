// Index files: a save/load round trip gives the same hierarchy, attributes and answers; every
// truncation, every byte flip and every consistent-but-wrong edit is Error(BadData), never a
// crash, and never an allocation sized by a corrupted field.
#include "geovor/locate/index_file.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <random>
#include <string>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/geo/site_reader.hpp"
#include "geovor/locate/locator.hpp"
#include "support/generators.hpp"

// The largest single allocation since the last reset: loading a corrupted file must never ask
// for more than the file holds.
namespace {
std::atomic<std::size_t> g_max_alloc{0};
}  // namespace
// Not inlined: GCC would otherwise pair the library's new with this delete's free() and warn.
__attribute__((noinline)) void* operator new(std::size_t n) {
  std::size_t seen = g_max_alloc.load(std::memory_order_relaxed);
  while (n > seen && !g_max_alloc.compare_exchange_weak(seen, n, std::memory_order_relaxed)) {
  }
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void operator delete(void* p) noexcept { std::free(p); }
__attribute__((noinline)) void operator delete(void* p, std::size_t) noexcept { std::free(p); }
// The nothrow forms too (std::stable_sort's buffer): else the sanitizer's new meets this free().
__attribute__((noinline)) void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return ::operator new(n);
  } catch (...) {
    return nullptr;
  }
}
__attribute__((noinline)) void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace geovor {
namespace {

namespace fs = std::filesystem;
using Bytes = std::string;

// A directory of this process's files, removed at exit.
const fs::path& temp_dir() {
  struct Dir {
    fs::path path = fs::path(::testing::TempDir()) / ("geovor_index_file_test_" + std::to_string(getpid()));
    Dir() { fs::create_directories(path); }
    ~Dir() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

std::string temp_path(const std::string& name) { return (temp_dir() / name).string(); }

Bytes read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_bytes(const std::string& path, const Bytes& b) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(b.data(), static_cast<std::streamsize>(b.size()));
}

std::uint64_t get64(const Bytes& b, std::size_t at) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + i]);
  return v;
}
std::uint32_t get32(const Bytes& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(b[at + i]);
  return v;
}
void set64(Bytes& b, std::size_t at, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) b[at + i] = static_cast<char>(v >> (8 * i));
}
void set32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<char>(v >> (8 * i));
}

struct SectionRef {
  std::size_t entry = 0;  // byte offset of the table entry
  std::size_t offset = 0, size = 0;
};

// The section of this kind and level (kinds as in index_file.hpp).
SectionRef find_section(const Bytes& b, std::uint32_t kind, std::uint32_t level = 0) {
  const std::uint32_t count = get32(b, 12);
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::size_t e = 32 + 32 * i;
    if (get32(b, e) == kind && get32(b, e + 4) == level) return {e, get64(b, e + 8), get64(b, e + 16)};
  }
  ADD_FAILURE() << "no section " << kind << " level " << level;
  return {};
}

// Recomputes every section checksum and the header checksum, so that an edit reaches the
// checks behind them.
void rehash(Bytes& b) {
  const std::size_t count = std::min<std::size_t>(get32(b, 12), (b.size() - 32) / 32);
  for (std::size_t i = 0; i < count; ++i) {
    const std::size_t e = 32 + 32 * i;
    const std::uint64_t off = get64(b, e + 8), size = get64(b, e + 16);
    if (off <= b.size() && size <= b.size() - off) set64(b, e + 24, xxh64(b.data() + off, size));
  }
  Bytes head = b.substr(0, 32 + 32 * count);
  set64(head, 24, 0);
  set64(b, 24, xxh64(head.data(), head.size()));
}

// A site table of n random sites with ids, a name with a comma, and a few exact duplicates.
SiteTable make_table(std::size_t n, std::uint64_t seed) {
  SiteTable t;
  t.source = "generated.csv";
  t.columns = {"id", "lat", "lon", "name"};
  t.id_column = 0;
  t.lat_column = 1;
  t.lon_column = 2;
  const std::vector<Vec3> pts = testing::uniform_on_sphere(n, seed);
  for (std::size_t i = 0; i < n + n / 50; ++i) {
    // After the n sites, every 50th one again (exact duplicates: merges).
    const Vec3& p = i < n ? pts[i] : pts[(i - n) * 50];
    const LatLon ll = SiteEncoder::to_lat_lon(p);
    InputSite s;
    s.row = i + 1;
    s.line = i + 2;
    s.id = "s";
    s.id += std::to_string(i);
    s.lat_deg = ll.lat_deg;
    s.lon_deg = ll.lon_deg;
    s.height_m = static_cast<double>(i % 7);
    s.unit = SiteEncoder::from_lat_lon(s.lat_deg, s.lon_deg);
    std::string name = "site ";
    name += std::to_string(i);
    name += ", \"x\"";
    s.fields = {s.id, std::to_string(s.lat_deg), std::to_string(s.lon_deg), name};
    t.sites.push_back(std::move(s));
  }
  t.rows_read = t.sites.size() + 3;
  t.rejected.resize(3);
  return t;
}

std::vector<Vec3> queries(std::size_t n, std::uint64_t seed) {
  std::vector<Vec3> q = testing::uniform_on_sphere(n / 2, seed);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> step(0, 2e-3);
  Vec3 w = testing::uniform_on_sphere(1, seed + 1)[0];
  while (q.size() < n) {
    w = testing::normalized(w + Vec3{step(rng), step(rng), step(rng)});
    q.push_back(w);
  }
  return q;
}

void expect_same_attributes(const SiteAttributes& a, const SiteAttributes& b) {
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.columns, b.columns);
  EXPECT_EQ(a.id_column, b.id_column);
  EXPECT_EQ(a.rows_read, b.rows_read);
  EXPECT_EQ(a.rejected, b.rejected);
  EXPECT_EQ(a.site_rows, b.site_rows);
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t r = 0; r < a.rows.size(); ++r) {
    EXPECT_EQ(a.rows[r].row, b.rows[r].row);
    EXPECT_EQ(a.rows[r].line, b.rows[r].line);
    EXPECT_EQ(a.rows[r].lat_deg, b.rows[r].lat_deg);
    EXPECT_EQ(a.rows[r].lon_deg, b.rows[r].lon_deg);
    EXPECT_EQ(a.rows[r].height_m, b.rows[r].height_m);
  }
  EXPECT_EQ(a.text_offsets, b.text_offsets);
  EXPECT_EQ(a.text, b.text);
}

void expect_same_hierarchy(const DelaunayHierarchy& a, const DelaunayHierarchy& b) {
  ASSERT_EQ(a.num_levels(), b.num_levels());
  for (int l = 0; l < a.num_levels(); ++l) {
    const auto x = a.level(l).arrays(), y = b.level(l).arrays();
    EXPECT_EQ(x.sites, y.sites) << "level " << l;
    EXPECT_EQ(x.triangles, y.triangles) << "level " << l;
    EXPECT_EQ(x.halfedges, y.halfedges) << "level " << l;
    EXPECT_EQ(x.site_edge, y.site_edge) << "level " << l;
    EXPECT_EQ(x.lifts, y.lifts) << "level " << l;
    EXPECT_EQ(x.hidden_by, y.hidden_by) << "level " << l;
    EXPECT_TRUE(std::ranges::equal(a.up_links(l), b.up_links(l))) << "level " << l;
    EXPECT_TRUE(std::ranges::equal(a.down_links(l), b.down_links(l))) << "level " << l;
  }
  EXPECT_EQ(a.options().ratio, b.options().ratio);
  EXPECT_EQ(a.options().max_levels, b.options().max_levels);
  EXPECT_EQ(a.options().seed, b.options().seed);
  EXPECT_EQ(a.base().options().merge_distance, b.base().options().merge_distance);
}

void expect_same_answers(const DelaunayHierarchy& a, const DelaunayHierarchy& b, std::size_t n) {
  Locator la(a), lb(b);
  for (const Vec3& q : queries(n, 99)) {
    const NearestResult x = la.nearest(q), y = lb.nearest(q);
    ASSERT_EQ(x.site, y.site);
    ASSERT_EQ(x.dist_m, y.dist_m);
  }
}

// Loads `path` expecting Error(BadData); returns its message.
std::string load_error(const std::string& path, unsigned threads) {
  try {
    const SiteIndex index = load_index(path, threads);
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::BadData) << e.what();
    return e.what();
  }
  ADD_FAILURE() << path << " loaded";
  return "";
}

// The same, and the same message on 2 and 3 threads and one per core (0): the sections are read
// and checked in parallel, the first error in the serial order reported.
std::string load_error(const std::string& path) {
  const std::string serial = load_error(path, 1);
  for (const unsigned threads : {2u, 3u, 0u}) EXPECT_EQ(load_error(path, threads), serial) << threads << " threads";
  return serial;
}

class IndexFile : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    table_ = new SiteTable(make_table(3000, 7));
    index_ = new SiteIndex(build_site_index(*table_));
    path_ = new std::string(temp_path("small.gvi"));
    std::remove(path_->c_str());
    save_index(*path_, index_->hierarchy, index_->attributes);
    bytes_ = new Bytes(read_bytes(*path_));
  }
  static void TearDownTestSuite() {
    delete table_;
    delete index_;
    delete path_;
    delete bytes_;
  }
  static SiteTable* table_;
  static SiteIndex* index_;
  static std::string* path_;
  static Bytes* bytes_;
};
SiteTable* IndexFile::table_ = nullptr;
SiteIndex* IndexFile::index_ = nullptr;
std::string* IndexFile::path_ = nullptr;
Bytes* IndexFile::bytes_ = nullptr;

TEST(Xxh64, KnownValues) {
  // Reference values from libxxhash 0.8.1's XXH64 (seed 0).
  EXPECT_EQ(xxh64("", 0), 0xef46db3751d8e999ULL);
  EXPECT_EQ(xxh64("a", 1), 0xd24ec4f1a98c6e5bULL);
  EXPECT_EQ(xxh64("abc", 3), 0x44bc2cf5ad770999ULL);
  EXPECT_EQ(xxh64("GEOVORIX", 8), 0xc58b3b1c2f2d03b1ULL);
  std::string pattern;
  for (int r = 0; r < 3; ++r)
    for (int i = 0; i < 256; ++i) pattern.push_back(static_cast<char>(i));
  pattern += "xyz";
  EXPECT_EQ(xxh64(pattern.data(), pattern.size()), 0xe921a1b45bd779f8ULL);
}

TEST(IndexFileAttributes, RowsAreGroupedBySite) {
  const SiteTable table = make_table(3000, 7);
  BuildReport report;
  const SiteIndex index = build_site_index(table, {}, {}, &report);
  const SiteAttributes& a = index.attributes;
  ASSERT_EQ(a.num_sites(), 3000u);
  ASSERT_EQ(a.num_rows(), 3060u);
  EXPECT_EQ(a.columns, table.columns);
  EXPECT_EQ(a.rows_read, 3063u);
  EXPECT_EQ(a.rejected, 3u);
  std::vector<char> merged(table.sites.size(), 0);
  for (const Merge& m : report.merges) merged[m.input] = 1;
  std::size_t pairs = 0;
  for (SiteId s = 0; s < a.num_sites(); ++s) {
    const std::uint64_t first = a.site_rows[s], count = a.site_rows[s + 1] - first;
    ASSERT_TRUE(count == 1 || count == 2);
    // The first row is the site's own (not merged), at the site's position.
    const std::size_t input = a.rows[first].row - 1;
    EXPECT_FALSE(merged[input]);
    EXPECT_EQ(a.site_id(s), table.sites[input].id);
    EXPECT_EQ(index.hierarchy.base().site(s), table.sites[input].unit);
    for (std::uint64_t r = first; r < first + count; ++r) {
      const InputSite& in = table.sites[a.rows[r].row - 1];
      EXPECT_EQ(a.row_id(r), in.id);
      EXPECT_EQ(a.rows[r].line, in.line);
      EXPECT_EQ(a.rows[r].lat_deg, in.lat_deg);
      EXPECT_EQ(a.rows[r].height_m, in.height_m);
      for (std::size_t c = 0; c < a.columns.size(); ++c) EXPECT_EQ(a.field(r, c), in.fields[c]);
      EXPECT_EQ(report.site_of_input[a.rows[r].row - 1], s);
    }
    if (count == 2) {
      ++pairs;
      EXPECT_TRUE(merged[a.rows[first + 1].row - 1]);
    }
  }
  EXPECT_EQ(pairs, 60u);
}

TEST_F(IndexFile, RoundTripIsIdentical) {
  const SiteIndex loaded = load_index(*path_);
  expect_same_hierarchy(index_->hierarchy, loaded.hierarchy);
  expect_same_attributes(index_->attributes, loaded.attributes);
  EXPECT_TRUE(loaded.hierarchy.validate().ok());
  expect_same_answers(index_->hierarchy, loaded.hierarchy, 20000);
  // Saving the loaded index gives the same bytes.
  const std::string again = temp_path("again.gvi");
  std::remove(again.c_str());
  save_index(again, loaded.hierarchy, loaded.attributes);
  EXPECT_EQ(read_bytes(again), *bytes_);
}

TEST_F(IndexFile, AnyThreadsLoadTheSame) {
  for (const unsigned threads : {2u, 3u, 8u, 0u}) {
    const SiteIndex loaded = load_index(*path_, threads);
    expect_same_hierarchy(index_->hierarchy, loaded.hierarchy);
    expect_same_attributes(index_->attributes, loaded.attributes);
  }
}

// Several broken sections: whatever the threads, the error is the first in the serial order (the
// levels' sections, level by level, then the attributes'), not the first a thread met.
TEST_F(IndexFile, FirstErrorInTheSerialOrder) {
  const std::string path = temp_path("two_errors.gvi");
  const SectionRef text = find_section(*bytes_, 23), sites1 = find_section(*bytes_, 10, 1),
                   tri0 = find_section(*bytes_, 11, 0), half0 = find_section(*bytes_, 12, 0);
  auto flip = [](Bytes& b, std::size_t at) { b[at] = static_cast<char>(b[at] ^ 1); };
  Bytes b = *bytes_;
  flip(b, text.offset + 5);  // the largest sections, read first
  flip(b, sites1.offset + 3);
  write_bytes(path, b);
  EXPECT_NE(load_error(path).find("sites, level 1): checksum mismatch"), std::string::npos);
  flip(b, half0.offset + 1);
  write_bytes(path, b);
  EXPECT_NE(load_error(path).find("half-edges, level 0): checksum mismatch"), std::string::npos);
  flip(b, tri0.offset + 2);
  write_bytes(path, b);
  EXPECT_NE(load_error(path).find("triangles, level 0): checksum mismatch"), std::string::npos);
  // A structural error of level 0 comes before a checksum error of level 1, and of the attributes.
  b = *bytes_;
  set32(b, tri0.offset + 4, 3000);  // a site id out of range
  rehash(b);
  flip(b, sites1.offset + 3);
  flip(b, text.offset + 5);
  write_bytes(path, b);
  EXPECT_NE(load_error(path).find("level 0: triangulation"), std::string::npos);
}

TEST_F(IndexFile, LoadedIndexStaysDynamic) {
  SiteIndex loaded = load_index(*path_);
  const InsertResult r = loaded.hierarchy.insert(testing::uniform_on_sphere(1, 12345)[0]);
  EXPECT_FALSE(r.merged);
  loaded.hierarchy.remove(17);
  EXPECT_TRUE(loaded.hierarchy.validate().ok());
}

TEST(IndexFileStations, RoundTripOfTheWeatherStations) {
  const SiteTable table = read_sites_csv_file(std::string(GEOVOR_SOURCE_DIR) + "/datasets/weather_stations.csv");
  BuildReport report;
  const SiteIndex index = build_site_index(table, {}, {}, &report);
  EXPECT_EQ(report.merges.size(), 3u);
  const std::string path = temp_path("stations.gvi");
  std::remove(path.c_str());
  save_index(path, index.hierarchy, index.attributes);
  const SiteIndex loaded = load_index(path);
  expect_same_hierarchy(index.hierarchy, loaded.hierarchy);
  expect_same_attributes(index.attributes, loaded.attributes);
  expect_same_answers(index.hierarchy, loaded.hierarchy, 20000);
  EXPECT_EQ(loaded.attributes.num_rows(), 5634u);
  EXPECT_EQ(loaded.attributes.columns, table.columns);
  // Every site's first row is a row of the table at that site's position.
  for (SiteId s = 0; s < loaded.attributes.num_sites(); ++s) {
    const SiteAttributes::Row& row = loaded.attributes.rows[loaded.attributes.site_rows[s]];
    ASSERT_EQ(SiteEncoder::from_lat_lon(row.lat_deg, row.lon_deg), loaded.hierarchy.base().site(s));
  }
}

TEST(IndexFileSave, RefusesAnExistingFileUnlessOverwriting) {
  const SiteTable table = make_table(100, 3);
  const SiteIndex index = build_site_index(table);
  const std::string path = temp_path("exists.gvi");
  write_bytes(path, "something");
  try {
    save_index(path, index.hierarchy, index.attributes);
    ADD_FAILURE() << "overwrote";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Io);
    EXPECT_NE(std::string(e.what()).find("exists"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_bytes(path), "something");
  save_index(path, index.hierarchy, index.attributes, true);
  EXPECT_EQ(load_index(path).attributes.num_rows(), table.sites.size());
  // No temporary file left behind.
  for (const auto& entry : fs::directory_iterator(fs::path(path).parent_path()))
    EXPECT_FALSE(entry.path().filename().string().starts_with(".gv-")) << entry.path();
  // Attributes of another site count are refused.
  SiteAttributes wrong = index.attributes;
  wrong.site_rows.pop_back();
  EXPECT_THROW(save_index(path, index.hierarchy, wrong, true), Error);
}

TEST(IndexFileSave, EmptyTopLevelsAreDropped) {
  const SiteTable table = make_table(3000, 11);
  SiteIndex index = build_site_index(table);
  DelaunayHierarchy& h = index.hierarchy;
  const int top = h.num_levels() - 1;
  ASSERT_GE(top, 2);
  // Remove every site of the top level (through its level-0 copy).
  std::vector<SiteId> victims;
  for (SiteId u = 0; u < h.level(top).site_capacity(); ++u) {
    if (!h.level(top).is_live(u)) continue;
    SiteId s = u;
    for (int l = top; l > 0; --l) s = h.down(l, s);
    victims.push_back(s);
  }
  for (const SiteId s : victims) h.remove(s);
  ASSERT_EQ(h.level(top).num_sites(), 0u);
  const std::string path = temp_path("trimmed.gvi");
  std::remove(path.c_str());
  save_index(path, h, index.attributes);
  const SiteIndex loaded = load_index(path);
  EXPECT_EQ(loaded.hierarchy.num_levels(), top);
  EXPECT_TRUE(loaded.hierarchy.validate().ok());
  expect_same_answers(h, loaded.hierarchy, 5000);
  for (const SiteId s : victims) EXPECT_FALSE(loaded.hierarchy.base().is_live(s));
}

TEST_F(IndexFile, NotAnIndex) {
  const std::string path = temp_path("not_an_index.gvi");
  write_bytes(path, "lat,lon\n1,2\n");
  EXPECT_NE(load_error(path).find("not a geovor index"), std::string::npos);
  EXPECT_FALSE(is_index_file(path));
  EXPECT_TRUE(is_index_file(*path_));
  // A path for sites: an index by its bytes, or by its name when it is none yet (a missing one).
  EXPECT_TRUE(is_index_path(*path_));
  EXPECT_TRUE(is_index_path(temp_path("no_such_file.gvi")));
  EXPECT_FALSE(is_index_path(temp_path("no_such_file.csv")));
  EXPECT_FALSE(is_index_path("-"));
  EXPECT_FALSE(is_index_path(".gvi"));
  write_bytes(path, "");
  EXPECT_NE(load_error(path).find("not a geovor index"), std::string::npos);
  try {
    (void)load_index(temp_path("no_such_file.gvi"));
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::Io);
  }
}

TEST_F(IndexFile, EveryTruncationIsAnError) {
  const std::string path = temp_path("truncated.gvi");
  const std::size_t n = bytes_->size();
  std::vector<std::size_t> cuts = {0, 1, 7, 8, 11, 12, 31, 32, 33, n - 1};
  for (std::size_t i = 1; i <= 40; ++i) cuts.push_back(n * i / 41);
  for (const std::size_t cut : cuts) {
    write_bytes(path, bytes_->substr(0, cut));
    const std::string msg = load_error(path);
    if (cut >= 32) {
      EXPECT_NE(msg.find("truncated: expected " + std::to_string(n) + " bytes, found " + std::to_string(cut)),
                std::string::npos)
          << msg;
    } else if (cut > 0) {
      EXPECT_NE(msg.find("truncated"), std::string::npos) << msg;
    }
  }
  // Extra bytes at the end are an error too.
  write_bytes(path, *bytes_ + "x");
  EXPECT_NE(load_error(path).find("header says"), std::string::npos);
}

TEST_F(IndexFile, EveryByteFlipIsAnError) {
  const std::string path = temp_path("flipped.gvi");
  std::mt19937_64 rng(5);
  // Every byte of the header and the table, then random bytes of the whole file.
  std::vector<std::size_t> at;
  const std::size_t table_end = 32 + 32 * std::size_t{get32(*bytes_, 12)};
  for (std::size_t i = 0; i < table_end; i += 3) at.push_back(i);
  for (int i = 0; i < 300; ++i) at.push_back(rng() % bytes_->size());
  for (const std::size_t i : at) {
    Bytes b = *bytes_;
    b[i] = static_cast<char>(b[i] ^ (1 << (rng() % 8)));
    write_bytes(path, b);
    const std::string msg = load_error(path);
    if (i >= table_end) {
      EXPECT_TRUE(msg.find("checksum mismatch") != std::string::npos || msg.find("padding") != std::string::npos)
          << i << ": " << msg;
    }
  }
}

TEST_F(IndexFile, UnsupportedVersion) {
  Bytes b = *bytes_;
  set32(b, 8, 7);
  const std::string path = temp_path("version.gvi");
  write_bytes(path, b);
  EXPECT_NE(load_error(path).find("unsupported version 7, this geovor reads 1 and 2"), std::string::npos);
}

TEST_F(IndexFile, HugeSizesAllocateNothingLarge) {
  const std::string path = temp_path("huge.gvi");
  const std::size_t limit = 2 * bytes_->size();
  auto check = [&](Bytes b, const char* expect) {
    rehash(b);
    write_bytes(path, b);
    g_max_alloc = 0;
    const std::string msg = load_error(path);
    EXPECT_LT(g_max_alloc.load(), limit) << msg;
    EXPECT_NE(msg.find(expect), std::string::npos) << msg;
  };
  Bytes b = *bytes_;
  set64(b, 16, std::uint64_t{1} << 60);  // the file size
  check(b, "truncated: expected 1152921504606846976 bytes");
  b = *bytes_;
  set32(b, 12, 0xffffffffu);  // the section count
  check(b, "sections do not fit");
  const SectionRef sites = find_section(*bytes_, 10, 0);
  for (const std::uint64_t size : {std::uint64_t{1} << 62, ~std::uint64_t{0}, std::uint64_t{bytes_->size()}}) {
    b = *bytes_;
    set64(b, sites.entry + 16, size);
    check(b, "do not fit the layout");
  }
  // Counts in the meta section (checksums made consistent): rows, sites, columns.
  const SectionRef meta = find_section(*bytes_, 1);
  b = *bytes_;
  set64(b, meta.offset + 64, std::uint64_t{1} << 61);
  check(b, "rows");
  b = *bytes_;
  set64(b, meta.offset + 72, ~std::uint64_t{0});
  check(b, "sites");
  b = *bytes_;
  set32(b, meta.offset + 60, 0xfffffff0u);
  check(b, "");
  b = *bytes_;
  set32(b, meta.offset, 200);  // levels
  check(b, "levels");
}

TEST_F(IndexFile, ConsistentButWrongEditsAreCaught) {
  const std::string path = temp_path("edited.gvi");
  auto expect_bad = [&](Bytes b, const std::string& expect) {
    rehash(b);
    write_bytes(path, b);
    const std::string msg = load_error(path);
    EXPECT_NE(msg.find(expect), std::string::npos) << msg;
  };
  const SectionRef tri0 = find_section(*bytes_, 11, 0);
  Bytes b = *bytes_;
  set32(b, tri0.offset + 4, 3000);  // a site id out of range
  expect_bad(b, "level 0: triangulation");
  b = *bytes_;
  set32(b, tri0.offset + 4, get32(b, tri0.offset));  // a repeated site
  expect_bad(b, "level 0: triangulation");
  const SectionRef up0 = find_section(*bytes_, 14, 0);
  b = *bytes_;
  for (std::size_t s = 0; s < up0.size / 4; ++s)
    if (get32(b, up0.offset + 4 * s) != 0xffffffffu) {
      set32(b, up0.offset + 4 * s, get32(b, up0.offset + 4 * s) + 1);  // an up link to the wrong copy
      break;
    }
  expect_bad(b, "bad up link");
  b = *bytes_;
  set32(b, up0.offset + 4 * 0, get32(b, up0.offset) == 0xffffffffu ? 0 : 0xffffffffu);  // a draw not followed
  expect_bad(b, "hierarchy");
  const SectionRef down1 = find_section(*bytes_, 15, 1);
  b = *bytes_;
  set32(b, down1.offset, 0xfffffff0u);  // seen from below: an up link whose copy does not link back
  expect_bad(b, "hierarchy: level 0 site");
  const SectionRef site_rows = find_section(*bytes_, 20);
  b = *bytes_;
  set64(b, site_rows.offset + 8 * 5, get64(b, site_rows.offset + 8 * 7));
  expect_bad(b, "site rows");
  const SectionRef offsets = find_section(*bytes_, 22);
  b = *bytes_;
  set64(b, offsets.offset + 8 * 3, std::uint64_t{1} << 40);
  expect_bad(b, "text offsets");
  const SectionRef meta = find_section(*bytes_, 1);
  b = *bytes_;
  set32(b, meta.offset + 4, 1);  // ratio
  expect_bad(b, "ratio");
  b = *bytes_;
  set64(b, meta.offset + 32, 0);  // merge distance
  expect_bad(b, "merge distance");
}

// Random edits with consistent checksums: either a BadData error or an index that answers
// queries; never a crash (run under ASan/UBSan by scripts/test.sh).
TEST_F(IndexFile, RehashedRandomEditsNeverCrash) {
  const std::string path = temp_path("fuzz.gvi");
  std::mt19937_64 rng(17);
  const std::vector<Vec3> q = queries(200, 3);
  int loaded = 0;
  for (int round = 0; round < 300; ++round) {
    Bytes b = *bytes_;
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e) {
      const std::size_t i = 32 + rng() % (b.size() - 32);
      b[i] = static_cast<char>(rng() % 3 == 0 ? 0xff : b[i] ^ (1 << (rng() % 8)));
    }
    rehash(b);
    write_bytes(path, b);
    std::string serial_error;
    try {
      (void)load_index(path, 1);
    } catch (const Error& e) {
      serial_error = e.what();
    }
    try {
      const SiteIndex index = load_index(path, 2);  // as on one thread
      EXPECT_EQ(serial_error, "");
      ++loaded;
      for (const LocateStrategy st : {LocateStrategy::Hierarchy, LocateStrategy::KeepJumpClimb, LocateStrategy::Walk}) {
        Locator locator(index.hierarchy, {st});
        for (const Vec3& v : q) {
          const NearestResult r = locator.nearest(v);
          ASSERT_LT(r.site, index.hierarchy.base().site_capacity());
          (void)index.attributes.site_id(r.site);
        }
      }
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::BadData) << e.what();
      EXPECT_EQ(e.what(), serial_error);
    }
  }
  // Some edits (a text byte, a low mantissa bit of a site) leave a loadable index.
  EXPECT_GT(loaded, 0);
}

// Weighted sites (version 2): the lifts of every weighted level and the hidden sites round-trip,
// the answers are the same, and inconsistent weights are refused.
TEST(IndexFileWeighted, RoundTripAndRefusedEdits) {
  SiteTable table = make_table(4000, 21);
  table.weighted = true;
  for (std::size_t i = 0; i < table.sites.size(); ++i) table.sites[i].weight_m = 2000.0 * static_cast<double>(i % 97);
  const SiteIndex index = build_site_index(table);
  ASSERT_TRUE(index.hierarchy.is_weighted());
  ASSERT_GT(index.hierarchy.base().num_hidden(), 0u);
  const std::string path = temp_path("weighted.gvi");
  std::remove(path.c_str());
  save_index(path, index.hierarchy, index.attributes);
  const Bytes bytes = read_bytes(path);
  EXPECT_EQ(get32(bytes, 8), 2u);  // a version-1 reader refuses it rather than ignore the weights
  const SiteIndex loaded = load_index(path);
  expect_same_hierarchy(index.hierarchy, loaded.hierarchy);
  expect_same_attributes(index.attributes, loaded.attributes);
  EXPECT_TRUE(loaded.hierarchy.validate().ok());
  expect_same_answers(index.hierarchy, loaded.hierarchy, 5000);
  const std::string again = temp_path("weighted_again.gvi");
  std::remove(again.c_str());
  save_index(again, loaded.hierarchy, loaded.attributes);
  EXPECT_EQ(read_bytes(again), bytes);

  const std::string edited = temp_path("weighted_edited.gvi");
  auto expect_bad = [&](Bytes b, const std::string& expect) {
    rehash(b);
    write_bytes(edited, b);
    const std::string msg = load_error(edited);
    EXPECT_NE(msg.find(expect), std::string::npos) << msg;
  };
  const SectionRef lifts0 = find_section(bytes, 16, 0);
  Bytes b = bytes;
  set64(b, lifts0.offset + 8 * 3, std::bit_cast<std::uint64_t>(1.5));
  expect_bad(b, "lift out of (0, 1]");
  const SectionRef hidden = find_section(bytes, 17, 0);
  SiteId first_hidden = kNoIndex, a_vertex = kNoIndex;
  for (SiteId s = 0; s < index.hierarchy.base().site_capacity(); ++s) {
    if (index.hierarchy.base().is_hidden(s) && first_hidden == kNoIndex) first_hidden = s;
    if (index.hierarchy.base().is_live(s) && a_vertex == kNoIndex) a_vertex = s;
  }
  b = bytes;
  set32(b, hidden.offset + 4 * a_vertex, first_hidden == 0 ? 1 : 0);  // a vertex said hidden
  expect_bad(b, "both hidden and a vertex");
  b = bytes;
  set32(b, hidden.offset + 4 * first_hidden, first_hidden == 0 ? 1 : 0);
  if (!index.hierarchy.base().is_live(first_hidden == 0 ? 1 : 0)) expect_bad(b, "its hider is no vertex");
  const SectionRef meta = find_section(bytes, 1);
  b = bytes;
  set32(b, meta.offset + 12, get32(b, meta.offset + 12) & ~4u);  // weights without the flag
  expect_bad(b, "version 2 without weighted sites");
  b = bytes;
  set32(b, 8, 1);
  expect_bad(b, "weighted sites in a version 1 file");
  if (index.hierarchy.num_levels() > 1 && index.hierarchy.level(1).is_weighted()) {
    const SectionRef lifts1 = find_section(bytes, 16, 1);
    b = bytes;
    set64(b, lifts1.offset, std::bit_cast<std::uint64_t>(std::bit_cast<double>(get64(b, lifts1.offset)) * 0.5));
    expect_bad(b, "another lift");
  }
}

}  // namespace
}  // namespace geovor
