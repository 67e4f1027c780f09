#include "geovor/locate/index_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <utility>

#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/delaunay/site_rows.hpp"
#include "geovor/geo/site_weights.hpp"
#include "geovor/core/output_target.hpp"

namespace geovor {
namespace {

// ---------------------------------------------------------------------------------------------
// XXH64

constexpr std::uint64_t kP1 = 11400714785074694791ULL, kP2 = 14029467366897019727ULL,
                        kP3 = 1609587929392839161ULL, kP4 = 9650029242287828579ULL,
                        kP5 = 2870177450012600261ULL;

std::uint64_t load64(const unsigned char* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);
  if constexpr (std::endian::native == std::endian::big) v = __builtin_bswap64(v);
  return v;
}
std::uint32_t load32(const unsigned char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  if constexpr (std::endian::native == std::endian::big) v = __builtin_bswap32(v);
  return v;
}
std::uint64_t xxh_round(std::uint64_t acc, std::uint64_t input) {
  acc += input * kP2;
  acc = std::rotl(acc, 31);
  return acc * kP1;
}
std::uint64_t xxh_merge(std::uint64_t acc, std::uint64_t val) {
  acc ^= xxh_round(0, val);
  return acc * kP1 + kP4;
}

// ---------------------------------------------------------------------------------------------
// Little-endian encoding

enum SectionKind : std::uint32_t {
  kMeta = 1,
  kNames = 2,
  kSites = 10,
  kTriangles = 11,
  kHalfedges = 12,
  kSiteEdge = 13,
  kUp = 14,
  kDown = 15,
  kLifts = 16,
  kHidden = 17,
  kSiteRows = 20,
  kRows = 21,
  kTextOffsets = 22,
  kText = 23,
};

const char* kind_name(std::uint32_t kind) {
  switch (kind) {
    case kMeta: return "meta";
    case kNames: return "names";
    case kSites: return "sites";
    case kTriangles: return "triangles";
    case kHalfedges: return "half-edges";
    case kSiteEdge: return "site edges";
    case kUp: return "up links";
    case kDown: return "down links";
    case kLifts: return "lifts";
    case kHidden: return "hidden sites";
    case kSiteRows: return "site rows";
    case kRows: return "rows";
    case kTextOffsets: return "text offsets";
    case kText: return "text";
  }
  return "unknown";
}
bool per_level(std::uint32_t kind) { return kind >= kSites && kind <= kLifts; }

constexpr std::uint32_t kFlagWeighted = 4;  // meta flags: the base's sites are weighted (version 2)
constexpr std::uint32_t kWeightedVersion = 2;

constexpr std::size_t kHeaderBytes = 32, kEntryBytes = 32, kMetaBytes = 80;
constexpr std::uint32_t kMaxSections = 1024;

static_assert(sizeof(Vec3) == 24 && std::is_trivially_copyable_v<Vec3>);
static_assert(sizeof(SiteAttributes::Row) == 40 && std::is_trivially_copyable_v<SiteAttributes::Row>);

// Byte-swaps every 4- or 8-byte word in place (big-endian hosts only: the file is little-endian).
template <typename T>
void swap_words(T* data, std::size_t count) {
  if constexpr (std::endian::native == std::endian::big) {
    constexpr std::size_t word = sizeof(T) % 8 == 0 ? 8 : 4;
    auto* bytes = reinterpret_cast<unsigned char*>(data);
    for (std::size_t i = 0; i < count * sizeof(T); i += word) std::reverse(bytes + i, bytes + i + word);
  } else {
    (void)data, (void)count;
  }
}

void put32(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>(v >> (8 * i)));
}
void put64(std::string& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>(v >> (8 * i)));
}
void put_f64(std::string& out, double v) { put64(out, std::bit_cast<std::uint64_t>(v)); }

std::size_t align8(std::size_t n) { return (n + 7) & ~std::size_t{7}; }

// One section to write: its bytes (little-endian already, or converted into `owned`).
struct OutSection {
  std::uint32_t kind = 0, level = 0;
  const void* data = nullptr;  // the caller's bytes, or nullptr for `owned`
  std::size_t size = 0;
  std::string owned;  // converted or encoded bytes
  std::uint64_t checksum = 0;
  const void* bytes() const { return data ? data : owned.data(); }
};

template <typename T>
OutSection array_section(std::uint32_t kind, std::uint32_t level, std::span<const T> values) {
  OutSection s;
  s.kind = kind;
  s.level = level;
  s.size = values.size_bytes();
  if constexpr (std::endian::native == std::endian::big) {
    s.owned.assign(reinterpret_cast<const char*>(values.data()), s.size);
    swap_words(reinterpret_cast<T*>(s.owned.data()), values.size());
  } else {
    s.data = values.data();
  }
  return s;
}

