#include "geovor/relax/lloyd.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>

#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/geo/site_encoder.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace geovor {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;

double seconds_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

Vec3 normalized(const Vec3& v) { return (1 / std::sqrt(norm2(v))) * v; }

// Angle between two unit vectors, accurate at every angle (atan2, not acos).
double angle_between(const Vec3& a, const Vec3& b) { return std::atan2(std::sqrt(norm2(cross(a, b))), dot(a, b)); }

// Cells of a perimeter below kSmallCellPerimeter (about 10 km across) take the gnomonic quadrature
// below for M's part across the site: the closed form's terms (edge angles, each to an ulp)
// cancel to a mass of ~ perimeter^2 / 14, so its direction errs by ~ 1e-16 k / |M| radians (1.3 km
// for a cell of a metre, 0.6 mm at this perimeter); the quadrature's error is ~ size^7.
constexpr double kSmallCellPerimeter = 0.01;

// The part of M across p of a small cell, from its gnomonic projection about the site p, where
// its edges are straight: x = (u e1 + v e2 + p) / sqrt(1 + q), q = u^2 + v^2, dA = du dv / (1 + q)^(3/2),
// so M's part across p is the integral of (u e1 + v e2) / (1 + q)^2 du dv, over the fan triangles
// (p, a_i, a_i+1), each by Radon's 7-point rule (exact to degree 5; the integrand is u - 2 u q +
// 3 u q^2 - 4 u q^3 ..., so the error is ~ q^3 relative). The coordinates are differences from p,
// so nothing cancels: the centroid is right to a few ulps of a radian.
Vec3 small_cell_tangential_mass(const VoronoiDiagram& vd, const Vec3& p, std::span<const TriId> tris) {
  // An orthonormal frame (e1, e2, p): e1 across the axis p is least aligned with.
  const Vec3 axis = std::fabs(p.x) <= std::fabs(p.y) && std::fabs(p.x) <= std::fabs(p.z) ? Vec3{1, 0, 0}
                    : std::fabs(p.y) <= std::fabs(p.z)                                   ? Vec3{0, 1, 0}
                                                                                          : Vec3{0, 0, 1};
  const Vec3 e1 = normalized(cross(p, axis));
  const Vec3 e2 = cross(p, e1);
  // Radon's rule: barycentric coordinates of the points on (g, h) and their weights, summing to 1.
  constexpr double kSqrt15 = 3.872983346207416885;
  constexpr double kA1 = (6 - kSqrt15) / 21, kA2 = (6 + kSqrt15) / 21;
  constexpr double kW0 = 9.0 / 40, kW1 = (155 - kSqrt15) / 1200, kW2 = (155 + kSqrt15) / 1200;
  constexpr std::array<std::array<double, 3>, 7> kRule{{{1.0 / 3, 1.0 / 3, kW0},
                                                        {kA1, kA1, kW1}, {kA1, 1 - 2 * kA1, kW1}, {1 - 2 * kA1, kA1, kW1},
                                                        {kA2, kA2, kW2}, {kA2, 1 - 2 * kA2, kW2}, {1 - 2 * kA2, kA2, kW2}}};
  auto project = [&](const Vec3& a) {
    const Vec3 da = a - p;  // exact for a near p: neither p's length nor the frame's rounding enters
    const double w = dot(a, p);
    return std::array<double, 2>{dot(da, e1) / w, dot(da, e2) / w};
  };
  const std::size_t d = tris.size();
  double mu = 0, mv = 0;
  std::array<double, 2> g = project(vd.vertex(tris[0]));
  for (std::size_t i = 0; i < d; ++i) {
    const std::array<double, 2> h = project(vd.vertex(tris[i + 1 == d ? 0 : i + 1]));
    const double jac = 0.5 * (g[0] * h[1] - g[1] * h[0]);  // planar area of (0, g, h)
    double su = 0, sv = 0;
    for (const auto& [l1, l2, wk] : kRule) {
      const double u = l1 * g[0] + l2 * h[0], v = l1 * g[1] + l2 * h[1];
      const double f = 1 / ((1 + u * u + v * v) * (1 + u * u + v * v));
      su += wk * u * f;
      sv += wk * v * f;
    }
    mu += jac * su;
    mv += jac * sv;
    g = h;
  }
  return mu * e1 + mv * e2;
}

