// geovor nearest --sites SITES [--queries FILE|-]: the exact nearest site (or k nearest) of every
// query of a CSV stream, streamed in blocks (memory constant in the number of queries), split
// over threads with the order kept.
//
// Throughput is the point: queries are read in 4 MiB blocks with fread, split at line ends,
// parsed with std::from_chars, located by one Locator per thread (kept from block to block, so
// the landmarks of Keep, Jump & Climb stay warm), formatted with std::to_chars into one buffer
// per thread and written with one fwrite each, in order.
#include <sys/stat.h>

#include <algorithm>
#include <charconv>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Geodesic.hpp>

#include "commands.hpp"
#include "geovor/core/error.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/query_line.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/locate/index_file.hpp"
#include "geovor/locate/locator.hpp"
#include "output_file.hpp"
#include "site_input.hpp"

namespace geovor::tools {
namespace {

struct NearestArgs {
  SiteInputArgs sites;
  std::vector<CLI::Option*> site_options;  // the table-only options, refused with an index
  std::string queries = "-";
  std::string output = "-";
  bool overwrite = false;
  std::string locator = "keep-jump-climb";
  std::size_t k = 1;
  CLI::Option* k_option = nullptr;
  std::string metric = "sphere";
  int threads = 1;
  bool strict = false;
};

constexpr std::size_t kBlockBytes = std::size_t{4} << 20;

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f != stdin && f != stdout) std::fclose(f);
  }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

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
  std::size_t size() const { return size_; }
  void truncate(std::size_t n) { size_ = n; }

 private:
  std::vector<char> buf_;
  std::size_t size_ = 0;
};

// One parsed query of a batch.
struct Query {
  std::uint64_t line = 0;
  double lat = 0, lon = 0;
  Vec3 q;
  std::string_view id;  // into the block, or into Worker::quoted_ids; empty: the line number
  std::uint32_t first = 0, count = 0;  // its answers in Worker::results
};

// One thread's part of a block, and its state kept from block to block.
struct Worker {
  Locator locator;
  QueryLineParser parser;
  QueryLine parsed;
  std::string reason;
  std::vector<Query> batch;
  std::vector<std::string> quoted_ids;  // ids of the batch that were quoted fields
  std::vector<NearestResult> results, k_results;
  OutBuf out;
  std::vector<std::pair<std::uint64_t, std::string>> errors;  // line, reason
  std::uint64_t answered = 0;
  bool stopped = false;  // --strict: stopped at the first malformed line

  Worker(const DelaunayHierarchy& h, const LocatorOptions& o, const QueryFormat& f) : locator(h, o), parser(f) {}
};

struct Context {
  const SiteIndex* index = nullptr;
  /// Each site's id, CSV-quoted when needed, ready to copy (one lookup per answer).
  std::vector<std::string_view> site_ids;
  std::string quoted_site_ids;  // storage of the quoted ones
  QueryFormat format;
  std::size_t k = 1;
  bool rank = false;  // --k given: a rank column
  bool geodesic = false;
  bool strict = false;
};

bool needs_quotes(std::string_view s) { return s.find_first_of(",\"\r\n") != std::string_view::npos; }

void quote_into(std::string& out, std::string_view s) {
  out.push_back('"');
  for (const char c : s) {
    if (c == '"') out.push_back('"');
    out.push_back(c);
  }
  out.push_back('"');
}

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
    quote_into(ctx.quoted_site_ids, id);
    ctx.site_ids[s] = std::string_view(ctx.quoted_site_ids).substr(at);
  }
}

// The k nearest sites by WGS84 geodesic distance (GeographicLib), ties to the lower id: the k'
// spherically nearest (k' = 2k, doubled while needed), until the lower bound 2 b sin(angle / 2)
// of every site not yet seen (as Locator::nearest_geodesic) exceeds the k-th geodesic distance.
void k_nearest_geodesic(Locator& locator, const SphericalDelaunay& base, double lat, double lon, const Vec3& q,
                        std::size_t k, std::vector<NearestResult>& out) {
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  const double b = GeographicLib::Constants::WGS84_a() * (1 - GeographicLib::Constants::WGS84_f());
  auto before = [](const NearestResult& x, const NearestResult& y) {
    return x.dist_m < y.dist_m || (x.dist_m == y.dist_m && x.site < y.site);
  };
  for (std::size_t want = 2 * k;; want *= 2) {
    std::vector<NearestResult> cand = locator.k_nearest(q, want);
    double last_angle = 0;
    for (NearestResult& c : cand) {
      const Vec3& p = base.site(c.site);
      last_angle = std::atan2(std::sqrt(norm2(cross(q, p))), dot(q, p));
      const LatLon ll = SiteEncoder::to_lat_lon(p);
      geod.Inverse(lat, lon, ll.lat_deg, ll.lon_deg, c.dist_m);
    }
    const std::size_t keep = std::min(k, cand.size());
    std::partial_sort(cand.begin(), cand.begin() + keep, cand.end(), before);
    const double lower_m = 2 * b * std::sin(last_angle / 2) * (1 - 1e-12) - 1e-6;
    if (cand.size() < want || keep == 0 || lower_m > cand[keep - 1].dist_m) {
      out.assign(cand.begin(), cand.begin() + keep);
      return;
    }
  }
}

