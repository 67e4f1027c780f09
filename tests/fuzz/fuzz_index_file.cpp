// Fuzz target: the index-file loader (load_index). Input: one mode byte, then the file's bytes.
// Mode bit 0 set: before loading, the header's file size and every checksum (sections, then
// header) are recomputed, so mutations of a valid index reach the structural checks behind the
// checksums. The loader must throw Error(BadData) or return an index whose structure is valid,
// whose attributes are consistent, and that the Locator can query.
#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "fuzz_check.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/locate/index_file.hpp"
#include "geovor/locate/locator.hpp"

namespace {

using namespace geovor;

std::uint64_t get64(const std::uint8_t* p) {
  std::uint64_t v;
  std::memcpy(&v, p, 8);  // the format is little-endian, as are the machines we fuzz on
  return v;
}
void put64(std::uint8_t* p, std::uint64_t v) { std::memcpy(p, &v, 8); }

// Rewrites the file size and the checksums that fit in the bytes (see index_file.hpp's layout).
void repair(std::vector<std::uint8_t>& f) {
  if (f.size() < 32) return;
  put64(f.data() + 16, f.size());
  std::uint32_t count;
  std::memcpy(&count, f.data() + 12, 4);
  const std::uint64_t table_end = 32 + 32 * std::uint64_t{count};
  if (table_end > f.size()) return;
  for (std::uint32_t i = 0; i < count; ++i) {
    std::uint8_t* e = f.data() + 32 + 32 * std::size_t{i};
    const std::uint64_t offset = get64(e + 8), size = get64(e + 16);
    if (offset <= f.size() && size <= f.size() - offset) put64(e + 24, xxh64(f.data() + offset, size));
  }
  put64(f.data() + 24, 0);
  put64(f.data() + 24, xxh64(f.data(), table_end));
}

// An in-memory file with a path (/proc/self/fd/N) for load_index, reused across inputs.
class MemFile {
 public:
  MemFile() : fd_(memfd_create("fuzz_index", 0)) { FUZZ_CHECK(fd_ >= 0, "memfd_create failed"); }
  ~MemFile() { close(fd_); }
  std::string write(const std::vector<std::uint8_t>& bytes) {
    FUZZ_CHECK(ftruncate(fd_, 0) == 0, "ftruncate failed");
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = pwrite(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(done));
      FUZZ_CHECK(n > 0, "pwrite failed");
      done += static_cast<std::size_t>(n);
    }
    return "/proc/self/fd/" + std::to_string(fd_);
  }

 private:
  int fd_;
};

void check_index(const SiteIndex& index) {
  const DelaunayHierarchy& h = index.hierarchy;
  FUZZ_CHECK(h.num_levels() >= 1, "no level");
  for (int l = 0; l < h.num_levels(); ++l) {
    const Validation v = h.level(l).validate_structure();
    FUZZ_CHECK(v.ok(), "level %d: %s", l, v.errors.front().c_str());
  }
  const SphericalDelaunay& base = h.base();
  const SiteAttributes& a = index.attributes;
  FUZZ_CHECK(a.num_sites() == base.site_capacity(), "%zu attribute sites, %zu sites", a.num_sites(), base.site_capacity());
  FUZZ_CHECK(a.text_offsets.size() == a.num_rows() * (1 + a.columns.size()) + 1, "text offsets");
  // Every id and field is a view of the text (string_view::substr throws past its end).
  std::size_t bytes = 0;
  for (SiteId s = 0; s < base.site_capacity(); ++s) {
    bytes += a.site_id(s).size();
    FUZZ_CHECK(a.site_rows[s + 1] <= a.num_rows(), "site rows");
  }
  for (std::size_t r = 0; r < a.num_rows(); ++r)
    for (std::size_t c = 0; c < a.columns.size(); ++c) bytes += a.field(r, c).size();
  FUZZ_CHECK(bytes <= (a.num_sites() + a.num_rows() * a.columns.size()) * a.text.size(), "text");
  // Queries on whatever triangulation was loaded: answers are live sites, and nothing crashes.
  Locator locator(h);
  const double points[][2] = {{0, 0}, {90, 0}, {-90, 0}, {45, -180}, {-33.5, 151.25}, {1e-9, 179.999999}};
  for (const auto& ll : points) {
    const Vec3 q = SiteEncoder::from_lat_lon(ll[0], ll[1]);
    const NearestResult r = locator.nearest(q);
    FUZZ_CHECK(base.num_sites() == 0 ? r.site == kNoIndex : base.is_live(r.site), "nearest is not a live site");
    for (const NearestResult& k : locator.k_nearest(q, 3)) FUZZ_CHECK(base.is_live(k.site), "k-nearest");
    const NearestResult g = locator.nearest_geodesic(ll[0], ll[1]);
    FUZZ_CHECK(base.num_sites() == 0 ? g.site == kNoIndex : base.is_live(g.site), "geodesic nearest");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static MemFile file;
  if (size == 0) return 0;
  std::vector<std::uint8_t> bytes(data + 1, data + size);
  if (data[0] & 1) repair(bytes);
  SiteIndex index;
  try {
    index = load_index(file.write(bytes));
  } catch (const Error& e) {
    FUZZ_CHECK(e.code() == ErrorCode::BadData, "%s", e.what());
    return 0;
  }
  check_index(index);
  return 0;
}
