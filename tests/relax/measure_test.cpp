// The ellipsoid's area measure on geocentric directions: its closed forms, the masses of cells
// summing to the total (random sites, sites at and around the poles, few sites), against
// GeographicLib's PolygonArea of finely densified rings, and the sphere's case against the
// diagram's own spherical areas.
#include "geovor/relax/measure.hpp"

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/PolygonArea.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"
#include "support/generators.hpp"

namespace geovor {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kWgs84AreaM2 = 510065621724088.5;

double sum_of_masses(const std::vector<Vec3>& sites, const SphereMeasure& m, std::vector<double> lifts = {}) {
  const SphericalDelaunay dt = lifts.empty() ? SphericalDelaunay::build(sites) : SphericalDelaunay::build(sites, lifts);
  const VoronoiDiagram vd(dt);
  double sum = 0;
  for (SiteId s = 0; s < vd.site_capacity(); ++s) {
    const double a = m.cell_mass(vd, s);
    EXPECT_GE(a, 0) << s;
    sum += a;
  }
  return sum;
}

// Geodetic latitude and longitude (degrees) of the point of WGS84 at direction x.
void lat_lon(const Vec3& x, double& lat, double& lon) {
  const double f = 1 / 298.257223563, e2 = f * (2 - f);
  lat = std::atan2(x.z, (1 - e2) * std::hypot(x.x, x.y)) * 180 / kPi;
  lon = std::atan2(x.y, x.x) * 180 / kPi;
}

// PolygonArea of the cell of s, each edge densified into `per_edge` geodesics.
double polygon_area(const VoronoiDiagram& vd, SiteId s, int per_edge) {
  GeographicLib::PolygonArea poly(GeographicLib::Geodesic::WGS84());
  std::vector<GreatArc> arcs;
  cell_arcs(vd, s, arcs);
  for (const GreatArc& arc : arcs)
    for (int k = 0; k < per_edge; ++k) {
      double lat, lon;
      lat_lon(arc.at(arc.angle_rad * k / per_edge), lat, lon);
      poly.AddPoint(lat, lon);
    }
  double perimeter, area;
  poly.Compute(false, true, perimeter, area);
  return area < 0 ? area + kWgs84AreaM2 : area;
}

TEST(EllipsoidAreaMeasure, ClosedForms) {
  const EllipsoidAreaMeasure m;
  EXPECT_NEAR(m.total(), kWgs84AreaM2, 1e-15 * kWgs84AreaM2);
  EXPECT_NEAR(m.total(), GeographicLib::Geodesic::WGS84().EllipsoidArea(), 1e-15 * kWgs84AreaM2);
  EXPECT_NEAR(m.zone_m2_per_rad(1), m.total() / (2 * kPi), 1e-15 * m.total());
  EXPECT_NEAR(m.zone_m2_per_rad(-1), 0, 1e-15 * m.total());
  EXPECT_NEAR(m.zone_m2_per_rad(0), m.total() / (4 * kPi), 1e-15 * m.total());
  // f at the equator is a^2, at the poles b^2; G' = f (central differences).
  const double a = 6378137, b = a * (1 - 1 / 298.257223563);
  EXPECT_NEAR(m.density_of_z(0), a * a, 1e-15 * a * a);
  EXPECT_NEAR(m.density_of_z(1), b * b, 1e-15 * a * a);
  for (const double z : {-0.9, -0.3, 0.1, 0.5, 0.95}) {
    const double h = 1e-4;
    const double d = (m.zone_m2_per_rad(z + h) - m.zone_m2_per_rad(z - h)) / (2 * h);
    EXPECT_NEAR(d, m.density_of_z(z), 1e-8 * a * a) << z;
    EXPECT_NEAR(m.mean_density(z, z + 0.04), (m.zone_m2_per_rad(z + 0.04) - m.zone_m2_per_rad(z)) / 0.04, 1e-11 * a * a);
  }
  // The density integrates to the total over the sphere (Gauss-Legendre in z, 2 pi in phi).
  double sum = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) sum += m.density_of_z(-1 + (i + 0.5) * 2.0 / n) * 2.0 / n;
  EXPECT_NEAR(2 * kPi * sum, m.total(), 1e-6 * m.total());
  EXPECT_THROW(EllipsoidAreaMeasure(0, 0), Error);
  EXPECT_THROW(EllipsoidAreaMeasure(1, 1), Error);
}

TEST(EllipsoidAreaMeasure, MassesSumToTheTotal) {
  const EllipsoidAreaMeasure m;
  for (const std::size_t n : {4u, 5u, 20u, 200u, 5000u}) {
    const std::vector<Vec3> sites = testing::uniform_on_sphere(n, 7 + n);
    EXPECT_NEAR(sum_of_masses(sites, m), m.total(), 1e-12 * m.total()) << n;
  }
  // Two sites (hemispheres), three (lunes).
  EXPECT_NEAR(sum_of_masses(testing::uniform_on_sphere(2, 3), m), m.total(), 1e-12 * m.total());
  EXPECT_NEAR(sum_of_masses(testing::uniform_on_sphere(3, 3), m), m.total(), 1e-12 * m.total());
}

