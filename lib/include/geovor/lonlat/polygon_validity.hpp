/// \file polygon_validity.hpp
/// \brief Exact validity of written lon/lat polygons (OGC simple features, as GEOS checks it),
/// and the cleanup of rings whose rounding collapsed an edge.
///
/// Every decision is an exact planar orientation (kernel::orient2d) on the doubles as written, so
/// "valid" here means valid for any reader of the file, at the precision written.
#pragma once

#include <cstdint>
#include <string>

#include "geovor/lonlat/geometry.hpp"

namespace geovor {

/// What became of a polygon (a cell, a triangle) when written at its precision.
enum class WrittenStatus : std::uint8_t {
  Written,     ///< a valid MultiPolygon
  Collapsed,   ///< no area is left at this precision: empty geometry
  Unwritable,  ///< rounding to this precision folds it (its written rings would cross themselves
               ///< or each other): empty geometry, never an invalid one
};

/// "written", "collapsed" or "unwritable".
const char* to_string(WrittenStatus status);

/// Makes `polygons` (as built from rounded positions) what may be written: spikes left by
/// collapsed edges removed (remove_spikes), a ring that passes twice through a position split
/// there into parts that touch (snap rounding merges the two sides of a thin part), collapsed
/// parts (fewer than 4 positions, or all on one line) dropped, then certified exactly
/// (is_star_shaped_ccw for one ring, else polygon_problem). Unless Written, `polygons` is left
/// empty. `cleaned`, if given, tells whether positions were removed.
WrittenStatus certify_written(MultiPolygon& polygons, bool* cleaned = nullptr);

/// Why `polygons` is not a valid MultiPolygon, or "" if it is: every ring closed with at least
/// four positions, no repeated position but the closing one, no two segments of one ring
/// touching or crossing except consecutive ones at their common end, segments of two parts
/// meeting only at a position of both (parts may touch at points, as OGC allows), exterior
/// rings counter-clockwise (positive planar area), no holes, and no part inside another.
/// O(n log n + k) for n segments (a sweep over their x extents; k candidate pairs).
std::string polygon_problem(const MultiPolygon& polygons);

/// A fast sufficient test of validity for one closed ring: every segment turns strictly
/// counter-clockwise about the mean of the ring's positions, exactly once around. True proves
/// the ring simple and counter-clockwise (it is star-shaped about that point); false proves
/// nothing (polygon_problem() decides). O(n).
bool is_star_shaped_ccw(const Ring& ring);

/// Removes what rounding to a grid leaves of a collapsed edge from a closed ring: consecutive
/// repeated positions and spikes (a, b, c on one line with c back towards a, as a, b, a: b is
/// dropped; exact), cyclically, until none is left. Both cells of a collapsed edge see the same
/// positions, so an exact spike a, b, a is cleaned the same on both sides; a chain folding back
/// and forth on one line may keep a different position of that line on each side (the same
/// segments, split differently). The ring is
/// closed again by a copy of its first position; it may end with fewer than 4 positions
/// (the ring collapsed).
void remove_spikes(Ring& ring);

}  // namespace geovor
