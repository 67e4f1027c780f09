#include "support/triangulation_checks.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "geovor/geo/site_reader.hpp"
#include "support/generators.hpp"

namespace geovor::testing {

std::vector<Tri> triangle_set(const SphericalDelaunay& dt, const std::vector<std::uint32_t>& label) {
  std::vector<Tri> out;
  for (TriId t = 0; t < dt.num_triangles(); ++t) {
    Tri x{dt.tri_site(t, 0), dt.tri_site(t, 1), dt.tri_site(t, 2)};
    if (!label.empty()) x = {label[x[0]], label[x[1]], label[x[2]]};
    std::rotate(x.begin(), std::min_element(x.begin(), x.end()), x.end());
    out.push_back(x);
  }
  std::sort(out.begin(), out.end());
  return out;
}

SphericalDelaunay build_checked(const std::vector<Vec3>& pts, BuildReport* report, bool global,
                                const DelaunayOptions& options) {
  BuildReport local;
  BuildReport* r = report ? report : &local;
  SphericalDelaunay dt = SphericalDelaunay::build(pts, options, r);
  const Validation v = dt.validate(r, global);
  EXPECT_TRUE(v.ok()) << (v.errors.empty() ? "" : v.errors.front());
  return dt;
}

void expect_as_rebuilt(const SphericalDelaunay& dt, const std::string& what) {
  const Validation v = dt.validate();
  ASSERT_TRUE(v.ok()) << what << ": " << v.errors.front();
  std::vector<Vec3> pts;
  std::vector<SiteId> id_of;
  for (SiteId s = 0; s < dt.site_capacity(); ++s)
    if (dt.is_live(s)) pts.push_back(dt.site(s)), id_of.push_back(s);
  BuildReport rep;
  const SphericalDelaunay fresh = SphericalDelaunay::build(pts, dt.options(), &rep);
  ASSERT_TRUE(rep.merges.empty()) << what << ": two sites within the merge distance";
  EXPECT_EQ(triangle_set(dt), triangle_set(fresh, id_of)) << what;
}

Vec3 jitter(const Vec3& p, double step, std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  const Vec3 r{g(rng), g(rng), g(rng)};
  return normalized(p + (step / std::sqrt(3.0)) * r);
}

std::vector<Vec3> weather_station_sites() {
  const SiteTable table = read_sites_csv_file(std::string(GEOVOR_SOURCE_DIR) + "/datasets/weather_stations.csv");
  std::vector<Vec3> pts;
  for (const auto& s : table.sites) pts.push_back(s.unit);
  const SphericalDelaunay dt = SphericalDelaunay::build(pts);  // without the duplicates
  return {dt.sites().begin(), dt.sites().end()};
}

}  // namespace geovor::testing
