#include "geovor/layers/nearest_join.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "geovor/core/ascii.hpp"
#include "geovor/core/default_init.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/geo/column_types.hpp"
#include "geovor/geo/query_line.hpp"
#include "geovor/layers/input_columns.hpp"

namespace geovor {
namespace {

// Output buffer with direct to_chars into its tail.
class OutBuf {
 public:
  char* reserve(std::size_t n) {
    if (buf_.size() - size_ < n) buf_.resize(std::max(buf_.size() * 2, size_ + n + 4096));
    return buf_.data() + size_;
  }
  void commit(char* end) { size_ = static_cast<std::size_t>(end - buf_.data()); }
  void put(char c) { *reserve(1) = c, ++size_; }
  void put(std::string_view s) {
    if (s.empty()) return;  // an empty view may have a null data(), which memcpy must not get
    std::memcpy(reserve(s.size()), s.data(), s.size());
    size_ += s.size();
  }
  template <typename T>
  void number(T v) {
    char* p = reserve(32);
    commit(std::to_chars(p, p + 32, v).ptr);
  }
  // A CSV field, quoted when it holds a comma, a quote or a line break.
  void field(std::string_view s) {
    if (s.find_first_of(",\"\r\n") == std::string_view::npos) return put(s);
    put('"');
    for (const char c : s) {
      if (c == '"') put('"');
      put(c);
    }
    put('"');
  }
  std::string_view view() const { return {buf_.data(), size_}; }
  void clear() { size_ = 0; }

 private:
  std::vector<char> buf_;
  std::size_t size_ = 0;
};

// One query of a batch: parsed, or malformed (then answered with an empty match).
struct Query {
  std::uint64_t line = 0;
  double lat = 0, lon = 0;
  std::string_view id;  // into the block, or into Worker::quoted_ids; null data(): the line number
  std::string_view text;  // the line as written (its fields, passed through), or null data(): empty fields
  bool malformed = false;
  std::uint32_t first = 0, count = 0;  // its answers in Worker::results (none: an empty match)
};

// One output row of the feature path: a query and its answers, owned (written on the calling thread).
struct FeatureRow {
  std::uint64_t line = 0;  // a stream's line
  LonLat point = kNullPoint;
  std::string query_id;
  std::vector<std::string> fields;  // the query's fields; empty when unknown (null)
  std::vector<NearestResult> results;
};

// One block of whole lines: read, answered by one worker, written.
struct Block {
  std::vector<char> in;  // the lines are in[0, size)
  std::size_t size = 0;
  std::uint64_t first_line = 0;
  OutBuf out;
  std::vector<FeatureRow> rows;  // the feature path's rows, instead of out
  std::vector<MalformedQuery> errors;
  std::uint64_t answered = 0, unmatched = 0;
  bool stopped = false;  // strict: stopped at its first malformed line
};

// One worker's state, kept from block to block.
struct Worker {
  Locator locator;
  QueryLineParser parser;
  QueryLine parsed;
  std::string reason;
  std::vector<Query> batch;
  std::vector<std::string> quoted_ids;  // ids of the batch that were quoted fields
  std::vector<NearestResult> results, k_results;
  std::vector<std::string_view> fields;  // a malformed line's fields
  std::string scratch;
  bool prepared = false;  // has taken the packed copy built for the workers (join_stream)

  Worker(const DelaunayHierarchy& h, const LocatorOptions& o, const QueryFormat& f) : locator(h, o), parser(f) {}
};

// A site's id text: a string_view without a constructor, so that the array of them is not written
// before prepare_site_ids() fills it on its threads (which touch its pages first).
struct IdText {
  const char* ptr;
  std::size_t len;
  IdText& operator=(std::string_view s) {
    ptr = s.data();
    len = s.size();
    return *this;
  }
  const char* data() const { return ptr; }
  operator std::string_view() const { return {ptr, len}; }
};

struct Context {
  const SiteIndex* index = nullptr;
  const NearestJoinOptions* options = nullptr;
  Metric metric = Metric::Sphere;  // options->metric, or the index's default
  QueryFormat format;
  bool features = false;  // rows as FeatureRow, not CSV text
  std::vector<FieldType> query_types;  // an OGR query layer's column types; empty: text
  bool declared = false;  // query_types are a stream's declared ones: each value checked
  std::string source;     // the stream's name, for a value not of its declared type
  // Each site's id, CSV-quoted when needed, ready to copy (one lookup per answer).
  std::vector<IdText, DefaultInitAllocator<IdText>> site_ids;
  std::string quoted_site_ids;  // storage of the quoted ones
  // The joined site fields: their columns, and each site's ",a,b" CSV text (empty without fields).
  std::vector<std::size_t> site_columns;
  std::vector<std::uint64_t> site_fields_at;  // site s: site_fields_text[at[s], at[s + 1])
  std::string site_fields_text;
  std::string empty_site_fields;   // ",,": the site fields of an empty match
  std::string empty_query_fields;  // ",,,": the query fields of a line whose fields are unknown