OutSection bytes_section(std::uint32_t kind, std::string bytes) {
  OutSection s;
  s.kind = kind;
  s.owned = std::move(bytes);
  s.size = s.owned.size();
  return s;
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

std::string sys_reason() { return std::strerror(errno); }

// ---------------------------------------------------------------------------------------------
// Reading

struct Entry {
  std::uint32_t kind, level;
  std::uint64_t offset, size, checksum;
};

class Reader {
 public:
  Reader(const std::string& path) : path_(path) {}

  [[noreturn]] void bad(const std::string& why) const { throw Error(ErrorCode::BadData, path_ + ": " + why); }

  std::string section_name(std::size_t i) const {
    const Entry& e = entries_[i];
    std::string name = "section " + std::to_string(i) + " (" + kind_name(e.kind);
    if (per_level(e.kind)) name += ", level " + std::to_string(e.level);
    return name + ")";
  }

  void open() {
    errno = 0;
    file_.reset(std::fopen(path_.c_str(), "rb"));
    if (!file_) throw Error(ErrorCode::Io, path_ + ": cannot open: " + sys_reason());
    struct stat st;
    if (fstat(fileno(file_.get()), &st) != 0) throw Error(ErrorCode::Io, path_ + ": cannot stat: " + sys_reason());
    if (!S_ISREG(st.st_mode)) throw Error(ErrorCode::Io, path_ + ": not a regular file");
    actual_size_ = static_cast<std::uint64_t>(st.st_size);
  }

  // Reads `size` bytes at `offset` (both already checked against the file size). Positional
  // reads: the levels and the attributes may be read by two threads at once.
  void read_at(std::uint64_t offset, void* into, std::size_t size) {
    std::size_t got = 0;
    while (got < size) {
      const ssize_t n = ::pread(fileno(file_.get()), static_cast<char*>(into) + got, size - got,
                                static_cast<off_t>(offset + got));
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw Error(ErrorCode::Io, path_ + ": read error: " + sys_reason());
      if (n == 0)
        bad("truncated while reading: expected " + std::to_string(offset + size) + " bytes, found " +
            std::to_string(offset + got));
      got += static_cast<std::size_t>(n);
    }
  }

  void read_header() {
    unsigned char head[kHeaderBytes];
    const std::size_t have = static_cast<std::size_t>(std::min<std::uint64_t>(actual_size_, kHeaderBytes));
    read_at(0, head, have);
    if (std::memcmp(head, kIndexMagic, std::min<std::size_t>(have, 8)) != 0 || have == 0)
      bad("not a geovor index file (it does not start with GEOVORIX)");
    if (have < 12) bad("truncated: expected at least " + std::to_string(kHeaderBytes) + " bytes, found " + std::to_string(have));
    version_ = load32(head + 8);
    if (version_ != kIndexVersion && version_ != kWeightedVersion)
      bad("unsupported version " + std::to_string(version_) + ", this geovor reads " + std::to_string(kIndexVersion) +
          " and " + std::to_string(kWeightedVersion));
    if (have < kHeaderBytes)
      bad("truncated: expected at least " + std::to_string(kHeaderBytes) + " bytes, found " + std::to_string(have));
    const std::uint32_t count = load32(head + 12);
    const std::uint64_t file_size = load64(head + 16);
    const std::uint64_t checksum = load64(head + 24);
    if (actual_size_ < file_size)
      bad("truncated: expected " + std::to_string(file_size) + " bytes, found " + std::to_string(actual_size_));
    if (actual_size_ > file_size)
      bad("the file has " + std::to_string(actual_size_) + " bytes, its header says " + std::to_string(file_size));
    if (count > kMaxSections || kHeaderBytes + std::uint64_t{kEntryBytes} * count > file_size)
      bad("corrupted header: " + std::to_string(count) + " sections do not fit in " + std::to_string(file_size) + " bytes");
    std::string table(kHeaderBytes + kEntryBytes * count, '\0');
    std::memcpy(table.data(), head, kHeaderBytes);
    read_at(kHeaderBytes, table.data() + kHeaderBytes, kEntryBytes * count);
    std::memset(table.data() + 24, 0, 8);
    if (xxh64(table.data(), table.size()) != checksum) bad("header checksum mismatch (corrupted header or section table)");
    // Layout: each section at the next multiple of 8 after the previous one, the last ending
    // at the end of the file.
    std::uint64_t pos = table.size();
    for (std::uint32_t i = 0; i < count; ++i) {
      const auto* p = reinterpret_cast<const unsigned char*>(table.data()) + kHeaderBytes + kEntryBytes * i;
      Entry e{load32(p), load32(p + 4), load64(p + 8), load64(p + 16), load64(p + 24)};
      entries_.push_back(e);
      if (e.offset != align8(pos) || e.size > file_size || e.offset > file_size - e.size)
        bad(section_name(i) + ": offset " + std::to_string(e.offset) + " and size " + std::to_string(e.size) +
            " do not fit the layout of a " + std::to_string(file_size) + "-byte file");
      pos = e.offset + e.size;
    }
    if (pos != file_size)
      bad("the sections end at byte " + std::to_string(pos) + ", the file at " + std::to_string(file_size));
    // The padding before each section is zero (no byte of the file goes unchecked).
    pos = table.size();
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      unsigned char pad[8] = {};
      const std::size_t n = static_cast<std::size_t>(entries_[i].offset - pos);
      read_at(pos, pad, n);
      for (std::size_t j = 0; j < n; ++j)
        if (pad[j] != 0) bad("non-zero padding before " + section_name(i));
      pos = entries_[i].offset + entries_[i].size;
    }
  }

  // The number of sections of this kind.
  std::size_t count(std::uint32_t kind) const {
    return static_cast<std::size_t>(std::count_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.kind == kind; }));
  }
  bool has(std::uint32_t kind, std::uint32_t level) const {
    return std::any_of(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.kind == kind && e.level == level; });
  }
  std::uint32_t version() const { return version_; }

  // The index of the one section of this kind and level (an error if there is none or several).
  std::size_t find(std::uint32_t kind, std::uint32_t level) const {
    std::size_t found = entries_.size();
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      if (entries_[i].kind != kind || entries_[i].level != level) continue;
      if (found != entries_.size()) bad("two " + std::string(kind_name(kind)) + " sections for level " + std::to_string(level));
      found = i;
    }
    if (found == entries_.size()) {
      std::string what = std::string("no ") + kind_name(kind) + " section";
      if (per_level(kind)) what += " for level " + std::to_string(level);
      bad(what);
    }
    return found;
  }

  // Reads section i as an array of T, checking that its size is `count` elements (or, with
  // count == npos, any multiple of sizeof(T)) and its checksum.
  template <typename T>
  std::vector<T> read_array(std::size_t i, std::size_t count = std::string::npos, std::size_t multiple = 1) {
    const Entry& e = entries_[i];
    if (count != std::string::npos ? e.size != std::uint64_t{count} * sizeof(T) : e.size % (sizeof(T) * multiple) != 0)
      bad(section_name(i) + ": " + std::to_string(e.size) + " bytes, expected " +
          (count != std::string::npos ? std::to_string(std::uint64_t{count} * sizeof(T))
                                      : "a multiple of " + std::to_string(sizeof(T) * multiple)));
    std::vector<T> v(static_cast<std::size_t>(e.size / sizeof(T)));  // e.size <= the file size
    read_at(e.offset, v.data(), static_cast<std::size_t>(e.size));
    check(i, v.data());
    swap_words(v.data(), v.size());
    return v;
  }

  std::string read_bytes(std::size_t i) {
    const Entry& e = entries_[i];
    std::string s(static_cast<std::size_t>(e.size), '\0');
    read_at(e.offset, s.data(), s.size());
    check(i, s.data());
    return s;
  }

  const Entry& entry(std::size_t i) const { return entries_[i]; }
  std::size_t num_sections() const { return entries_.size(); }
  const std::string& path() const { return path_; }

 private:
  void check(std::size_t i, const void* data) const {
    if (xxh64(data, static_cast<std::size_t>(entries_[i].size)) != entries_[i].checksum)
      bad(section_name(i) + ": checksum mismatch");
  }

  std::string path_;
  File file_;
  std::uint64_t actual_size_ = 0;
  std::uint32_t version_ = 0;
  std::vector<Entry> entries_;
};

