#include "request_metrics.hpp"

#include <cmath>
#include <iterator>

#include "geovor/io/number_format.hpp"

namespace geovor::service {
namespace {

std::string real(double v) {
  std::string out;
  append_real(out, v);
  return out;
}

// kBucketsS as Prometheus writes them.
constexpr const char* kBucketLabels[] = {"0.0001", "0.00025", "0.0005", "0.001", "0.0025", "0.005",
                                         "0.01",   "0.025",   "0.05",   "0.1",   "1",      "10"};
static_assert(std::size(kBucketLabels) == RequestMetrics::kBucketsS.size());

}  // namespace

RequestMetrics::RequestMetrics(std::vector<std::string> routes) : routes_(routes.size() + 1) {
  for (std::size_t i = 0; i < routes.size(); ++i) routes_[i].name = std::move(routes[i]);
  routes_.back().name = "other";
}

void RequestMetrics::record(const std::string& route, int status, double seconds) {
  std::size_t r = 0;
  while (r + 1 < routes_.size() && routes_[r].name != route) ++r;
  routes_[r].by_status[status >= 0 && status < 600 ? status : 0].fetch_add(1, std::memory_order_relaxed);
  std::size_t b = 0;
  while (b < kBucketsS.size() && seconds > kBucketsS[b]) ++b;
  buckets_[b].fetch_add(1, std::memory_order_relaxed);
  count_.fetch_add(1, std::memory_order_relaxed);
  sum_us_.fetch_add(static_cast<std::uint64_t>(std::llround(seconds * 1e6)), std::memory_order_relaxed);
}

void RequestMetrics::record_reload(bool ok) { (ok ? reloads_ok_ : reloads_failed_).fetch_add(1, std::memory_order_relaxed); }

std::string RequestMetrics::text(const std::string& gauges) const {
  std::string t =
      "# HELP geovor_requests_total Requests answered, by route and HTTP status.\n"
      "# TYPE geovor_requests_total counter\n";
  std::string errors =
      "# HELP geovor_request_errors_total Requests answered with a 4xx or 5xx status, by route.\n"
      "# TYPE geovor_request_errors_total counter\n";
  for (const Route& r : routes_) {
    std::uint64_t failed = 0;
    for (int s = 0; s < 600; ++s) {
      const std::uint64_t n = r.by_status[s].load(std::memory_order_relaxed);
      if (n == 0) continue;
      t += "geovor_requests_total{route=\"" + r.name + "\",code=\"" + std::to_string(s) + "\"} " + std::to_string(n) + "\n";
      if (s >= 400) failed += n;
    }
    errors += "geovor_request_errors_total{route=\"" + r.name + "\"} " + std::to_string(failed) + "\n";
  }
  t += errors;
  t += "# HELP geovor_request_duration_seconds Time from a request read to its response written.\n"
       "# TYPE geovor_request_duration_seconds histogram\n";
  std::uint64_t cumulative = 0;
  for (std::size_t b = 0; b <= kBucketsS.size(); ++b) {
    cumulative += buckets_[b].load(std::memory_order_relaxed);
    const std::string le = b < kBucketsS.size() ? kBucketLabels[b] : "+Inf";
    t += "geovor_request_duration_seconds_bucket{le=\"" + le + "\"} " + std::to_string(cumulative) + "\n";
  }
  t += "geovor_request_duration_seconds_sum " + real(static_cast<double>(sum_us_.load()) * 1e-6) + "\n";
  t += "geovor_request_duration_seconds_count " + std::to_string(count_.load()) + "\n";
  t += "# HELP geovor_reloads_total Reloads of the served data, done (ok) or refused (failed: the old data kept).\n"
       "# TYPE geovor_reloads_total counter\n";
  t += "geovor_reloads_total{result=\"ok\"} " + std::to_string(reloads_ok_.load()) + "\n";
  t += "geovor_reloads_total{result=\"failed\"} " + std::to_string(reloads_failed_.load()) + "\n";
  return t + gauges;
}

}  // namespace geovor::service
