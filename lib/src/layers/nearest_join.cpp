#include "geovor/layers/nearest_join.hpp"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/geo/query_line.hpp"
#include "geovor/geo/site_encoder.hpp"

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

// One parsed query of a batch.
struct Query {
  std::uint64_t line = 0;
  double lat = 0, lon = 0;
  std::string_view id;  // into the block, or into Worker::quoted_ids; null data(): the line number
  std::uint32_t first = 0, count = 0;  // its answers in Worker::results
};

// One block of whole lines: read, answered by one worker, written.
struct Block {
  std::vector<char> in;  // the lines are in[0, size)
  std::size_t size = 0;
  std::uint64_t first_line = 0;
  OutBuf out;
  std::vector<MalformedQuery> errors;
  std::uint64_t answered = 0;
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
  bool prepared = false;  // has the packed copy built in the background

  Worker(const DelaunayHierarchy& h, const LocatorOptions& o, const QueryFormat& f) : locator(h, o), parser(f) {}
};

struct Context {
  const SiteIndex* index = nullptr;
  const NearestJoinOptions* options = nullptr;
  QueryFormat format;
  // Each site's id, CSV-quoted when needed, ready to copy (one lookup per answer).
  std::vector<std::string_view> site_ids;
  std::string quoted_site_ids;  // storage of the quoted ones
};

bool needs_quotes(std::string_view s) { return s.find_first_of(",\"\r\n") != std::string_view::npos; }

void prepare_site_ids(Context& ctx) {
  const SiteAttributes& a = ctx.index->attributes;
  const std::size_t n = a.num_sites();
  std::size_t quoted_bytes = 0;
  for (SiteId s = 0; s < n; ++s) {
    const std::string_view id = a.site_id(s);
    if (needs_quotes(id)) quoted_bytes += 2 * id.size() + 2;
  }
  ctx.quoted_site_ids.reserve(quoted_bytes);  // never reallocated below: the views stay valid
  ctx.site_ids.resize(n);
  for (SiteId s = 0; s < n; ++s) {
    const std::string_view id = a.site_id(s);
    if (!needs_quotes(id)) {
      ctx.site_ids[s] = id;
      continue;
    }
    const std::size_t at = ctx.quoted_site_ids.size();
    ctx.quoted_site_ids.push_back('"');
    for (const char c : id) {
      if (c == '"') ctx.quoted_site_ids.push_back('"');
      ctx.quoted_site_ids.push_back(c);
    }
    ctx.quoted_site_ids.push_back('"');
    ctx.site_ids[s] = std::string_view(ctx.quoted_site_ids).substr(at);
  }
}

constexpr std::size_t kBatch = 256;

// Locates the batch's queries, then formats them (prefetching the site ids ahead: with sites in
// input order, an answer's id is rarely in cache).
void answer_batch(const Context& ctx, Worker& w, Block& b) {
  const NearestJoinOptions& o = *ctx.options;
  const bool geodesic = o.metric == Metric::Geodesic;
  w.results.clear();
  for (Query& q : w.batch) {
    q.first = static_cast<std::uint32_t>(w.results.size());
    if (o.k == 1) {
      w.results.push_back(geodesic ? w.locator.nearest_geodesic(q.lat, q.lon)
                                   : w.locator.nearest(SiteEncoder::from_lat_lon(q.lat, q.lon)));
    } else {
      k_nearest(w.locator, q.lat, q.lon, o.k, o.metric, w.k_results);
      w.results.insert(w.results.end(), w.k_results.begin(), w.k_results.end());
    }
    q.count = static_cast<std::uint32_t>(w.results.size() - q.first);
  }
  const std::size_t n = w.results.size();
  const std::string_view* ids = ctx.site_ids.data();
  for (std::size_t i = 0; i < n && i < 8; ++i) __builtin_prefetch(&ids[w.results[i].site]);
  std::size_t i = 0;
  for (const Query& q : w.batch) {
    char line_text[24];
    std::string_view qid = q.id;
    if (qid.data() == nullptr)
      qid = std::string_view(line_text, static_cast<std::size_t>(std::to_chars(line_text, line_text + 24, q.line).ptr - line_text));
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
      b.out.put('\n');
    }
  }
  b.answered += w.batch.size();
  w.batch.clear();
  w.quoted_ids.clear();
}

