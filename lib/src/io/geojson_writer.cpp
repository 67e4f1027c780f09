#include "geovor/io/geojson_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <system_error>
#include <type_traits>
#include <utility>

#include "geovor/core/coordinate_grid.hpp"
#include "geovor/core/error.hpp"
#include "geovor/io/output_target.hpp"

namespace geovor {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Numbers

constexpr double kPow10d[10] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};

char* write_scaled(char* out, bool negative, std::uint64_t digits_value, int precision);
// Writes text as a JSON string, quotes included (append_json_string()), to p, which has room for
// 6 * text.size() + 2 characters; returns the end.
char* put_json_string(char* p, std::string_view text);

constexpr std::uint64_t pow10u(int p) {
  std::uint64_t r = 1;
  for (int i = 0; i < p; ++i) r *= 10;
  return r;
}
constexpr std::uint64_t kPow10u[18] = {pow10u(0),  pow10u(1),  pow10u(2),  pow10u(3),  pow10u(4),  pow10u(5),
                                       pow10u(6),  pow10u(7),  pow10u(8),  pow10u(9),  pow10u(10), pow10u(11),
                                       pow10u(12), pow10u(13), pow10u(14), pow10u(15), pow10u(16), pow10u(17)};
// "00" to "99", for writing decimals two at a time.
constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

// ---------------------------------------------------------------------------------------------
// Longitude arcs, for bounding boxes

struct Arc {
  double west, east;  // west <= east, both in [-180, 180]
};

// Sorts and merges overlapping or touching intervals in place.
void merge_arcs(std::vector<Arc>& arcs) {
  if (arcs.empty()) return;
  std::sort(arcs.begin(), arcs.end(), [](const Arc& a, const Arc& b) { return a.west < b.west; });
  std::size_t n = 0;
  for (std::size_t i = 1; i < arcs.size(); ++i) {
    if (arcs[i].west <= arcs[n].east) {
      arcs[n].east = std::max(arcs[n].east, arcs[i].east);
    } else {
      arcs[++n] = arcs[i];
    }
  }
  arcs.resize(n + 1);
}