  std::string_view site_fields_csv(SiteId s) const {
    if (site_columns.empty()) return {};
    return std::string_view(site_fields_text).substr(site_fields_at[s], site_fields_at[s + 1] - site_fields_at[s]);
  }
};

bool needs_quotes(std::string_view s) { return s.find_first_of(",\"\r\n") != std::string_view::npos; }

void append_csv(std::string& out, std::string_view s) {
  if (!needs_quotes(s)) {
    out += s;
    return;
  }
  out.push_back('"');
  for (const char c : s) {
    if (c == '"') out.push_back('"');
    out.push_back(c);
  }
  out.push_back('"');
}

void prepare_site_ids(Context& ctx, unsigned threads) {
  const SiteAttributes& a = ctx.index->attributes;
  const std::size_t n = a.num_sites();
  const unsigned t = static_cast<unsigned>(std::min<std::size_t>(thread_count(threads), n / 65536 + 1));
  ctx.site_ids.resize(n);
  // The ids that need no quotes, on every thread; the others' quoted bytes counted by slice.
  std::vector<std::size_t> quoted_at(t + 1, 0);
  parallel_for(n, t, [&](unsigned slice, std::size_t begin, std::size_t end) {
    std::size_t bytes = 0;
    for (std::size_t s = begin; s < end; ++s) {
      const std::string_view id = a.site_id(static_cast<SiteId>(s));
      if (!needs_quotes(id)) {
        ctx.site_ids[s] = id;
        continue;
      }
      ctx.site_ids[s] = std::string_view{};  // quoted below (a site without rows keeps this empty id)
      bytes += id.size() + 2 + static_cast<std::size_t>(std::count(id.begin(), id.end(), '"'));
    }
    quoted_at[slice + 1] = bytes;
  });
  for (unsigned slice = 0; slice < t; ++slice) quoted_at[slice + 1] += quoted_at[slice];
  if (quoted_at[t] == 0) return;
  ctx.quoted_site_ids.resize(quoted_at[t]);  // never reallocated below: the views stay valid
  parallel_for(n, t, [&](unsigned slice, std::size_t begin, std::size_t end) {
    char* out = ctx.quoted_site_ids.data() + quoted_at[slice];
    for (std::size_t s = begin; s < end; ++s) {
      if (ctx.site_ids[s].data() != nullptr || !needs_quotes(a.site_id(static_cast<SiteId>(s)))) continue;
      const char* start = out;
      *out++ = '"';
      for (const char c : a.site_id(static_cast<SiteId>(s))) {
        if (c == '"') *out++ = '"';
        *out++ = c;
      }
      *out++ = '"';
      ctx.site_ids[s] = std::string_view(start, static_cast<std::size_t>(out - start));
    }
  });
}

// The index's columns of options.site_fields, or Error(InvalidArgument) naming the unknown one.
std::vector<std::size_t> site_columns(const SiteIndex& index, const NearestJoinOptions& options) {
  const SiteAttributes& a = index.attributes;
  std::vector<std::size_t> columns;
  for (const std::string& name : options.site_fields) {
    const int c = find_column(a.columns, name);
    if (c < 0) {
      std::string found;
      for (const auto& n : a.columns) found += (found.empty() ? "" : ", ") + n;
      throw Error(ErrorCode::InvalidArgument, "site field '" + name + "' is not a column of the sites (" + a.source +
                                                  ": " + found + ")");
    }
    columns.push_back(static_cast<std::size_t>(c));
  }
  return columns;
}

void prepare_site_fields(Context& ctx) {
  ctx.site_columns = site_columns(*ctx.index, *ctx.options);
  ctx.empty_site_fields.assign(ctx.site_columns.size(), ',');
  if (ctx.site_columns.empty() || ctx.features) return;
  const SiteAttributes& a = ctx.index->attributes;
  const std::size_t n = a.num_sites();
  ctx.site_fields_at.assign(n + 1, 0);
  for (SiteId s = 0; s < n; ++s) {
    ctx.site_fields_at[s] = ctx.site_fields_text.size();
    if (a.site_rows[s] == a.site_rows[s + 1]) continue;
    for (const std::size_t c : ctx.site_columns) {
      ctx.site_fields_text.push_back(',');
      append_csv(ctx.site_fields_text, a.field(a.site_rows[s], c));
    }
  }
  ctx.site_fields_at[n] = ctx.site_fields_text.size();
}

// The site's value of each joined field, for a feature.
void site_values(const Context& ctx, SiteId s, std::vector<FieldValue>& values) {
  const SiteAttributes& a = ctx.index->attributes;
  for (const std::size_t c : ctx.site_columns) {
    if (a.site_rows[s] == a.site_rows[s + 1]) {
      values.emplace_back(std::monostate{});
    } else {
      values.emplace_back(std::string(a.field(a.site_rows[s], c)));
    }
  }
}

// Writes a row's features: one per answer, or one with an empty match.
void write_feature_row(const Context& ctx, FeatureWriter& writer, const FeatureRow& row,
                       std::vector<FieldValue>& values) {
  const NearestJoinOptions& o = *ctx.options;
  const SiteAttributes& a = ctx.index->attributes;
  const std::size_t n = std::max<std::size_t>(row.results.size(), 1);
  for (std::size_t r = 0; r < n; ++r) {
    values.clear();
    values.emplace_back(row.query_id);
    const NearestResult* res = r < row.results.size() ? &row.results[r] : nullptr;
    if (o.rank_column) values.emplace_back(res ? FieldValue(static_cast<std::int64_t>(r + 1)) : FieldValue());
    values.emplace_back(res ? FieldValue(static_cast<std::int64_t>(res->site)) : FieldValue());
    values.emplace_back(res ? FieldValue(std::string(a.site_id(res->site))) : FieldValue());
    values.emplace_back(res ? FieldValue(res->dist_m) : FieldValue());
    for (std::size_t i = 0; i < ctx.format.columns.size(); ++i) {
      if (i >= row.fields.size() || i >= ctx.query_types.size()) {
        values.emplace_back(i >= row.fields.size() ? FieldValue() : FieldValue(row.fields[i]));
      } else if (ctx.declared) {
        const std::optional<std::string> v = declared_value(ctx.query_types[i], row.fields[i]);
        if (!v)
          throw Error(ErrorCode::BadData, ctx.source + ": line " + std::to_string(row.line) + ", column '" +
                                              ctx.format.columns[i] + "': " +
                                              not_of_declared_type(ctx.query_types[i], row.fields[i]));
        values.emplace_back(typed_value(ctx.query_types[i], *v));
      } else {
        values.emplace_back(typed_value(ctx.query_types[i], row.fields[i]));
      }
    }
    if (res) {
      site_values(ctx, res->site, values);
    } else {
      values.resize(values.size() + ctx.site_columns.size());
    }
    writer.write(row.point, values);
  }
}

constexpr std::size_t kBatch = 256;

// Locates one query into w.results: its answers within max_distance_m, nearest first.
void locate(const NearestJoinOptions& o, Metric metric, Worker& w, double lat, double lon) {
  nearest_within(w.locator, lat, lon, o.k, metric, o.max_distance_m, w.k_results);
  w.results.insert(w.results.end(), w.k_results.begin(), w.k_results.end());
}

// The feature rows of a batch.
void batch_features(const Context& ctx, Worker& w, Block& b) {
  std::string scratch;
  std::vector<std::string_view> fields;
  for (const Query& q : w.batch) {
    FeatureRow& row = b.rows.emplace_back();
    row.line = q.line;
    if (!q.malformed) row.point = {q.lon, q.lat};
    row.query_id = q.id.data() ? std::string(q.id) : std::to_string(q.line);
    if (ctx.format.header && q.text.data() && !*split_query_fields(q.text, fields, scratch))
      for (const std::string_view f : fields) row.fields.emplace_back(f);
    row.results.assign(w.results.begin() + q.first, w.results.begin() + q.first + q.count);
  }
}

// Locates the batch's queries, then formats them (prefetching the site ids ahead: with sites in
// input order, an answer's id is rarely in cache).
void answer_batch(const Context& ctx, Worker& w, Block& b) {
  const NearestJoinOptions& o = *ctx.options;
  w.results.clear();
  for (Query& q : w.batch) {
    q.first = static_cast<std::uint32_t>(w.results.size());
    if (!q.malformed) locate(o, ctx.metric, w, q.lat, q.lon);
    q.count = static_cast<std::uint32_t>(w.results.size() - q.first);
    if (q.count == 0 && !q.malformed) ++b.unmatched;
    if (!q.malformed) ++b.answered;
  }
  if (ctx.features) {
    batch_features(ctx, w, b);
  } else {
    const bool header = ctx.format.header;
    const std::string_view empty_match = o.rank_column ? ",,,," : ",,,";
    const std::size_t n = w.results.size();
    const IdText* ids = ctx.site_ids.data();
    for (std::size_t i = 0; i < n && i < 8; ++i) __builtin_prefetch(&ids[w.results[i].site]);
    std::size_t i = 0;
    for (const Query& q : w.batch) {
      char line_text[24];
      std::string_view qid = q.id;
      if (qid.data() == nullptr)
        qid = std::string_view(line_text, static_cast<std::size_t>(std::to_chars(line_text, line_text + 24, q.line).ptr - line_text));
      if (q.count == 0) {
        b.out.field(qid);
        b.out.put(empty_match);
        if (header) {
          if (q.text.data()) {
            b.out.put(',');
            b.out.put(q.text);
          } else {
            b.out.put(ctx.empty_query_fields);
          }
        }
        b.out.put(ctx.empty_site_fields);
        b.out.put('\n');
        continue;
      }
      for (std::uint32_t r = 0; r < q.count; ++r, ++i) {
        if (i + 8 < n) __builtin_prefetch(&ids[w.results[i + 8].site]);
        if (i + 4 < n) __builtin_prefetch(ids[w.results[i + 4].site].data());
        const NearestResult& res = w.results[i];
        b.out.field(qid);
        b.out.put(',');
        if (o.rank_column) {
          b.out.number(r + 1);
          b.out.put(',');
        }
        b.out.number(res.site);
        b.out.put(',');
        b.out.put(ids[res.site]);
        b.out.put(',');
        b.out.number(res.dist_m);
        if (header) {
          b.out.put(',');
          b.out.put(q.text);
        }
        b.out.put(ctx.site_fields_csv(res.site));
        b.out.put('\n');
      }
    }
  }
  w.batch.clear();
  w.quoted_ids.clear();
}

// A malformed line's query: its id when its fields split into the format's count, and its
// fields as written when they are the header's.
Query malformed_query(const Context& ctx, Worker& w, std::string_view line, std::uint64_t line_no) {
  Query q;
  q.line = line_no;
  q.malformed = true;
  const QueryFormat& f = ctx.format;
  if (*split_query_fields(line, w.fields, w.scratch)) return q;
  const std::size_t nf = w.fields.size();
  if (f.header ? nf != f.fields : nf != 2 && nf != 3) return q;
  if (f.header) q.text = line;
  const int id_col = f.header ? f.id : (nf == 3 ? 2 : -1);
  if (id_col >= 0) {
    w.quoted_ids.emplace_back(w.fields[static_cast<std::size_t>(id_col)]);
    q.id = w.quoted_ids.back();
    if (q.id.data() == nullptr) q.id = std::string_view(line.data(), 0);
  }
  return q;
}

// Parses, locates and formats the lines of a block.
void answer_block(const Context& ctx, Worker& w, Block& b) {
  b.out.clear();
  b.rows.clear();
  b.errors.clear();
  b.answered = b.unmatched = 0;
  b.stopped = false;
  w.batch.clear();
  w.quoted_ids.clear();
  w.quoted_ids.reserve(kBatch);  // never reallocated within a batch: the views stay valid
  const char* const end = b.in.data() + b.size;
  std::uint64_t line_no = b.first_line;
  for (const char* p = b.in.data(); p < end && !b.stopped; ++line_no) {
    const char* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    const char* line_end = nl ? nl : end;
    std::string_view line(p, static_cast<std::size_t>(line_end - p));
    p = nl ? nl + 1 : end;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) continue;
    if (!w.parser.parse(line, w.parsed, w.reason)) {
      b.errors.push_back({line_no, 0, std::move(w.reason)});
      b.stopped = ctx.options->strict;
      if (!b.stopped) w.batch.push_back(malformed_query(ctx, w, line, line_no));
    } else {
      Query q;
      q.line = line_no;
      q.lat = w.parsed.lat_deg;
      q.lon = w.parsed.lon_deg;
      q.id = w.parsed.id;
      q.text = line;
      if (w.parsed.id_quoted) {
        w.quoted_ids.emplace_back(q.id);  // the parser's buffer is reused by the next line
        q.id = w.quoted_ids.back();
      }
      w.batch.push_back(q);
    }
    if (w.batch.size() == kBatch) answer_batch(ctx, w, b);
  }
  if (!w.batch.empty()) answer_batch(ctx, w, b);
}

// Reads the stream in blocks of whole lines (the last one may lack its line end), numbering them.
class BlockReader {
 public:
  BlockReader(std::FILE* in, const std::string& name, std::size_t block_bytes)
      : in_(in), name_(name), block_bytes_(std::max<std::size_t>(block_bytes, 1)) {}

