/// \file cgal_hull_oracle.cpp
/// \brief CGAL side of the lifted-hull oracle (exact constructions: a file of its own).
#include "support/cgal_hull_oracle.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <map>

namespace geovor::testing {

std::vector<std::array<std::uint32_t, 3>> cgal_lifted_hull(std::span<const Vec3> points,
                                                           std::span<const double> lifts,
                                                           std::vector<std::uint32_t>* vertices) {
  using K = CGAL::Exact_predicates_exact_constructions_kernel;
  using Point = K::Point_3;
  using RT = K::RT;
  std::vector<Point> lifted;
  std::map<Point, std::uint32_t> index;
  for (std::size_t i = 0; i < points.size(); ++i) {
    lifted.emplace_back(RT(points[i].x), RT(points[i].y), RT(points[i].z), RT(lifts[i]));
    index.emplace(lifted.back(), static_cast<std::uint32_t>(i));
  }
  CGAL::Surface_mesh<Point> hull;
  CGAL::convex_hull_3(lifted.begin(), lifted.end(), hull);
  std::vector<std::array<std::uint32_t, 3>> out;
  for (const auto f : hull.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (const auto v : hull.vertices_around_face(hull.halfedge(f))) t[k++] = index.at(hull.point(v));
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  if (vertices) {
    vertices->clear();
    for (const auto v : hull.vertices()) vertices->push_back(index.at(hull.point(v)));
    std::sort(vertices->begin(), vertices->end());
  }
  return out;
}

}  // namespace geovor::testing