// The smallest arc containing every interval (merged: sorted, disjoint): the complement of the
// largest gap between consecutive intervals on the circle, -180 and 180 being one meridian.
// Ties go to the gap across the antimeridian, so that boxes do not cross it when they need not.
void smallest_arc(const std::vector<Arc>& merged, double& west, double& east) {
  double best_gap = (merged.front().west + 360.0) - merged.back().east;  // across +-180
  west = merged.front().west;
  east = merged.back().east;
  for (std::size_t i = 0; i + 1 < merged.size(); ++i) {
    const double gap = merged[i + 1].west - merged[i].east;
    if (gap > best_gap) {
      best_gap = gap;
      west = merged[i + 1].west;
      east = merged[i].east;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Geometry checks

std::string position_problem(const LonLat& p) {
  if (!std::isfinite(p.lon_deg) || !std::isfinite(p.lat_deg)) return "a coordinate is not finite";
  if (p.lon_deg < -180.0 || p.lon_deg > 180.0) {
    return "longitude " + std::to_string(p.lon_deg) + " is outside [-180, 180]";
  }
  if (p.lat_deg < -90.0 || p.lat_deg > 90.0) {
    return "latitude " + std::to_string(p.lat_deg) + " is outside [-90, 90]";
  }
  return "";
}

std::string positions_problem(const std::vector<LonLat>& ps) {
  // One branch-free pass first (NaN fails every comparison); the message only on failure.
  bool ok = true;
  for (const LonLat& p : ps) {
    ok &= (p.lon_deg >= -180.0) & (p.lon_deg <= 180.0) & (p.lat_deg >= -90.0) & (p.lat_deg <= 90.0);
  }
  if (ok) return "";
  for (const LonLat& p : ps) {
    if (auto why = position_problem(p); !why.empty()) return why;
  }
  return "";
}

std::string ring_problem(const Ring& ring) {
  if (ring.size() < 4) {
    return "a ring has " + std::to_string(ring.size()) + " positions, fewer than 4";
  }
  if (auto why = positions_problem(ring); !why.empty()) return why;
  // RFC 7946 §3.1.6: the first and last positions "MUST contain identical values".
  if (!(ring.front() == ring.back())) {
    return "a ring is not closed (its last position differs from its first)";
  }
  return "";
}

GeometryType type_of(const Geometry& g) {
  return static_cast<GeometryType>(g.index());  // variant order = enum order
}
static_assert(std::is_same_v<std::variant_alternative_t<0, Geometry>, LonLat> &&
              std::is_same_v<std::variant_alternative_t<1, Geometry>, MultiLineString> &&
              std::is_same_v<std::variant_alternative_t<2, Geometry>, MultiPolygon>);
static_assert(static_cast<int>(GeometryType::Point) == 0 &&
              static_cast<int>(GeometryType::MultiLineString) == 1 &&
              static_cast<int>(GeometryType::MultiPolygon) == 2);

// ---------------------------------------------------------------------------------------------
// Output file handling

std::string errno_text(int err) { return std::strerror(err); }

// The text of features as a GeoJSON file frames them. encode() is const and keeps no state, so
// one encoder serves any number of threads at once.
class GeoJsonEncoder final : public FeatureEncoder {
 public:
  GeoJsonEncoder(const std::string& path, GeoJsonFraming framing, GeometryType geometry_type,
                 const std::vector<Field>& schema, const WriterOptions& options)
      : path_(path), framing_(framing), geometry_type_(geometry_type), precision_(options.precision) {
    if (precision_ < 0 || precision_ > 17) {
      throw Error(ErrorCode::InvalidArgument,
                  "coordinate precision " + std::to_string(precision_) + " is not within 0..17");
    }
    for (std::size_t i = 0; i < schema.size(); ++i) {
      if (schema[i].name == options.id_field) id_index_ = static_cast<int>(i);
    }
    if (!options.id_field.empty() && id_index_ < 0) {
      throw Error(ErrorCode::InvalidArgument,
                  "id field '" + options.id_field + "' is not a field of the schema");
    }
    // Property keys, escaped once.
    for (std::size_t i = 0; i < schema.size(); ++i) {
      std::string key;
      if (i > 0) key += ',';
      append_json_string(key, schema[i].name);
      key += ':';
      keys_chars_ += key.size();
      keys_.push_back(std::move(key));
    }
  }

  void encode(const Geometry& geometry, std::span<const FieldValue> values, std::uint64_t number,
              EncodedFeatures& out) const override {
    const bool has_id = id_index_ >= 0 && static_cast<std::size_t>(id_index_) < values.size() &&
                        !std::holds_alternative<std::monostate>(values[id_index_]);
    std::size_t values_bound = 0;
    for (const FieldValue& v : values) values_bound += value_bound(v);
    if (has_id) values_bound += value_bound(values[id_index_]);
    encode_with(geometry, values.size(), number, out, has_id, values_bound,
                [&](char* p, std::size_t i) { return put_json_value(p, values[i]); });
  }

  void encode_json(const Geometry& geometry, std::span<const std::string_view> json_values, std::uint64_t number,
                   EncodedFeatures& out) const override {
    const bool has_id = id_index_ >= 0 && static_cast<std::size_t>(id_index_) < json_values.size() &&
                        json_values[id_index_] != "null";
    std::size_t values_bound = 0;
    for (const std::string_view v : json_values) values_bound += v.size();
    if (has_id) values_bound += json_values[id_index_].size();
    encode_with(geometry, json_values.size(), number, out, has_id, values_bound, [&](char* p, std::size_t i) {
      std::memcpy(p, json_values[i].data(), json_values[i].size());
      return p + json_values[i].size();
    });
  }

  // The feature's text, each value written by put(p, i) (which returns the end; the values
  // together, the id's twice if has_id, take at most values_bound characters); has_id: the id
  // field's value is not null. The text is written in place, into room made for the longest
  // possible text, which spares a call and a capacity check per piece.
  template <typename PutValue>
  void encode_with(const Geometry& geometry, std::size_t num_values, std::uint64_t number, EncodedFeatures& out,
                   bool has_id, std::size_t values_bound, const PutValue& put) const {
    if (num_values != keys_.size()) {
      throw Error(ErrorCode::InvalidArgument,
                  path_ + ": feature " + std::to_string(number) + " has " +
                      std::to_string(num_values) + " values for " +
                      std::to_string(keys_.size()) + " fields");
    }
    if (type_of(geometry) != geometry_type_) {
      throw Error(ErrorCode::InvalidArgument,
                  path_ + ": feature " + std::to_string(number) + " is a " +
                      to_string(type_of(geometry)) + " in a " +
                      to_string(geometry_type_) + " layer");
    }
    if (auto why = geometry_problem(geometry); !why.empty()) {
      throw Error(ErrorCode::InvalidArgument,
                  path_ + ": feature " + std::to_string(number) + ": " + why);
    }
    const std::optional<BBox> box = geojson_bbox(geometry);
    std::string& t = out.text;
    const std::size_t old_size = t.size();
    t.resize(old_size + kFeatureFrameChars + keys_chars_ + values_bound + kBBoxChars + geometry_bound(geometry));
    char* p = t.data() + old_size;
    // Every feature of a collection starts with its separator; the writer drops the first one.
    if (framing_ == GeoJsonFraming::RecordSeparated) *p++ = '\x1e';
    if (framing_ == GeoJsonFraming::FeatureCollection) p = put_text(p, ",\n");
    p = put_text(p, "{\"type\":\"Feature\"");
    if (has_id) {
      p = put_text(p, ",\"id\":");
      p = put(p, static_cast<std::size_t>(id_index_));
    }
    if (box) {
      p = put_text(p, ",\"bbox\":");
      p = put_bbox(p, *box);
    }
    p = put_text(p, ",\"properties\":{");
    for (std::size_t i = 0; i < num_values; ++i) {
      std::memcpy(p, keys_[i].data(), keys_[i].size());
      p = put(p + keys_[i].size(), i);
    }
    p = put_text(p, "},\"geometry\":");
    p = put_geometry(p, geometry);
    *p++ = '}';
    if (framing_ != GeoJsonFraming::FeatureCollection) *p++ = '\n';
    t.resize(static_cast<std::size_t>(p - t.data()));
    out.boxes.push_back(box);
  }

  void put_bbox(std::string& t, const BBox& b) const {
    char buf[kBBoxChars];
    t.append(buf, static_cast<std::size_t>(put_bbox(buf, b) - buf));
  }

 private:
  // Longest text of a feature's framing without its keys, values, bbox and geometry (the
  // literals of encode_with(): 2 + 17 + 6 + 8 + 15 + 13 + 2 characters, rounded up).
  static constexpr std::size_t kFeatureFrameChars = 80;
  static constexpr std::size_t kBBoxChars = 4 * kMaxCoordinateChars + 8;
  static constexpr std::size_t kPositionChars = 2 * kMaxCoordinateChars + 4;  // [x,y],

  // Copies a string literal without its terminating zero; returns the end.
  template <std::size_t N>
  static char* put_text(char* p, const char (&text)[N]) {
    std::memcpy(p, text, N - 1);
    return p + (N - 1);
  }

  // Longest text put_json_value() writes for v.
  static std::size_t value_bound(const FieldValue& v) {
    if (const auto* s = std::get_if<std::string>(&v)) return 6 * s->size() + 2;
    return std::max<std::size_t>(kMaxRealChars, 24);
  }

  static char* put_json_value(char* p, const FieldValue& v) {
    if (const auto* i = std::get_if<std::int64_t>(&v)) return std::to_chars(p, p + 24, *i).ptr;
    if (const auto* d = std::get_if<double>(&v)) {
      if (!std::isfinite(*d)) return put_text(p, "null");  // JSON has no NaN or infinity (GDAL writes null too)
      return format_real(p, *d);
    }
    if (const auto* s = std::get_if<std::string>(&v)) return put_json_string(p, *s);
    return put_text(p, "null");
  }

  // Longest text put_geometry() writes for g.
  static std::size_t geometry_bound(const Geometry& g) {
    constexpr std::size_t kHead = 48;  // {"type":"MultiLineString","coordinates":[ ... ]}
    if (std::holds_alternative<LonLat>(g)) return kHead + kPositionChars;
    std::size_t n = kHead;
    if (const auto* lines = std::get_if<MultiLineString>(&g)) {
      for (const LineString& line : *lines) n += 3 + line.size() * kPositionChars;
    } else {
      for (const Polygon& poly : std::get<MultiPolygon>(g)) {
        n += 3 + 3 + poly.exterior.size() * kPositionChars;
        for (const Ring& hole : poly.holes) n += 3 + hole.size() * kPositionChars;
      }
    }
    return n;
  }

  char* put_bbox(char* p, const BBox& b) const {
    *p++ = '[';
    p = format_coordinate(p, b.west, precision_);
    *p++ = ',';
    p = format_coordinate(p, b.south, precision_);
    *p++ = ',';
    p = format_coordinate(p, b.east, precision_);
    *p++ = ',';
    p = format_coordinate(p, b.north, precision_);
    *p++ = ']';
    return p;
  }

  char* put_positions(char* p, const std::vector<LonLat>& ps) const {
    *p++ = '[';
    for (std::size_t i = 0; i < ps.size(); ++i) {
      if (i > 0) *p++ = ',';
      *p++ = '[';
      p = format_coordinate(p, ps[i].lon_deg, precision_);
      *p++ = ',';
      p = format_coordinate(p, ps[i].lat_deg, precision_);
      *p++ = ']';
    }
    *p++ = ']';
    return p;
  }

  char* put_geometry(char* p, const Geometry& g) const {
    if (const auto* pt = std::get_if<LonLat>(&g)) {
      p = put_text(p, "{\"type\":\"Point\",\"coordinates\":[");
      p = format_coordinate(p, pt->lon_deg, precision_);
      *p++ = ',';
      p = format_coordinate(p, pt->lat_deg, precision_);
      return put_text(p, "]}");
    }
    if (const auto* lines = std::get_if<MultiLineString>(&g)) {
      p = put_text(p, "{\"type\":\"MultiLineString\",\"coordinates\":[");
      for (std::size_t i = 0; i < lines->size(); ++i) {
        if (i > 0) *p++ = ',';
        p = put_positions(p, (*lines)[i]);
      }
      return put_text(p, "]}");
    }
    const auto& polys = std::get<MultiPolygon>(g);
    p = put_text(p, "{\"type\":\"MultiPolygon\",\"coordinates\":[");
    for (std::size_t i = 0; i < polys.size(); ++i) {
      if (i > 0) *p++ = ',';
      *p++ = '[';
      p = put_positions(p, polys[i].exterior);
      for (const Ring& hole : polys[i].holes) {
        *p++ = ',';
        p = put_positions(p, hole);
      }
      *p++ = ']';
    }
    return put_text(p, "]}");
  }

  std::string path_;
  GeoJsonFraming framing_;
  GeometryType geometry_type_;
  std::vector<std::string> keys_;  // ,"name":
  std::size_t keys_chars_ = 0;     // of all keys_
  int precision_;
  int id_index_ = -1;
};

// Buffered output of one GeoJSON file (or stdout).
class GeoJsonWriter final : public FeatureWriter {
 public:
  GeoJsonWriter(const std::string& path, GeoJsonFraming framing, GeometryType geometry_type,
                const std::vector<Field>& schema, const WriterOptions& options)
      : path_(path), framing_(framing), encoder_(path, framing, geometry_type, schema, options) {
    if (path_ == "-") {
      file_ = stdout;
    } else {
      overwrite_ = options.overwrite;
      if (check_output_target(path_, options.overwrite) == OutputTargetState::Special) {
        file_ = std::fopen(path_.c_str(), "wb");
        if (file_ == nullptr) throw Error(ErrorCode::Io, path_ + ": cannot open: " + errno_text(errno));
      } else {
        open_temporary();
      }
    }
    buffer_.reserve(kFlushAt + (std::size_t{1} << 16));
    if (framing_ == GeoJsonFraming::FeatureCollection) {
      buffer_ += "{\"type\":\"FeatureCollection\",\"name\":";
      append_json_string(buffer_, options.layer);
      buffer_ += ",\"features\":[\n";
    }
  }

  ~GeoJsonWriter() override {
    if (!finished_) discard();
  }

  void write(const Geometry& geometry, std::span<const FieldValue> values) override {
    check_usable();
    one_.clear();
    encoder_.encode(geometry, values, count_ + 1, one_);
    take(one_);
  }

  const FeatureEncoder* encoder() const override { return &encoder_; }

  void write_encoded(const EncodedFeatures& features) override {
    check_usable();
    take(features);
  }

  void finish() override {
    if (failed_) throw Error(ErrorCode::Io, path_ + ": the writer failed earlier");
    if (finished_) return;
    if (framing_ == GeoJsonFraming::FeatureCollection) {
      buffer_ += count_ > 0 ? "\n]" : "]";
      if (const std::optional<BBox> box = extent_.result()) {
        buffer_ += ",\"bbox\":";
        encoder_.put_bbox(buffer_, *box);
      }
      buffer_ += "}\n";
    }
    flush();
    if (stage_ != nullptr) write_stage(true);
    if (file_ == stdout) {
      if (std::fflush(stdout) != 0) fail("cannot write to stdout", errno);
      finished_ = true;
      return;
    }
    // Durable before it becomes visible under its name; errors of a full disk can surface here.
    if (std::fflush(file_) != 0) fail("cannot write", errno);
    if (!temp_.active()) {  // a device or a FIFO, written in place
      if (std::fclose(std::exchange(file_, nullptr)) != 0) fail("cannot write", errno);
      finished_ = true;
      return;
    }
    if (::fsync(::fileno(file_)) != 0 && errno != EINVAL && errno != EROFS) fail("cannot write", errno);
    FILE* f = std::exchange(file_, nullptr);
    if (std::fclose(f) != 0) fail("cannot write", errno);
    // Never over a file that appeared meanwhile, unless overwriting (Error(Io), temporary removed).
    try {
      temp_.commit(path_, overwrite_);
    } catch (...) {
      failed_ = true;
      throw;
    }
    finished_ = true;
  }

 private:
  // Text is written once kFlushAt is pending; encoded blocks from kDirectAt are written straight
  // from the caller's memory.
  static constexpr std::size_t kFlushAt = std::size_t{1} << 20;
  static constexpr std::size_t kDirectAt = std::size_t{1} << 16;
  static constexpr std::size_t kWriteBackEvery = std::size_t{8} << 20;
  static constexpr std::size_t kDirectBlock = 4096, kStageSize = std::size_t{4} << 20;

  void check_usable() const {
    if (failed_) throw Error(ErrorCode::Io, path_ + ": the writer failed earlier");
    if (finished_) throw Error(ErrorCode::InvalidArgument, path_ + ": write() after finish()");
  }

  // Appends encoded features; the first feature of a collection loses its leading ",\n".
  void take(const EncodedFeatures& features) {
    if (features.boxes.empty()) return;
    std::string_view text = features.text;
    if (framing_ == GeoJsonFraming::FeatureCollection && count_ == 0) text.remove_prefix(2);
    for (const std::optional<BBox>& box : features.boxes)
      if (box) extent_.add(*box);
    count_ += features.boxes.size();
    if (text.size() >= kDirectAt) {
      flush();
      write_out(text.data(), text.size());
      return;
    }
    buffer_ += text;
    if (buffer_.size() >= kFlushAt) flush();
  }

  // A temporary file next to the target (output_target.hpp: short name, removed on signals).
  void open_temporary() {
    temp_ = TemporaryOutput(path_, TemporaryOutput::Kind::File);
    file_ = temp_.take_stdio(path_);
    enable_direct();
  }

  // Removes the temporary file; nothing under the final name was touched.
  void discard() noexcept {
    if (file_ != nullptr && file_ != stdout) std::fclose(file_);
    file_ = nullptr;
    temp_.discard();
  }

  [[noreturn]] void fail(const std::string& what, int err) {
    failed_ = true;
    discard();
    throw Error(ErrorCode::Io, path_ + ": " + what + (err != 0 ? ": " + errno_text(err) : ""));
  }

  // Direct I/O of the temporary file where its file system allows it: the text is staged in an
  // aligned buffer and written in whole blocks with O_DIRECT, which spares the kernel's copy into
  // the page cache (a fifth of the CPU time of a large cells file); the last partial block is
  // written normally. Any refusal (EINVAL) falls back to normal writes.
  void enable_direct() {
    const int fd = ::fileno(file_);
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags == -1 || ::fcntl(fd, F_SETFL, flags | O_DIRECT) != 0) return;
    stage_.reset(static_cast<char*>(std::aligned_alloc(kDirectBlock, kStageSize)));
    if (stage_ == nullptr) {
      disable_direct();
      return;
    }
    direct_ = true;
  }
  void disable_direct() {
    const int fd = ::fileno(file_);
    const int flags = ::fcntl(fd, F_GETFL);
    if (flags != -1) ::fcntl(fd, F_SETFL, flags & ~O_DIRECT);
    direct_ = false;
  }
  // Writes n bytes to the temporary file's descriptor (whole blocks while direct_).
  void write_fd(const char* data, std::size_t n) {
    const int fd = ::fileno(file_);
    while (n > 0) {
      const ssize_t w = ::write(fd, data, n);
      if (w < 0) {
        if (errno == EINTR) continue;
        if (errno == EINVAL && direct_) {
          disable_direct();
          continue;
        }
        fail("cannot write", errno);
      }
      data += w, n -= static_cast<std::size_t>(w);
      if (n % kDirectBlock != 0 && direct_) disable_direct();  // a short write broke the alignment
    }
  }
  // Writes the staged bytes: the whole blocks, and the rest too if `all` (then direct I/O ends).
  void write_stage(bool all) {
    const std::size_t blocks = staged_ / kDirectBlock * kDirectBlock;
    write_fd(stage_.get(), blocks);
    std::memmove(stage_.get(), stage_.get() + blocks, staged_ - blocks);
    staged_ -= blocks;
    if (all && staged_ > 0) {
      if (direct_) disable_direct();
      write_fd(stage_.get(), staged_);
      staged_ = 0;
    }
  }

  void write_out(const char* data, std::size_t n) {
    if (stage_ != nullptr) {
      while (n > 0) {
        const std::size_t k = std::min(n, kStageSize - staged_);
        std::memcpy(stage_.get() + staged_, data, k);
        staged_ += k, data += k, n -= k;
        if (staged_ == kStageSize) write_stage(false);
      }
      return;
    }
    errno = 0;
    if (std::fwrite(data, 1, n, file_) != n) fail(file_ == stdout ? "cannot write to stdout" : "cannot write", errno);
    // Start the write-back of the temporary file as it grows (without waiting for it), so that
    // finish()'s fsync has little left to wait for.
    unsynced_ += n;
    if (unsynced_ >= kWriteBackEvery && temp_.active()) {
      unsynced_ = 0;
      if (std::fflush(file_) != 0) fail("cannot write", errno);
      ::sync_file_range(::fileno(file_), 0, 0, SYNC_FILE_RANGE_WRITE);  // a hint: errors surface in fsync
    }
  }

  void flush() {
    if (buffer_.empty()) return;
    write_out(buffer_.data(), buffer_.size());
    buffer_.clear();
  }

  std::string path_;
  TemporaryOutput temp_;  // the file written, unless a device or stdout
  bool overwrite_ = false;
  GeoJsonFraming framing_;
  GeoJsonEncoder encoder_;
  FILE* file_ = nullptr;
  std::string buffer_;    // text not yet written
  EncodedFeatures one_;   // write()'s feature
  BBoxUnion extent_;
  std::uint64_t count_ = 0;
  std::size_t unsynced_ = 0;  // bytes written since the last write-back request
  struct FreeAligned {
    void operator()(char* p) const { std::free(p); }
  };
  std::unique_ptr<char, FreeAligned> stage_;  // the temporary file's text not yet written (fd I/O)
  std::size_t staged_ = 0;
  bool direct_ = false;  // O_DIRECT is on
  bool finished_ = false;
  bool failed_ = false;
};

}  // namespace

// ---------------------------------------------------------------------------------------------

char* format_coordinate(char* out, double value, int precision) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  const bool negative = (bits >> 63) != 0;
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  const int e = biased == 0 ? -1074 : biased - 1075;  // value = m * 2^e, m < 2^53
  if (biased == 0x7ff || e >= 0 || precision < 0 || precision > 17) {
    // |value| >= 2^52 (an integer), not finite, or a bad precision: shortest round trip.
    return std::to_chars(out, out + kMaxCoordinateChars, value).ptr;
  }
  // Fast path: t = fl(value * 10^p) is within half an ulp of the exact product X; with
  // |t| < 2^31 that is at most 2^-22. Unless t lies within 1e-6 of a half-integer, X rounds to
  // the same integer as t, so rounding t (to nearest, with the 1.5 * 2^52 trick) is exact.
  if (precision <= 9) {
    const double t = std::abs(value) * kPow10d[precision];
    if (t < 2147483648.0) {
      volatile double big = 6755399441055744.0;  // 1.5 * 2^52; volatile: never folded away
      const double r = (t + big) - big;
      const double dist = std::abs(t - r);
      if (std::abs(dist - 0.5) > 1e-6) {
        return write_scaled(out, negative, static_cast<std::uint64_t>(r), precision);
      }
    }
  }
  const unsigned __int128 one = 1;
  const unsigned __int128 q = scaled_decimal(value, precision);
  if (q >= (one << 63)) {
    // |value| * 10^p beyond 2^63 (|value| < 2^52 here, so at most 36 characters).
    char tmp[64];
    char* end = std::to_chars(tmp, tmp + sizeof tmp, value, std::chars_format::fixed, precision).ptr;
    if (std::find(tmp, end, '.') != end) {
      while (end[-1] == '0') --end;
      if (end[-1] == '.') --end;
    }
    char* begin = tmp;
    if (end - begin == 2 && tmp[0] == '-' && tmp[1] == '0') ++begin;
    return std::copy(begin, end, out);
  }
  return write_scaled(out, negative, static_cast<std::uint64_t>(q), precision);
}