// Parses, locates and formats the lines of a block.
void answer_block(const Context& ctx, Worker& w, Block& b) {
  b.out.clear();
  b.errors.clear();
  b.answered = 0;
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
      b.errors.push_back({line_no, std::move(w.reason)});
      b.stopped = ctx.options->strict;
      continue;
    }
    Query q;
    q.line = line_no;
    q.lat = w.parsed.lat_deg;
    q.lon = w.parsed.lon_deg;
    q.id = w.parsed.id;
    if (w.parsed.id_quoted) {
      w.quoted_ids.emplace_back(q.id);  // the parser's buffer is reused by the next line
      q.id = w.quoted_ids.back();
    }
    w.batch.push_back(q);
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

}  // namespace

NearestJoinReport nearest_join(const SiteIndex& index, std::FILE* queries, const std::string& source,
                               const NearestJoinOptions& options,
                               const std::function<void(std::string_view)>& write,
                               const std::function<void(const MalformedQuery&)>& on_malformed) {
  Context ctx;
  ctx.index = &index;
  ctx.options = &options;
  prepare_site_ids(ctx);
  BlockReader reader(queries, source, options.block_bytes);
  if (const std::optional<std::string_view> first = reader.first_line()) {
    ctx.format = detect_query_format(*first, source);
    if (ctx.format.header) reader.skip_first_line();
  }
  write(options.rank_column ? "query_id,rank,site_index,site_id,distance_m\n" : "query_id,site_index,site_id,distance_m\n");

  const unsigned cores = thread_count(0);
  const unsigned threads = std::min(thread_count(options.threads), kMaxThreadsPerCore * cores);
  // With several workers the packed copy of the hierarchy (LocatorOptions::packed) is built by a
  // task beside them once the stream has shown it is long (rebuild_after queries, as a Locator
  // would), while they go on walking the hierarchy; each takes the copy at its next block. A
  // worker building it itself would keep the others waiting for it (DelaunayHierarchy::walk_graph()).
  const bool background = threads > 1 && options.locator.packed;
  LocatorOptions worker_options = options.locator;
  if (background) worker_options.rebuild_after = std::numeric_limits<std::uint64_t>::max();
  const std::uint64_t build_after =
      options.locator.rebuild_after > 0 ? options.locator.rebuild_after
                                        : std::max<std::uint64_t>(1024, index.hierarchy.base().num_sites() / 8);
  std::atomic<std::uint64_t> answered{0};
  std::atomic<bool> build_started{false}, built{false};
  std::unique_ptr<Locator> owner;  // holds the packed copy once built
  TaskGroup build;
  auto build_in_background = [&](std::uint64_t queries) {
    if (answered.fetch_add(queries, std::memory_order_relaxed) + queries < build_after) return;
    if (build_started.exchange(true)) return;
    build.run([&] {
      index.hierarchy.walk_graph(threads);  // on every core: the workers walk slowly meanwhile
      auto locator = std::make_unique<Locator>(index.hierarchy, options.locator);
      locator->prepare();
      owner = std::move(locator);
      built.store(true, std::memory_order_release);
    });
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
        if (background && !worker.prepared && built.load(std::memory_order_acquire)) {
          worker.locator.prepare();  // the copy `owner` holds: nothing is built
          worker.prepared = true;
        }
        answer_block(ctx, worker, b);
        if (b.stopped) stop.store(true, std::memory_order_relaxed);
        if (background) build_in_background(b.answered);
      },
      [&](Block& b) {
        if (report.stopped) return;  // blocks read after the stop
        write(b.out.view());
        report.answered += b.answered;
        report.malformed += b.errors.size();
        if (on_malformed)
          for (const MalformedQuery& m : b.errors) on_malformed(m);
        report.stopped = b.stopped;
      });
  build.wait();
  return report;
}

}  // namespace geovor