constexpr std::size_t kBatch = 256;

// Locates the batch's queries, then formats them (prefetching the site ids ahead: with sites in
// input order, an answer's id is rarely in cache).
void answer_batch(const Context& ctx, Worker& w) {
  const SphericalDelaunay& base = ctx.index->hierarchy.base();
  w.results.clear();
  for (Query& q : w.batch) {
    q.first = static_cast<std::uint32_t>(w.results.size());
    if (ctx.k == 1) {
      w.results.push_back(ctx.geodesic ? w.locator.nearest_geodesic(q.lat, q.lon) : w.locator.nearest(q.q));
    } else {
      if (ctx.geodesic)
        k_nearest_geodesic(w.locator, base, q.lat, q.lon, q.q, ctx.k, w.k_results);
      else
        w.k_results = w.locator.k_nearest(q.q, ctx.k);
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
      w.out.field(qid);
      w.out.put(',');
      if (ctx.rank) {
        w.out.number(r + 1);
        w.out.put(',');
      }
      w.out.number(res.site);
      w.out.put(',');
      w.out.put(ids[res.site]);
      w.out.put(',');
      w.out.number(res.dist_m);
      w.out.put('\n');
    }
  }
  w.answered += w.batch.size();
  w.batch.clear();
  w.quoted_ids.clear();
}

// Parses, locates and formats the lines of [begin, end), the first being line `first_line`.
void process(const Context& ctx, Worker& w, const char* begin, const char* end, std::uint64_t first_line) {
  w.out.clear();
  w.errors.clear();
  w.answered = 0;
  w.stopped = false;
  w.batch.clear();
  w.quoted_ids.clear();
  w.quoted_ids.reserve(kBatch);  // never reallocated within a batch: the views stay valid
  std::uint64_t line_no = first_line;
  for (const char* p = begin; p < end && !w.stopped; ++line_no) {
    const char* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
    const char* line_end = nl ? nl : end;
    std::string_view line(p, static_cast<std::size_t>(line_end - p));
    p = nl ? nl + 1 : end;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) continue;
    auto reject = [&](std::string reason) {
      w.errors.emplace_back(line_no, std::move(reason));
      if (ctx.strict) w.stopped = true;
    };
    if (!w.parser.parse(line, w.parsed, w.reason)) {
      reject(std::move(w.reason));
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
    q.q = SiteEncoder::from_lat_lon(q.lat, q.lon);
    w.batch.push_back(q);
    if (w.batch.size() == kBatch) answer_batch(ctx, w);
  }
  if (!w.batch.empty()) answer_batch(ctx, w);
}

// Reads the query stream in blocks of whole lines (the last one may lack its line end).
class LineBlocks {
 public:
  LineBlocks(std::FILE* in, const std::string& name) : in_(in), name_(name), buf_(kBlockBytes) {}

  // The first line (line end excluded, a UTF-8 byte order mark skipped), not consumed; nullopt
  // for an empty stream.
  std::optional<std::string_view> first_line() {
    fill();
    if (size_ >= 3 && std::memcmp(buf_.data(), "\xEF\xBB\xBF", 3) == 0) done_ = 3;
    if (size_ == done_) return std::nullopt;
    const std::string_view rest(buf_.data() + done_, size_ - done_);
    return rest.substr(0, rest.find('\n'));
  }
  // Consumes the first line (after first_line()).
  void skip_first_line() {
    const std::string_view rest(buf_.data() + done_, size_ - done_);
    const std::size_t nl = rest.find('\n');
    done_ += nl == std::string_view::npos ? rest.size() : nl + 1;
  }
  // The next block of whole lines; empty at the end of the stream.
  std::string_view next() {
    fill();
    std::size_t last = size_;
    if (!eof_)
      while (data_end(last) != '\n') --last;  // fill() left a line end in the buffer
    const std::string_view block(buf_.data(), last);
    done_ = last;
    return block;
  }