namespace {

// The 8 decimal digits of x < 10^8 as the bytes of a word, the most significant in the lowest
// byte (the first in memory), without division instructions: x is split into two halves of 4
// digits in 32-bit lanes, each into two pairs in 16-bit lanes, each into two digits in bytes
// (the multiply-shift pairs divide exactly by 100 and by 10 in their ranges).
std::uint64_t eight_digits(std::uint64_t x) {
  static_assert(std::endian::native == std::endian::little);
  const std::uint64_t halves = (x / 10000) | ((x % 10000) << 32);
  const std::uint64_t high_pairs = ((halves * 10486) >> 20) & ((0x7FULL << 32) | 0x7FULL);
  const std::uint64_t pairs = ((halves - 100 * high_pairs) << 16) + high_pairs;
  std::uint64_t tens = ((pairs * 103) >> 10) & ((0xFULL << 48) | (0xFULL << 32) | (0xFULL << 16) | 0xFULL);
  tens += (pairs - 10 * tens) << 8;
  return tens;
}

// Writes +-q / 10^P with trailing zeros trimmed; "0" (never "-0") for q == 0. P is a template
// argument so that the divisions by 10^P compile to multiplications.
template <int P>
char* write_scaled_p(char* out, bool negative, std::uint64_t digits_value) {
  if (digits_value == 0) {
    *out++ = '0';
    return out;
  }
  if (negative) *out++ = '-';
  // The whole part (coordinates: below 1000), then the P decimals without their trailing zeros,
  // written two at a time from the end (no temporary buffer to copy).
  constexpr std::uint64_t scale = pow10u(P);
  std::uint64_t decimals_value = digits_value % scale;
  const std::uint64_t whole = digits_value / scale;
  if (whole < 10) {
    *out++ = static_cast<char>('0' + whole);
  } else if (whole < 100) {
    std::memcpy(out, kDigitPairs + 2 * whole, 2);
    out += 2;
  } else if (whole < 1000) {
    *out++ = static_cast<char>('0' + whole / 100);
    std::memcpy(out, kDigitPairs + 2 * (whole % 100), 2);
    out += 2;
  } else {
    out = std::to_chars(out, out + 24, whole).ptr;
  }
  if constexpr (P >= 1 && P <= 8) {
    // The decimals as 8 digits (P, then zeros) in one word, and its trailing zeros dropped.
    if (decimals_value != 0) {
      std::uint64_t digits = eight_digits(decimals_value * pow10u(8 - P));
      const int kept = 8 - std::countl_zero(digits) / 8;  // the last digits are the high bytes
      digits += 0x3030303030303030;                        // '0' in every byte
      *out++ = '.';
      std::memcpy(out, &digits, 8);  // within kMaxCoordinateChars, the rest overwritten later
      out += kept;
    }
    return out;
  }
  if (decimals_value != 0) {
    int decimals = P;
    while (decimals_value % 10 == 0) decimals_value /= 10, --decimals;
    *out++ = '.';
    char* end = out + decimals;
    char* p = end;
    for (; p - out >= 2; decimals_value /= 100) {
      p -= 2;
      std::memcpy(p, kDigitPairs + 2 * (decimals_value % 100), 2);
    }
    if (p != out) *--p = static_cast<char>('0' + decimals_value);
    out = end;
  }
  return out;
}

template <int... P>
constexpr auto scaled_writers(std::integer_sequence<int, P...>) {
  return std::array<char* (*)(char*, bool, std::uint64_t), sizeof...(P)>{&write_scaled_p<P>...};
}
constexpr auto kScaledWriters = scaled_writers(std::make_integer_sequence<int, 18>());

char* write_scaled(char* out, bool negative, std::uint64_t digits_value, int precision) {
  if (precision == 7) return write_scaled_p<7>(out, negative, digits_value);  // the default, inlined
  return kScaledWriters[static_cast<std::size_t>(precision)](out, negative, digits_value);
}

}  // namespace

