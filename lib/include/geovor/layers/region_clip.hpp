/// \file region_clip.hpp
/// \brief Cells clipped to regions (the Thiessen method, coverage cut to a coastline, service
/// areas per district): the pieces of every cell inside every region, with their areas and their
/// shares of the region (what `geovor cells --clip` writes).
///
/// The clip is that of the cells as they are written (CellGeometry at the output's precision:
/// densified, cut at +-180, closed around the poles) against the regions as a GIS reads them
/// (straight edges in longitude/latitude), in the plane of longitude and latitude, by GEOS's
/// robust overlay (OverlayNG snap-rounded to the grid of the output's decimals): the pieces tile
/// each region as QGIS draws it, and each piece is valid at the precision written.
///
/// The region's straight edges are halved before the clip while a piece's midpoint and the
/// geodesic between its ends part by more than the cells' densify_m, so that the pieces follow
/// them as drawn and their geodesic measures are those of the region as drawn (a 90-degree edge
/// along -70 latitude, as Natural Earth draws Antarctica, is not the geodesic between its ends).
///
/// Measures: a piece's area_m2 is that of its rings as written on the WGS84 ellipsoid
/// (ellipsoid_area_m2: geodesics between the written vertices, as PolygonArea); a region's area
/// is the sum of its pieces' (the region as the cells tile it), so that its shares sum to 1
/// within rounding. A region polygon that GEOS finds invalid (a self-intersection, a bow tie) is
/// repaired with GEOS's MakeValid and reported. Where a region's vertex sits on a pole between
/// edges that are neither meridians nor the pole's own line (not how GIS data draws a polar
/// region: Natural Earth's Antarctica runs along -90), the wedge it draws folds on the sphere,
/// and a piece there can measure 0 or less as written: such a piece is kept and reported.
///
/// Speed: each region's candidate cells are found from our structures, not by testing every
/// cell: the cell of each of its polygons' first vertex is found by a greedy walk over the cells'
/// neighbours, then the cells meeting the polygon are walked from there (the cells meeting a
/// connected polygon are connected through their neighbours); each cell's test is a GEOS
/// prepared intersection.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "geovor/io/ogr_region_reader.hpp"
#include "geovor/lonlat/cell_geometry.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace geovor {

/// Options of clip_cells_to_regions(); every default is documented.
struct RegionClipOptions {
  /// Threads clipping regions at once (0: one per core). DEFAULT: 0. The result does not depend
  /// on it.
  unsigned threads = 0;
};

/// One piece: the part of a site's cell inside a region.
struct ClipPiece {
  SiteId site = kNoIndex;
  std::uint32_t region = 0;  ///< index in RegionTable::regions
  MultiPolygon geometry;     ///< exterior rings counter-clockwise, at the cells' precision
  double area_m2 = 0;        ///< of the rings as written
  double region_share = 0;   ///< area_m2 over the region's area
};

/// A region repaired or left out, with why.
struct RegionProblem {
  std::uint32_t region = 0;
  std::string reason;
};

/// What clip_cells_to_regions() found beside the pieces.
struct RegionClipReport {
  std::vector<double> region_area_m2;      ///< by region: the sum of its pieces' area_m2
  std::vector<SiteId> sites_outside;        ///< live sites whose cell meets no region, in order
  /// Regions repaired (MakeValid), empty at this precision, with an overlay GEOS refused, or with a
  /// piece that measures 0 or less as written.
  std::vector<RegionProblem> problems;
  std::size_t cells_tested = 0;             ///< cells tested against a region (the walk's cost)
};

/// The pieces of the cells of `cells` (built at the output's precision) inside the regions,
/// ordered by site, then region.
std::vector<ClipPiece> clip_cells_to_regions(const VoronoiDiagram& diagram, const CellGeometry& cells,
                                             const RegionTable& regions, const RegionClipOptions& options,
                                             RegionClipReport& report);

}  // namespace geovor