  // The first line (line end excluded, a UTF-8 byte order mark skipped), not consumed; nullopt
  // for an empty stream. Call before next().
  std::optional<std::string_view> first_line() {
    fill(pending_, pending_size_);
    if (pending_size_ >= 3 && std::memcmp(pending_.data(), "\xEF\xBB\xBF", 3) == 0) skip_ = 3;
    if (pending_size_ == skip_) return std::nullopt;
    const std::string_view rest(pending_.data() + skip_, pending_size_ - skip_);
    return rest.substr(0, rest.find('\n'));
  }
  // Consumes the first line (after first_line()).
  void skip_first_line() {
    const std::string_view rest(pending_.data() + skip_, pending_size_ - skip_);
    const std::size_t nl = rest.find('\n');
    skip_ += nl == std::string_view::npos ? rest.size() : nl + 1;
    ++line_no_;
  }
  // Fills `b` with the next block; false at the end of the stream.
  bool next(Block& b) {
    // The bytes read ahead (a partial line, or the first block) start the block.
    b.in.resize(std::max(block_bytes_, pending_size_ - skip_));
    std::memcpy(b.in.data(), pending_.data() + skip_, pending_size_ - skip_);
    std::size_t size = pending_size_ - skip_;
    pending_size_ = skip_ = 0;
    fill(b.in, size);
    std::size_t cut = size;
    if (!eof_) {  // fill() left a line end in the buffer
      while (b.in[cut - 1] != '\n') --cut;
    }
    pending_.resize(std::max(pending_.size(), size - cut));
    std::memcpy(pending_.data(), b.in.data() + cut, size - cut);
    pending_size_ = size - cut;
    b.size = cut;
    b.first_line = line_no_;
    line_no_ += static_cast<std::uint64_t>(std::count(b.in.data(), b.in.data() + cut, '\n'));
    return cut > 0;
  }

