#include "geovor/io/geojson_writer.hpp"

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
#include <limits>
#include <system_error>
#include <type_traits>
#include <utility>

#include "geovor/core/copy_short.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/output_target.hpp"
#include "io/direct_output.hpp"

namespace geovor {
namespace {

GeometryType type_of(const Geometry& g) {
  return static_cast<GeometryType>(g.index());  // variant order = enum order
}
static_assert(std::is_same_v<std::variant_alternative_t<0, Geometry>, LonLat> &&
              std::is_same_v<std::variant_alternative_t<1, Geometry>, MultiLineString> &&
              std::is_same_v<std::variant_alternative_t<2, Geometry>, MultiPolygon>);
static_assert(static_cast<int>(GeometryType::Point) == 0 &&
              static_cast<int>(GeometryType::MultiLineString) == 1 &&
              static_cast<int>(GeometryType::MultiPolygon) == 2);

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
      json_.push_back(schema[i].json);
    }
  }

  void encode(const Geometry& geometry, std::span<const FieldValue> values, std::uint64_t number,
              EncodedFeatures& out) const override {
    const bool has_id = id_index_ >= 0 && static_cast<std::size_t>(id_index_) < values.size() &&
                        !std::holds_alternative<std::monostate>(values[id_index_]);
    std::size_t values_bound = 0;
    for (const FieldValue& v : values) values_bound += value_bound(v);
    if (has_id) values_bound += value_bound(values[id_index_]);
    encode_with(geometry, values.size(), number, out, has_id, values_bound, [&](char* p, std::size_t i) {
      // A JSON field's text is the value itself (a list), not a string.
      if (const auto* s = std::get_if<std::string>(&values[i]); s && i < json_.size() && json_[i]) {
        std::memcpy(p, s->data(), s->size());
        return p + s->size();
      }
      return put_json_value(p, values[i]);
    });
  }

  void encode_json(const Geometry& geometry, std::span<const std::string_view> json_values, std::uint64_t number,
                   EncodedFeatures& out) const override {
    const bool has_id = id_index_ >= 0 && static_cast<std::size_t>(id_index_) < json_values.size() &&
                        json_values[id_index_] != "null";
    std::size_t values_bound = 0;
    for (const std::string_view v : json_values) values_bound += v.size();
    if (has_id) values_bound += json_values[id_index_].size();
    encode_with(geometry, json_values.size(), number, out, has_id, values_bound,
                [&](char* p, std::size_t i) { return copy_short(p, json_values[i]); });
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
    // Coordinates are within [-180, 180] here (geometry_problem): coordinate_chars_bound.
    const std::size_t coordinate_chars = static_cast<std::size_t>(coordinate_chars_bound(precision_));
    t.resize(old_size + kFeatureFrameChars + keys_chars_ + values_bound + (4 * coordinate_chars + 8) +
             geometry_bound(geometry, 2 * coordinate_chars + 4));
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
      p = put(copy_short(p, keys_[i]), i);
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

  // Longest text put_geometry() writes for g, a position taking at most position_chars ([x,y],).
  static std::size_t geometry_bound(const Geometry& g, std::size_t position_chars) {
    constexpr std::size_t kHead = 48;  // {"type":"MultiLineString","coordinates":[ ... ]}
    if (std::holds_alternative<LonLat>(g)) return kHead + position_chars;
    std::size_t n = kHead;
    if (const auto* lines = std::get_if<MultiLineString>(&g)) {
      for (const LineString& line : *lines) n += 3 + line.size() * position_chars;
    } else {
      for (const Polygon& poly : std::get<MultiPolygon>(g)) {
        n += 3 + 3 + poly.exterior.size() * position_chars;
        for (const Ring& hole : poly.holes) n += 3 + hole.size() * position_chars;
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
      if (is_null_point(*pt)) return put_text(p, "null");
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
  std::vector<bool> json_;         // Field::json, by field
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
    if (!temp_.active()) out_.attach(file_, false);  // stdout, a device or a FIFO
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
    try {
      out_.finish();
    } catch (const DirectOutput::Failure& f) {
      fail("cannot write", f.err);
    }
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
    out_.attach(file_, true);
    out_.enable_direct();
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

  // Writes n bytes to the output; a failure fails the writer (the file is removed).
  void write_out(const char* data, std::size_t n) {
    try {
      out_.write(data, n);
    } catch (const DirectOutput::Failure& f) {
      fail(file_ == stdout ? "cannot write to stdout" : "cannot write", f.err);
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
  DirectOutput out_;  // file_'s bytes, through direct I/O for a temporary file
  bool finished_ = false;
  bool failed_ = false;
};

// Features as text handed to a sink (a response being built), in the file's framing.
class GeoJsonSinkWriter final : public FeatureWriter {
 public:
  GeoJsonSinkWriter(std::function<void(std::string_view)> sink, GeoJsonFraming framing, GeometryType geometry_type,
                    const std::vector<Field>& schema, const WriterOptions& options)
      : sink_(std::move(sink)), framing_(framing), encoder_("response", framing, geometry_type, schema, options) {
    if (framing_ == GeoJsonFraming::FeatureCollection) {
      std::string head = "{\"type\":\"FeatureCollection\",\"name\":";
      append_json_string(head, options.layer);
      sink_(head + ",\"features\":[\n");
    }
  }
  void write(const Geometry& geometry, std::span<const FieldValue> values) override {
    one_.clear();
    encoder_.encode(geometry, values, count_ + 1, one_);
    write_encoded(one_);
  }
  const FeatureEncoder* encoder() const override { return &encoder_; }
  void write_encoded(const EncodedFeatures& features) override {
    if (features.boxes.empty()) return;
    std::string_view text = features.text;
    if (framing_ == GeoJsonFraming::FeatureCollection && count_ == 0) text.remove_prefix(2);
    for (const std::optional<BBox>& box : features.boxes)
      if (box) extent_.add(*box);
    count_ += features.boxes.size();
    sink_(text);
  }
  void finish() override {
    if (finished_ || framing_ != GeoJsonFraming::FeatureCollection) return void(finished_ = true);
    std::string tail = count_ > 0 ? "\n]" : "]";
    if (const std::optional<BBox> box = extent_.result()) {
      tail += ",\"bbox\":";
      encoder_.put_bbox(tail, *box);
    }
    sink_(tail + "}\n");
    finished_ = true;
  }

 private:
  std::function<void(std::string_view)> sink_;
  GeoJsonFraming framing_;
  GeoJsonEncoder encoder_;
  EncodedFeatures one_;
  BBoxUnion extent_;
  std::uint64_t count_ = 0;
  bool finished_ = false;
};

}  // namespace

std::unique_ptr<FeatureWriter> open_geojson_writer(const std::string& path, GeoJsonFraming framing,
                                                   GeometryType geometry_type,
                                                   const std::vector<Field>& schema,
                                                   const WriterOptions& options) {
  return std::make_unique<GeoJsonWriter>(path, framing, geometry_type, schema, options);
}

}  // namespace geovor

namespace geovor {

std::unique_ptr<FeatureWriter> open_geojson_writer(std::function<void(std::string_view)> sink, GeoJsonFraming framing,
                                                   GeometryType geometry_type, const std::vector<Field>& schema,
                                                   const WriterOptions& options) {
  return std::make_unique<GeoJsonSinkWriter>(std::move(sink), framing, geometry_type, schema, options);
}

}  // namespace geovor
