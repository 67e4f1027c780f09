/// \file delaunay_geometry.hpp
/// \brief The Delaunay triangles and edges of a SphericalDelaunay as RFC 7946 lon/lat polygons
/// and lines, for GIS export (`geovor delaunay`).
///
/// The same rules as the Voronoi cells (cell_geometry.hpp): edges are great-circle arcs densified
/// by adaptive bisection so that no point of a written segment is farther than densify_m from
/// the arc; points within kSnapRad of a pole or of the antimeridian are moved onto it; a polygon
/// or line crossing +-180 is cut there (both parts meet the antimeridian at the same latitude); a
/// triangle holding a pole is closed through (+-180, +-90); rings are counter-clockwise and closed
/// by an exact copy of the first position. The tolerance of an edge's densification is also at
/// most a quarter of the least height of its two faces (not below 2^-46 radians, 0.09 mm, well
/// above rounding noise), so that a thin triangle (three sites near one great circle, or on one
/// latitude, whose sides bulge by less than densify_m from straight lon/lat segments) is drawn
/// with its true shape and orientation instead of a flat or inverted ring. An edge is always
/// densified from its smaller site id to the larger and reversed where needed, so the two
/// triangles of an edge, and the edge's own line, carry bit-identical positions: the written
/// triangles tile without gaps or overlaps.
///
/// Face kinds, decided exactly by orient(a, b, c) = orientation_3(O, a, b, c):
///  - Proper (> 0): a spherical triangle smaller than a hemisphere, bounded by minor arcs.
///  - GreatCircle (= 0): its three sites lie on one great circle; the face is the hemisphere on
///    the left of that circle (when every site lies on one great circle, or when three or more
///    sites on one great circle bound the hull of sites that all lie on one side of it).
///  - Ghost (< 0): its circumcircle is larger than a hemisphere (all sites lie in one open
///    hemisphere; CGAL's "ghost faces"). The face of the hull is then the outside of its three
///    sites' triangle; what is written is that small triangle itself (the region a GIS can
///    draw), which overlaps the Proper triangles: the Proper triangles alone tile the spherical
///    convex hull of the sites.
///
/// The faces outside the triangulation of the sites' convex hull ("outer" faces) are the Ghost
/// faces and, when some face is Proper, the GreatCircle faces too (three or more sites on one
/// great circle bounding a hull whose other sites are on one side of it: a flat face of the 3D
/// hull, through the centre). The other faces (the Proper ones, or every face when all sites lie
/// on one great circle) tile the hull, or the sphere. A hull edge has exactly one outer face; an
/// outer edge has two (it is a diagonal of the hull's outside, not an edge of its triangulation).
#pragma once

#include <cstdint>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"
#include "geovor/core/coordinate_grid.hpp"
#include "geovor/lonlat/geometry.hpp"
#include "geovor/lonlat/polygon_validity.hpp"

namespace geovor {

/// Options of DelaunayGeometry; every default is documented.
struct DelaunayGeometryOptions {
  /// Largest distance (metres, on the sphere of radius SiteEncoder::kEarthRadiusM) between a
  /// written straight lon/lat segment's midpoint and the true great-circle arc. DEFAULT: 100 m.
  /// REQUIRES: > 0.
  double densify_m = 100;
  /// Arcs longer than this (degrees) are always split. DEFAULT: 1 degree. REQUIRES: in (0, 180].
  double max_step_deg = 1;
  /// Recursion depth cap of the bisection of one arc, except within metres of a pole (as
  /// CellGeometryOptions::max_depth). DEFAULT: 20. REQUIRES: in [1, 40].
  int max_depth = 20;
  /// Decimals of the written coordinates (0..17), or kFullPrecision for formats that store
  /// doubles: positions are computed as a reader gets them back (snap_to_decimals), so that
  /// each triangle is certified, and its area measured, as written. DEFAULT: kFullPrecision.
  int precision = kFullPrecision;
};

enum class FaceKind : std::uint8_t { Proper, GreatCircle, Ghost };

/// "proper", "great_circle" or "ghost".
const char* to_string(FaceKind kind);

/// Builds the lon/lat geometry of the triangles and edges of one triangulation, which must
/// outlive this object. Construction converts every site and classifies every triangle once
/// (O(n)); each triangle or edge is
/// then built in O(its output size). Thread-safe after construction.
class DelaunayGeometry {
 public:
  /// Sites closer than this (metres, and never more than densify_m) to a pole are drawn at the
  /// pole (the South Pole station is 0.17 m from it). Less than half the merge distance (2^-24 of
  /// the radius, 0.38 m), so that two sites are never drawn at one point: with 1 m, two sites
  /// 0.4 m apart near a pole made a triangle with two equal corners, written as a self-crossing
  /// polygon around the whole Earth.
  static constexpr double kPoleSnapM = 0.18;