 private:
  // Reads into buf after its first `size` bytes until it is full (grown while it holds no line
  // end) or the stream ends.
  void fill(std::vector<char>& buf, std::size_t& size) {
    if (buf.size() < block_bytes_) buf.resize(block_bytes_);
    for (;;) {
      if (!eof_ && size < buf.size()) {
        const std::size_t want = buf.size() - size;
        const std::size_t got = std::fread(buf.data() + size, 1, want, in_);
        size += got;
        if (got < want) {
          if (std::ferror(in_)) throw Error(ErrorCode::Io, name_ + ": read error: " + std::strerror(errno));
          eof_ = true;
        }
      }
      if (eof_ || std::memchr(buf.data(), '\n', size) != nullptr) return;
      buf.resize(buf.size() * 2);
    }
  }

  std::FILE* in_;
  std::string name_;
  std::size_t block_bytes_;
  std::vector<char> pending_;  // read ahead: [skip_, pending_size_)
  std::size_t pending_size_ = 0, skip_ = 0;
  std::uint64_t line_no_ = 1;  // of the next line
  bool eof_ = false;
};

// More threads than this per core only queue for the cores, each holding blocks in memory.
constexpr unsigned kMaxThreadsPerCore = 4;

// The join's field names (the header's comment): own fields, query columns, site fields.
std::vector<std::string> field_names(const SiteIndex& index, const std::vector<std::string>& query_columns,
                                     const NearestJoinOptions& options, const std::vector<std::size_t>& site_cols) {
  std::vector<std::string> names = {"query_id"};
  if (options.rank_column) names.push_back("rank");
  for (const char* n : {"site_index", "site_id", "distance_m"}) names.push_back(n);
  auto add = [&](std::string name, const char* prefix) {
    auto taken = [&](const std::string& n) {
      return std::any_of(names.begin(), names.end(), [&](const std::string& m) { return ascii_iequals(m, n); });
    };
    while (taken(name)) name = prefix + name;
    names.push_back(std::move(name));
  };
  for (std::size_t c = 0; c < query_columns.size(); ++c)
    add(query_columns[c].empty() ? "field_" + std::to_string(c + 1) : query_columns[c], "src_");
  for (const std::size_t c : site_cols) add(index.attributes.columns[c], "site_");
  return names;
}

// query_types: the query columns' types (an OGR layer's), or empty (CSV text: String).
std::vector<Field> fields_of(const std::vector<std::string>& names, bool rank,
                             const std::vector<FieldType>& query_types = {}) {
  std::vector<Field> fields;
  const std::size_t first_query = rank ? 5 : 4;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::size_t own = i - (rank ? 1 : 0);
    FieldType t = FieldType::String;
    if ((rank && i == 1) || own == 1) t = FieldType::Integer64;
    if (own == 3) t = FieldType::Real;
    if (i >= first_query && i - first_query < query_types.size()) t = query_types[i - first_query];
    fields.push_back({names[i], t});
  }
  return fields;
}

