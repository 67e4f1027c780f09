/// \file cgal_oracle.cpp
/// \brief CGAL side of the oracle; the only support file that includes CGAL.
#include "support/cgal_oracle.hpp"

#include <CGAL/Delaunay_triangulation_on_sphere_2.h>
#include <CGAL/Delaunay_triangulation_on_sphere_traits_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_on_sphere_face_base_2.h>
#include <CGAL/Triangulation_on_sphere_vertex_base_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/spatial_sort_on_sphere.h>

#include <boost/iterator/transform_iterator.hpp>

#include <algorithm>
#include <chrono>

namespace geovor::testing {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Traits = CGAL::Delaunay_triangulation_on_sphere_traits_2<K>;
using Point = Traits::Point_on_sphere_2;  // K::Point_3

// The vertex info maps a CGAL vertex back to its input index.
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, Traits,
                                                       CGAL::Triangulation_on_sphere_vertex_base_2<Traits>>;
using Fb = CGAL::Triangulation_on_sphere_face_base_2<Traits>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using IndexedDt = CGAL::Delaunay_triangulation_on_sphere_2<Traits, Tds>;
using PlainDt = CGAL::Delaunay_triangulation_on_sphere_2<Traits>;

// Unit sphere at the origin, stated explicitly so the precision bounds are those of radius 1.
Traits unit_sphere_traits() { return Traits(Point(0, 0, 0), 1.0); }

Point to_point(const Vec3& v) { return Point(v.x, v.y, v.z); }

// A point that remembers its input index through CGAL's spatial sort (as CGAL's Point_3_with_iterator).
struct IndexedPoint : Point {
  IndexedPoint(const Vec3& v, std::uint32_t i) : Point(v.x, v.y, v.z), index(i) {}
  std::uint32_t index;
};

struct ToPoint {
  Point operator()(const Vec3& v) const { return to_point(v); }
};

}  // namespace

std::vector<Tri> cgal_triangles(std::span<const Vec3> points, std::vector<std::uint32_t>* rejected) {
  const Traits traits = unit_sphere_traits();
  std::vector<IndexedPoint> order;
  order.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) order.emplace_back(points[i], static_cast<std::uint32_t>(i));
  // Same order as CGAL's range insert (minus its extra random shuffle), so the walks stay short.
  CGAL::spatial_sort_on_sphere(order.begin(), order.end(), traits, 1.0, traits.center());

  IndexedDt dt(traits);
  std::vector<std::uint32_t> lost;
  IndexedDt::Face_handle hint;
  for (const IndexedPoint& p : order) {
    const std::size_t before = dt.number_of_vertices();
    const IndexedDt::Vertex_handle v = dt.insert(static_cast<const Point&>(p), hint);
    if (v == IndexedDt::Vertex_handle()) {  // not on the sphere
      lost.push_back(p.index);
      continue;
    }
    if (dt.number_of_vertices() > before) {
      v->info() = p.index;
    } else if (v->point() == static_cast<const Point&>(p) && p.index < v->info()) {
      // Exact duplicates keep the smallest index, so the labels do not depend on CGAL's order.
      lost.push_back(v->info());
      v->info() = p.index;
    } else {  // later duplicate, or too close: CGAL returned the existing vertex
      lost.push_back(p.index);
    }
    hint = v->face();
  }

  std::vector<Tri> tris;
  if (dt.dimension() == 2) {
    tris.reserve(dt.number_of_faces());
    for (auto f = dt.all_faces_begin(); f != dt.all_faces_end(); ++f) {
      Tri t{f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()};
      // Rotation (not sorting) keeps the orientation.
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      tris.push_back(t);
    }
    std::sort(tris.begin(), tris.end());
  }
  if (rejected != nullptr) {
    std::sort(lost.begin(), lost.end());
    *rejected = std::move(lost);
  }
  return tris;
}

double cgal_build_seconds(std::span<const Vec3> points, std::size_t* num_vertices) {
  // The transform iterator has value type Point_3, so CGAL's Point_3 range insert is chosen and
  // converts while copying into its own buffer.
  const auto first = boost::make_transform_iterator(points.data(), ToPoint{});
  const auto last = boost::make_transform_iterator(points.data() + points.size(), ToPoint{});
  const auto start = std::chrono::steady_clock::now();
  PlainDt dt(unit_sphere_traits());
  dt.insert(first, last);
  const auto stop = std::chrono::steady_clock::now();
  if (num_vertices != nullptr) *num_vertices = dt.number_of_vertices();
  return std::chrono::duration<double>(stop - start).count();
}

struct CgalSphereLocator::Impl {
  Impl() : dt(unit_sphere_traits()) {}
  IndexedDt dt;
};

CgalSphereLocator::CgalSphereLocator(std::span<const Vec3> points, double* build_seconds)
    : impl_(std::make_unique<Impl>()) {
  const auto start = std::chrono::steady_clock::now();
  const Traits traits = unit_sphere_traits();
  std::vector<IndexedPoint> order;
  order.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) order.emplace_back(points[i], static_cast<std::uint32_t>(i));
  CGAL::spatial_sort_on_sphere(order.begin(), order.end(), traits, 1.0, traits.center());
  IndexedDt& dt = impl_->dt;
  IndexedDt::Face_handle hint;
  for (const IndexedPoint& p : order) {
    const std::size_t before = dt.number_of_vertices();
    const IndexedDt::Vertex_handle v = dt.insert(static_cast<const Point&>(p), hint);
    if (v == IndexedDt::Vertex_handle()) continue;  // not on the sphere
    if (dt.number_of_vertices() > before || (v->point() == static_cast<const Point&>(p) && p.index < v->info()))
      v->info() = p.index;  // new vertex, or an exact duplicate with a smaller index
    hint = v->face();
  }
  const auto stop = std::chrono::steady_clock::now();
  if (build_seconds != nullptr) *build_seconds = std::chrono::duration<double>(stop - start).count();
}

CgalSphereLocator::~CgalSphereLocator() = default;

std::size_t CgalSphereLocator::num_vertices() const { return impl_->dt.number_of_vertices(); }

double CgalSphereLocator::locate_seconds(std::span<const Vec3> queries, std::uint64_t* checksum,
                                         double max_seconds, std::size_t* done) const {
  const IndexedDt& dt = impl_->dt;
  std::uint64_t sum = 0;
  std::size_t i = 0;
  const auto start = std::chrono::steady_clock::now();
  auto stop = start;
  IndexedDt::Face_handle hint;
  while (i < queries.size()) {
    const std::size_t end = std::min(queries.size(), i + 1024);
    for (; i < end; ++i) {
      const IndexedDt::Face_handle f = dt.locate(to_point(queries[i]), hint);
      if (f != IndexedDt::Face_handle()) {
        sum += std::uint64_t{f->vertex(0)->info()} + f->vertex(1)->info() + f->vertex(2)->info();
        hint = f;
      }
    }
    stop = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(stop - start).count() > max_seconds) break;
  }
  if (checksum != nullptr) *checksum = sum;
  if (done != nullptr) *done = i;
  return std::chrono::duration<double>(stop - start).count();
}

double cgal_locate_seconds(std::span<const Vec3> points, std::span<const Vec3> queries, std::uint64_t* checksum) {
  const CgalSphereLocator locator(points);
  return locator.locate_seconds(queries, checksum);
}

}  // namespace geovor::testing
