// Private to the lonlat module: snap rounding of polylines to the decimal grid of a precision
// (Hobby, "Practical segment intersection with finite precision output", 1999; Guibas and
// Marimont, "Rounding arrangements dynamically", 1998). Rounding each vertex to the nearest grid
// point alone can make two segments that passed on either side of a vertex cross it: the thin
// lunes of sites on one meridian, whose tips are narrower than a decimal step over kilometres.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace geovor::lonlat {

/// A vertex of a polyline: where it was computed and where it is written (its position rounded
/// to the grid: the centre of its hot pixel), with a tag of the caller's carried along.
struct SnapVertex {
  double raw_lon, raw_lat;  // degrees, as computed
  double lon, lat;          // degrees, as written (snap_to_decimals of raw, precision decimals)
  std::uint32_t tag;
};

/// The tag of a vertex snap_round() makes: where a segment crosses the antimeridian (lon and
/// raw_lon +-180, lat its written latitude); the caller gives it a point on the sphere.
inline constexpr std::uint32_t kNewVertex = ~std::uint32_t{0};

/// The finest precision snap_round() takes: a step of 1e-12 degree is still some 700 ulps of a
/// longitude near 180, so the squares of the grid are what the doubles written can tell apart.
inline constexpr int kSnapRoundMaxPrecision = 12;

/// Hobby's snap rounding on the grid of step h = 10^-precision degrees. A hot pixel is the closed
/// square of side h centred on the written position of a vertex of `paths` or of `extra`. Each
/// segment of each path (between the raw positions of consecutive vertices) is rerouted through
/// the centres of the hot pixels it meets, other than those of its own ends, in the order in
/// which it meets them: a copy of a vertex written there (the one with the smallest raw
/// position, so the result does not depend on the order of the input) is inserted; then so is a
/// copy of every hot pixel whose centre lies exactly inside a written segment (in order along it),
/// so paths that coincide along a line have the same vertices there. If no two raw
/// segments cross, no two written segments of the rerouted paths cross: they meet only at
/// common written vertices, or coincide (which leaves spikes for remove_spikes, and rings that
/// touch themselves at a vertex). The antimeridian is a segment of the arrangement too: where a
/// segment crosses it (longitudes more than 180 degrees apart; at the latitude of its straight
/// lon/lat line, or crossing_lat) becomes a vertex of its path on it (tagged kNewVertex) before
/// anything is routed, and a hot pixel on it is one on both sides. A segment with an end at a
/// pole is left as it is. `extra` gives hot pixels only.
/// REQUIRES: 0 <= precision <= kSnapRoundMaxPrecision. Returns the vertices inserted.
/// O((n + k) log n) for n vertices and k insertions, on typical input (hot pixels in Z order).
/// `crossing_lat`, if given, is the raw latitude at which the segment p -> q crosses the
/// antimeridian (the caller's great-circle arc; by default its straight lon/lat line).
std::size_t snap_round(std::vector<std::vector<SnapVertex>>& paths, std::span<const SnapVertex> extra,
                       int precision,
                       const std::function<double(const SnapVertex& p, const SnapVertex& q)>& crossing_lat = {});

}  // namespace geovor::lonlat
