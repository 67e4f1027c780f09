#include "geovor/voronoi/voronoi_diagram.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>
#include <numbers>

#include "geovor/core/assert.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/core/small_angle.hpp"
#include "geovor/delaunay/halfedge.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"

namespace geovor {
namespace {

Vec3 normalized(const Vec3& v) { return (1 / std::sqrt(norm2(v))) * v; }

template <class T, class A>
std::size_t bytes_of(const std::vector<T, A>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace

namespace {

// p q - r s within 2 ulps (Kahan's algorithm with fused multiply-adds).
inline double diff_of_products(double p, double q, double r, double s) {
  const double rs = r * s;
  const double err = std::fma(-r, s, rs);
  return std::fma(p, q, -rs) + err;
}

// Of the triangle a, b, c with squared sides lab = |b - a|^2, lbc, lca: the corner opposite the
// longest side (0: a, 1: b, 2: c; ties to the earlier corner), where the two shortest sides
// meet. By index, not by branches: which side is longest is a coin toss per triangle, and the
// mispredicted branches had cost a third of triangle_area_sr's time.
inline int corner_opposite_longest(double lab, double lbc, double lca) {
  const int not_a = (lbc < lab) | (lbc < lca), not_b = lca < lab;
  return not_a * (1 + not_b);
}

}  // namespace

Vec3 VoronoiDiagram::circumcenter(const Vec3& a, const Vec3& b, const Vec3& c) {
  // Differences first: for nearby sites they are exact (Sterbenz), so the direction is accurate.
  // From the corner opposite the longest side ((b - a) x (c - a) is the same at every corner):
  // there the two sides are the shortest. From a far corner they are long, rounded and, for
  // sites on one great circle, nearly parallel: two sites 0.7 m apart and a third 76 degrees
  // away gave a vertex 4e-10 radians (3 mm) off their bisector, across the braid of their
  // lunes' tips (the sides' chords crossed there).
  const Vec3 ab = b - a, bc = c - b, ca = a - c;
  // The corner's sides: u out of it, -w into it (selected, not indexed: no copies through memory).
  const int k = corner_opposite_longest(norm2(ab), norm2(bc), norm2(ca));
  const Vec3 u = k == 0 ? ab : k == 1 ? bc : ca;
  const Vec3 w = -1.0 * (k == 0 ? ca : k == 1 ? ab : bc);
  Vec3 n = cross(u, w);
  // A sliver (sides within 1e-4 radians of parallel): the products cancel, and the plain cross
  // product loses its digits (the vertices of thin lunes of sites on one meridian, centimetres
  // off); each component to 2 ulps instead.
  if (norm2(n) < 1e-8 * norm2(u) * norm2(w))
    n = {diff_of_products(u.y, w.z, u.z, w.y), diff_of_products(u.z, w.x, u.x, w.z),
         diff_of_products(u.x, w.y, u.y, w.x)};
  const double n2 = norm2(n);
  // Distinct points of the sphere are never collinear in R^3.
  GEOVOR_ASSERT(n2 > 0);
  // Division, not a reciprocal: sqrt(c^2) = |c|, so a vertex on an axis (sites on the equator)
  // is exactly that axis.
  const double len = std::sqrt(n2);
  return {n.x / len, n.y / len, n.z / len};
}

Vec3 VoronoiDiagram::circumcenter(const SphericalDelaunay& dt, SiteId u, SiteId v, SiteId w) {
  // Rotated to start at the smallest id, so that a vertex's bits do not depend on how the
  // triangulation stores its triangles (Lloyd's iterations give the same result whether the
  // triangulation is rebuilt or updated).
  const SiteId s[3] = {u, v, w};
  const int k = u < v ? (u < w ? 0 : 2) : (v < w ? 1 : 2);
  const SiteId a = s[k], b = s[(k + 1) % 3], c = s[(k + 2) % 3];
  const double ca = dt.lift(a), cb = dt.lift(b), cc = dt.lift(c);
  // Equal lifts: the Voronoi vertex itself, the same bits as without weights.
  if (ca == cb && cb == cc) return circumcenter(dt.site(a), dt.site(b), dt.site(c));
  return power_vertex(dt.site(a), ca, dt.site(b), cb, dt.site(c), cc);
}

Vec3 VoronoiDiagram::power_vertex(const Vec3& a, double ca, const Vec3& b, double cb, const Vec3& c, double cc) {
  // The normal of the plane through a / ca, b / cb, c / cc, scaled by ca cb cc:
  // ca (b x c) + cb (c x a) + cc (a x b) = ca (b - a) x (c - a) + (cb - ca) (c x a) + (cc - ca) (a x b),
  // whose first term is the circumcentre's, accurate for nearby sites.
  const Vec3 centre = circumcenter(a, b, c);
  const Vec3 ab = b - a, ac = c - a;
  const double len = std::sqrt(norm2(cross(ab, ac)));
  const Vec3 n = (ca * len) * centre + (cb - ca) * cross(c, a) + (cc - ca) * cross(a, b);
  const double n2 = norm2(n);
  GEOVOR_ASSERT(n2 > 0);
  const double l = std::sqrt(n2);
  return {n.x / l, n.y / l, n.z / l};
}

Vec3 VoronoiDiagram::arc_midpoint(const Vec3& a, const Vec3& b, const Vec3& axis) {
  const double c = dot(a, b);
  // |a + b| >= 1 below 120 degrees: the chord midpoint is accurate and on the arc.
  if (c > -0.5) return normalized(a + b);
  // Long arcs: rotate a about the axis by half the signed angle. The sine comes from the axis,
  // so a 180-degree arc (a + b ~ 0) still has a well-defined side.
  double theta = std::atan2(dot(cross(a, b), axis), c);
  // Edges turn positively by at most 180 degrees; a negative angle here is a rounded 180.
  if (theta < 0) theta = std::numbers::pi;
  const Vec3 t = normalized(cross(axis, a));  // direction of travel at a
  return normalized(std::cos(theta / 2) * a + std::sin(theta / 2) * t);
}

namespace {

// 2 atan(det / den), the solid angle of a triangle from Van Oosterom and Strackee's quotient.
inline double solid_angle(double det, double den) {
  if (den > 0 && std::fabs(det) <= kSmallAngleMax * den) return 2 * atan_small(det / den);
  return 2 * std::atan2(det, den);
}

// det(a, b, c) at the corner opposite the longest side (triangle_area_sr), from the sides
// ab = b - a, bc = c - b, ca = a - c and their squared lengths.
inline double det_at_shortest_sides(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& ab, const Vec3& bc,
                                    const Vec3& ca, double lab, double lbc, double lca) {
  const Vec3* const corner[3] = {&a, &b, &c};
  const Vec3 from[3] = {ab, bc, ca}, to[3] = {ca, ab, bc};  // the corner's sides: from, -to
  const int k = corner_opposite_longest(lab, lbc, lca);
  return dot(*corner[k], cross(from[k], -1.0 * to[k]));
}

// triangle_area_sr(apex, b, c) bit for bit, given what depends on one corner only: db = b - apex,
// dc = c - apex, their squared lengths nb, nc, and sb = apex.b, sc = apex.c (a fan's triangles
// share them), and bc_dot = b.c. As triangle_area_sr with a = apex: ab = db, ca = -dc (negation
// is exact), |ca|^2 = nc.
inline double fan_triangle_area_sr(const Vec3& apex, const Vec3& b, const Vec3& c, const Vec3& db, const Vec3& dc,
                                   double nb, double nc, double sb, double sc, double bc_dot) {
  const Vec3 bc = c - b;
  return solid_angle(det_at_shortest_sides(apex, b, c, db, bc, -1.0 * dc, nb, norm2(bc), nc), 1 + sb + bc_dot + sc);
}

}  // namespace

double VoronoiDiagram::triangle_area_sr(const Vec3& a, const Vec3& b, const Vec3& c) {
  // tan(omega / 2) = det(a, b, c) / (1 + a.b + b.c + c.a): atan2 keeps the full range (-2pi, 2pi);
  // the small triangles of most cells take the polynomial instead (same value within an ulp).
  // det(a, b, c) = p . ((q - p) x (r - p)) for the corner p opposite the longest side: the two
  // sides there are exact differences for a small triangle and not nearly parallel for a
  // sliver, so det keeps its digits (a . (b x c) lost them all below 1e-15 sr).
  const Vec3 ab = b - a, bc = c - b, ca = a - c;
  return solid_angle(det_at_shortest_sides(a, b, c, ab, bc, ca, norm2(ab), norm2(bc), norm2(ca)),
                     1 + dot(a, b) + dot(b, c) + dot(c, a));
}

VoronoiDiagram::VoronoiDiagram(const SphericalDelaunay& dt, unsigned threads) { assign(dt, threads); }

void VoronoiDiagram::assign(const SphericalDelaunay& dt, unsigned threads) {
  const std::size_t cap = dt.site_capacity();
  num_cells_ = dt.num_sites();
  const std::size_t nt = num_cells_ >= 3 ? dt.num_triangles() : 0;
  const std::span<const SiteId> tri_sites = dt.triangles();
  threads = thread_count(threads);
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, std::max<std::size_t>(1, nt / 32768)));
  // The circumcentres, of triangles [begin, end).
  auto centres = [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      const SiteId* v = &tri_sites[3 * t];
      vertices_[t] = circumcenter(dt, v[0], v[1], v[2]);
    }
  };
  vertices_.clear();
  // With several threads, the others compute the vertices, in chunks taken in turn, while this
  // one does the sequential scans below and then takes the chunks left; they only write
  // vertices_, which nothing else reads before they are joined. With two, the other one also
  // sizes vertices_ (so that its pages are first touched there) before any chunk is taken.
  constexpr std::size_t kCentreChunk = 8192;
  std::atomic<std::size_t> next_chunk{0};
  std::atomic<bool> sized{threads > 2};
  auto take_centres = [&] {
    sized.wait(false);
    if (vertices_.size() != nt) return;  // the sizing failed: its task rethrows on wait()
    for (;;) {
      const std::size_t begin = kCentreChunk * next_chunk.fetch_add(1, std::memory_order_relaxed);
      if (begin >= nt) return;
      centres(begin, std::min(nt, begin + kCentreChunk));
    }
  };
  TaskGroup centre_tasks;
  if (threads > 2) vertices_.resize(nt);
  for (unsigned i = 1; i < threads; ++i)
    centre_tasks.run([&, i] {
      if (i == 1 && threads == 2) {
        struct Signal {
          std::atomic<bool>& sized;
          ~Signal() {
            sized.store(true);
            sized.notify_all();
          }
        } signal{sized};
        vertices_.resize(nt);
      }
      take_centres();
    });

