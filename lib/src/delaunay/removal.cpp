// Removing a site: its star is replaced by the faces of the hull of its link that it sees,
// found by the same exact code. Why that fills the hole: docs/delaunay.md, "Removal".
#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "geovor/core/assert.hpp"
#include "geovor/core/error.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/kernel/predicates.hpp"

namespace geovor {

void SphericalDelaunay::remove(SiteId s) {
  require_unweighted("remove");
  if (!is_live(s)) throw Error(ErrorCode::InvalidArgument, "remove: site " + std::to_string(s) + " is not live");
  touch();
  remove_keeping_tolerances(s);
}

void SphericalDelaunay::remove_site(SiteId s) {
  GEOVOR_ASSERT(priority_.empty());
  if (num_live_ <= 3) {
    // Fewer than three sites remain: no triangle.
    triangles_.clear();
    halfedges_.clear();
    for (SiteId t = 0; t < sites_.size(); ++t)
      if (alive(t)) site_edge_[t] = kNoIndex;
    site_edge_[s] = kRemoved;
    --num_live_;
    last_site_ = any_live_site();
    return;
  }

  // The star of s: link vertices w_i counter-clockwise, the star triangles (s, w_i, w_i+1), and
  // the outer half-edges w_i+1 -> w_i across the link.
  std::vector<SiteId> link;
  std::vector<TriId> star;
  std::vector<HalfedgeId> outer;
  const HalfedgeId e0 = site_edge_[s];
  HalfedgeId e = e0;
  do {
    link.push_back(triangles_[next_halfedge(e)]);
    star.push_back(tri_of(e));
    outer.push_back(halfedges_[next_halfedge(e)]);
    e = next_around_site(e);
  } while (e != e0);
  const std::size_t k = link.size();

  // The hole is filled by the faces of the hull of the link that s sees (docs/delaunay.md), built
  // by the same exact code with the global ids as perturbation priorities.
  SphericalDelaunay hull(options_);
  hull.sites_.reserve(k);
  hull.priority_ = link;
  for (std::size_t i = 0; i < k; ++i) {
    hull.sites_.push_back(sites_[link[i]]);
    hull.site_edge_.push_back(kRemoved);
    const InsertResult r = hull.insert_site(static_cast<SiteId>(i), hull.last_site_);
    GEOVOR_ASSERT(!r.merged);
  }
  std::vector<TriId> fill;
  std::vector<TriId> slot_of(hull.num_triangles(), kNoIndex);
  for (TriId t = 0; t < hull.num_triangles(); ++t) {
    const SiteId a = link[hull.triangles_[3 * t]], b = link[hull.triangles_[3 * t + 1]],
                 c = link[hull.triangles_[3 * t + 2]];
    if (kernel::perturbed_in_sphere(sites_[a], priority(a), sites_[b], priority(b), sites_[c],
                                    priority(c), sites_[s], priority(s)) == Sign::Positive) {
      slot_of[t] = star[fill.size()];
      fill.push_back(t);
    }
  }
  GEOVOR_ASSERT(fill.size() == k - 2);

  for (const TriId ht : fill) {
    const TriId t = slot_of[ht];
    for (int j = 0; j < 3; ++j) {
      const HalfedgeId he = 3 * ht + j;
      const std::uint32_t la = hull.triangles_[he];
      triangles_[3 * t + j] = link[la];
      const HalfedgeId htw = hull.halfedges_[he];
      if (slot_of[tri_of(htw)] != kNoIndex) {
        halfedges_[3 * t + j] = 3 * slot_of[tri_of(htw)] + htw % 3;
      } else {
        // A boundary edge of the hole: w_la -> w_la+1, glued to the outer half-edge.
        GEOVOR_ASSERT(hull.triangles_[next_halfedge(he)] == (la + 1) % k);
        halfedges_[3 * t + j] = outer[la];
        halfedges_[outer[la]] = 3 * t + j;
      }
    }
  }
  for (std::size_t i = 0; i < k; ++i) site_edge_[link[(i + 1) % k]] = outer[i];
  site_edge_[s] = kRemoved;
  --num_live_;
  last_site_ = link[0];

  // Two star slots are left over: fill them with the last triangles of the arrays.
  free_triangle_slots({star.begin() + static_cast<std::ptrdiff_t>(k - 2), star.end()});
}

void SphericalDelaunay::move_triangle(TriId from, TriId to) {
  for (int j = 0; j < 3; ++j) {
    const HalfedgeId ef = 3 * from + j, et = 3 * to + j;
    triangles_[et] = triangles_[ef];
    halfedges_[et] = halfedges_[ef];
    halfedges_[halfedges_[et]] = et;
    if (site_edge_[triangles_[et]] == ef) site_edge_[triangles_[et]] = et;
  }
}

}  // namespace geovor
