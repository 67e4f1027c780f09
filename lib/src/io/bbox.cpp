#include "geovor/io/bbox.hpp"

#include <algorithm>
#include <iterator>
#include <limits>

namespace geovor {
namespace {

struct Arc {
  double west, east;  // west <= east, both in [-180, 180]
};

// Sorts and merges overlapping or touching intervals in place.
void merge_arcs(std::vector<Arc>& arcs) {
  if (arcs.empty()) return;
  std::sort(arcs.begin(), arcs.end(), [](const Arc& a, const Arc& b) { return a.west < b.west; });
  std::size_t n = 0;
  for (std::size_t i = 1; i < arcs.size(); ++i) {
    if (arcs[i].west <= arcs[n].east) {
      arcs[n].east = std::max(arcs[n].east, arcs[i].east);
    } else {
      arcs[++n] = arcs[i];
    }
  }
  arcs.resize(n + 1);
}

// The smallest arc containing every interval (merged: sorted, disjoint): the complement of the
// largest gap between consecutive intervals on the circle, -180 and 180 being one meridian.
// Ties go to the gap across the antimeridian, so that boxes do not cross it when they need not.
void smallest_arc(const std::vector<Arc>& merged, double& west, double& east) {
  double best_gap = (merged.front().west + 360.0) - merged.back().east;  // across +-180
  west = merged.front().west;
  east = merged.back().east;
  for (std::size_t i = 0; i + 1 < merged.size(); ++i) {
    const double gap = merged[i + 1].west - merged[i].east;
    if (gap > best_gap) {
      best_gap = gap;
      west = merged[i + 1].west;
      east = merged[i].east;
    }
  }
}

}  // namespace

std::optional<BBox> geojson_bbox(const Geometry& geometry) {
  if (const auto* p = std::get_if<LonLat>(&geometry)) {
    if (is_null_point(*p)) return std::nullopt;
    return BBox{p->lon_deg, p->lat_deg, p->lon_deg, p->lat_deg};
  }
  // One longitude interval per part; latitudes over everything. The first part is kept aside
  // so that the common single-part geometry allocates nothing.
  Arc first{0, 0};
  std::size_t parts = 0;
  std::vector<Arc> arcs;
  double south = std::numeric_limits<double>::infinity();
  double north = -south;
  auto add_part = [&](const std::vector<LonLat>& ps) {
    if (ps.empty()) return;
    Arc arc{ps.front().lon_deg, ps.front().lon_deg};
    for (const LonLat& q : ps) {
      arc.west = std::min(arc.west, q.lon_deg);
      arc.east = std::max(arc.east, q.lon_deg);
      south = std::min(south, q.lat_deg);
      north = std::max(north, q.lat_deg);
    }
    if (++parts == 1) {
      first = arc;
    } else {
      if (parts == 2) arcs.push_back(first);
      arcs.push_back(arc);
    }
  };
  if (const auto* lines = std::get_if<MultiLineString>(&geometry)) {
    for (const LineString& line : *lines) add_part(line);
  } else {
    // Holes lie inside their exterior ring: the exterior alone gives the box.
    for (const Polygon& poly : std::get<MultiPolygon>(geometry)) add_part(poly.exterior);
  }
  if (parts == 0) return std::nullopt;
  if (parts == 1) return BBox{first.west, south, first.east, north};
  merge_arcs(arcs);
  BBox box{0, south, 0, north};
  smallest_arc(arcs, box.west, box.east);
  return box;
}

void BBoxUnion::add(const BBox& box) {
  if (empty_) {
    south_ = box.south;
    north_ = box.north;
    empty_ = false;
  } else {
    south_ = std::min(south_, box.south);
    north_ = std::max(north_, box.north);
  }
  if (box.west <= box.east) {
    add_interval(box.west, box.east);
  } else {  // crosses the antimeridian
    add_interval(box.west, 180.0);
    add_interval(-180.0, box.east);
  }
}

void BBoxUnion::add_interval(double west, double east) {
  // Inside a merged interval: the last one starting at or before `west`.
  const auto after = std::upper_bound(merged_.begin(), merged_.end(), west,
                                      [](double w, const Interval& i) { return w < i.west; });
  if (after != merged_.begin() && east <= std::prev(after)->east) return;
  intervals_.push_back({west, east});
  // Merged early (a tiling's boxes then soon fall inside), and at least as often as the merged
  // intervals' count allows for O(n log n) in all.
  if (intervals_.size() > std::max<std::size_t>(4096, merged_.size())) compact();
}

void BBoxUnion::compact() const {
  if (intervals_.empty()) return;
  std::vector<Arc> arcs;
  arcs.reserve(merged_.size() + intervals_.size());
  for (const Interval& i : merged_) arcs.push_back({i.west, i.east});
  for (const Interval& i : intervals_) arcs.push_back({i.west, i.east});
  merge_arcs(arcs);
  intervals_.clear();
  merged_.clear();
  for (const Arc& a : arcs) merged_.push_back({a.west, a.east});
}

std::optional<BBox> BBoxUnion::result() const {
  if (empty_) return std::nullopt;
  compact();
  std::vector<Arc> arcs;
  for (const Interval& i : merged_) arcs.push_back({i.west, i.east});
  BBox box{0, south_, 0, north_};
  smallest_arc(arcs, box.west, box.east);
  return box;
}

}  // namespace geovor