char* format_real(char* out, double value) {
  char* end = std::to_chars(out, out + kMaxRealChars, value).ptr;
  if (std::isfinite(value) && std::find_if(out, end, [](char c) {
                                return c == '.' || c == 'e' || c == 'E';
                              }) == end) {
    *end++ = '.';
    *end++ = '0';
  }
  return end;
}

namespace {

// The bytes of w (8 bytes of text, little-endian) that need escaping or UTF-8 checking, as their
// high bits: below 0x20, from 0x80, '"' and '\\' (the "has a byte less than n" and "has a zero
// byte" bit tricks; only the lowest flag is exact, which is the one used).
std::uint64_t special_bytes(std::uint64_t w) {
  constexpr std::uint64_t kOnes = 0x0101010101010101, kHigh = 0x8080808080808080;
  const std::uint64_t quote = w ^ (kOnes * '"'), backslash = w ^ (kOnes * '\\');
  const std::uint64_t below_space = (w - kOnes * 0x20) & ~w;
  const std::uint64_t is_quote = (quote - kOnes) & ~quote, is_backslash = (backslash - kOnes) & ~backslash;
  return (below_space | is_quote | is_backslash | w) & kHigh;
}

// Writes s[i] (and the rest of its UTF-8 sequence) escaped to p; advances i and returns the end.
char* escape_one(char* p, const unsigned char* s, std::size_t n, std::size_t& i) {
  static constexpr char kHex[] = "0123456789abcdef";
  const unsigned char c = s[i];
  if (c >= 0x20 && c != '"' && c != '\\' && c < 0x80) {
    *p++ = static_cast<char>(c);
    ++i;
    return p;
  }
  if (c >= 0x80) {
    // Length and validity of a UTF-8 sequence (RFC 3629: no overlongs, no surrogates,
    // nothing above U+10FFFF).
    std::size_t len = 0;
    if (c >= 0xC2 && c <= 0xDF) {
      len = 2;
    } else if (c >= 0xE0 && c <= 0xEF) {
      len = 3;
    } else if (c >= 0xF0 && c <= 0xF4) {
      len = 4;
    }
    bool ok = len != 0 && i + len <= n;
    for (std::size_t k = 1; ok && k < len; ++k) ok = (s[i + k] & 0xC0) == 0x80;
    if (ok && len == 3) {
      const unsigned char c1 = s[i + 1];
      ok = !(c == 0xE0 && c1 < 0xA0) && !(c == 0xED && c1 >= 0xA0);
    }
    if (ok && len == 4) {
      const unsigned char c1 = s[i + 1];
      ok = !(c == 0xF0 && c1 < 0x90) && !(c == 0xF4 && c1 >= 0x90);
    }
    if (ok) {
      std::memcpy(p, s + i, len);
      i += len;
      return p + len;
    }
    ++i;
    *p++ = '\xEF', *p++ = '\xBF', *p++ = '\xBD';  // U+FFFD
    return p;
  }
  ++i;
  *p++ = '\\';
  switch (c) {
    case '"':
      *p++ = '"';
      break;
    case '\\':
      *p++ = '\\';
      break;
    case '\b':
      *p++ = 'b';
      break;
    case '\f':
      *p++ = 'f';
      break;
    case '\n':
      *p++ = 'n';
      break;
    case '\r':
      *p++ = 'r';
      break;
    case '\t':
      *p++ = 't';
      break;
    default:
      *p++ = 'u', *p++ = '0', *p++ = '0', *p++ = kHex[c >> 4], *p++ = kHex[c & 15];
  }
  return p;
}

// Writes text escaped as append_json_string() does (without the quotes) to p, which has room for
// 6 characters per byte (the longest escape, \u00XX); returns the end. Plain runs are
// copied 8 bytes at a time, up to the first byte that needs attention.
char* escape_json(char* p, const unsigned char* s, std::size_t n) {
  static_assert(std::endian::native == std::endian::little);
  std::size_t i = 0;
  while (i + 8 <= n) {
    std::uint64_t w;
    std::memcpy(&w, s + i, 8);
    std::memcpy(p, &w, 8);  // the plain prefix stays, the rest is overwritten
    const std::uint64_t special = special_bytes(w);
    if (special == 0) {
      p += 8, i += 8;
      continue;
    }
    const std::size_t plain = static_cast<std::size_t>(std::countr_zero(special)) / 8;
    p += plain, i += plain;
    p = escape_one(p, s, n, i);
  }
  while (i < n) p = escape_one(p, s, n, i);
  return p;
}

char* put_json_string(char* p, std::string_view text) {
  *p++ = '"';
  p = escape_json(p, reinterpret_cast<const unsigned char*>(text.data()), text.size());
  *p++ = '"';
  return p;
}

}  // namespace

