#include "geovor/locate/knn.hpp"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Geodesic.hpp>

#include <algorithm>
#include <cmath>

#include "geovor/core/error.hpp"
#include "geovor/geo/lat_lon.hpp"
#include "geovor/geo/site_encoder.hpp"

namespace geovor {
namespace {

bool before(const NearestResult& x, const NearestResult& y) {
  return x.dist_m < y.dist_m || (x.dist_m == y.dist_m && x.site < y.site);
}

// A lower bound of the geodesic distance of a site at `angle` (radians) from the query, and of
// every site at a larger angle: the chord on the sphere of the polar radius, less a margin for
// the rounding of the angle and GeographicLib's accuracy.
double geodesic_lower_bound_m(const Vec3& q, const Vec3& p) {
  static const double polar_radius_m =
      GeographicLib::Constants::WGS84_a() * (1 - GeographicLib::Constants::WGS84_f());
  const double angle = std::atan2(std::sqrt(norm2(cross(q, p))), dot(q, p));
  return 2 * polar_radius_m * std::sin(angle / 2) * (1 - 1e-12) - 1e-6;
}

double geodesic_m(double lat_deg, double lon_deg, const Vec3& p) {
  const LatLon ll = SiteEncoder::to_lat_lon(p);
  double s12 = 0;
  GeographicLib::Geodesic::WGS84().Inverse(lat_deg, lon_deg, ll.lat_deg, ll.lon_deg, s12);
  return s12;
}

}  // namespace

const char* to_string(Metric m) {
  switch (m) {
    case Metric::Sphere: return "sphere";
    case Metric::Geodesic: return "geodesic";
    case Metric::Power: return "power";
  }
  return "?";
}

Metric parse_metric(const std::string& name) {
  for (const Metric m : {Metric::Sphere, Metric::Geodesic, Metric::Power})
    if (name == to_string(m)) return m;
  throw Error(ErrorCode::InvalidArgument, "unknown metric '" + name + "'; use sphere, geodesic or power");
}

Metric default_metric(const DelaunayHierarchy& hierarchy) {
  return hierarchy.is_weighted() ? Metric::Power : Metric::Sphere;
}

void check_metric(const DelaunayHierarchy& hierarchy, Metric metric) {
  if (metric != Metric::Power && hierarchy.is_weighted())
    throw Error(ErrorCode::InvalidArgument, std::string("metric ") + to_string(metric) +
                                                ": the sites are weighted, their metric is power (the site whose power "
                                                "cell holds the query); index them without weights for distances alone");
}

void k_nearest(Locator& locator, double lat_deg, double lon_deg, std::size_t k, Metric metric,
               std::vector<NearestResult>& out) {
  check_metric(locator.hierarchy(), metric);
  out.clear();
  const Vec3 q = SiteEncoder::from_lat_lon(lat_deg, lon_deg);
  if (k == 0) return;
  if (metric != Metric::Geodesic) {  // the Locator's order: nearness, or power
    locator.nearest_first(q, [&](SiteId s, const Vec3& p) {
      out.push_back({s, great_circle_m(q, p)});
      return out.size() < k;
    });
    return;
  }
  // out is a max-heap (by `before`) of the k best so far.
  locator.nearest_first(q, [&](SiteId s, const Vec3& p) {
    if (out.size() == k && geodesic_lower_bound_m(q, p) > out.front().dist_m) return false;
    const NearestResult r{s, geodesic_m(lat_deg, lon_deg, p)};
    if (out.size() < k) {
      out.push_back(r);
      std::push_heap(out.begin(), out.end(), before);
    } else if (before(r, out.front())) {
      std::pop_heap(out.begin(), out.end(), before);
      out.back() = r;
      std::push_heap(out.begin(), out.end(), before);
    }
    return true;
  });
  std::sort_heap(out.begin(), out.end(), before);
}

void within(Locator& locator, double lat_deg, double lon_deg, double max_distance_m, Metric metric,
            std::vector<NearestResult>& out) {
  check_metric(locator.hierarchy(), metric);
  out.clear();
  if (!(max_distance_m >= 0)) return;
  const Vec3 q = SiteEncoder::from_lat_lon(lat_deg, lon_deg);
  if (metric != Metric::Geodesic) {
    out = locator.within(q, max_distance_m);
    return;
  }
  locator.nearest_first(q, [&](SiteId s, const Vec3& p) {
    if (geodesic_lower_bound_m(q, p) > max_distance_m) return false;
    const double d = geodesic_m(lat_deg, lon_deg, p);
    if (d <= max_distance_m) out.push_back({s, d});
    return true;
  });
  std::sort(out.begin(), out.end(), before);
}

void nearest_within(Locator& locator, double lat_deg, double lon_deg, std::size_t k, Metric metric,
                    double max_distance_m, std::vector<NearestResult>& out) {
  if (k == 1) {
    check_metric(locator.hierarchy(), metric);
    out.assign(1, metric == Metric::Geodesic ? locator.nearest_geodesic(lat_deg, lon_deg)
                                             : locator.nearest(SiteEncoder::from_lat_lon(lat_deg, lon_deg)));
  } else {
    k_nearest(locator, lat_deg, lon_deg, k, metric, out);
  }
  std::erase_if(out, [&](const NearestResult& r) { return r.site == kNoIndex || !(r.dist_m <= max_distance_m); });
}

}  // namespace geovor