  sites_.assign(dt.sites().begin(), dt.sites().end());
  lifts_.assign(dt.lifts().begin(), dt.lifts().end());
  live_.assign(cap, 0);
  cells_.assign(cap, Range{});
  order_.clear();
  cell_tris_.clear();
  cell_nbrs_.clear();
  pair_[0] = pair_[1] = kNoIndex;
  std::size_t found = 0;
  for (SiteId s = 0; s < cap; ++s) {
    if (dt.is_live(s)) {
      live_[s] = 1;
      if (found < 2) pair_[found] = s;
      ++found;
    }
  }
  GEOVOR_ASSERT(found == num_cells_);
  if (num_cells_ == 0) {
    kind_ = Kind::Empty;
    return;
  }
  if (num_cells_ <= 2) {
    kind_ = num_cells_ == 1 ? Kind::WholeSphere : Kind::Hemispheres;
    for (std::size_t i = 0; i < num_cells_; ++i) order_.push_back(pair_[i]);
    return;
  }
  kind_ = Kind::Cells;
  pair_[0] = pair_[1] = kNoIndex;
  GEOVOR_ASSERT(nt == 2 * num_cells_ - 4);
  if (threads == 1) {
    vertices_.resize(nt);
    centres(0, nt);
  }

  // Degrees and the storage order, by one sequential scan of the triangles (which the
  // triangulation keeps in a spatially coherent order); then each star is walked once, counter-
  // clockwise, in that order, so the walks stay in cache.
  std::vector<std::uint32_t>& degree = degree_;
  degree.assign(cap, 0);
  order_.reserve(num_cells_);
  for (const SiteId s : tri_sites) {
    if (degree[s]++ == 0) order_.push_back(s);
  }
  GEOVOR_ASSERT(order_.size() == num_cells_);
  std::uint32_t k = 0;
  for (const SiteId s : order_) {
    cells_[s] = {k, k + degree[s]};
    k += degree[s];
  }
  GEOVOR_ASSERT(k == 3 * nt);
  cell_tris_.resize(3 * nt);
  cell_nbrs_.resize(3 * nt);
  // The stars, in chunks of the storage order (the centres finished and joined first: they
  // share the cores).
  if (threads > 1) take_centres();
  centre_tasks.wait();
  auto stars = [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t j = begin; j < end; ++j) {
      const SiteId s = order_[j];
      // Start at the edge to the smallest neighbour: the cell's lists (and the polygons and sums
      // built from them) then do not depend on how the triangulation stores its stars.
      HalfedgeId e0 = dt.site_edge(s);
      GEOVOR_ASSERT(e0 != kNoIndex);
      for (HalfedgeId e = dt.next_around_site(e0), first = e0; e != first; e = dt.next_around_site(e))
        if (tri_sites[prev_halfedge(e)] < tri_sites[prev_halfedge(e0)]) e0 = e;
      std::uint32_t i = cells_[s].begin;
      HalfedgeId e = e0;
      do {
        GEOVOR_ASSERT(i < cells_[s].end);
        cell_tris_[i] = tri_of(e);
        // prev(e) runs from the neighbour w into s; its twin, the next half-edge around s, lies in
        // the next triangle: the edge vertex(t_i) -> vertex(t_i+1) is dual to (s, w).
        cell_nbrs_[i] = tri_sites[prev_halfedge(e)];
        ++i;
        e = dt.next_around_site(e);
      } while (e != e0);
      GEOVOR_ASSERT(i == cells_[s].end);  // the star is one cycle through every triangle of s
    }
  };
  parallel_chunks(order_.size(), 4096, threads, stars);
}