void append_json_string(std::string& out, std::string_view text) {
  const auto* s = reinterpret_cast<const unsigned char*>(text.data());
  const std::size_t n = text.size();
  // Short strings (nearly all) through a stack buffer: one append, no checks per character.
  constexpr std::size_t kShort = 256;
  if (n <= kShort) {
    char buf[6 * kShort + 2];
    buf[0] = '"';
    char* end = escape_json(buf + 1, s, n);
    *end++ = '"';
    out.append(buf, static_cast<std::size_t>(end - buf));
    return;
  }
  const std::size_t old = out.size();
  out.resize(old + 6 * n + 2);
  char* p = out.data() + old;
  *p++ = '"';
  p = escape_json(p, s, n);
  *p++ = '"';
  out.resize(static_cast<std::size_t>(p - out.data()));
}

void append_json_value(std::string& out, const FieldValue& value) {
  if (const auto* i = std::get_if<std::int64_t>(&value)) {
    char buf[24];
    out.append(buf, static_cast<std::size_t>(std::to_chars(buf, buf + sizeof buf, *i).ptr - buf));
  } else if (const auto* d = std::get_if<double>(&value)) {
    if (!std::isfinite(*d)) {
      out += "null";  // JSON has no NaN or infinity (GDAL writes null too by default)
      return;
    }
    char buf[kMaxRealChars];
    out.append(buf, static_cast<std::size_t>(format_real(buf, *d) - buf));
  } else if (const auto* s = std::get_if<std::string>(&value)) {
    append_json_string(out, *s);
  } else {
    out += "null";
  }
}