 private:
  char data_end(std::size_t n) const { return buf_[n - 1]; }
  // Drops the consumed bytes, then reads until the buffer is full (grown while it holds no line
  // end) or the stream ends.
  void fill() {
    std::memmove(buf_.data(), buf_.data() + done_, size_ - done_);
    size_ -= done_;
    done_ = 0;
    for (;;) {
      if (!eof_ && size_ < buf_.size()) {
        const std::size_t want = buf_.size() - size_;
        const std::size_t got = std::fread(buf_.data() + size_, 1, want, in_);
        size_ += got;
        if (got < want) {
          if (std::ferror(in_)) throw Error(ErrorCode::Io, name_ + ": read error: " + std::strerror(errno));
          eof_ = true;
        }
      }
      if (eof_ || std::memchr(buf_.data(), '\n', size_) != nullptr) return;
      buf_.resize(buf_.size() * 2);
    }
  }

  std::FILE* in_;
  std::string name_;
  std::vector<char> buf_;
  std::size_t size_ = 0, done_ = 0;
  bool eof_ = false;
};

// Whether --sites names an index file (by its header, or a .gvi name) rather than a site table.
bool is_index_path(const std::string& path) {
  return path != "-" && (is_index_file(path) || (path.size() > 4 && path.ends_with(".gvi")));
}

int run(NearestArgs& args) {
  const std::string& sites_path = args.sites.input;
  if (args.queries == "-" && sites_path == "-")
    throw Error(ErrorCode::InvalidArgument, "--sites and --queries cannot both be standard input");
  if (args.k < 1) throw Error(ErrorCode::InvalidArgument, "--k must be at least 1");
  if (args.threads < 1) throw Error(ErrorCode::InvalidArgument, "--threads must be at least 1");
  if (args.metric != "sphere" && args.metric != "geodesic")
    throw Error(ErrorCode::InvalidArgument, "--metric must be sphere or geodesic, not '" + args.metric + "'");
  LocatorOptions locator_options;
  locator_options.strategy = parse_strategy(args.locator);
  struct stat st;
  if (args.output != "-" && !args.overwrite && stat(args.output.c_str(), &st) == 0 && S_ISREG(st.st_mode))
    throw Error(ErrorCode::Io, args.output + ": exists; use --overwrite to replace it");

  // The sites: an index file, or a table built here.
  const bool is_index = is_index_path(sites_path);
  SiteIndex index;
  if (is_index) {
    for (const CLI::Option* o : args.site_options)
      if (o->count() > 0)
        throw Error(ErrorCode::InvalidArgument, o->get_name() + " applies to a site table; " + sites_path +
                                                    " is an index (its columns were chosen by geovor index)");
    index = load_index(sites_path);
  } else {
    index = build_index_from_table(args.sites, nullptr);
  }

  // The streams.
  File in(args.queries == "-" ? stdin : std::fopen(args.queries.c_str(), "rb"));
  const std::string qname = args.queries == "-" ? "<stdin>" : args.queries;
  if (!in) throw Error(ErrorCode::Io, args.queries + ": cannot open: " + std::strerror(errno));
  OutputFile out(args.output, args.overwrite);  // a temporary file renamed by commit(): never half-written
  auto write = [&](std::string_view s) { out.write(s.data(), s.size()); };

  LineBlocks blocks(in.get(), qname);
  Context ctx;
  ctx.index = &index;
  ctx.k = args.k;
  ctx.rank = args.k_option->count() > 0;
  ctx.geodesic = args.metric == "geodesic";
  ctx.strict = args.strict;
  prepare_site_ids(ctx);
  const std::optional<std::string_view> first = blocks.first_line();
  std::uint64_t line_no = 1;  // of the next line to process
  if (first) ctx.format = detect_query_format(*first, qname);
  if (ctx.format.header) {
    blocks.skip_first_line();
    line_no = 2;
  }
  write(ctx.rank ? "query_id,rank,site_index,site_id,distance_m\n" : "query_id,site_index,site_id,distance_m\n");

  const int threads = args.threads;
  std::vector<std::unique_ptr<Worker>> workers;
  for (int t = 0; t < threads; ++t)
    workers.push_back(std::make_unique<Worker>(index.hierarchy, locator_options, ctx.format));
  std::uint64_t answered = 0, rejected = 0;
  for (;;) {
    const std::string_view block = blocks.next();
    if (block.empty()) break;
    // Split at line ends into one part per thread.
    std::vector<const char*> cut{block.data()};
    std::vector<std::uint64_t> first_line{line_no};
    const char* const end = block.data() + block.size();
    for (int t = 1; t < threads; ++t) {
      const char* c = std::max(cut.back(), block.data() + block.size() * t / threads);
      const char* nl = c < end ? static_cast<const char*>(std::memchr(c, '\n', static_cast<std::size_t>(end - c))) : nullptr;
      c = nl ? nl + 1 : end;
      first_line.push_back(first_line.back() + static_cast<std::uint64_t>(std::count(cut.back(), c, '\n')));
      cut.push_back(c);
    }
    cut.push_back(end);
    line_no = first_line.back() + static_cast<std::uint64_t>(std::count(cut[threads - 1], end, '\n'));
    if (threads == 1) {
      process(ctx, *workers[0], cut[0], cut[1], first_line[0]);
    } else {
      std::vector<std::thread> pool;
      std::vector<std::exception_ptr> failed(static_cast<std::size_t>(threads));
      for (int t = 1; t < threads; ++t)
        pool.emplace_back([&, t] {
          try {
            process(ctx, *workers[t], cut[t], cut[t + 1], first_line[t]);
          } catch (...) {
            failed[static_cast<std::size_t>(t)] = std::current_exception();
          }
        });
      try {
        process(ctx, *workers[0], cut[0], cut[1], first_line[0]);
      } catch (...) {
        failed[0] = std::current_exception();
      }
      for (auto& th : pool) th.join();
      for (const auto& e : failed)
        if (e) std::rethrow_exception(e);
    }
    for (const auto& w : workers) {
      write(w->out.view());
      answered += w->answered;
      rejected += w->errors.size();
      for (const auto& [line, reason] : w->errors)
        std::fprintf(stderr, "%s: line %llu: %s\n", qname.c_str(), static_cast<unsigned long long>(line), reason.c_str());
      if (w->stopped) {
        out.commit();  // the answers before the malformed line are kept
        throw Error(ErrorCode::BadData, qname + ": stopped at the first malformed query (--strict); " +
                                            std::to_string(answered) + " queries answered before it");
      }
    }
  }
  out.commit();
  if (rejected > 0)
    std::fprintf(stderr, "geovor nearest: %llu queries answered, %llu malformed lines skipped\n",
                 static_cast<unsigned long long>(answered), static_cast<unsigned long long>(rejected));
  return kOk;
}

}  // namespace