// The centroids of the cells of `sites` (in storage order) into target/energy; threads split the
// list into contiguous blocks, which keeps each thread's walk spatially coherent.
void centroids(const VoronoiDiagram& vd, std::span<const SiteId> sites, unsigned threads, std::vector<Vec3>& target,
               std::vector<double>& energy, std::vector<std::uint8_t>& defined) {
  const std::size_t n = sites.size();
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(1, n / 4096)));
  parallel_for(n, threads, [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      const SiteId s = sites[i];
      const CellCentroid c = cell_centroid(vd, s);
      target[s] = c.centroid;
      energy[s] = c.energy;
      defined[s] = c.defined;
    }
  });
}

// Rebuilds dt from `wanted` (ids = indices, as dt has no removed site). A target merged into
// another site is refused: it goes back to its old position and the build is redone.
MoveStats rebuild(SphericalDelaunay& dt, const std::vector<Vec3>& wanted) {
  const std::vector<Vec3> old(dt.sites().begin(), dt.sites().end());
  std::vector<Vec3> target = wanted;
  MoveStats stats;
  for (;;) {
    BuildReport report;
    SphericalDelaunay next = SphericalDelaunay::build(target, dt.options(), &report);
    if (report.merges.empty()) {
      dt = std::move(next);
      break;
    }
    // Refuse one move per merge, the merged point's if it moved, else its partner's. Each pass
    // reverts at least one site for good, and the old positions are all separated: it ends.
    std::vector<std::uint32_t> input_of_site(target.size(), kNoIndex);
    std::vector<char> merged(target.size(), 0);
    for (const Merge& m : report.merges) merged[m.input] = 1;
    for (std::uint32_t i = 0; i < target.size(); ++i)
      if (!merged[i] && report.site_of_input[i] != kNoIndex) input_of_site[report.site_of_input[i]] = i;
    for (const Merge& m : report.merges) {
      const std::uint32_t i = m.input, j = input_of_site[m.site];
      const std::uint32_t undo = target[i] != old[i] ? i : j;
      GEOVOR_ASSERT(undo != kNoIndex);
      if (target[undo] == old[undo]) continue;  // already reverted for another merge
      target[undo] = old[undo];
      ++stats.refused;
    }
  }
  for (SiteId s = 0; s < old.size(); ++s) stats.moved += dt.site(s) != old[s];
  return stats;
}

// The positions when the moves from `old` to `wanted` are not all separated by the merge
// distance (chord `md`): while two positions are closer, the move of the larger id of the two
// (of the one that moved, if only one did) is refused, all such pairs at once, and again. One
// rule, whatever order a strategy moves the sites in. `old` is separated, so it ends. Pairs are
// found in a hash grid of cells of side md (rare: only after a strategy refused a move).
std::vector<Vec3> separated_positions(const std::vector<Vec3>& old, const std::vector<Vec3>& wanted, double md) {
  std::vector<Vec3> pos = wanted;
  const double md2 = md * md;
  auto cell = [md](const Vec3& p) {
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(p.x / md)),
                                       static_cast<std::int64_t>(std::floor(p.y / md)),
                                       static_cast<std::int64_t>(std::floor(p.z / md))};
  };
  auto key = [](const std::array<std::int64_t, 3>& c) {
    // Cells of a unit vector are within +-2^25 per axis: 26 bits each.
    return (static_cast<std::uint64_t>(c[0] + (1 << 25)) << 52) ^ (static_cast<std::uint64_t>(c[1] + (1 << 25)) << 26) ^
           static_cast<std::uint64_t>(c[2] + (1 << 25));
  };
  for (;;) {
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
    grid.reserve(pos.size());
    for (std::uint32_t i = 0; i < pos.size(); ++i) grid[key(cell(pos[i]))].push_back(i);
    std::vector<std::uint32_t> undo;
    for (std::uint32_t i = 0; i < pos.size(); ++i) {
      const auto c = cell(pos[i]);
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (std::int64_t dy = -1; dy <= 1; ++dy)
          for (std::int64_t dz = -1; dz <= 1; ++dz) {
            const auto it = grid.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
            if (it == grid.end()) continue;
            for (const std::uint32_t j : it->second) {
              if (j <= i || !(norm2(pos[i] - pos[j]) < md2)) continue;
              const bool moved_i = !(pos[i] == old[i]), moved_j = !(pos[j] == old[j]);
              GEOVOR_ASSERT(moved_i || moved_j);
              undo.push_back(moved_j ? j : i);
            }
          }
    }
    if (undo.empty()) return pos;
    for (const std::uint32_t k : undo) pos[k] = old[k];
  }
}

}  // namespace

const char* to_string(Relocation r) {
  switch (r) {
    case Relocation::Rebuild: return "rebuild";
    case Relocation::Naive: return "naive";
    case Relocation::Filtered: return "filtered";
  }
  return "?";
}