std::string geometry_problem(const Geometry& geometry) {
  if (const auto* p = std::get_if<LonLat>(&geometry)) return position_problem(*p);
  if (const auto* lines = std::get_if<MultiLineString>(&geometry)) {
    for (const LineString& line : *lines) {
      if (line.size() < 2) {
        return "a line string has " + std::to_string(line.size()) + " positions, fewer than 2";
      }
      if (auto why = positions_problem(line); !why.empty()) return why;
    }
    return "";
  }
  for (const Polygon& poly : std::get<MultiPolygon>(geometry)) {
    if (auto why = ring_problem(poly.exterior); !why.empty()) return why;
    for (const Ring& hole : poly.holes) {
      if (auto why = ring_problem(hole); !why.empty()) return why;
    }
  }
  return "";
}

std::optional<BBox> geojson_bbox(const Geometry& geometry) {
  if (const auto* p = std::get_if<LonLat>(&geometry)) {
    return BBox{p->lon_deg, p->lat_deg, p->lon_deg, p->lat_deg};
  }
  // One longitude interval per part; latitudes over everything. The first part is kept aside
  // so that the common single-part geometry allocates nothing.
  Arc first{0, 0};
  std::size_t parts = 0;
  std::vector<Arc> arcs;
  double south = std::numeric_limits<double>::infinity();
  double north = -south;
  auto add_part = [&](const std::vector<LonLat>& ps) {
    if (ps.empty()) return;
    Arc arc{ps.front().lon_deg, ps.front().lon_deg};
    for (const LonLat& q : ps) {
      arc.west = std::min(arc.west, q.lon_deg);
      arc.east = std::max(arc.east, q.lon_deg);
      south = std::min(south, q.lat_deg);
      north = std::max(north, q.lat_deg);
    }
    if (++parts == 1) {
      first = arc;
    } else {
      if (parts == 2) arcs.push_back(first);
      arcs.push_back(arc);
    }
  };
  if (const auto* lines = std::get_if<MultiLineString>(&geometry)) {
    for (const LineString& line : *lines) add_part(line);
  } else {
    // Holes lie inside their exterior ring: the exterior alone gives the box.
    for (const Polygon& poly : std::get<MultiPolygon>(geometry)) add_part(poly.exterior);
  }
  if (parts == 0) return std::nullopt;
  if (parts == 1) return BBox{first.west, south, first.east, north};
  merge_arcs(arcs);
  BBox box{0, south, 0, north};
  smallest_arc(arcs, box.west, box.east);
  return box;
}

