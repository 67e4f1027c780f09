#include "lonlat/snap_rounding.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <tuple>

#include "geovor/core/assert.hpp"
#include "geovor/core/coordinate_grid.hpp"

namespace geovor::lonlat {
namespace {

struct HotPixel {
  std::int64_t ix, iy;  // the written position, in steps
  SnapVertex vertex;    // the vertex with the smallest raw position written there
};

// Pixels in Z order (Morton codes of their steps, made non-negative): the pixels of any square
// of 2^l x 2^l steps aligned on multiples of 2^l (a quadtree node) are one run of the order.
using Key = unsigned __int128;
constexpr std::int64_t kOffset = std::int64_t{1} << 60;  // |steps| < 2^48 up to 12 decimals
std::uint64_t spread32(std::uint64_t x) {  // the 32 low bits of x to the even bits
  x &= 0xffffffffULL;
  x = (x | x << 16) & 0x0000ffff0000ffffULL;
  x = (x | x << 8) & 0x00ff00ff00ff00ffULL;
  x = (x | x << 4) & 0x0f0f0f0f0f0f0f0fULL;
  x = (x | x << 2) & 0x3333333333333333ULL;
  x = (x | x << 1) & 0x5555555555555555ULL;
  return x;
}
Key spread(std::uint64_t v) { return (static_cast<Key>(spread32(v >> 32)) << 64) | spread32(v); }
Key morton(std::uint64_t x, std::uint64_t y) { return spread(x) | (spread(y) << 1); }

// Whether the segment p -> q (raw positions) meets the closed square of half side r centred at
// (gx, gy), and the parameters at which it enters and leaves it (Liang-Barsky clipping).
bool meets_square(const SnapVertex& p, const SnapVertex& q, double gx, double gy, double r, double& enter,
                  double& leave) {
  const double x0 = p.raw_lon - gx, y0 = p.raw_lat - gy;
  const double dx = q.raw_lon - p.raw_lon, dy = q.raw_lat - p.raw_lat;
  double t0 = 0, t1 = 1;
  auto clip = [&](double den, double num) {  // den * t <= num
    if (den == 0) return num >= 0;
    const double t = num / den;
    if (den < 0) {
      if (t > t1) return false;
      t0 = std::max(t0, t);
    } else {
      if (t < t0) return false;
      t1 = std::min(t1, t);
    }
    return true;
  };
  if (!(clip(-dx, x0 + r) && clip(dx, r - x0) && clip(-dy, y0 + r) && clip(dy, r - y0))) return false;
  enter = t0;
  leave = t1;
  return true;
}

}  // namespace

std::size_t snap_round(std::vector<std::vector<SnapVertex>>& paths, std::span<const SnapVertex> extra,
                       int precision,
                       const std::function<double(const SnapVertex& p, const SnapVertex& q)>& crossing_lat) {
  GEOVOR_ASSERT(precision >= 0 && precision <= kSnapRoundMaxPrecision);
  const double scale = std::pow(10.0, precision);  // steps per degree
  const double half = 0.5 / scale;                 // half a step, degrees
  // A contact at an end (see route), degrees: the noise of a clip of coordinates up to 180 (2^-40,
  // 32 ulps of a longitude over 128), a 1024th of a step at 10 decimals and more.
  const double touch = std::min(0x1p-40, 1 / (1024 * scale));
  auto steps = [scale](double written) { return static_cast<std::int64_t>(std::llround(written * scale)); };

  // A segment's ends in one sheet of the plane: an end on the antimeridian (raw -180) is taken
  // on the side of the other end, and a segment whose ends are more than 180 degrees apart
  // crosses the antimeridian, at the latitude of its straight lon/lat line. An end only written
  // on it stays in the sheet of its raw longitude (moved to the other end's, from 0.3 to -179.7,
  // its own pixel became one the segment met, and the noding ran through the whole row).
  auto on_side = [](SnapVertex v, double side) {
    if (std::fabs(v.raw_lon) == 180) v.raw_lon = side > 0 ? 180 : -180;
    if (v.lon == -180 && side > 0 && v.raw_lon > 0) v.lon = 180;
    if (v.lon == 180 && side < 0 && v.raw_lon < 0) v.lon = -180;
    return v;
  };
  struct Crossing {
    bool crosses;
    SnapVertex at_p;  // the crossing, on p's side
  };
  auto crossing = [&](const SnapVertex& p, const SnapVertex& q) {
    Crossing c{false, {}};
    if (!(std::fabs(q.raw_lon - p.raw_lon) > 180) || std::fabs(p.raw_lon) == 180 || std::fabs(q.raw_lon) == 180) return c;
    const double p_side = p.raw_lon > 0 ? 180 : -180;
    auto straight = [&] {  // the straight line's latitude there, q taken in p's sheet
      const double t = (p_side - p.raw_lon) / (q.raw_lon + 2 * p_side - p.raw_lon);
      return p.raw_lat + std::clamp(t, 0.0, 1.0) * (q.raw_lat - p.raw_lat);
    };
    const double lat = crossing_lat ? crossing_lat(p, q) : straight();
    c.crosses = true;
    c.at_p = {p_side, lat, p_side, snap_to_decimals(lat, precision), kNewVertex};
    return c;
  };

  // Each crossing of the antimeridian becomes a vertex on it, before anything is routed: the
  // arrangement's segments then end on the antimeridian, as the cut takes them.
  std::size_t inserted = 0;
  std::vector<SnapVertex> out;
  for (std::vector<SnapVertex>& path : paths) {
    out.clear();
    for (std::size_t i = 0; i < path.size(); ++i) {
      if (i > 0)
        if (const Crossing c = crossing(path[i - 1], path[i]); c.crosses) out.push_back(c.at_p), ++inserted;
      out.push_back(path[i]);
    }
    if (out.size() != path.size()) path.swap(out);
  }

  std::vector<HotPixel> pixels;
  {
    std::size_t total = extra.size();
    for (const auto& path : paths) total += path.size();
    pixels.reserve(total + total / 16);  // a few on the antimeridian twice
  }
  auto add = [&](const SnapVertex& v) {
    pixels.push_back({steps(v.lon), steps(v.lat), v});
    if (std::fabs(v.lon) == 180) {  // on the antimeridian: a hot pixel in both sheets
      SnapVertex mirror = v;
      mirror.lon = -v.lon;
      if (std::fabs(mirror.raw_lon) == 180) mirror.raw_lon = -v.raw_lon;
      pixels.push_back({steps(mirror.lon), steps(mirror.lat), mirror});
    }
  };
  for (const auto& path : paths)
    for (const SnapVertex& v : path) add(v);
  for (const SnapVertex& v : extra) add(v);
  std::sort(pixels.begin(), pixels.end(), [](const HotPixel& a, const HotPixel& b) {
    return std::tie(a.ix, a.iy, a.vertex.raw_lon, a.vertex.raw_lat) <
           std::tie(b.ix, b.iy, b.vertex.raw_lon, b.vertex.raw_lat);
  });
  pixels.erase(std::unique(pixels.begin(), pixels.end(),
                           [](const HotPixel& a, const HotPixel& b) { return a.ix == b.ix && a.iy == b.iy; }),
               pixels.end());

  // The pixels in Z order.
  std::vector<std::pair<Key, std::uint32_t>> order(pixels.size());
  for (std::uint32_t k = 0; k < pixels.size(); ++k)
    order[k] = {morton(static_cast<std::uint64_t>(pixels[k].ix + kOffset), static_cast<std::uint64_t>(pixels[k].iy + kOffset)), k};
  std::sort(order.begin(), order.end());

  std::vector<std::pair<double, std::uint32_t>> hits;
  std::vector<std::uint32_t> candidates;  // the pixels in a segment's box
  using Wide = __int128;                  // products of steps (below 2^49 each)
  std::vector<std::pair<Wide, std::uint32_t>> on_line;
  // Appends to `out` the hot pixels the segment p -> q of one sheet meets, but its ends', in order.
  auto route = [&](const SnapVertex& p, const SnapVertex& q, std::vector<SnapVertex>& out) {
    if (std::fabs(p.raw_lat) == 90 || std::fabs(q.raw_lat) == 90) return;
    // The pixels the segment's box reaches (two steps of margin), in a level of cells at least
    // as large: at most 2 x 2 cells.
    const std::int64_t x_lo = static_cast<std::int64_t>(std::floor(std::min(p.raw_lon, q.raw_lon) * scale)) - 2;
    const std::int64_t x_hi = static_cast<std::int64_t>(std::ceil(std::max(p.raw_lon, q.raw_lon) * scale)) + 2;
    const std::int64_t y_lo = static_cast<std::int64_t>(std::floor(std::min(p.raw_lat, q.raw_lat) * scale)) - 2;
    const std::int64_t y_hi = static_cast<std::int64_t>(std::ceil(std::max(p.raw_lat, q.raw_lat) * scale)) + 2;
    const std::uint64_t extent = static_cast<std::uint64_t>(std::max(x_hi - x_lo, y_hi - y_lo));
    const int l = std::min(60, static_cast<int>(std::bit_width(extent)));
    const std::int64_t pix = steps(p.lon), piy = steps(p.lat), qix = steps(q.lon), qiy = steps(q.lat);
    hits.clear();
    candidates.clear();
    const std::int64_t side = std::int64_t{1} << l;
    for (std::int64_t cx = (x_lo + kOffset) >> l; cx <= (x_hi + kOffset) >> l; ++cx)
      for (std::int64_t cy = (y_lo + kOffset) >> l; cy <= (y_hi + kOffset) >> l; ++cy) {
        const Key first = morton(static_cast<std::uint64_t>(cx << l), static_cast<std::uint64_t>(cy << l));
        const Key last = morton(static_cast<std::uint64_t>((cx << l) + side - 1), static_cast<std::uint64_t>((cy << l) + side - 1));
        auto it = std::lower_bound(order.begin(), order.end(), std::pair<Key, std::uint32_t>{first, 0});
        for (; it != order.end() && it->first <= last; ++it) {
          const HotPixel& h = pixels[it->second];
          if (h.ix < x_lo || h.ix > x_hi || h.iy < y_lo || h.iy > y_hi) continue;
          candidates.push_back(it->second);
          if ((h.ix == pix && h.iy == piy) || (h.ix == qix && h.iy == qiy)) continue;
          double enter = 0, leave = 0;
          if (!meets_square(p, q, h.vertex.lon, h.vertex.lat, half, enter, leave)) continue;
          // Met only at an end (within the noise of the clip): that end lies on the pixel's
          // boundary, where rounding wrote it in the pixel beside (a tie, half to even); the
          // segment leaves from there, it does not pass through this one. Routed through it, a
          // side from a Voronoi vertex at 121.66015625 (7 decimals) went 1e-7 east and back, across
          // the meridian from the pole to that vertex (not snap rounded): fuzz_cells.
          const double length = std::hypot(q.raw_lon - p.raw_lon, q.raw_lat - p.raw_lat);
          if (leave * length <= touch || (1 - enter) * length <= touch) continue;
          hits.push_back({enter, it->second});
        }
      }
    std::sort(hits.begin(), hits.end());
    // Each written segment also takes the hot pixels whose centres lie exactly on it, which its
    // raw segment need not have met: where paths collapse onto one line, each then has every
    // position of the line (the same line split differently on each side had been two different
    // geodesic paths, and areas that did not sum to the ellipsoid's: fuzz_cells at 0 decimals).
    std::int64_t ax = pix, ay = piy;
    auto node = [&](std::int64_t bx, std::int64_t by) {
      const std::int64_t dx = bx - ax, dy = by - ay;
      if (std::gcd(dx, dy) >= 2) {  // else no grid point lies strictly between a and b
        on_line.clear();
        const Wide length2 = Wide{dx} * dx + Wide{dy} * dy;
        for (const std::uint32_t k : candidates) {
          const std::int64_t cx = pixels[k].ix - ax, cy = pixels[k].iy - ay;
          if (Wide{dx} * cy != Wide{dy} * cx) continue;
          const Wide t = Wide{dx} * cx + Wide{dy} * cy;
          if (t > 0 && t < length2) on_line.push_back({t, k});
        }
        std::sort(on_line.begin(), on_line.end());
        for (const auto& [t, k] : on_line) out.push_back(pixels[k].vertex);
        inserted += on_line.size();
      }
      ax = bx, ay = by;
    };
    for (const auto& [enter, k] : hits) {
      node(pixels[k].ix, pixels[k].iy);
      out.push_back(pixels[k].vertex);
    }
    node(qix, qiy);
    inserted += hits.size();
  };

  for (std::vector<SnapVertex>& path : paths) {
    if (path.size() < 2) continue;
    out.clear();
    out.push_back(path[0]);
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      const SnapVertex &p = path[i], &q = path[i + 1];
      // In the sheet of the end off the antimeridian (an end on it is on both).
      const double side = std::fabs(p.raw_lon) == 180 ? q.raw_lon : p.raw_lon;
      route(on_side(p, side), on_side(q, side), out);
      out.push_back(q);
    }
    if (out.size() != path.size()) path.swap(out);
  }
  return inserted;
}

}  // namespace geovor::lonlat