// The centroid formula. Let e be a constant vector and f(x) = e.x on the unit sphere S. f is a
// degree-1 spherical harmonic: Laplace-Beltrami(f) = -2 f. By the divergence theorem on S, for a
// region C bounded by arcs,
//   integral_C f dA = -1/2 integral_C Lap(f) dA = -1/2 integral_dC grad(f).nu ds,
// nu the outward unit conormal (tangent to S, normal to the boundary). grad(f) = e - (e.x) x.
// Along an arc from a to b counter-clockwise seen from outside (C on the left), on the great circle
// of unit normal n (x.n = 0), the direction of travel is t = n x x and the left, x x t, is n
// itself: n points into C and nu = -n. So grad(f).nu = -e.n + (e.x)(x.n) = -e.n, constant on the
// arc, and integral_C e.x dA = 1/2 sum over the arcs of length(arc) e.n. For every e:
//   M = integral_C x dA = 1/2 sum over the edges of angle(a, b) n_ab.
// (Check: the northern hemisphere, bounded by the equator counter-clockwise seen from the north,
// n = z, length 2 pi: M = pi z, and integral of z over it is 2 pi integral_0^1 z dz = pi.)
// The Voronoi edge between s and neighbour w lies in their bisector plane, and the cell of s is
// {x : x.(s - w) >= 0}, so n = normalize(s - w).
CellCentroid cell_centroid(const VoronoiDiagram& vd, SiteId s) {
  CellCentroid c;
  if (!vd.has_cell(s)) return c;
  const Vec3& p = vd.site(s);
  c.centroid = p;
  switch (vd.kind()) {
    case VoronoiDiagram::Kind::Empty:
      return c;
    case VoronoiDiagram::Kind::WholeSphere:
      c.area_sr = 4 * kPi;  // M = 0 by symmetry: no centroid
      c.energy = 2 * c.area_sr;
      return c;
    case VoronoiDiagram::Kind::Hemispheres: {
      const Vec3 n = vd.hemisphere_normal(s);  // the equator of the cell, length 2 pi
      c.area_sr = 2 * kPi;
      c.mass = kPi * n;
      c.energy = 2 * c.area_sr - 2 * dot(p, c.mass);
      c.centroid = n;
      c.defined = true;
      return c;
    }
    case VoronoiDiagram::Kind::Cells:
      break;
  }
  const std::span<const TriId> tris = vd.cell_vertices(s);
  const std::span<const SiteId> nbrs = vd.cell_neighbors(s);
  const std::size_t d = tris.size();
  Vec3 m{};
  double area = 0, perimeter = 0;
  // The diagram starts each cell at its smallest neighbour: the sum's order is canonical.
  for (std::size_t i = 0; i < d; ++i) {
    const Vec3& a = vd.vertex(tris[i]);
    const Vec3& b = vd.vertex(tris[i + 1 == d ? 0 : i + 1]);
    const Vec3 n = normalized(p - vd.site(nbrs[i]));
    const double cos_ab = dot(a, b);
    double theta = std::atan2(dot(cross(a, b), n), cos_ab);
    // Edges turn positively by 0 to 180 degrees: a negative angle is a rounded 0 or 180.
    if (theta < 0) theta = cos_ab < 0 ? kPi : 0;
    m = m + theta * n;
    perimeter += theta;
    if (cos_ab < 0) {
      // Long edge: two fan triangles, as in VoronoiDiagram::cell_area_sr.
      const Vec3 mid = VoronoiDiagram::arc_midpoint(a, b, n);
      area += VoronoiDiagram::triangle_area_sr(p, a, mid) + VoronoiDiagram::triangle_area_sr(p, mid, b);
    } else {
      area += VoronoiDiagram::triangle_area_sr(p, a, b);
    }
  }
  c.mass = 0.5 * m;
  if (d >= 3 && perimeter < kSmallCellPerimeter) {
    const Vec3 radial = dot(c.mass, p) * p;  // ~ the area: no cancellation
    c.mass = radial + small_cell_tangential_mass(vd, p, tris);
  }
  c.area_sr = area;
  c.energy = std::max(0.0, 2 * area - 2 * dot(p, c.mass));  // >= 0; rounding may dip below
  const double m2 = norm2(c.mass);
  // M vanishes only for symmetric cells near the whole sphere; there the direction is noise.
  if (m2 > 1e-24 * area * area) {
    c.centroid = normalized(c.mass);
    c.defined = true;
  }
  return c;
}

