// geodesic_s12 (our batched short-edge solver) against GeographicLib's Geodesic::GenInverse,
// the reference whose S12 it reproduces, on the edges of a Voronoi diagram of random sites
// (as `geovor cells` sums them for the cells' areas). Same process, same edges, best of R runs.
// Usage: geovor_bench_geodesic_area [SITES=171075] [RUNS=5]
#include <GeographicLib/Geodesic.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "bench_common.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/lonlat/ellipsoid_area.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

using namespace geovor;

int main(int argc, char** argv) {
  const std::size_t n = argc > 1 ? std::strtoull(argv[1], nullptr, 10) : 171075;
  const int runs = argc > 2 ? std::atoi(argv[2]) : 5;
  // Uniform random sites (Gaussian directions), their diagram, and each Voronoi edge once.
  std::mt19937_64 rng(1);
  std::normal_distribution<double> gauss;
  std::vector<Vec3> sites(n);
  for (Vec3& p : sites) {
    p = {gauss(rng), gauss(rng), gauss(rng)};
    p = (1 / std::sqrt(dot(p, p))) * p;
  }
  const SphericalDelaunay dt = SphericalDelaunay::build(sites);
  const VoronoiDiagram vd(dt);
  std::vector<LatLon> vertex(vd.num_vertices());
  for (TriId t = 0; t < vd.num_vertices(); ++t) vertex[t] = SiteEncoder::to_lat_lon(vd.vertex(t));
  std::vector<GeodesicEdge> edges;
  for (SiteId s = 0; s < dt.site_capacity(); ++s) {
    if (!vd.has_cell(s)) continue;
    const auto tris = vd.cell_vertices(s);
    const auto nbrs = vd.cell_neighbors(s);
    for (std::size_t i = 0; i < tris.size(); ++i) {
      if (nbrs[i] < s) continue;
      const LatLon a = vertex[tris[i]], b = vertex[tris[(i + 1) % tris.size()]];
      edges.push_back({a.lat_deg, a.lon_deg, b.lat_deg, b.lon_deg});
    }
  }
  const GeographicLib::Geodesic& geod = GeographicLib::Geodesic::WGS84();
  std::vector<double> ref(edges.size()), ours(edges.size());
  using Clock = std::chrono::steady_clock;
  double best_ref = 1e300, best_ours = 1e300;
  for (int r = 0; r < runs; ++r) {
    auto t0 = Clock::now();
    for (std::size_t i = 0; i < edges.size(); ++i) {
      double s12, t;
      geod.GenInverse(edges[i].lat1_deg, edges[i].lon1_deg, edges[i].lat2_deg, edges[i].lon2_deg,
                      GeographicLib::Geodesic::AREA, s12, t, t, t, t, t, ref[i]);
    }
    auto t1 = Clock::now();
    geodesic_s12(edges, ours);
    auto t2 = Clock::now();
    best_ref = std::min(best_ref, std::chrono::duration<double>(t1 - t0).count());
    best_ours = std::min(best_ours, std::chrono::duration<double>(t2 - t1).count());
  }
  double worst = 0;
  for (std::size_t i = 0; i < edges.size(); ++i) worst = std::max(worst, std::fabs(ours[i] - ref[i]));
  std::printf("%zu Voronoi edges of %zu random sites, on %s, best of %d\n", edges.size(), n,
              bench::cpu_model().c_str(), runs);
  std::printf("GeographicLib GenInverse: %7.1f ns/edge\n", 1e9 * best_ref / edges.size());
  std::printf("geodesic_s12:             %7.1f ns/edge\n", 1e9 * best_ours / edges.size());
  std::printf("speedup: %.2fx; largest |S12 difference| %.3g m^2\n", best_ref / best_ours, worst);
}