  /// @exception Error(InvalidArgument) if an option is out of range.
  explicit DelaunayGeometry(const SphericalDelaunay& dt, const DelaunayGeometryOptions& options = {});

  /// Exact kind of triangle t (see the file comment), decided once for every triangle at
  /// construction.
  FaceKind kind(TriId t) const { return kinds_[t]; }

  /// Whether triangle t lies outside the triangulation of the sites' convex hull (see the file
  /// comment): a Ghost face, or a GreatCircle face while some face is Proper.
  bool is_outer(TriId t) const {
    return kinds_[t] == FaceKind::Ghost || (kinds_[t] == FaceKind::GreatCircle && has_proper_);
  }

  /// Whether the edge of half-edge e is an edge of the boundary of the sites' convex hull:
  /// exactly one of its two faces is outer. None when the sites lie in no closed hemisphere, or
  /// all on one great circle.
  bool is_hull_edge(HalfedgeId e) const;

  /// Whether both faces of the edge of half-edge e are outer: the edge is not an edge of the
  /// triangulation of the sites' convex hull.
  bool is_outer_edge(HalfedgeId e) const;

  /// The polygon written for triangle t (see the file comment), reusing `out`'s storage, at
  /// options().precision, cleaned and certified exactly (certify_written): unless the status is
  /// Written, `out` is empty (the triangle collapses or folds at that precision; the caller
  /// reports it), never invalid.
  WrittenStatus triangle_polygon(TriId t, MultiPolygon& out) const;

  /// The line of the edge of half-edge e (from its origin to its destination), cut at the
  /// antimeridian and at a pole it passes through. Both half-edges of an edge give the same
  /// positions in opposite orders. Empty when its positions collapse to one at
  /// options().precision.
  void edge_line(HalfedgeId e, MultiLineString& out) const;

  /// Solid angle (steradians) of the region written for triangle t: below 2 pi for a Proper
  /// triangle or a Ghost's small triangle, 2 pi for a GreatCircle face.
  double triangle_area_sr(TriId t) const;

  /// Great-circle length of the edge of half-edge e, in metres on the sphere of radius
  /// SiteEncoder::kEarthRadiusM (relative error about 1e-15).
  double edge_length_m(HalfedgeId e) const;

  /// Radius (metres on the same sphere) of the circumcircle of triangle t: the distance from its
  /// sites to its Voronoi vertex; more than a quarter of the circumference for a Ghost face.
  double circumradius_m(TriId t) const;

  const SphericalDelaunay& triangulation() const { return *dt_; }
  const DelaunayGeometryOptions& options() const { return options_; }

 private:
  const SphericalDelaunay* dt_;
  DelaunayGeometryOptions options_;
  struct SitePt {
    Vec3 v;
    double lon, lat;
  };
  std::vector<SitePt> sites_;  // snapped position and lon/lat (degrees) of every site
  std::vector<FaceKind> kinds_;  // by triangle
  bool has_proper_ = false;       // some triangle is Proper
  // Square of the least height (unit sphere) of every triangle's sides, at least kMinThickness;
  // +infinity for a GreatCircle face.
  std::vector<double> thickness2_;
  static constexpr double kMinThickness = 0x1p-46;
  // The bound of the densification of the edge of half-edge e: the least thickness2 of its faces,
  // but not below 2^-30 of the edge's chord squared (a ghost triangle near a pole, thousands of
  // kilometres long and thinner than a micrometre, took 187,000 positions; such a triangle, if
  // it then folds, is certified unwritable and reported, never written invalid).
  double edge_bound2(HalfedgeId e) const;
};

}  // namespace geovor
