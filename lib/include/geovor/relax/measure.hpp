/// \file measure.hpp
/// \brief SphereMeasure: a measure on the directions of the unit sphere (a density per steradian),
/// what the balance solver (balance.hpp) shares out between power cells; EllipsoidAreaMeasure: the
/// area of the WGS84 ellipsoid seen through the site encoding (geocentric directions).
///
/// The solver needs three things of a measure: its total, the mass of a cell, and integrals of
/// the density times a linear function along a cell's edges (the Hessian, docs/weighted.md). A
/// demand raster is another subclass; everything else stays.
///
/// The ellipsoid's area per steradian of geocentric direction x, with z = x_3, k = e^2 / (1 - e^2):
///
///     f(z) = a^2 sqrt(1 + k (2 + k) z^2) / (1 + k z^2)^2,
///
/// (X = s x with s^-2 = (1 - z^2) / a^2 + z^2 / b^2; the area element is s^2 / (nu . x) dOmega, nu
/// the unit normal at X), a function of z alone: the ellipsoid is of revolution. On the unit
/// sphere dOmega = dz dphi (Archimedes), so with G(z) = integral of f from -1 to z the mass of a
/// region C is, by Green's theorem in the (phi, z) plane,
///
///     mass(C) = - contour integral over the boundary of C (counter-clockwise) of G(z) dphi
///               + 2 pi G(1) [C holds the north pole],
///
/// exact for any region bounded by great-circle arcs. G has a closed form: the zone of the
/// ellipsoid between the equator and geodetic latitude phi has, per radian of longitude, the area
/// b^2 / 2 (sin phi / (1 - e^2 sin^2 phi) + atanh(e sin phi) / e), and the geodetic latitude of
/// direction z is tan phi = tan(geocentric latitude) / (1 - e^2); G(1) = total / (2 pi).
#pragma once

#include <vector>

#include "geovor/core/types.hpp"

namespace geovor {

class VoronoiDiagram;

/// An arc of a great circle: x(t) = cos t from + sin t (normal x from), t in [0, angle_rad],
/// counter-clockwise about the unit `normal` seen from its tip (a cell's edge has the cell on its
/// left: the normal is the bisector normal pointing into the cell). REQUIRES: from . normal = 0.
struct GreatArc {
  Vec3 from;
  Vec3 normal;
  double angle_rad = 0;
  /// The point at angle t along the arc.
  Vec3 at(double t) const;
};

/// The boundary of the cell of s in `diagram`: its edges counter-clockwise (the cell on the left),
/// cell_neighbors(s)[i] across arcs[i] (one arc of 2 pi for a hemisphere; none for the whole
/// sphere or no cell). Zero-length edges are kept (angle 0).
void cell_arcs(const VoronoiDiagram& diagram, SiteId s, std::vector<GreatArc>& arcs);

/// A finite positive measure on the unit sphere with a density (per steradian).
class SphereMeasure {
 public:
  virtual ~SphereMeasure() = default;
  /// The mass of the whole sphere (m^2 for areas).
  virtual double total() const = 0;
  /// The density at unit vector x (mass per steradian).
  virtual double density(const Vec3& x) const = 0;
  /// The mass of the cell of s (0 without a cell). Thread-safe.
  virtual double cell_mass(const VoronoiDiagram& diagram, SiteId s) const = 0;
  /// Integral along `arc` of density(x) (x . w) ds, ds in radians on the unit sphere: the
  /// Hessian's edge term with w = q_j. Default: Gauss-Legendre of density() on pieces of at most
  /// pi / 8 (8 points; 4 below 0.01 rad), to about 1e-15 relative for densities as smooth as the
  /// ellipsoid's. Thread-safe.
  virtual double edge_moment(const GreatArc& arc, const Vec3& w) const;
};

/// The WGS84 area (m^2) of the points of the ellipsoid whose geocentric directions are in the set
/// (SiteEncoder's encoding), or of another ellipsoid of revolution (flattening 0: a sphere).
class EllipsoidAreaMeasure final : public SphereMeasure {
 public:
  /// WGS84: a = 6378137 m, f = 1 / 298.257223563.
  EllipsoidAreaMeasure();
  /// Equatorial radius a_m > 0, flattening 0 <= flattening < 1 (0: the sphere of radius a_m).
  /// @exception Error(InvalidArgument) otherwise.
  EllipsoidAreaMeasure(double a_m, double flattening);

  /// 2 pi a^2 (1 + (1 - e^2) atanh(e) / e): 510,065,621,724,088.5 m^2 for WGS84.
  double total() const override { return total_m2_; }
  double density(const Vec3& x) const override { return density_of_z(x.z); }
  double cell_mass(const VoronoiDiagram& diagram, SiteId s) const override;

  /// f(z): area per steradian at the directions of height z (see the file comment).
  double density_of_z(double z) const;
  /// G(z) = integral of f from -1 to z (closed form): the area per radian of longitude south of
  /// the directions of height z. G(1) = total / (2 pi).
  double zone_m2_per_rad(double z) const;
  /// (G(z2) - G(z1)) / (z2 - z1), the mean of f on [z1, z2], accurate when z1 and z2 are close
  /// (Gauss-Legendre of f there); f(z1) when they are equal.
  double mean_density(double z1, double z2) const;

 private:
  double a_m_, e2_, k_, total_m2_, g_north_;
};

}  // namespace geovor