// Checks that offsets start at 0, never decrease and end at `end`.
bool offsets_ok(const std::vector<std::uint64_t>& v, std::uint64_t end) {
  if (v.empty() || v.front() != 0 || v.back() != end) return false;
  for (std::size_t i = 1; i < v.size(); ++i)
    if (v[i] < v[i - 1]) return false;
  return true;
}

}  // namespace

// ---------------------------------------------------------------------------------------------

std::uint64_t xxh64(const void* data, std::size_t size, std::uint64_t seed) {
  const auto* p = static_cast<const unsigned char*>(data);
  const unsigned char* const end = p + size;
  std::uint64_t h;
  if (size >= 32) {
    std::uint64_t v1 = seed + kP1 + kP2, v2 = seed + kP2, v3 = seed, v4 = seed - kP1;
    const unsigned char* const limit = end - 32;
    do {
      v1 = xxh_round(v1, load64(p));
      v2 = xxh_round(v2, load64(p + 8));
      v3 = xxh_round(v3, load64(p + 16));
      v4 = xxh_round(v4, load64(p + 24));
      p += 32;
    } while (p <= limit);
    h = std::rotl(v1, 1) + std::rotl(v2, 7) + std::rotl(v3, 12) + std::rotl(v4, 18);
    h = xxh_merge(h, v1);
    h = xxh_merge(h, v2);
    h = xxh_merge(h, v3);
    h = xxh_merge(h, v4);
  } else {
    h = seed + kP5;
  }
  h += static_cast<std::uint64_t>(size);
  // Compare what is left, never p + 8 with end: a pointer past the end (or off null) is UB.
  for (; end - p >= 8; p += 8) {
    h ^= xxh_round(0, load64(p));
    h = std::rotl(h, 27) * kP1 + kP4;
  }
  if (end - p >= 4) {
    h ^= static_cast<std::uint64_t>(load32(p)) * kP1;
    h = std::rotl(h, 23) * kP2 + kP3;
    p += 4;
  }
  for (; p < end; ++p) {
    h ^= (*p) * kP5;
    h = std::rotl(h, 11) * kP1;
  }
  h ^= h >> 33;
  h *= kP2;
  h ^= h >> 29;
  h *= kP3;
  h ^= h >> 32;
  return h;
}