TEST(EllipsoidAreaMeasure, PoleCells) {
  const EllipsoidAreaMeasure m;
  // The poles themselves as sites, sites crowding around them, and a pole on a vertex.
  std::vector<Vec3> sites = testing::uniform_on_sphere(100, 11);
  sites.push_back({0, 0, 1});
  sites.push_back({0, 0, -1});
  EXPECT_NEAR(sum_of_masses(sites, m), m.total(), 1e-12 * m.total());
  std::vector<Vec3> polar;
  for (int i = 0; i < 60; ++i) {
    const double lat = (i % 2 ? 1 : -1) * (89.0 + 0.9 * std::sin(i * 1.7)), lon = i * 37.0 - 180;
    polar.push_back(SiteEncoder::from_lat_lon(lat, std::fmod(lon + 540, 360) - 180));
  }
  for (const Vec3& p : testing::uniform_on_sphere(40, 5)) polar.push_back(p);
  EXPECT_NEAR(sum_of_masses(polar, m), m.total(), 1e-12 * m.total());
  // Three sites at 120 degrees around the pole: the pole is a vertex of all three cells.
  std::vector<Vec3> vertex_at_pole;
  for (int i = 0; i < 3; ++i) vertex_at_pole.push_back(SiteEncoder::from_lat_lon(80, -170 + 120 * i));
  for (const Vec3& p : testing::uniform_on_sphere(30, 9))
    if (p.z < 0.9) vertex_at_pole.push_back(p);
  EXPECT_NEAR(sum_of_masses(vertex_at_pole, m), m.total(), 1e-12 * m.total());
  // Weighted cells around the poles.
  std::vector<double> lifts;
  for (std::size_t i = 0; i < polar.size(); ++i) lifts.push_back(std::cos(0.02 * (i % 7)));
  EXPECT_NEAR(sum_of_masses(polar, m, lifts), m.total(), 1e-12 * m.total());
}

TEST(EllipsoidAreaMeasure, AgainstGeographicLibPolygonArea) {
  const EllipsoidAreaMeasure m;
  std::vector<Vec3> sites = testing::uniform_on_sphere(40, 21);
  sites.push_back({0, 0, 1});  // a cell around the north pole
  sites.push_back(SiteEncoder::from_lat_lon(-89.5, 30));  // and one around the south pole
  const VoronoiDiagram vd(SphericalDelaunay::build(sites));
  for (SiteId s = 0; s < vd.site_capacity(); ++s) {
    const double mass = m.cell_mass(vd, s);
    EXPECT_NEAR(mass, polygon_area(vd, s, 3000), 1e-9 * mass) << s;
  }
}

TEST(EllipsoidAreaMeasure, SphereIsTheSphericalArea) {
  const EllipsoidAreaMeasure unit(1, 0);
  EXPECT_NEAR(unit.total(), 4 * kPi, 1e-15);
  std::vector<Vec3> sites = testing::uniform_on_sphere(300, 4);
  sites.push_back({0, 0, 1});
  const VoronoiDiagram vd(SphericalDelaunay::build(sites));
  for (SiteId s = 0; s < vd.site_capacity(); ++s)
    EXPECT_NEAR(unit.cell_mass(vd, s), vd.cell_area_sr(s), 1e-12 * vd.cell_area_sr(s)) << s;
  // Tiny cells: a cluster 10 m across keeps its digits.
  const std::vector<Vec3> tiny = testing::clustered(50, 1, 1.5e-6, 3);
  const VoronoiDiagram small(SphericalDelaunay::build(tiny));
  for (SiteId s = 0; s < small.site_capacity(); ++s) {
    const double a = small.cell_area_sr(s);
    if (a < 1e-6) {
      EXPECT_NEAR(unit.cell_mass(small, s), a, 1e-8 * a) << s;
    }
  }
}

TEST(EllipsoidAreaMeasure, EdgeMomentsConvergeWhenRefined) {
  const EllipsoidAreaMeasure m;
  const VoronoiDiagram vd(SphericalDelaunay::build(testing::uniform_on_sphere(12, 8)));
  std::vector<GreatArc> arcs;
  for (SiteId s = 0; s < vd.site_capacity(); ++s) {
    cell_arcs(vd, s, arcs);
    for (const GreatArc& arc : arcs) {
      const Vec3 w{0.3, -0.2, 0.9};
      const double coarse = m.edge_moment(arc, w);
      double fine = 0;  // 64 sub-arcs
      for (int k = 0; k < 64; ++k)
        fine += m.edge_moment(GreatArc{arc.at(arc.angle_rad * k / 64), arc.normal, arc.angle_rad / 64}, w);
      EXPECT_NEAR(coarse, fine, 1e-12 * m.density_of_z(0) * std::max(1e-3, arc.angle_rad));
    }
  }
}

}  // namespace
}  // namespace geovor
