/// \file cgal_oracle.hpp
/// \brief Independent oracle: CGAL's own Delaunay triangulation on the sphere, as sorted index triples.
///
/// No CGAL type appears here so that tests and the benchmark need not include CGAL (GPL) headers.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "geovor/core/types.hpp"

namespace geovor::testing {

using Tri = std::array<std::uint32_t, 3>;

/// Triangles of CGAL's Delaunay_triangulation_on_sphere_2<Delaunay_triangulation_on_sphere_traits_2<Epick>>
/// built on `points` (unit vectors; CGAL sphere centre (0,0,0), radius 1), as indices into `points`, each
/// rotated so that its smallest index comes first (orientation kept: counter-clockwise seen from outside),
/// the list sorted. Includes CGAL's ghost faces (all faces of the TDS) when dimension()==2, else empty.
/// Points CGAL rejects (too close, not on sphere, exact duplicates) are reported in `rejected`
/// (sorted input indices) if non-null.
///
/// Of exact duplicates, the smallest index is the vertex. Otherwise insertion follows CGAL's
/// spatial_sort_on_sphere (fixed seed), so which one of two too-close points survives is
/// deterministic but not necessarily the smaller index. CGAL's "too close" is a chord <= 2^-23,
/// twice geovor's kMinSeparation: points 2^-24..2^-23 apart are merged by CGAL only.
/// All sites on one plane (a great or small circle) leave CGAL in dimension 1: no triangles, and
/// its 1D insertion is quadratic (20,000 points on the equator take ~17 s), so keep such n small.
std::vector<Tri> cgal_triangles(std::span<const Vec3> points,
                                std::vector<std::uint32_t>* rejected = nullptr);

/// CGAL's build time (seconds) for the benchmark, inserting the range with CGAL's own spatial sort
/// (insert(begin, end)); the conversion to CGAL points is done lazily inside CGAL's own copy, so
/// it is timed and adds no extra buffer to the memory peak.
double cgal_build_seconds(std::span<const Vec3> points, std::size_t* num_vertices = nullptr);

/// CGAL's point location on the sphere, for the locate benchmark: a Delaunay_triangulation_on_sphere_2
/// (Epick) built once as in cgal_triangles() (spatial sort, insertion with the previous vertex's
/// face as hint, input indices as vertex info), then located into as often as wanted.
class CgalSphereLocator {
 public:
  /// Builds the triangulation; `build_seconds`, if non-null, receives the build time.
  explicit CgalSphereLocator(std::span<const Vec3> points, double* build_seconds = nullptr);
  ~CgalSphereLocator();
  CgalSphereLocator(const CgalSphereLocator&) = delete;
  CgalSphereLocator& operator=(const CgalSphereLocator&) = delete;

  /// Seconds to locate() every query (unit vectors) in order, each with the previous query's face
  /// as hint (the first with none). `checksum`, if non-null, receives the sum over the queries of
  /// the input indices of the located face's three vertices (ghost faces included), so that the
  /// work cannot be optimised away and runs can be compared. The run stops early once it has taken
  /// more than `max_seconds` (checked every 1024 queries); `done`, if non-null, receives the
  /// number of queries located.
  double locate_seconds(std::span<const Vec3> queries, std::uint64_t* checksum = nullptr,
                        double max_seconds = 1e300, std::size_t* done = nullptr) const;
  std::size_t num_vertices() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One-shot form of CgalSphereLocator: builds on `points` (not timed), then returns the time to
/// locate `queries` with the previous face as hint, and the checksum of the located faces.
double cgal_locate_seconds(std::span<const Vec3> points, std::span<const Vec3> queries,
                           std::uint64_t* checksum = nullptr);

}  // namespace geovor::testing