void SiteAttributes::append_row(const InputSite& site) {
  rows.push_back({site.row, site.line, site.lat_deg, site.lon_deg, site.height_m});
  text += site.id;
  text_offsets.push_back(text.size());
  for (std::size_t c = 0; c < columns.size(); ++c) {
    if (c < site.fields.size()) text += site.fields[c];
    text_offsets.push_back(text.size());
  }
  ++site_rows.back();
}

SiteAttributes make_site_attributes(const SiteTable& table, const BuildReport& report, std::size_t site_capacity) {
  const std::size_t n = table.sites.size();
  if (report.site_of_input.size() != n)
    throw Error(ErrorCode::InvalidArgument, "make_site_attributes: the report is not of this table's build");
  SiteAttributes a;
  a.source = table.source;
  a.columns = table.columns;
  a.id_column = table.id_column;
  a.rows_read = table.rows_read;
  a.rejected = table.rejected.size();
  for (const SiteId s : report.site_of_input)
    if (s >= site_capacity) throw Error(ErrorCode::InvalidArgument, "make_site_attributes: site id out of range");
  // Rows per site, the site's own (not merged) row first, then the merged ones in input order.
  const SiteRows site_rows = rows_of_sites(report, site_capacity);
  a.rows.reserve(n);
  a.text_offsets.reserve(n * (1 + a.columns.size()) + 1);
  std::size_t bytes = 0;
  for (const InputSite& s : table.sites) {
    bytes += s.id.size();
    for (const auto& f : s.fields) bytes += f.size();
  }
  a.text.reserve(bytes);
  for (const std::uint32_t row : site_rows.inputs) a.append_row(table.sites[row]);
  a.site_rows.assign(site_rows.begin.begin(), site_rows.begin.end());
  return a;
}

SiteIndex build_site_index(const SiteTable& table, const DelaunayOptions& options, const HierarchyOptions& hierarchy,
                           BuildReport* report) {
  std::vector<Vec3> points;
  points.reserve(table.sites.size());
  for (const InputSite& s : table.sites) points.push_back(s.unit);
  BuildReport local;
  BuildReport& r = report ? *report : local;
  SiteIndex index;
  index.hierarchy = table.weighted ? DelaunayHierarchy::build(points, site_lifts(table), options, hierarchy, &r)
                                   : DelaunayHierarchy::build(points, options, hierarchy, &r);
  index.attributes = make_site_attributes(table, r, index.hierarchy.base().site_capacity());
  return index;
}

// ---------------------------------------------------------------------------------------------
// Saving

