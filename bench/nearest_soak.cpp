// nearest_soak: streams generated queries through `geovor nearest` (a pipe into its stdin, its
// output to /dev/null) and prints the command's resident memory at the start and the end and its
// throughput over time: the load test of issue 5 (constant memory over 10^8 queries).
//
//   geovor_bench_nearest_soak [--geovor EXE] [--sites FILE] [--queries N] [--interval S]
//                             [--random] [--threads T] [--locator NAME]
//                             [--check-constant-memory [--first N1]]
//
// Queries are headerless `lat,lon` lines: by default a random walk over the globe with 11 km
// steps (a vehicle track: the coherent stream the default locator suits), with --random uniform
// points on the sphere (then use --locator hierarchy). The first 2^20 lines are generated once
// and replayed in turn (one jump every 2^20 queries), so that the generator costs a memcpy per
// line and the figures are geovor's, not the generator's. Memory is read from /proc/PID/status
// (VmRSS now, VmHWM the peak so far); "start" is sampled once the first N1 queries (default
// 10^6, at most N/3) have gone into the pipe, i.e. with the sites loaded and the stream's
// buffers in use; "end" just before the pipe is closed, and the peak of the whole run from
// wait4(). Throughput is the rate at which geovor takes queries from the pipe (the pipe and
// geovor's 4 MiB read block hold at most a few hundred thousand queries ahead).
//
// --check-constant-memory (for ctest; nothing is timed): exit 1 unless the peak of the whole run
// exceeds the peak after the first N1 queries by less than max(4 MiB, 5 %). A per-query leak of
// 2 bytes or more over 3 x 10^6 queries fails it.
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace {

#ifndef GEOVOR_EXE
#define GEOVOR_EXE "geovor"
#endif
#ifndef GEOVOR_SOURCE_DIR
#define GEOVOR_SOURCE_DIR "."
#endif

struct Memory {
  long rss_kb = -1, hwm_kb = -1;
};

Memory memory_of(pid_t pid) {
  Memory m;
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) m.rss_kb = std::atol(line.c_str() + 6);
    if (line.rfind("VmHWM:", 0) == 0) m.hwm_kb = std::atol(line.c_str() + 6);
  }
  return m;
}

double load_average() {
  double l = -1;
  if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &l) != 1) l = -1;
    std::fclose(f);
  }
  return l;
}

[[noreturn]] void usage(const char* why) {
  std::fprintf(stderr,
               "nearest_soak: %s\nusage: nearest_soak [--geovor EXE] [--sites FILE] [--queries N] [--interval S]\n"
               "                    [--random] [--threads T] [--locator NAME] [--check-constant-memory [--first N1]]\n",
               why);
  std::exit(2);
}

constexpr double kPi = 3.14159265358979323846;

// Query generator: a random walk of 11 km steps (0.1 degree of great circle), or uniform points.
class Generator {
 public:
  explicit Generator(bool random) : random_(random), rng_(42) {}

  // Appends one "lat,lon\n" line.
  void line(std::string& out) {
    double lat, lon;
    if (random_) {
      lat = std::asin(2 * unit_(rng_) - 1) * 180 / kPi;
      lon = 360 * unit_(rng_) - 180;
    } else {
      step();
      lat = std::asin(std::clamp(z_, -1.0, 1.0)) * 180 / kPi;
      lon = std::atan2(y_, x_) * 180 / kPi;
    }
    char buf[64];
    char* p = std::to_chars(buf, buf + 64, lat, std::chars_format::fixed, 6).ptr;
    *p++ = ',';
    p = std::to_chars(p, buf + 64, lon, std::chars_format::fixed, 6).ptr;
    *p++ = '\n';
    out.append(buf, p);
  }