// The CSV header line of the join.
std::string csv_header(const std::vector<std::string>& names) {
  std::string h;
  for (const std::string& n : names) {
    if (!h.empty()) h.push_back(',');
    append_csv(h, n);
  }
  h.push_back('\n');
  return h;
}

// Where a stream's rows go: CSV text, or features.
struct Sink {
  const std::function<void(std::string_view)>* write = nullptr;
  const OpenJoinWriter* open = nullptr;
  std::unique_ptr<FeatureWriter> writer;
  std::vector<FieldValue> values;
};

// The stream's declared column types (NearestJoinOptions::query_field_types) into ctx.
void declare_query_types(Context& ctx, const std::string& source) {
  if (!ctx.features)
    throw Error(ErrorCode::InvalidArgument, "--query-field-type types the query columns of point features (GeoPackage, "
                                            "FlatGeobuf, ...); geovor's CSV output has no types");
  const std::vector<std::string>& columns = ctx.format.columns;
  ctx.query_types.assign(columns.size(), FieldType::String);
  for (const FieldTypeOverride& d : ctx.options->query_field_types) {
    const int c = find_column(columns, d.column);
    if (c < 0) {
      std::string list;
      for (const std::string& n : columns) list += (list.empty() ? "" : ", ") + n;
      throw Error(ErrorCode::InvalidArgument, source + ": --query-field-type names '" + d.column +
                                                  "', which is no column of the queries" + did_you_mean(columns, d.column) + " (" +
                                                  (columns.empty() ? std::string("the stream has no header") : "columns: " + list) + ")");
    }
    ctx.query_types[static_cast<std::size_t>(c)] = d.type;
  }
  ctx.declared = true;
  ctx.source = source;
}