void BBoxUnion::add(const BBox& box) {
  if (empty_) {
    south_ = box.south;
    north_ = box.north;
    empty_ = false;
  } else {
    south_ = std::min(south_, box.south);
    north_ = std::max(north_, box.north);
  }
  if (box.west <= box.east) {
    add_interval(box.west, box.east);
  } else {  // crosses the antimeridian
    add_interval(box.west, 180.0);
    add_interval(-180.0, box.east);
  }
}

void BBoxUnion::add_interval(double west, double east) {
  // Inside a merged interval: the last one starting at or before `west`.
  const auto after = std::upper_bound(merged_.begin(), merged_.end(), west,
                                      [](double w, const Interval& i) { return w < i.west; });
  if (after != merged_.begin() && east <= std::prev(after)->east) return;
  intervals_.push_back({west, east});
  // Merged early (a tiling's boxes then soon fall inside), and at least as often as the merged
  // intervals' count allows for O(n log n) in all.
  if (intervals_.size() > std::max<std::size_t>(4096, merged_.size())) compact();
}

void BBoxUnion::compact() const {
  if (intervals_.empty()) return;
  std::vector<Arc> arcs;
  arcs.reserve(merged_.size() + intervals_.size());
  for (const Interval& i : merged_) arcs.push_back({i.west, i.east});
  for (const Interval& i : intervals_) arcs.push_back({i.west, i.east});
  merge_arcs(arcs);
  intervals_.clear();
  merged_.clear();
  for (const Arc& a : arcs) merged_.push_back({a.west, a.east});
}

std::optional<BBox> BBoxUnion::result() const {
  if (empty_) return std::nullopt;
  compact();
  std::vector<Arc> arcs;
  for (const Interval& i : merged_) arcs.push_back({i.west, i.east});
  BBox box{0, south_, 0, north_};
  smallest_arc(arcs, box.west, box.east);
  return box;
}

std::unique_ptr<FeatureWriter> open_geojson_writer(const std::string& path, GeoJsonFraming framing,
                                                   GeometryType geometry_type,
                                                   const std::vector<Field>& schema,
                                                   const WriterOptions& options) {
  return std::make_unique<GeoJsonWriter>(path, framing, geometry_type, schema, options);
}

}  // namespace geovor
