// RequestMetrics' Prometheus text: counts by route and status, errors, a cumulative histogram.
#include "request_metrics.hpp"

#include <gtest/gtest.h>

namespace geovor::service {
namespace {

bool has_line(const std::string& text, const std::string& line) { return text.find("\n" + line + "\n") != std::string::npos; }

TEST(RequestMetrics, CountsAndHistogram) {
  RequestMetrics m({"GET /nearest", "POST /nearest"});
  m.record("GET /nearest", 200, 0.0002);
  m.record("GET /nearest", 200, 0.003);
  m.record("GET /nearest", 400, 0.00005);
  m.record("GET /nowhere", 404, 20);
  m.record_reload(true);
  m.record_reload(false);
  m.record_reload(false);
  const std::string t = m.text("geovor_sites 7\n");
  EXPECT_TRUE(has_line(t, "geovor_requests_total{route=\"GET /nearest\",code=\"200\"} 2")) << t;
  EXPECT_TRUE(has_line(t, "geovor_requests_total{route=\"GET /nearest\",code=\"400\"} 1")) << t;
  EXPECT_TRUE(has_line(t, "geovor_requests_total{route=\"other\",code=\"404\"} 1")) << t;
  EXPECT_TRUE(has_line(t, "geovor_request_errors_total{route=\"GET /nearest\"} 1")) << t;
  EXPECT_TRUE(has_line(t, "geovor_request_errors_total{route=\"POST /nearest\"} 0")) << t;
  EXPECT_TRUE(has_line(t, "geovor_request_duration_seconds_bucket{le=\"0.0001\"} 1")) << t;
  EXPECT_TRUE(has_line(t, "geovor_request_duration_seconds_bucket{le=\"0.00025\"} 2")) << t;
  EXPECT_TRUE(has_line(t, "geovor_request_duration_seconds_bucket{le=\"0.005\"} 3")) << t;
  EXPECT_TRUE(has_line(t, "geovor_request_duration_seconds_bucket{le=\"10\"} 3")) << t;
  EXPECT_TRUE(has_line(t, "geovor_request_duration_seconds_bucket{le=\"+Inf\"} 4")) << t;
  EXPECT_TRUE(has_line(t, "geovor_request_duration_seconds_count 4")) << t;
  EXPECT_TRUE(has_line(t, "geovor_reloads_total{result=\"ok\"} 1")) << t;
  EXPECT_TRUE(has_line(t, "geovor_reloads_total{result=\"failed\"} 2")) << t;
  EXPECT_EQ(t.substr(t.size() - 15), "geovor_sites 7\n");
}

}  // namespace
}  // namespace geovor::service