void save_index(const std::string& path, const DelaunayHierarchy& h, const SiteAttributes& a, bool overwrite) {
  if (h.num_levels() == 0) throw Error(ErrorCode::InvalidArgument, "save_index: empty hierarchy");
  if (a.num_sites() != h.base().site_capacity())
    throw Error(ErrorCode::InvalidArgument, "save_index: attributes for " + std::to_string(a.num_sites()) +
                                                " sites, the hierarchy has " + std::to_string(h.base().site_capacity()));
  const std::size_t fields = 1 + a.columns.size();
  if (a.site_rows.back() != a.rows.size() || a.text_offsets.size() != a.rows.size() * fields + 1 ||
      a.text_offsets.back() != a.text.size())
    throw Error(ErrorCode::InvalidArgument, "save_index: inconsistent attributes");
  // Empty levels at the top (their sites all removed) are not saved.
  int levels = h.num_levels();
  while (levels > 1 && h.level(levels - 1).num_sites() == 0) --levels;

  const DelaunayOptions& dopt = h.base().options();
  const HierarchyOptions& hopt = h.options();
  std::string meta;
  put32(meta, static_cast<std::uint32_t>(levels));
  put32(meta, hopt.ratio);
  put32(meta, hopt.max_levels);
  const bool weighted = h.is_weighted();
  put32(meta, (dopt.spatial_sort ? 1u : 0u) | (dopt.brio ? 2u : 0u) | (weighted ? kFlagWeighted : 0u));
  put64(meta, hopt.seed);
  put64(meta, dopt.seed);
  put_f64(meta, dopt.merge_distance);
  put64(meta, a.rows_read);
  put64(meta, a.rejected);
  put32(meta, static_cast<std::uint32_t>(a.id_column));
  put32(meta, static_cast<std::uint32_t>(a.columns.size()));
  put64(meta, a.rows.size());
  put64(meta, a.num_sites());
  std::string names;
  put64(names, a.source.size());
  names += a.source;
  for (const std::string& c : a.columns) {
    put64(names, c.size());
    names += c;
  }

  std::vector<SphericalDelaunay::Arrays> arrays(static_cast<std::size_t>(levels));
  std::vector<OutSection> sections;
  sections.push_back(bytes_section(kMeta, std::move(meta)));
  sections.push_back(bytes_section(kNames, std::move(names)));
  std::vector<SiteId> top_up;  // the new top level's up links, when levels were dropped
  for (int l = 0; l < levels; ++l) {
    auto& ar = arrays[static_cast<std::size_t>(l)] = h.level(l).arrays();
    const auto lv = static_cast<std::uint32_t>(l);
    sections.push_back(array_section<Vec3>(kSites, lv, ar.sites));
    sections.push_back(array_section<SiteId>(kTriangles, lv, ar.triangles));
    sections.push_back(array_section<HalfedgeId>(kHalfedges, lv, ar.halfedges));
    sections.push_back(array_section<HalfedgeId>(kSiteEdge, lv, ar.site_edge));
    std::span<const SiteId> up = h.up_links(l);
    if (l == levels - 1 && levels < h.num_levels()) {
      top_up.assign(up.size(), kNoIndex);
      up = top_up;
    }
    sections.push_back(array_section<SiteId>(kUp, lv, up));
    if (l > 0) sections.push_back(array_section<SiteId>(kDown, lv, h.down_links(l)));
    if (!ar.lifts.empty()) sections.push_back(array_section<double>(kLifts, lv, ar.lifts));
  }
  if (weighted) sections.push_back(array_section<SiteId>(kHidden, 0, arrays[0].hidden_by));
  sections.push_back(array_section<std::uint64_t>(kSiteRows, 0, a.site_rows));
  sections.push_back(array_section<SiteAttributes::Row>(kRows, 0, a.rows));
  sections.push_back(array_section<std::uint64_t>(kTextOffsets, 0, a.text_offsets));
  sections.push_back(array_section<char>(kText, 0, std::span<const char>(a.text.data(), a.text.size())));

  std::string head;
  head.append(kIndexMagic, 8);
  put32(head, weighted ? kWeightedVersion : kIndexVersion);  // an older geovor refuses weights
  put32(head, static_cast<std::uint32_t>(sections.size()));
  put64(head, 0);  // file size, below
  put64(head, 0);  // checksum, below
  std::uint64_t pos = kHeaderBytes + kEntryBytes * sections.size();
  for (OutSection& s : sections) {
    s.checksum = xxh64(s.bytes(), s.size);
    pos = align8(pos);
    put32(head, s.kind);
    put32(head, s.level);
    put64(head, pos);
    put64(head, s.size);
    put64(head, s.checksum);
    pos += s.size;
  }
  for (int i = 0; i < 8; ++i) head[16 + i] = static_cast<char>(pos >> (8 * i));
  const std::uint64_t checksum = xxh64(head.data(), head.size());
  for (int i = 0; i < 8; ++i) head[24 + i] = static_cast<char>(checksum >> (8 * i));

  if (!overwrite && access(path.c_str(), F_OK) == 0) throw Error(ErrorCode::Io, output_exists(path));
  // Renaming over a device or a FIFO (/dev/null as root) would replace it.
  if (struct stat st; stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw Error(ErrorCode::Io, path + ": not a regular file; an index must be one");
  // A temporary file next to the target with a short name (output_target.hpp), removed on
  // errors and signals.
  TemporaryOutput temp(path, TemporaryOutput::Kind::File);
  const int fd = temp.take_fd();
  auto fail = [&](const std::string& what) {
    const std::string reason = sys_reason();
    temp.discard();
    throw Error(ErrorCode::Io, path + ": " + what + ": " + reason);
  };
  File f(fdopen(fd, "wb"));
  if (!f) {
    close(fd);
    fail("cannot write");
  }
  static const char zeros[8] = {};
  std::uint64_t written = head.size();
  bool ok = std::fwrite(head.data(), 1, head.size(), f.get()) == head.size();
  for (const OutSection& s : sections) {
    if (!ok) break;
    const std::size_t pad = align8(written) - written;
    ok = std::fwrite(zeros, 1, pad, f.get()) == pad && std::fwrite(s.bytes(), 1, s.size, f.get()) == s.size;
    written += pad + s.size;
  }
  if (!ok) fail("write error");
  if (std::fclose(f.release()) != 0) fail("write error");
  // Never over a file that appeared while writing, unless overwriting.
  const int err = rename_into_place(temp.path(), path, overwrite);
  if (err == EEXIST && !overwrite) {
    temp.discard();
    throw Error(ErrorCode::Io, output_exists(path));
  }
  if (err != 0) {
    errno = err;
    fail("cannot rename " + temp.path() + " to it");
  }
  temp.release();
}

// ---------------------------------------------------------------------------------------------
// Loading

bool is_index_file(const std::string& path) {
  // Reading a pipe's or FIFO's first bytes would consume them: only a regular file is looked into.
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  File f(std::fopen(path.c_str(), "rb"));
  if (!f) return false;
  char magic[8];
  return std::fread(magic, 1, 8, f.get()) == 8 && std::memcmp(magic, kIndexMagic, 8) == 0;
}

bool is_index_path(const std::string& path) {
  return path != "-" && (is_index_file(path) || (path.size() > 4 && path.ends_with(".gvi")));
}

SiteIndex load_index(const std::string& path, unsigned threads) {
  Reader in(path);
  in.open();
  in.read_header();

  // Meta and names.
  const std::size_t meta_i = in.find(kMeta, 0);
  if (in.entry(meta_i).size != kMetaBytes)
    in.bad(in.section_name(meta_i) + ": " + std::to_string(in.entry(meta_i).size) + " bytes, expected " +
           std::to_string(kMetaBytes));
  const std::string meta = in.read_bytes(meta_i);
  const auto* m = reinterpret_cast<const unsigned char*>(meta.data());
  const std::uint32_t levels = load32(m);
  HierarchyOptions hopt;
  hopt.ratio = load32(m + 4);
  hopt.max_levels = load32(m + 8);
  const std::uint32_t flags = load32(m + 12);
  hopt.seed = load64(m + 16);
  DelaunayOptions dopt;
  dopt.seed = load64(m + 24);
  dopt.merge_distance = std::bit_cast<double>(load64(m + 32));
  dopt.spatial_sort = (flags & 1) != 0;
  dopt.brio = (flags & 2) != 0;
  SiteIndex index;
  SiteAttributes& a = index.attributes;
  a.rows_read = load64(m + 40);
  a.rejected = load64(m + 48);
  a.id_column = static_cast<std::int32_t>(load32(m + 56));
  const std::uint32_t num_columns = load32(m + 60);
  const std::uint64_t num_rows = load64(m + 64);
  const std::uint64_t num_sites = load64(m + 72);
  if (levels < 1 || levels > 16) in.bad("meta: " + std::to_string(levels) + " levels (1 to 16 expected)");
  if ((flags & ~7u) != 0) in.bad("meta: unknown flags");
  const bool weighted = (flags & kFlagWeighted) != 0;
  if (weighted != (in.version() == kWeightedVersion))
    in.bad(weighted ? "meta: weighted sites in a version 1 file" : "version 2 without weighted sites");
  if (!(dopt.merge_distance >= SphericalDelaunay::kMinSeparation) || !std::isfinite(dopt.merge_distance))
    in.bad("meta: merge distance out of range");
  if (a.id_column < -1 || (a.id_column >= 0 && static_cast<std::uint32_t>(a.id_column) >= num_columns))
    in.bad("meta: id column out of range");
  // Every section is accounted for: meta, names, 5 or 6 per level, 4 of attributes; weighted:
  // the lifts of level 0 and of the levels above that have weights, and the hidden sites.
  const std::size_t lift_sections = in.count(kLifts);
  if (weighted ? !in.has(kLifts, 0) || in.count(kHidden) != 1 : lift_sections + in.count(kHidden) > 0)
    in.bad(weighted ? "weighted sites without their lifts and hidden sites" : "lifts or hidden sites without weights");
  if (lift_sections > levels) in.bad(std::to_string(lift_sections) + " lifts sections for " + std::to_string(levels) + " levels");
  const std::size_t expected_sections = 2 + 6 * std::size_t{levels} - 1 + 4 + lift_sections + (weighted ? 1 : 0);
  if (in.num_sections() != expected_sections)
    in.bad(std::to_string(in.num_sections()) + " sections, expected " + std::to_string(expected_sections) + " for " +
           std::to_string(levels) + " levels");

  {
    const std::string names = in.read_bytes(in.find(kNames, 0));
    std::size_t p = 0;
    auto next = [&](std::string& out) {
      if (names.size() - p < 8) in.bad("names: truncated");
      const std::uint64_t len = load64(reinterpret_cast<const unsigned char*>(names.data()) + p);
      p += 8;
      if (len > names.size() - p) in.bad("names: truncated");
      out.assign(names, p, static_cast<std::size_t>(len));
      p += static_cast<std::size_t>(len);
    };
    next(a.source);
    if (num_columns > names.size() / 8) in.bad("names: truncated");
    a.columns.resize(num_columns);
    for (std::string& c : a.columns) next(c);
    if (p != names.size()) in.bad("names: " + std::to_string(names.size() - p) + " bytes too many");
  }

  // Every section is one job: find it, check its size, read it, check its checksum. The jobs run
  // on `threads` threads (core/parallel.hpp), the largest first, each into its own array. Errors
  // are reported in the serial order: each level's sections, then its from_arrays(), then the
  // hierarchy's links, then the attributes' sections and offsets. A job whose count depends on
  // another section (a level's site count, its triangles) takes it from that section's size,
  // which is the count read whenever that section is valid; when it is not, its own error comes
  // first. No job allocates more than its section's bytes.
  struct Job {
    std::function<void()> read;
    std::uint64_t bytes = 0;
    std::exception_ptr error;
  };
  std::vector<Job> jobs;
  auto section_bytes = [&](std::uint32_t kind, std::uint32_t level) -> std::uint64_t {
    for (std::size_t i = 0; i < in.num_sections(); ++i)
      if (in.entry(i).kind == kind && in.entry(i).level == level) return in.entry(i).size;
    return 0;
  };
  auto add = [&](std::uint32_t kind, std::uint32_t level, std::function<void()> read) {
    jobs.push_back({std::move(read), section_bytes(kind, level), nullptr});
  };
  // A level's count of sites and of half-edges, as its sites and triangles sections give them.
  auto sites_of = [&](std::uint32_t l) { return static_cast<std::size_t>(in.entry(in.find(kSites, l)).size / sizeof(Vec3)); };
  auto halfedges_of = [&](std::uint32_t l) {
    return static_cast<std::size_t>(in.entry(in.find(kTriangles, l)).size / sizeof(SiteId));
  };
  std::vector<SphericalDelaunay::Arrays> arrays(levels);
  std::vector<std::vector<SiteId>> up(levels), down(levels);
  std::vector<std::size_t> level_end(levels);  // past the level's last job
  std::size_t lifts_read = 0;
  for (std::uint32_t l = 0; l < levels; ++l) {
    add(kSites, l, [&, l] { arrays[l].sites = in.read_array<Vec3>(in.find(kSites, l)); });
    add(kTriangles, l, [&, l] { arrays[l].triangles = in.read_array<SiteId>(in.find(kTriangles, l), std::string::npos, 3); });
    add(kHalfedges, l, [&, l] { arrays[l].halfedges = in.read_array<HalfedgeId>(in.find(kHalfedges, l), halfedges_of(l)); });
    add(kSiteEdge, l, [&, l] { arrays[l].site_edge = in.read_array<HalfedgeId>(in.find(kSiteEdge, l), sites_of(l)); });
    add(kUp, l, [&, l] { up[l] = in.read_array<SiteId>(in.find(kUp, l), sites_of(l)); });
    if (l > 0) add(kDown, l, [&, l] { down[l] = in.read_array<SiteId>(in.find(kDown, l), sites_of(l)); });
    if (in.has(kLifts, l)) {
      add(kLifts, l, [&, l] { arrays[l].lifts = in.read_array<double>(in.find(kLifts, l), sites_of(l)); });
      ++lifts_read;
    }
    if (weighted && l == 0) add(kHidden, 0, [&] { arrays[0].hidden_by = in.read_array<SiteId>(in.find(kHidden, 0), sites_of(0)); });
    level_end[l] = jobs.size();
  }
  // The attributes, each job first checking the counts its size depends on.
  const std::size_t fields = 1 + std::size_t{num_columns};
  auto check_rows = [&] {
    if (num_rows > in.entry(in.find(kRows, 0)).size / sizeof(SiteAttributes::Row))
      in.bad("meta: " + std::to_string(num_rows) + " rows, the rows section is smaller");
  };
  auto check_offsets = [&] {
    check_rows();
    const std::size_t offsets_i = in.find(kTextOffsets, 0);
    if (in.entry(offsets_i).size / 8 / fields < num_rows) in.bad(in.section_name(offsets_i) + ": too small for the rows");
  };
  const std::size_t attributes_begin = jobs.size();
  jobs.push_back({check_rows, 0, nullptr});  // the check alone, first as it always was
  add(kSiteRows, 0, [&] {
    a.site_rows = in.read_array<std::uint64_t>(in.find(kSiteRows, 0), static_cast<std::size_t>(num_sites) + 1);
  });
  add(kRows, 0, [&] {
    check_rows();
    a.rows = in.read_array<SiteAttributes::Row>(in.find(kRows, 0), static_cast<std::size_t>(num_rows));
  });
  add(kTextOffsets, 0, [&] {
    check_offsets();
    a.text_offsets =
        in.read_array<std::uint64_t>(in.find(kTextOffsets, 0), static_cast<std::size_t>(num_rows) * fields + 1);
  });
  add(kText, 0, [&] {
    check_offsets();
    a.text = in.read_bytes(in.find(kText, 0));
  });

  std::vector<std::size_t> order(jobs.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return jobs[x].bytes > jobs[y].bytes; });
  auto run_job = [](Job& job) {
    try {
      job.read();
    } catch (...) {
      job.error = std::current_exception();
    }
  };
  parallel_chunks(order.size(), 1, threads, [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) run_job(jobs[order[i]]);
  });

  // Then, in the serial order, each level's first error or its structure (from_arrays(), on
  // `threads` threads), the hierarchy's links, the attributes' first error and their offsets.
  auto rethrow_first = [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      if (jobs[i].error) std::rethrow_exception(jobs[i].error);
  };
  std::vector<SphericalDelaunay> dts;
  dts.reserve(levels);
  for (std::uint32_t l = 0; l < levels; ++l) {
    rethrow_first(l == 0 ? 0 : level_end[l - 1], level_end[l]);
    try {
      dts.push_back(SphericalDelaunay::from_arrays(std::move(arrays[l]), dopt, threads));
    } catch (const Error& e) {
      in.bad("level " + std::to_string(l) + ": " + e.what());
    }
  }
  if (lifts_read != lift_sections) in.bad("a lifts section for a level that does not exist");
  if (dts[0].site_capacity() != num_sites)
    in.bad("meta: " + std::to_string(num_sites) + " sites, level 0 has " + std::to_string(dts[0].site_capacity()));
  try {
    index.hierarchy = DelaunayHierarchy::from_parts(hopt, std::move(dts), std::move(up), std::move(down));
  } catch (const Error& e) {
    in.bad(e.what());
  }
  rethrow_first(attributes_begin, jobs.size());
  if (!offsets_ok(a.site_rows, num_rows)) in.bad("site rows: offsets out of order or range");
  if (!offsets_ok(a.text_offsets, a.text.size())) in.bad("text offsets: out of order or range");
  const SphericalDelaunay& base = index.hierarchy.base();
  for (SiteId s = 0; s < base.site_capacity(); ++s)
    if (base.is_live(s) && a.site_rows[s] == a.site_rows[s + 1])
      in.bad("site " + std::to_string(s) + " has no row");
  return index;
}

}  // namespace geovor