double lloyd_energy(const VoronoiDiagram& vd, unsigned threads) {
  std::vector<Vec3> target(vd.site_capacity());
  std::vector<double> energy(vd.site_capacity(), 0.0);
  std::vector<std::uint8_t> defined(vd.site_capacity(), 0);
  centroids(vd, vd.storage_order(), thread_count(threads), target, energy, defined);
  double sum = 0;  // in id order: the same with any number of threads
  for (const double e : energy) sum += e;
  return sum;
}

LloydReport lloyd(SphericalDelaunay& dt, const LloydOptions& options,
                  const std::function<void(const LloydIteration&)>& on_iteration) {
  if (options.iterations < 0)
    throw Error(ErrorCode::InvalidArgument, "lloyd: iterations must be >= 0, got " + std::to_string(options.iterations));
  if (!(options.tolerance_rad >= 0))
    throw Error(ErrorCode::InvalidArgument, "lloyd: tolerance_rad must be >= 0");
  if (options.relocation == Relocation::Rebuild && dt.site_capacity() != dt.num_sites())
    throw Error(ErrorCode::InvalidArgument,
                "lloyd: the rebuild strategy needs a triangulation without removed sites (it would renumber them)");
  const unsigned threads = thread_count(options.threads);
  const std::size_t cap = dt.site_capacity();
  std::vector<Vec3> target(cap), old(cap);
  std::vector<double> energy(cap, 0.0);
  std::vector<std::uint8_t> defined(cap, 0);
  LloydReport report;
  VoronoiDiagram vd;
  for (int it = 1; it <= options.iterations; ++it) {
    LloydIteration r;
    r.iteration = it;
    const auto t0 = Clock::now();
    std::copy(dt.sites().begin(), dt.sites().end(), old.begin());
    std::copy(old.begin(), old.end(), target.begin());  // removed and undefined sites stay
    std::fill(energy.begin(), energy.end(), 0.0);
    std::fill(defined.begin(), defined.end(), std::uint8_t{1});
    vd.assign(dt);  // its storage reused from the last iteration
    centroids(vd, vd.storage_order(), threads, target, energy, defined);
    for (SiteId s = 0; s < cap; ++s) {
      r.energy += energy[s];
      r.undefined += defined[s] == 0;
    }
    const auto t1 = Clock::now();
    switch (options.relocation) {
      case Relocation::Rebuild:
        r.moves = rebuild(dt, target);
        break;
      case Relocation::Naive: {
        RelocationOptions naive;
        naive.filter = false;
        naive.flips = false;
        r.moves = dt.move_all(target, naive);
        break;
      }
      case Relocation::Filtered:
        r.moves = dt.move_all(target);
        break;
    }
    // Which of two moves within the merge distance of each other is refused depended on the
    // strategy's order: then the positions are decided by one rule, and the triangulation
    // (unique for them) is built from them. Not with removed sites, which a build renumbers.
    if (r.moves.refused > 0 && dt.site_capacity() == dt.num_sites()) {
      const std::vector<Vec3> pos = separated_positions(old, target, dt.options().merge_distance);
      BuildReport build_report;
      dt = SphericalDelaunay::build(pos, dt.options(), &build_report);
      GEOVOR_ASSERT(build_report.merges.empty());
      r.moves.moved = r.moves.refused = 0;
      for (SiteId s = 0; s < cap; ++s) {
        r.moves.moved += !(pos[s] == old[s]);
        r.moves.refused += !(pos[s] == target[s]);
      }
      r.moves.rebuilt = r.moves.moved;
    }
    const auto t2 = Clock::now();
    double sum = 0;
    for (SiteId s = 0; s < cap; ++s) {
      if (!dt.is_live(s)) continue;
      const double a = angle_between(old[s], dt.site(s));
      sum += a;
      r.max_move_rad = std::max(r.max_move_rad, a);
    }
    r.mean_move_rad = dt.num_sites() ? sum / static_cast<double>(dt.num_sites()) : 0;
    r.max_move_m = r.max_move_rad * SiteEncoder::kEarthRadiusM;
    r.mean_move_m = r.mean_move_rad * SiteEncoder::kEarthRadiusM;
    const auto t3 = Clock::now();
    r.centroid_seconds = seconds_between(t0, t1);
    r.relocation_seconds = seconds_between(t1, t2);
    r.seconds = seconds_between(t0, t3);
    report.iterations.push_back(r);
    if (on_iteration) on_iteration(r);
    if (options.tolerance_rad > 0 && r.max_move_rad <= options.tolerance_rad) break;
  }
  report.final_energy = lloyd_energy(VoronoiDiagram(dt), threads);
  return report;
}

}  // namespace geovor