// The metric asked, or the index's; an error where it does not apply to the index's sites.
Metric join_metric(const SiteIndex& index, const NearestJoinOptions& options) {
  const Metric metric = options.metric.value_or(default_metric(index.hierarchy));
  check_metric(index.hierarchy, metric);
  return metric;
}

NearestJoinReport join_stream(const SiteIndex& index, std::FILE* queries, const std::string& source,
                              const NearestJoinOptions& options, Sink& sink,
                              const std::function<void(const MalformedQuery&)>& on_malformed) {
  Context ctx;
  ctx.index = &index;
  ctx.options = &options;
  ctx.metric = join_metric(index, options);
  ctx.features = sink.open != nullptr;
  const unsigned cores = thread_count(0);
  const unsigned threads = std::min(thread_count(options.threads), kMaxThreadsPerCore * cores);
  prepare_site_fields(ctx);  // an unknown site field before anything is read
  if (!ctx.features) prepare_site_ids(ctx, threads);
  BlockReader reader(queries, source, options.block_bytes);
  if (const std::optional<std::string_view> first = reader.first_line()) {
    ctx.format = detect_query_format(*first, source, options.columns);
    if (ctx.format.header) reader.skip_first_line();
  }
  ctx.empty_query_fields.assign(ctx.format.header ? ctx.format.fields : 0, ',');
  const std::vector<std::string> names = field_names(index, ctx.format.columns, options, ctx.site_columns);
  if (!options.query_field_types.empty()) declare_query_types(ctx, source);
  if (ctx.features)
    sink.writer = (*sink.open)(fields_of(names, options.rank_column, ctx.query_types));
  else
    (*sink.write)(csv_header(names));

  // With several workers the packed copy of the hierarchy (LocatorOptions::packed) is built once the
  // stream has shown it is long (rebuild_after queries, as a Locator would): the first worker to
  // start a block after that builds it on every core (DelaunayHierarchy::walk_graph(threads)) and
  // the others wait for it at their next block. Walking the hierarchy meanwhile, as they did, took
  // the cores from the build at a fraction of the packed copy's speed (docs/design.md).
  const bool shared_build = threads > 1 && options.locator.packed;
  LocatorOptions worker_options = options.locator;
  if (shared_build) worker_options.rebuild_after = std::numeric_limits<std::uint64_t>::max();
  const std::uint64_t build_after =
      options.locator.rebuild_after > 0 ? options.locator.rebuild_after
                                        : std::max<std::uint64_t>(1024, index.hierarchy.base().num_sites() / 8);
  std::atomic<std::uint64_t> answered{0};
  std::atomic<bool> build_due{false};
  std::once_flag built;
  auto take_packed_copy = [&](Worker& worker) {
    std::call_once(built, [&] { index.hierarchy.walk_graph(std::min(threads, cores)); });  // the others wait
    worker.locator.prepare();  // the copy just built: nothing is built
    worker.prepared = true;
  };

  std::vector<std::unique_ptr<Worker>> workers(threads);  // made by their own thread, at first use
  std::atomic<bool> stop{false};  // a strict stop: read no further
  NearestJoinReport report;
  ordered_pipeline<Block>(
      threads, 2 * std::size_t{threads},
      [&](Block& b) { return !stop.load(std::memory_order_relaxed) && reader.next(b); },
      [&](Block& b, unsigned w) {
        if (!workers[w]) workers[w] = std::make_unique<Worker>(index.hierarchy, worker_options, ctx.format);
        Worker& worker = *workers[w];
        if (shared_build && !worker.prepared && build_due.load(std::memory_order_relaxed)) take_packed_copy(worker);
        answer_block(ctx, worker, b);
        if (b.stopped) stop.store(true, std::memory_order_relaxed);
        if (shared_build && answered.fetch_add(b.answered, std::memory_order_relaxed) + b.answered >= build_after)
          build_due.store(true, std::memory_order_relaxed);
      },
      [&](Block& b) {
        if (report.stopped) return;  // blocks read after the stop
        if (ctx.features) {
          for (const FeatureRow& row : b.rows) write_feature_row(ctx, *sink.writer, row, sink.values);
        } else {
          (*sink.write)(b.out.view());
        }
        report.answered += b.answered;
        report.unmatched += b.unmatched;
        report.malformed += b.errors.size();
        if (on_malformed)
          for (const MalformedQuery& m : b.errors) on_malformed(m);
        report.stopped = b.stopped;
      });
  if (sink.writer) sink.writer->finish();
  return report;
}

