/// \file lloyd.hpp
/// \brief Lloyd's iterations toward a spherical centroidal Voronoi tessellation (SCVT; Du, Gunzburger
/// and Ju 2003): every site moves to the centroid of its Voronoi cell, the cells are recomputed,
/// and so on. The kind of mesh climate and ocean models (MPAS) run on.
///
/// Centroid of a cell C on the unit sphere: M / |M| with M = integral over C of x dA, the mass centre
/// projected back to the sphere; it minimises integral over C of |x - s|^2 dA over unit vectors s.
/// M is exact in closed form (derivation in lloyd.cpp):
///   M = 1/2 sum over the edges (a, b) of C, counter-clockwise, of angle(a, b) * n_ab,
/// n_ab the unit normal of the edge's great circle pointing into C. For the Voronoi edge between
/// site s and neighbour w the normal is normalize(s - w) (its bisector plane), which stays exact for
/// zero-length edges (co-circular sites) and 180-degree edges (lunes, three sites), where the cross
/// product of the end vertices is useless. The terms (~ the cell's size s) cancel to a mass of
/// ~ s^2, leaving its direction an error of ~ 1e-16 / s^2 radians; so in a cell of a perimeter
/// below 0.01 radians (64 km) M's part across the site comes from the cell's gnomonic projection
/// instead, where the edges are straight, by a 7-point rule on its fan triangles (error ~ s^7).
/// The centroid of the cell of the given vertices is right to about 1e-10 radians (under a
/// millimetre) at every size, and to about 1e-15 radians in the small cells.
///
/// Energy (the quantity Lloyd's iterations decrease): E = sum over cells of integral over the cell
/// of |x - s|^2 dA (sr, unit sphere). Since |x - s|^2 = 2 - 2 x.s on the sphere, each cell's term
/// is 2 area - 2 s.M: closed form too. Its absolute rounding error is a few ulps of the cell's area
/// (the two terms nearly cancel), about 1e-15 on the whole sphere, against E ~ 8 pi / n for n
/// well-spread sites.
///
/// Why the energy decreases: for a fixed partition, moving s to M/|M| minimises each cell's term
/// (2 area - 2 s.M is smallest for s along M); for fixed sites, the Voronoi partition minimises
/// the sum. So E(iteration k+1) <= E(iteration k), strictly until a fixed point (a CVT).
///
/// Determinism: the Voronoi diagram's cells and vertices do not depend on how the triangles are
/// stored (each cell starts at its smallest neighbour), so centroids are summed in a canonical order, so the positions after
/// every iteration are bit-identical with every relocation strategy (whenever the triangulations
/// are, i.e. always but for co-circular ties).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "geovor/core/types.hpp"
#include "geovor/delaunay/spherical_delaunay.hpp"

namespace geovor {

class VoronoiDiagram;

/// How the triangulation follows the sites after each iteration.
enum class Relocation : std::uint8_t {
  Rebuild,   ///< SphericalDelaunay::build() of the new positions from scratch
  Naive,     ///< move_all() with RelocationOptions{.filter = false, .flips = false}: remove + insert
  Filtered,  ///< move_all() with the default RelocationOptions: tolerance filter, then flips
};

/// "rebuild", "naive" or "filtered".
const char* to_string(Relocation r);

/// Options of lloyd(); every default is documented.
struct LloydOptions {
  /// Number of iterations (each: cells, centroids, move). DEFAULT: 10. REQUIRES: >= 0.
  int iterations = 10;
  /// Stop early once the largest displacement of an iteration is at most this (radians on the
  /// unit sphere), if > 0. DEFAULT: 0 (run every iteration).
  double tolerance_rad = 0;
  /// DEFAULT: Relocation::Filtered (the fastest; every strategy gives the same result).
  Relocation relocation = Relocation::Filtered;
  /// Threads computing the centroids (0: one per core). DEFAULT: 1. The result does not depend
  /// on it.
  unsigned threads = 1;
};

/// The centroid of one cell.
struct CellCentroid {
  Vec3 mass;            ///< M = integral over the cell of x dA (unit sphere)
  double area_sr = 0;   ///< area of the cell (steradians)
  double energy = 0;    ///< integral over the cell of |x - site|^2 dA = 2 area - 2 site.M
  bool defined = false; ///< false when M vanishes (one site: the whole sphere) or no cell
  /// normalize(M) if defined, else the site itself.
  Vec3 centroid;
};

/// The centroid of the cell of s (closed form, see the file comment), O(degree).
CellCentroid cell_centroid(const VoronoiDiagram& diagram, SiteId s);

/// What one iteration did. Distances are angles on the unit sphere (radians) and metres on the
/// sphere of radius SiteEncoder::kEarthRadiusM.
struct LloydIteration {
  int iteration = 0;         ///< 1-based
  double energy = 0;         ///< E of the sites at the start of the iteration, with their cells
  double max_move_rad = 0;   ///< largest displacement of a site in this iteration
  double max_move_m = 0;
  double mean_move_rad = 0;  ///< mean displacement over the live sites (refused moves count 0)
  double mean_move_m = 0;
  std::size_t undefined = 0; ///< sites whose centroid is undefined (kept in place)
  MoveStats moves;           ///< what the relocation did (Rebuild: moved and refused only)
  double centroid_seconds = 0;   ///< Voronoi diagram + centroids + energy
  double relocation_seconds = 0; ///< updating the triangulation
  double seconds = 0;            ///< the whole iteration
};

/// The whole run.
struct LloydReport {
  std::vector<LloydIteration> iterations;
  double final_energy = 0;  ///< E of the final sites with their cells
};

/// Runs Lloyd's iterations on `dt` in place: each live site moves to the centroid of its cell;
/// ids never change. A site whose centroid lies within the merge distance of another site stays
/// where it was (counted in MoveStats::refused): while two new positions are closer than the
/// merge distance, the move of the larger id of the two (of the one that moved, if only one did)
/// is refused, so every strategy refuses the same moves and gives the same sites, to the bit
/// (on a triangulation with removed sites, refusals follow the strategy's order). A site whose
/// centroid is undefined stays too.
/// Fewer than three sites: one site stays; two sites go to the two poles of their bisector (a
/// fixed point after one iteration). `on_iteration`, if given, is called after every iteration.
/// @exception Error(InvalidArgument) for invalid options, or Relocation::Rebuild on a
///   triangulation with removed sites (a rebuild would renumber them).
LloydReport lloyd(SphericalDelaunay& dt, const LloydOptions& options = {},
                  const std::function<void(const LloydIteration&)>& on_iteration = {});

/// E of the live sites of `diagram` (see the file comment).
double lloyd_energy(const VoronoiDiagram& diagram, unsigned threads = 1);

}  // namespace geovor