void VoronoiDiagram::prefetch(SiteId s, int stage) const {
  if (kind_ != Kind::Cells || s >= cells_.size()) return;
  if (stage == 0) {
    __builtin_prefetch(&live_[s]);
    __builtin_prefetch(&cells_[s]);
    return;
  }
  const Range r = cells_[s];
  if (r.end <= r.begin) return;
  // The lists' first and last lines (a cell has about six entries: one or two lines each).
  __builtin_prefetch(&cell_nbrs_[r.begin]);
  __builtin_prefetch(&cell_nbrs_[r.end - 1]);
  __builtin_prefetch(&cell_tris_[r.begin]);
  __builtin_prefetch(&cell_tris_[r.end - 1]);
}

Vec3 VoronoiDiagram::hemisphere_normal(SiteId s) const {
  GEOVOR_ASSERT(kind_ == Kind::Hemispheres && has_cell(s));
  const SiteId other = s == pair_[0] ? pair_[1] : pair_[0];
  return bisector_normal(s, other);
}

Vec3 VoronoiDiagram::bisector_normal(SiteId s, SiteId other) const {
  if (lifts_.empty() || lifts_[s] == lifts_[other]) return normalized(sites_[s] - sites_[other]);
  // The power bisector's plane x . (q_s - q_other) = 0, scaled by both lifts.
  return normalized(lifts_[other] * sites_[s] - lifts_[s] * sites_[other]);
}

