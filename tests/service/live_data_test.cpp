// LiveData: a reload swaps the data whole, a failed load keeps the old data, and a request that
// holds the old data keeps it until it is done, while reloads run beside requests.
#include "live_data.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor::service {
namespace {

std::shared_ptr<const ServedData> sites(std::size_t n) {
  SiteTable t;
  t.source = "live.csv";
  for (std::size_t i = 0; i < n; ++i) {
    InputSite s;
    s.row = i + 1;
    s.id = std::to_string(i);
    s.lat_deg = -80.0 + 160.0 * static_cast<double>(i) / static_cast<double>(n);
    s.lon_deg = static_cast<double>(i * 37 % 360) - 180;
    s.unit = SiteEncoder::from_lat_lon(s.lat_deg, s.lon_deg);
    t.sites.push_back(s);
  }
  t.rows_read = n;
  return make_served_data(build_site_index(t), "", {});
}

std::size_t served_sites(const LiveData& live) { return live.current()->nearest.index().hierarchy.base().num_sites(); }

TEST(LiveData, ReloadSwapsOrKeepsTheOldData) {
  std::size_t next = 10;
  bool fail = false;
  LiveData live([&] {
    if (fail) throw Error(ErrorCode::BadData, "stations.gvi: not an index");
    return sites(next);
  });
  EXPECT_EQ(served_sites(live), 10u);
  const std::shared_ptr<const ServedData> held = live.current();  // a request in flight
  next = 20;
  const ReloadResult ok = live.reload();
  EXPECT_TRUE(ok.ok);
  EXPECT_EQ(ok.message, "20 sites");
  EXPECT_EQ(served_sites(live), 20u);
  EXPECT_EQ(held->nearest.index().hierarchy.base().num_sites(), 10u);  // still whole
  fail = true;
  const ReloadResult failed = live.reload();
  EXPECT_FALSE(failed.ok);
  EXPECT_EQ(failed.message, "stations.gvi: not an index");
  EXPECT_EQ(served_sites(live), 20u);
}

TEST(LiveData, RequestsDuringReloadsAllAnswer) {
  std::atomic<std::size_t> next{30};
  LiveData live([&] { return sites(next.load()); });
  std::atomic<bool> done{false};
  std::atomic<int> answered{0}, failed{0};
  std::vector<std::thread> clients;
  for (int c = 0; c < 4; ++c)
    clients.emplace_back([&] {
      while (!done) {
        const Response r = live.current()->nearest.nearest({{"lat", "10"}, {"lon", "20"}});
        (r.status == 200 ? answered : failed)++;
      }
    });
  for (int i = 0; i < 20; ++i) {
    next = 30 + static_cast<std::size_t>(i % 3);
    EXPECT_TRUE(live.reload().ok);
  }
  done = true;
  for (std::thread& t : clients) t.join();
  EXPECT_EQ(failed.load(), 0);
  EXPECT_GT(answered.load(), 0);
}

}  // namespace
}  // namespace geovor::service
