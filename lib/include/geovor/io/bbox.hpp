/// \file bbox.hpp
/// \brief RFC 7946 bounding boxes of geometries and of a collection of them (longitude arcs on
/// the circle, -180 and 180 being one meridian).
#pragma once

#include <optional>
#include <vector>

#include "geovor/lonlat/geometry.hpp"

namespace geovor {

/// The RFC 7946 bbox of a geometry, or nullopt for an empty one.
/// Longitudes: each part (a polygon's exterior ring, a line string) spans the plain interval of
/// its longitudes (parts never cross the antimeridian, see geometry.hpp); the bbox is the
/// smallest arc of the circle of longitudes containing every part, -180 and 180 being the same
/// meridian. So a MultiPolygon cut at the antimeridian (parts touching both -180 and 180) gets
/// west > east (§5.2), and a ring around a pole, which spans [-180, 180], gets
/// [-180, south, 180, 90] (§5.3). When the whole circle is covered, west = -180 and east = 180;
/// on ties the arc that does not cross the antimeridian wins.
std::optional<BBox> geojson_bbox(const Geometry& geometry);

/// The union of RFC 7946 bboxes (a FeatureCollection's bbox): the smallest longitude arc
/// containing every box, with the same rules as geojson_bbox(). The pending intervals are merged
/// whenever they outnumber both 4,096 and the intervals merged so far (O(n log n) in all), and a
/// box inside the merged intervals costs one binary search (a tiling's boxes soon all are).
class BBoxUnion {
 public:
  void add(const BBox& box);
  /// nullopt if nothing was added.
  std::optional<BBox> result() const;

 private:
  struct Interval {
    double west, east;  // west <= east
  };
  void add_interval(double west, double east);
  void compact() const;
  mutable std::vector<Interval> merged_;     // sorted by west, disjoint
  mutable std::vector<Interval> intervals_;  // pending
  double south_ = 0, north_ = 0;
  bool empty_ = true;
};

}  // namespace geovor