Command add_nearest_command(CLI::App& app) {
  auto args = std::make_shared<NearestArgs>();
  CLI::App* cmd = app.add_subcommand("nearest", "The exact nearest site (or k nearest) of every query of a CSV stream");
  cmd->add_option("--sites", args->sites.input,
                  "An index file (geovor index), or sites: CSV with a header (- for stdin) or any OGR point layer")
      ->required();
  cmd->add_option("--queries", args->queries, "Query CSV: lat,lon[,id] lines, with or without a header (default -: stdin)");
  cmd->add_option("-o,--output", args->output, "Output CSV (default -: stdout)");
  cmd->add_flag("--overwrite", args->overwrite, "Replace an existing output file");
  cmd->add_option("--locator", args->locator,
                  "Strategy: walk, jump-walk, keep-jump-walk, hierarchy, climb or keep-jump-climb (default)");
  args->k_option = cmd->add_option("--k", args->k, "The k nearest sites, one row each with a rank column");
  cmd->add_option("--metric", args->metric, "sphere (great circle on the mean-radius sphere, default) or geodesic (WGS84)");
  cmd->add_option("--threads", args->threads, "Threads (default 1); the output order is the input order");
  cmd->add_flag("--strict", args->strict, "Stop at the first malformed query line (exit 3)");
  args->site_options.push_back(cmd->add_option("--lat-field", args->sites.reader.lat_field, "Latitude column of the site table"));
  args->site_options.push_back(cmd->add_option("--lon-field", args->sites.reader.lon_field, "Longitude column of the site table"));
  args->site_options.push_back(cmd->add_option("--id-field", args->sites.reader.id_field,
                                               "Identifier column of the site table (default: id, icao, code or name; else the row number)"));
  args->site_options.push_back(cmd->add_option("--ecef-fields", args->sites.ecef_fields, "X,Y,Z ECEF columns of the site table"));
  args->site_options.push_back(cmd->add_option("--merge-m", args->sites.merge_m, "Merge sites closer than this many metres"));
  cmd->footer(
      "Writes CSV: query_id,site_index,site_id,distance_m (with --k: query_id,rank,site_index,site_id,\n"
      "distance_m, one row per neighbour, nearest first). query_id is the query's id column (query_id,\n"
      "id, icao, code or name) or its line number. Malformed query lines are reported on stderr with\n"
      "their line number and skipped (--strict: exit 3).\n"
      "Example: geovor nearest --sites stations.gvi --queries points.csv -o nearest.csv");
  return {[args] { return run(*args); },
          [args] { return !is_index_path(args->sites.input) && site_input_needs_gdal(args->sites); }};
}

}  // namespace geovor::tools
