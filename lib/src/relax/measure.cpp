#include "geovor/relax/measure.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <span>
#include <string>

#include "geovor/core/error.hpp"
#include "geovor/voronoi/voronoi_diagram.hpp"

namespace geovor {
namespace {

constexpr double kPi = std::numbers::pi;

struct Node {
  double x, w;  // node on [-1, 1] and its weight
};
// Gauss-Legendre rules (nodes symmetric: both signs are used).
constexpr std::array<Node, 2> kGauss4{{{0.3399810435848562648, 0.6521451548625461427},
                                       {0.8611363115940525752, 0.3478548451374538574}}};
constexpr std::array<Node, 4> kGauss8{{{0.1834346424956498049, 0.3626837833783619830},
                                       {0.5255324099163289858, 0.3137066458778872873},
                                       {0.7966664774136267396, 0.2223810344533744706},
                                       {0.9602898564975362317, 0.1012285362903762592}}};

// Longest piece an arc is integrated on: the integrands below stay analytic well beyond it.
constexpr double kMaxPieceRad = kPi / 8;
// Pieces shorter than this take 4 points instead of 8 (error ~ (length / distance to the nearest
// singularity)^8, below 1e-17 here).
constexpr double kShortPieceRad = 0.01;

// Integral over t in [0, length] of g(t) by Gauss-Legendre, 8 points or 4 on a short piece.
template <class G>
double gauss(double length, G&& g) {
  const double h = 0.5 * length;
  double sum = 0;
  auto rule = [&](auto nodes) {
    for (const Node& n : nodes) sum += n.w * (g(h - h * n.x) + g(h + h * n.x));
  };
  if (length < kShortPieceRad) rule(kGauss4);
  else rule(kGauss8);
  return h * sum;
}

// Calls piece(sub_arc) for pieces of at most kMaxPieceRad covering `arc`.
template <class Piece>
void for_each_piece(const GreatArc& arc, Piece&& piece) {
  const int n = std::max(1, static_cast<int>(std::ceil(arc.angle_rad / kMaxPieceRad)));
  const double step = arc.angle_rad / n;
  for (int i = 0; i < n; ++i) piece(GreatArc{i == 0 ? arc.from : arc.at(i * step), arc.normal, step});
}

Vec3 normalized(const Vec3& v) { return (1 / std::sqrt(norm2(v))) * v; }

// Largest and smallest height z on the arc (an extremum of z inside it is where the great circle
// tops out, at the projection of the axis onto its plane).
void z_range(const GreatArc& arc, double& lo, double& hi) {
  const Vec3 end = arc.at(arc.angle_rad);
  lo = std::min(arc.from.z, end.z);
  hi = std::max(arc.from.z, end.z);
  const Vec3 top{-arc.normal.z * arc.normal.x, -arc.normal.z * arc.normal.y, 1 - arc.normal.z * arc.normal.z};
  const double top_len = std::sqrt(std::max(0.0, 1 - arc.normal.z * arc.normal.z));
  if (top_len == 0) return;  // the arc is on the equator
  const Vec3 u = cross(arc.normal, arc.from);
  for (const double sign : {1.0, -1.0}) {  // the top, then the bottom
    double t = std::atan2(sign * dot(top, u), sign * dot(top, arc.from));
    if (t < 0) t += 2 * kPi;
    if (t <= arc.angle_rad) (sign > 0 ? hi : lo) = sign * top_len;
  }
}

}  // namespace

Vec3 GreatArc::at(double t) const { return std::cos(t) * from + std::sin(t) * cross(normal, from); }

void cell_arcs(const VoronoiDiagram& vd, SiteId s, std::vector<GreatArc>& arcs) {
  arcs.clear();
  if (!vd.has_cell(s)) return;
  if (vd.kind() == VoronoiDiagram::Kind::Hemispheres) {
    const Vec3 n = vd.hemisphere_normal(s);
    // Any point of the bisector great circle: n crossed with the axis it is least aligned with.
    const Vec3 axis = std::fabs(n.x) <= std::fabs(n.y) && std::fabs(n.x) <= std::fabs(n.z) ? Vec3{1, 0, 0}
                      : std::fabs(n.y) <= std::fabs(n.z)                                   ? Vec3{0, 1, 0}
                                                                                            : Vec3{0, 0, 1};
    arcs.push_back({normalized(cross(n, axis)), n, 2 * kPi});
    return;
  }
  if (vd.kind() != VoronoiDiagram::Kind::Cells) return;
  const std::span<const TriId> tris = vd.cell_vertices(s);
  const std::span<const SiteId> nbrs = vd.cell_neighbors(s);
  const std::size_t d = tris.size();
  for (std::size_t i = 0; i < d; ++i) {
    const Vec3& a = vd.vertex(tris[i]);
    const Vec3& b = vd.vertex(tris[i + 1 == d ? 0 : i + 1]);
    const Vec3 n = vd.bisector_normal(s, nbrs[i]);
    const double cos_ab = dot(a, b);
    double theta = std::atan2(dot(cross(a, b), n), cos_ab);
    // Edges turn positively by 0 to 180 degrees: a negative angle is a rounded 0 or 180.
    if (theta < 0) theta = cos_ab < 0 ? kPi : 0;
    // The vertex projected onto the edge's plane, so that the arc runs exactly on it.
    arcs.push_back({normalized(a - dot(a, n) * n), n, theta});
  }
}

double SphereMeasure::edge_moment(const GreatArc& arc, const Vec3& w) const {
  double sum = 0;
  for_each_piece(arc, [&](const GreatArc& p) {
    sum += gauss(p.angle_rad, [&](double t) {
      const Vec3 x = p.at(t);
      return density(x) * dot(x, w);
    });
  });
  return sum;
}

EllipsoidAreaMeasure::EllipsoidAreaMeasure() : EllipsoidAreaMeasure(6378137.0, 1 / 298.257223563) {}

EllipsoidAreaMeasure::EllipsoidAreaMeasure(double a_m, double flattening) : a_m_(a_m) {
  if (!(a_m > 0) || !std::isfinite(a_m) || !(flattening >= 0 && flattening < 1))
    throw Error(ErrorCode::InvalidArgument, "EllipsoidAreaMeasure: needs a > 0 and 0 <= flattening < 1");
  e2_ = flattening * (2 - flattening);
  k_ = e2_ / (1 - e2_);
  const double e = std::sqrt(e2_);
  total_m2_ = e2_ == 0 ? 4 * kPi * a_m * a_m : 2 * kPi * a_m * a_m * (1 + (1 - e2_) * std::atanh(e) / e);
  g_north_ = total_m2_ / (2 * kPi);
}

double EllipsoidAreaMeasure::density_of_z(double z) const {
  const double z2 = z * z, q = 1 + k_ * z2;
  return a_m_ * a_m_ * std::sqrt(1 + k_ * (2 + k_) * z2) / (q * q);
}

double EllipsoidAreaMeasure::zone_m2_per_rad(double z) const {
  z = std::clamp(z, -1.0, 1.0);
  // sin of the geodetic latitude from tan(phi) = z / ((1 - e^2) sqrt(1 - z^2)).
  const double c = (1 - e2_) * std::sqrt((1 - z) * (1 + z));
  const double sphi = z / std::sqrt(c * c + z * z);
  const double e = std::sqrt(e2_);
  const double b2 = a_m_ * a_m_ * (1 - e2_);
  const double odd = e2_ == 0 ? a_m_ * a_m_ * z
                              : 0.5 * b2 * (sphi / (1 - e2_ * sphi * sphi) + std::atanh(e * sphi) / e);
  return 0.5 * g_north_ + odd;
}

double EllipsoidAreaMeasure::mean_density(double z1, double z2) const {
  // f is analytic with its nearest complex singularities at |z| > 8 (for WGS84): 4 Gauss points
  // on an interval of 0.25 leave ~1e-16; beyond it the closed form loses at most a few ulps.
  if (std::fabs(z2 - z1) > 0.25) return (zone_m2_per_rad(z2) - zone_m2_per_rad(z1)) / (z2 - z1);
  const double m = 0.5 * (z1 + z2), h = 0.5 * (z2 - z1);
  double sum = 0;
  for (const Node& n : kGauss4) sum += n.w * (density_of_z(m - h * n.x) + density_of_z(m + h * n.x));
  return 0.5 * sum;
}

// The file comment's boundary formula with a constant K subtracted from G: along a piece of an
// edge, x dy - y dx = normal_z dt (x cross x' is the normal), so dphi = normal_z dt / (1 - z^2),
// and (G - K) dphi is regular where the piece runs for the right K:
//  - a cell away from the poles (|z| <= 0.7 on its boundary): K = G(z_r), z_r a height of the
//    cell, integrand (z - z_r) mean_density(z_r, z) / (x^2 + y^2); the terms are then ~ the cell's
//    size times its density variation, not G(1), so small cells keep their digits;
//  - a cell that comes near the north pole only: K = G(1), integrand -mean_density(z, 1) / (1 + z),
//    regular at the pole, so a pole on the boundary (a vertex, an edge) is no special case;
//  - near the south pole only: K = G(-1) = 0, integrand mean_density(-1, z) / (1 - z);
//  - near both (a cell of a few sites): each piece takes the K of its half, G(1) or 0, and the
//    north pieces add G(1) times their change of longitude.
// With one K for the whole boundary, the contour integral of K dphi is 2 pi K ([north in C] -
// [south in C]), so mass = -sum of the pieces' integrals + 2 pi (G(1) - K) [north in C]
// + 2 pi K [south in C].
double EllipsoidAreaMeasure::cell_mass(const VoronoiDiagram& vd, SiteId s) const {
  if (!vd.has_cell(s)) return 0;
  if (vd.kind() == VoronoiDiagram::Kind::WholeSphere) return total_m2_;
  thread_local std::vector<GreatArc> arcs, pieces;
  cell_arcs(vd, s, arcs);
  if (arcs.empty()) return 0;
  // The poles: inside iff strictly on the inner side of every edge's plane (the cell is convex).
  bool north = true, south = true;
  for (const GreatArc& arc : arcs) {
    north = north && arc.normal.z > 0;
    south = south && arc.normal.z < 0;
  }
  pieces.clear();
  double lo_all = 1, hi_all = -1;
  for (const GreatArc& arc : arcs)
    for_each_piece(arc, [&](const GreatArc& p) {
      double lo, hi;
      z_range(p, lo, hi);
      pieces.push_back(p);
      lo_all = std::min(lo_all, lo);
      hi_all = std::max(hi_all, hi);
    });
  constexpr double kPolar = 0.7;
  const bool near_north = north || hi_all > kPolar, near_south = south || lo_all < -kPolar;
  double integral = 0;
  if (!near_north && !near_south) {
    const double zr = std::clamp(arcs[0].from.z, -kPolar, kPolar);
    for (const GreatArc& p : pieces)
      integral += p.normal.z * gauss(p.angle_rad, [&](double t) {
        const Vec3 x = p.at(t);
        return (x.z - zr) * mean_density(zr, x.z) / (x.x * x.x + x.y * x.y);
      });
    return -integral;  // no pole inside
  }
  auto north_integrand = [&](const GreatArc& p) {
    return p.normal.z * gauss(p.angle_rad, [&](double t) {
      const double z = p.at(t).z;
      return -mean_density(z, 1) / (1 + z);
    });
  };
  auto south_integrand = [&](const GreatArc& p) {
    return p.normal.z * gauss(p.angle_rad, [&](double t) {
      const double z = p.at(t).z;
      return mean_density(-1, z) / (1 - z);
    });
  };
  if (near_north != near_south) {
    for (const GreatArc& p : pieces) integral += near_north ? north_integrand(p) : south_integrand(p);
    const double k = near_north ? g_north_ : 0.0;
    return -integral + 2 * kPi * ((north ? g_north_ - k : 0.0) + (south ? k : 0.0));
  }
  double longitude = 0;  // sum of the north pieces' changes of longitude
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const GreatArc& p = pieces[i];
    if (p.at(0.5 * p.angle_rad).z > 0) {
      integral += north_integrand(p);
      const Vec3 a = p.from, b = p.at(p.angle_rad);
      longitude += std::atan2(a.x * b.y - a.y * b.x, a.x * b.x + a.y * b.y);
    } else {
      integral += south_integrand(p);
    }
  }
  return -(integral + g_north_ * longitude) + (north ? 2 * kPi * g_north_ : 0.0);
}

}  // namespace geovor