 private:
  // Moves the unit vector (x, y, z) by 0.1 degree in a direction turning slowly at random.
  void step() {
    heading_ += 0.2 * (unit_(rng_) - 0.5);
    // East and north at the point, then the step along the heading.
    double ex = -y_, ey = x_;  // east = (0, 0, 1) x p, normalised; its z is 0
    double en = std::hypot(ex, ey);
    if (en < 1e-9) ex = 1, ey = 0, en = 1;  // at a pole any direction will do
    ex /= en, ey /= en;
    const double nx = -z_ * ey, ny = z_ * ex, nz = x_ * ey - y_ * ex;  // north = p x east
    const double d = 0.1 * kPi / 180;
    const double tx = std::cos(heading_) * nx + std::sin(heading_) * ex;
    const double ty = std::cos(heading_) * ny + std::sin(heading_) * ey;
    const double tz = std::cos(heading_) * nz;
    x_ = std::cos(d) * x_ + std::sin(d) * tx;
    y_ = std::cos(d) * y_ + std::sin(d) * ty;
    z_ = std::cos(d) * z_ + std::sin(d) * tz;
    const double n = std::sqrt(x_ * x_ + y_ * y_ + z_ * z_);
    x_ /= n, y_ /= n, z_ /= n;
  }

  bool random_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
  double x_ = 0.6, y_ = 0.0, z_ = 0.8, heading_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  std::string geovor = GEOVOR_EXE;
  std::string sites = std::string(GEOVOR_SOURCE_DIR) + "/datasets/weather_stations.csv";
  std::string locator;
  unsigned long long total = 100000000ULL, first = 1000000ULL;
  double interval_s = 10;
  bool random = false, check = false;
  int threads = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(("missing value after " + a).c_str());
      return argv[++i];
    };
    if (a == "--geovor") geovor = value();
    else if (a == "--sites") sites = value();
    else if (a == "--queries") total = std::strtoull(value().c_str(), nullptr, 10);
    else if (a == "--first") first = std::strtoull(value().c_str(), nullptr, 10);
    else if (a == "--interval") interval_s = std::atof(value().c_str());
    else if (a == "--threads") threads = std::atoi(value().c_str());
    else if (a == "--locator") locator = value();
    else if (a == "--random") random = true;
    else if (a == "--check-constant-memory") check = true;
    else usage(("unknown option " + a).c_str());
  }
  if (total < 3) usage("--queries must be at least 3");
  first = std::min(first, total / 3);

  int fds[2];
  if (pipe(fds) != 0) {
    std::perror("pipe");
    return 1;
  }
  std::vector<std::string> args = {geovor, "nearest", "--sites", sites, "--queries", "-", "--threads", std::to_string(threads)};
  if (!locator.empty()) args.insert(args.end(), {"--locator", locator});
  const pid_t pid = fork();
  if (pid < 0) {
    std::perror("fork");
    return 1;
  }
  if (pid == 0) {
    dup2(fds[0], STDIN_FILENO);
    close(fds[0]);
    close(fds[1]);
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    std::vector<char*> cargs;
    for (auto& s : args) cargs.push_back(s.data());
    cargs.push_back(nullptr);
    execv(cargs[0], cargs.data());
    std::perror(cargs[0]);
    _exit(127);
  }
  close(fds[0]);
  signal(SIGPIPE, SIG_IGN);  // geovor failing early shows as a write error, then its exit code

  std::printf("nearest_soak: %s nearest --sites %s, %llu %s queries, %d thread(s)%s%s\n", geovor.c_str(),
              sites.c_str(), total, random ? "random" : "random-walk", threads,
              locator.empty() ? "" : ", locator ", locator.c_str());
  std::printf("load average at start: %.2f (%ld cores online)\n", load_average(), sysconf(_SC_NPROCESSORS_ONLN));
  std::printf("%10s %14s %14s %12s %12s\n", "seconds", "queries", "queries/s", "VmRSS_MiB", "VmHWM_MiB");
  std::fflush(stdout);

  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  auto last_t = t0;
  unsigned long long written = 0, last_written = 0;
  Memory start_mem, end_mem;
  double start_s = 0;
  // The track: kTrack lines, in chunks of kChunk lines (offsets into `track`).
  constexpr unsigned long long kChunk = 4096;  // lines per write()
  constexpr unsigned long long kTrack = 1ULL << 20;
  Generator gen(random);
  std::string track;
  std::vector<std::size_t> chunk_at{0};
  for (unsigned long long k = 1; k <= kTrack; ++k) {
    gen.line(track);
    if (k % kChunk == 0) chunk_at.push_back(track.size());
  }
  const std::size_t chunks = chunk_at.size() - 1;
  bool failed = false;
  for (std::size_t c = 0; written < total && !failed; c = (c + 1) % chunks) {
    const unsigned long long n = std::min(kChunk, total - written);
    std::size_t end = chunk_at[c + 1];
    if (n < kChunk) {  // the last, partial chunk: cut after its n-th line
      end = chunk_at[c];
      for (unsigned long long k = 0; k < n; ++k) end = track.find('\n', end) + 1;
    }
    const std::string_view buf(track.data() + chunk_at[c], end - chunk_at[c]);
    for (std::size_t off = 0; off < buf.size();) {
      const ssize_t w = write(fds[1], buf.data() + off, buf.size() - off);
      if (w < 0) {
        if (errno == EINTR) continue;
        std::fprintf(stderr, "nearest_soak: write to geovor: %s\n", std::strerror(errno));
        failed = true;
        break;
      }
      off += static_cast<std::size_t>(w);
    }
    written += n;
    if (start_mem.hwm_kb < 0 && written >= first) {
      start_mem = memory_of(pid);
      start_s = std::chrono::duration<double>(Clock::now() - t0).count();
      std::printf("start (after %llu queries, %.1f s): VmRSS %.1f MiB, VmHWM %.1f MiB\n", written, start_s,
                  start_mem.rss_kb / 1024.0, start_mem.hwm_kb / 1024.0);
      std::fflush(stdout);
    }
    const auto now = Clock::now();
    const double since = std::chrono::duration<double>(now - last_t).count();
    if (since >= interval_s) {
      const Memory m = memory_of(pid);
      std::printf("%10.1f %14llu %14.0f %12.1f %12.1f\n", std::chrono::duration<double>(now - t0).count(), written,
                  static_cast<double>(written - last_written) / since, m.rss_kb / 1024.0, m.hwm_kb / 1024.0);
      std::fflush(stdout);
      last_t = now;
      last_written = written;
    }
  }
  end_mem = memory_of(pid);
  close(fds[1]);
  int status = 0;
  struct rusage usage {};
  wait4(pid, &status, 0, &usage);
  const double total_s = std::chrono::duration<double>(Clock::now() - t0).count();
  std::printf("end (after %llu queries, %.1f s): VmRSS %.1f MiB, VmHWM %.1f MiB; peak of the run %.1f MiB\n", written,
              total_s, end_mem.rss_kb / 1024.0, end_mem.hwm_kb / 1024.0, usage.ru_maxrss / 1024.0);
  std::printf("throughput: %.0f queries/s overall, %.0f after the start sample; geovor CPU %.1f s user, %.1f s system\n",
              static_cast<double>(written) / total_s,
              static_cast<double>(written - first) / std::max(1e-9, total_s - start_s),
              static_cast<double>(usage.ru_utime.tv_sec) + usage.ru_utime.tv_usec * 1e-6,
              static_cast<double>(usage.ru_stime.tv_sec) + usage.ru_stime.tv_usec * 1e-6);
  struct rusage self {};
  getrusage(RUSAGE_SELF, &self);
  std::printf("generator CPU %.1f s; load average at end: %.2f\n",
              static_cast<double>(self.ru_utime.tv_sec + self.ru_stime.tv_sec) +
                  (self.ru_utime.tv_usec + self.ru_stime.tv_usec) * 1e-6,
              load_average());
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "nearest_soak: geovor nearest failed (status %d)\n", status);
    return 1;
  }
  if (failed) return 1;
  if (check) {
    const long growth_kb = usage.ru_maxrss - start_mem.hwm_kb;
    const long allowed_kb = std::max(4096L, start_mem.hwm_kb / 20);
    std::printf("peak grew by %ld KiB from %llu to %llu queries (allowed %ld KiB)\n", growth_kb, first, written,
                allowed_kb);
    if (start_mem.hwm_kb <= 0 || growth_kb >= allowed_kb) {
      std::fprintf(stderr, "nearest_soak: memory is not constant in the number of queries\n");
      return 1;
    }
  }
  return 0;
}