double VoronoiDiagram::cell_area_sr(SiteId s) const {
  if (!has_cell(s)) return 0;
  switch (kind_) {
    case Kind::Empty:
      return 0;
    case Kind::WholeSphere:
      return 4 * std::numbers::pi;
    case Kind::Hemispheres:
      return 2 * std::numbers::pi;
    case Kind::Cells:
      break;
  }
  const std::span<const TriId> tris = cell_vertices(s);
  const std::span<const SiteId> nbrs = cell_neighbors(s);
  const Vec3& site = sites_[s];
  const std::size_t d = tris.size();
  // The fan's apex: the site, unless a vertex lies far from it (a lune of (nearly) co-circular
  // sites reaching (nearly) the site's antipode). A fan triangle with two (nearly) antipodal
  // corners has both terms of the Van Oosterom-Strackee quotient near 0, and lost up to 1e-5 of
  // the cell; the apex is then the direction of the edges' midpoints summed by length, inside it.
  // A power cell need not hold its site: its apex is always that direction.
  Vec3 apex = site;
  bool far = !lifts_.empty();
  for (const TriId t : tris) far |= dot(site, vertices_[t]) < -0.5;
  auto half = [&](std::size_t i, const Vec3& a, const Vec3& b) {
    return dot(a, b) < 0 ? arc_midpoint(a, b, bisector_normal(s, nbrs[i])) : normalized(a + b);
  };
  if (far) {
    Vec3 sum;
    for (std::size_t i = 0; i < d; ++i) {
      const Vec3& a = vertices_[tris[i]];
      const Vec3& b = vertices_[tris[i + 1 == d ? 0 : i + 1]];
      if (a == b) continue;
      sum = sum + std::sqrt(norm2(a - b)) * half(i, a, b);  // by length: tiny edges count little
    }
    if (norm2(sum) > 1e-6) apex = normalized(sum);
  }
  // The fan's triangles share their sides from the apex: each vertex's difference, squared
  // length and product with the apex are computed once (fan_triangle_area_sr).
  struct Corner {
    Vec3 d;
    double n, s;
  };
  auto corner = [&apex](const Vec3& v) {
    const Vec3 dv = v - apex;
    return Corner{dv, norm2(dv), dot(apex, v)};
  };
  const Vec3& first = vertices_[tris[0]];
  const Corner first_corner = corner(first);
  Corner here = first_corner;
  double area = 0;
  for (std::size_t i = 0; i < d; ++i) {
    const Vec3& a = vertices_[tris[i]];
    const Vec3& b = i + 1 == d ? first : vertices_[tris[i + 1]];
    const Corner next = i + 1 == d ? first_corner : corner(b);
    const double ab_dot = dot(a, b);
    if (ab_dot < 0) {
      // Long edge: two halves, so that no fan triangle has a side near 180 degrees.
      const Vec3 m = half(i, a, b);
      area += triangle_area_sr(apex, a, m) + triangle_area_sr(apex, m, b);
    } else {
      area += fan_triangle_area_sr(apex, a, b, here.d, next.d, here.n, next.n, here.s, next.s, ab_dot);
    }
    here = next;
  }
  return area;
}

std::size_t VoronoiDiagram::memory_bytes() const {
  return bytes_of(sites_) + bytes_of(lifts_) + bytes_of(live_) + bytes_of(vertices_) + bytes_of(cells_) +
         bytes_of(order_) + bytes_of(cell_tris_) + bytes_of(cell_nbrs_);
}

}  // namespace geovor