// The join of a table of queries, row by row on the calling thread.
NearestJoinReport join_table(const SiteIndex& index, const SiteTable& queries, const NearestJoinOptions& options,
                             Sink& sink, const std::function<void(const MalformedQuery&)>& on_malformed) {
  if (!options.query_field_types.empty())
    throw Error(ErrorCode::InvalidArgument, queries.source + ": a table of queries keeps its own column types; declare "
                                                             "them when reading it (SiteReaderOptions::field_types)");
  Context ctx;
  ctx.index = &index;
  ctx.options = &options;
  ctx.metric = join_metric(index, options);
  ctx.features = true;  // rows are made as FeatureRow; CSV text is made from them below
  prepare_site_fields(ctx);
  ctx.format.header = true;
  ctx.format.columns = queries.columns;
  ctx.format.fields = queries.columns.size();
  const std::vector<std::string> names = field_names(index, ctx.format.columns, options, ctx.site_columns);
  if (sink.open) {
    ctx.query_types = queries.column_types;  // an OGR layer's types carry over to the features
    sink.writer = (*sink.open)(fields_of(names, options.rank_column, ctx.query_types));
  } else {
    (*sink.write)(csv_header(names));
  }
  const int query_id_column = options.columns.id_field.empty() ? find_column(queries.columns, "query_id") : -1;
  Worker w(index.hierarchy, options.locator, ctx.format);
  NearestJoinReport report;
  std::string text;
  auto emit = [&](const FeatureRow& row) {
    if (sink.writer) return write_feature_row(ctx, *sink.writer, row, sink.values);
    const SiteAttributes& a = index.attributes;
    const std::size_t n = std::max<std::size_t>(row.results.size(), 1);
    for (std::size_t r = 0; r < n; ++r) {
      text.clear();
      const NearestResult* res = r < row.results.size() ? &row.results[r] : nullptr;
      append_csv(text, row.query_id);
      char d[32];
      auto number = [&](auto v) {
        text.push_back(',');
        text.append(d, static_cast<std::size_t>(std::to_chars(d, d + 32, v).ptr - d));
      };
      if (options.rank_column) {
        if (res) number(r + 1);
        else text.push_back(',');
      }
      if (res) {
        number(res->site);
        text.push_back(',');
        append_csv(text, a.site_id(res->site));
        number(res->dist_m);
      } else {
        text += ",,,";
      }
      for (std::size_t c = 0; c < ctx.format.fields; ++c) {
        text.push_back(',');
        if (c < row.fields.size()) append_csv(text, row.fields[c]);
      }
      for (const std::size_t c : ctx.site_columns) {
        text.push_back(',');
        if (res && a.site_rows[res->site] != a.site_rows[res->site + 1]) append_csv(text, a.field(a.site_rows[res->site], c));
      }
      text.push_back('\n');
      (*sink.write)(text);
    }
  };
  std::size_t si = 0, ri = 0;
  while (si < queries.sites.size() || ri < queries.rejected.size()) {
    FeatureRow row;
    if (ri == queries.rejected.size() || (si < queries.sites.size() && queries.sites[si].row < queries.rejected[ri].row)) {
      const InputSite& q = queries.sites[si++];
      row.point = {q.lon_deg, q.lat_deg};
      row.query_id = query_id_column >= 0 ? q.fields[static_cast<std::size_t>(query_id_column)] : q.id;
      row.fields = q.fields;
      w.results.clear();
      locate(options, ctx.metric, w, q.lat_deg, q.lon_deg);
      row.results = w.results;
      ++report.answered;
      if (row.results.empty()) ++report.unmatched;
    } else {
      const RejectedRow& q = queries.rejected[ri++];
      const MalformedQuery m{q.line, q.row, q.reason};
      ++report.malformed;
      if (on_malformed) on_malformed(m);
      if (options.strict) {
        report.stopped = true;
        break;
      }
      row.query_id = std::to_string(q.row);
    }
    emit(row);
  }
  if (sink.writer) sink.writer->finish();
  return report;
}

}  // namespace

