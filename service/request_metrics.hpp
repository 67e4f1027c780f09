/// \file request_metrics.hpp
/// \brief `geovor serve`'s /metrics: requests counted by route and status, and a latency
/// histogram, in Prometheus' text exposition format (version 0.0.4). Thread-safe; recording is a
/// few relaxed atomic increments, so it costs nothing measurable beside a lookup.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace geovor::service {

class RequestMetrics {
 public:
  /// The upper bounds of the latency histogram's buckets, in seconds (Prometheus `le`), then +Inf.
  static constexpr std::array<double, 12> kBucketsS = {0.0001, 0.00025, 0.0005, 0.001, 0.0025, 0.005,
                                                      0.01,   0.025,   0.05,   0.1,   1,      10};

  /// The routes counted apart (any other path counts as "other").
  explicit RequestMetrics(std::vector<std::string> routes);

  /// Counts one answered request: its route ("METHOD /path", one of the routes, else "other"), its HTTP status
  /// and its duration from the request's first byte read to the response handed to the socket.
  void record(const std::string& route, int status, double seconds);
  /// Counts one reload, done or refused (the old data kept).
  void record_reload(bool ok);

  /// The text of /metrics: geovor_requests_total{route,code}, geovor_request_errors_total{route}
  /// (4xx and 5xx), geovor_request_duration_seconds (histogram over every request),
  /// geovor_reloads_total{result="ok"|"failed"}, then `gauges` as given (lines "name value").
  std::string text(const std::string& gauges) const;

 private:
  struct Route {
    std::string name;
    std::array<std::atomic<std::uint64_t>, 600> by_status{};  // index: status 0..599
  };
  std::vector<Route> routes_;
  std::array<std::atomic<std::uint64_t>, kBucketsS.size() + 1> buckets_{};
  std::atomic<std::uint64_t> count_{0};
  std::atomic<std::uint64_t> sum_us_{0};
  std::atomic<std::uint64_t> reloads_ok_{0}, reloads_failed_{0};
};

}  // namespace geovor::service