std::vector<Field> nearest_join_fields(const SiteIndex& index, const std::vector<std::string>& query_columns,
                                       const NearestJoinOptions& options) {
  join_metric(index, options);
  return fields_of(field_names(index, query_columns, options, site_columns(index, options)), options.rank_column);
}

NearestJoinReport nearest_join(const SiteIndex& index, std::FILE* queries, const std::string& source,
                               const NearestJoinOptions& options,
                               const std::function<void(std::string_view)>& write,
                               const std::function<void(const MalformedQuery&)>& on_malformed) {
  Sink sink;
  sink.write = &write;
  return join_stream(index, queries, source, options, sink, on_malformed);
}

NearestJoinReport nearest_join(const SiteIndex& index, std::FILE* queries, const std::string& source,
                               const NearestJoinOptions& options, const OpenJoinWriter& open,
                               const std::function<void(const MalformedQuery&)>& on_malformed) {
  Sink sink;
  sink.open = &open;
  return join_stream(index, queries, source, options, sink, on_malformed);
}

NearestJoinReport nearest_join(const SiteIndex& index, const SiteTable& queries, const NearestJoinOptions& options,
                               const std::function<void(std::string_view)>& write,
                               const std::function<void(const MalformedQuery&)>& on_malformed) {
  Sink sink;
  sink.write = &write;
  return join_table(index, queries, options, sink, on_malformed);
}

NearestJoinReport nearest_join(const SiteIndex& index, const SiteTable& queries, const NearestJoinOptions& options,
                               const OpenJoinWriter& open,
                               const std::function<void(const MalformedQuery&)>& on_malformed) {
  Sink sink;
  sink.open = &open;
  return join_table(index, queries, options, sink, on_malformed);
}

}  // namespace geovor
