#include "geovor/lonlat/polygon_validity.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "geovor/kernel/predicates.hpp"

namespace geovor {
namespace {

int orient(const LonLat& a, const LonLat& b, const LonLat& c) {
  return static_cast<int>(kernel::orient2d(a.lon_deg, a.lat_deg, b.lon_deg, b.lat_deg, c.lon_deg, c.lat_deg));
}

// c lies on the closed segment [a, b], given orient(a, b, c) == 0.
bool on_segment(const LonLat& a, const LonLat& b, const LonLat& c) {
  return std::min(a.lon_deg, b.lon_deg) <= c.lon_deg && c.lon_deg <= std::max(a.lon_deg, b.lon_deg) &&
         std::min(a.lat_deg, b.lat_deg) <= c.lat_deg && c.lat_deg <= std::max(a.lat_deg, b.lat_deg);
}

// The closed segments [a, b] and [c, d] share a point.
bool segments_meet(const LonLat& a, const LonLat& b, const LonLat& c, const LonLat& d) {
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
         (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
}

double planar_area2(const Ring& r) {
  double twice = 0;
  for (std::size_t i = 0; i + 1 < r.size(); ++i)
    twice += (r[i].lon_deg - r[0].lon_deg) * (r[i + 1].lat_deg - r[0].lat_deg) -
             (r[i + 1].lon_deg - r[0].lon_deg) * (r[i].lat_deg - r[0].lat_deg);
  return twice;
}

// p strictly inside the closed ring r (p on no segment of r), by exact crossing parity.
bool inside(const Ring& r, const LonLat& p) {
  bool in = false;
  for (std::size_t i = 0; i + 1 < r.size(); ++i) {
    const LonLat &a = r[i], &b = r[i + 1];
    const bool a_below = a.lat_deg <= p.lat_deg, b_below = b.lat_deg <= p.lat_deg;
    if (a_below == b_below) continue;
    // The segment crosses the horizontal line through p: is the crossing right of p?
    const int o = orient(a, b, p);
    if (b_below ? o < 0 : o > 0) in = !in;
  }
  return in;
}

// Every position of r on one line (r has no area and no fold).
bool collinear(const Ring& r) {
  const auto q = std::find_if(r.begin(), r.end(), [&r](const LonLat& p) { return !(p == r.front()); });
  if (q == r.end()) return true;
  return std::all_of(r.begin(), r.end(), [&](const LonLat& p) { return orient(r.front(), *q, p) == 0; });
}

// Square degrees: a hundredth of a square metre at the equator, a square of 1e-6 degree.
constexpr double kTinyLoopDeg2 = 1e-12;

// Splits a closed ring that passes more than once through a position (snap rounding merges
// the two sides of a thin part into one path, and the ring touches itself there) into closed
// rings that do not, appended to `parts`; `ring` keeps the last one. Returns whether it split.
bool split_at_repeats(Ring& ring, std::vector<Ring>& parts) {
  if (ring.size() < 5) return false;
  const std::size_t n = ring.size() - 1;  // the last position closes the ring
  // Each position's number among the distinct ones, by a sort (rings run to hundreds of
  // thousands of positions; a hash map's nodes had cost a cache miss each, a quarter of the
  // time of a column of lunes at 4 decimals).
  struct Entry {
    LonLat p;
    std::uint32_t i;
  };
  std::vector<Entry> sorted(n);
  for (std::uint32_t i = 0; i < n; ++i) sorted[i] = {ring[i], i};
  std::sort(sorted.begin(), sorted.end(), [](const Entry& a, const Entry& b) {
    return a.p.lon_deg < b.p.lon_deg || (a.p.lon_deg == b.p.lon_deg && a.p.lat_deg < b.p.lat_deg);
  });
  std::vector<std::uint32_t> id(n);
  std::uint32_t distinct = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0 && !(sorted[k].p == sorted[k - 1].p)) ++distinct;
    id[sorted[k].i] = distinct;
  }
  if (distinct + 1 == n) return false;  // no position twice: the ring as it is
  // A stack walk: a position already on the stack (where[its number]) closes the loop above it.
  constexpr std::size_t kOff = ~std::size_t{0};
  std::vector<std::size_t> where(distinct + 1, kOff);
  std::vector<LonLat> stack;
  std::vector<std::uint32_t> stack_id;
  for (std::size_t i = 0; i < n; ++i) {
    const LonLat& p = ring[i];
    const std::size_t at = where[id[i]];
    if (at == kOff) {
      where[id[i]] = stack.size();
      stack.push_back(p);
      stack_id.push_back(id[i]);
      continue;
    }
    Ring loop(stack.begin() + static_cast<std::ptrdiff_t>(at), stack.end());
    loop.push_back(p);
    parts.push_back(std::move(loop));
    for (std::size_t k = at + 1; k < stack.size(); ++k) where[stack_id[k]] = kOff;
    stack.resize(at + 1);
    stack_id.resize(at + 1);
  }
  stack.push_back(stack.front());
  ring.swap(stack);
  return true;
}

}  // namespace

std::string polygon_problem(const MultiPolygon& polygons) {
  struct Seg {
    double xmin, xmax, ymin, ymax;
    std::uint32_t ring, index, ring_size;  // index of the segment in its ring, segments in it
  };
  std::vector<const Ring*> rings;
  for (const Polygon& poly : polygons) {
    if (!poly.holes.empty()) return "a polygon has holes";
    rings.push_back(&poly.exterior);
  }
  std::vector<Seg> segs;
  for (std::uint32_t k = 0; k < rings.size(); ++k) {
    const Ring& r = *rings[k];
    if (r.size() < 4) return "a ring has fewer than 4 positions";
    if (!(r.front() == r.back())) return "a ring is not closed";
    for (const LonLat& p : r)
      if (!std::isfinite(p.lon_deg) || !std::isfinite(p.lat_deg)) return "a coordinate is not finite";
    if (!(planar_area2(r) > 0)) return "a ring is not counter-clockwise or has no area";
    const std::uint32_t n = static_cast<std::uint32_t>(r.size() - 1);
    for (std::uint32_t i = 0; i < n; ++i) {
      const LonLat &a = r[i], &b = r[i + 1];
      if (a == b) return "a ring repeats a position";
      segs.push_back({std::min(a.lon_deg, b.lon_deg), std::max(a.lon_deg, b.lon_deg),
                      std::min(a.lat_deg, b.lat_deg), std::max(a.lat_deg, b.lat_deg), k, i, n});
    }
  }
  // Sweep along the axis in which the segments are thinner, relative to the extent of all of
  // them (rings near a pole have segments long in longitude and thin in latitude).
  double xlo = 180, xhi = -180, ylo = 90, yhi = -90, xsum = 0, ysum = 0;
  for (const Seg& t : segs) {
    xlo = std::min(xlo, t.xmin), xhi = std::max(xhi, t.xmax), xsum += t.xmax - t.xmin;
    ylo = std::min(ylo, t.ymin), yhi = std::max(yhi, t.ymax), ysum += t.ymax - t.ymin;
  }
  if (ysum * (xhi - xlo) < xsum * (yhi - ylo))
    for (Seg& t : segs) std::swap(t.xmin, t.ymin), std::swap(t.xmax, t.ymax);  // sweep in y
  std::sort(segs.begin(), segs.end(), [](const Seg& a, const Seg& b) { return a.xmin < b.xmin; });
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const Seg& s = segs[i];
    const Ring& rs = *rings[s.ring];
    const LonLat &a = rs[s.index], &b = rs[s.index + 1];
    for (std::size_t j = i + 1; j < segs.size() && segs[j].xmin <= s.xmax; ++j) {
      const Seg& t = segs[j];
      if (t.ymin > s.ymax || t.ymax < s.ymin) continue;
      const Ring& rt = *rings[t.ring];
      const LonLat &c = rt[t.index], &d = rt[t.index + 1];
      if (s.ring == t.ring) {
        const std::uint32_t n = s.ring_size;
        const bool s_then_t = (s.index + 1) % n == t.index;
        if (s_then_t || (t.index + 1) % n == s.index) {
          // Consecutive segments p -> q -> r share q; collinear, r must not turn back towards p.
          const LonLat& p = s_then_t ? a : c;
          const LonLat& q = s_then_t ? b : d;
          const LonLat& r = s_then_t ? d : b;
          auto side = [](double u, double v) { return (u > v) - (u < v); };
          if (orient(p, q, r) == 0 &&
              ((side(p.lon_deg, q.lon_deg) != 0 && side(p.lon_deg, q.lon_deg) == side(r.lon_deg, q.lon_deg)) ||
               (side(p.lat_deg, q.lat_deg) != 0 && side(p.lat_deg, q.lat_deg) == side(r.lat_deg, q.lat_deg))))
            return "a ring folds back on itself (spike)";
          continue;
        }
      }
      if (segments_meet(a, b, c, d)) {
        if (s.ring == t.ring) return "a ring intersects itself";
        // Parts may touch at a common position (OGC): one shared end, not overlapping there.
        const int shared = (a == c) + (a == d) + (b == c) + (b == d);
        const LonLat& e = a == c || a == d ? a : b;
        const LonLat& x = e == a ? b : a;
        const LonLat& y = e == c ? d : c;
        auto side = [](double u, double v) { return (u > v) - (u < v); };
        const bool overlap = orient(e, x, y) == 0 && side(x.lon_deg, e.lon_deg) == side(y.lon_deg, e.lon_deg) &&
                             side(x.lat_deg, e.lat_deg) == side(y.lat_deg, e.lat_deg);
        if (shared != 1 || overlap) return "two parts cross or overlap";
      }
    }
  }
  // No two rings cross: parts must not lie inside one another, tested at a position of one
  // that is not on the other (they meet only at common positions). Only a part whose bounding
  // box holds the other's can hold it: a sweep in longitude finds those pairs (snap rounding
  // pinches a thin band into thousands of parts side by side, which all pairs made quadratic).
  struct Box {
    double xmin = 180, xmax = -180, ymin = 90, ymax = -90;
    std::uint32_t ring = 0;
  };
  std::vector<Box> boxes(rings.size());
  for (std::uint32_t k = 0; k < rings.size(); ++k) {
    Box& b = boxes[k];
    b.ring = k;
    for (const LonLat& p : *rings[k])
      b.xmin = std::min(b.xmin, p.lon_deg), b.xmax = std::max(b.xmax, p.lon_deg),
      b.ymin = std::min(b.ymin, p.lat_deg), b.ymax = std::max(b.ymax, p.lat_deg);
  }
  std::sort(boxes.begin(), boxes.end(), [](const Box& a, const Box& b) { return a.xmin < b.xmin; });
  std::vector<std::vector<LonLat>> sorted_positions(rings.size());  // filled on first use
  auto position_less = [](const LonLat& a, const LonLat& b) {
    return a.lon_deg < b.lon_deg || (a.lon_deg == b.lon_deg && a.lat_deg < b.lat_deg);
  };
  // "" if part k is outside part l, else why not.
  auto outside = [&](std::uint32_t k, std::uint32_t l) -> const char* {
    std::vector<LonLat>& on_l = sorted_positions[l];
    if (on_l.empty()) {
      on_l.assign(rings[l]->begin(), rings[l]->end());
      std::sort(on_l.begin(), on_l.end(), position_less);
    }
    const Ring& rk = *rings[k];
    const auto p = std::find_if(rk.begin(), rk.end(), [&](const LonLat& q) {
      return !std::binary_search(on_l.begin(), on_l.end(), q, position_less);
    });
    if (p == rk.end()) return "two parts share all their positions";
    if (inside(*rings[l], *p)) return "a part lies inside another";
    return "";
  };
  auto holds = [](const Box& outer, const Box& inner) {
    return outer.xmin <= inner.xmin && inner.xmax <= outer.xmax && outer.ymin <= inner.ymin && inner.ymax <= outer.ymax;
  };
  std::vector<Box> active;  // boxes that began at or before the current one and reach it
  for (const Box& b : boxes) {
    std::erase_if(active, [&](const Box& a) { return a.xmax < b.xmin; });
    for (const Box& a : active) {
      if (holds(a, b))
        if (const char* why = outside(b.ring, a.ring); *why) return why;
      if (holds(b, a))
        if (const char* why = outside(a.ring, b.ring); *why) return why;
    }
    active.push_back(b);
  }
  return {};
}

bool is_star_shaped_ccw(const Ring& ring) {
  const std::size_t n = ring.size() < 4 ? 0 : ring.size() - 1;
  if (n < 3) return false;
  double cx = 0, cy = 0;
  for (std::size_t i = 0; i < n; ++i) cx += ring[i].lon_deg, cy += ring[i].lat_deg;
  cx /= static_cast<double>(n), cy /= static_cast<double>(n);
  int turns = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const LonLat &a = ring[i], &b = ring[i + 1];
    if (kernel::orient2d(cx, cy, a.lon_deg, a.lat_deg, b.lon_deg, b.lat_deg) != Sign::Positive) return false;
    // Counter-clockwise about c, crossing the ray from c towards +x upwards (the half-open rule).
    turns += a.lat_deg < cy && b.lat_deg >= cy;
  }
  return turns == 1;
}

const char* to_string(WrittenStatus status) {
  switch (status) {
    case WrittenStatus::Written:
      return "written";
    case WrittenStatus::Collapsed:
      return "collapsed";
    case WrittenStatus::Unwritable:
      return "unwritable";
  }
  return "?";
}

WrittenStatus certify_written(MultiPolygon& polygons, bool* cleaned_out) {
  if (cleaned_out) *cleaned_out = false;
  // Fast path: one ring, star-shaped about its mean (the typical cell), is valid as it stands.
  if (polygons.size() == 1 && polygons[0].holes.empty() && is_star_shaped_ccw(polygons[0].exterior))
    return WrittenStatus::Written;
  if (polygons.empty()) return WrittenStatus::Collapsed;
  bool cleaned = false;
  for (Polygon& poly : polygons) {
    const std::size_t before = poly.exterior.size();
    remove_spikes(poly.exterior);
    cleaned |= poly.exterior.size() != before;
  }
  // Rings that touch themselves become parts that touch (each cleaned again); a part without
  // area (its positions collinear) is dropped.
  std::vector<Ring> split;
  for (Polygon& poly : polygons)
    if (split_at_repeats(poly.exterior, split)) {
      remove_spikes(poly.exterior);
      cleaned = true;
    }
  for (Ring& r : split) {
    remove_spikes(r);
    if (r.size() >= 4) polygons.push_back(Polygon{std::move(r), {}});
  }
  // A ring whose positions all lie on one line (two sides rounded onto one meridian, a ring
  // along a pole line) has collapsed. So has a clockwise loop smaller than kTinyLoopDeg2: snap
  // rounding can route a path around a few pixels once more than it should (the tips of 19
  // cells of a co-circular ring meeting in three pixels: A B C A B), and the loop split off
  // there winds the wrong way; larger ones stay, and the ring is reported unwritable.
  for (Polygon& poly : polygons) {
    if (poly.exterior.size() < 4) continue;
    const double twice_area = planar_area2(poly.exterior);
    if (collinear(poly.exterior) || (twice_area < 0 && -twice_area <= 2 * kTinyLoopDeg2)) {
      poly.exterior.clear();
      cleaned = true;
    }
  }
  if (cleaned_out) *cleaned_out = cleaned;
  if (cleaned) {
    std::erase_if(polygons, [](const Polygon& poly) { return poly.exterior.size() < 4; });
    if (polygons.empty()) return WrittenStatus::Collapsed;
  }
  if (!polygon_problem(polygons).empty()) {
    polygons.clear();
    return WrittenStatus::Unwritable;
  }
  return WrittenStatus::Written;
}

void remove_spikes(Ring& ring) {
  if (ring.empty()) return;
  if (ring.size() > 1 && ring.back() == ring.front()) ring.pop_back();
  // b is the tip of a spike between a and c: the three on one line, c back towards a (exact).
  auto folds = [](const LonLat& a, const LonLat& b, const LonLat& c) {
    if (orient(a, b, c) != 0) return false;
    return a.lon_deg != b.lon_deg ? (b.lon_deg > a.lon_deg) != (c.lon_deg > b.lon_deg)
                                  : (b.lat_deg > a.lat_deg) != (c.lat_deg > b.lat_deg);
  };
  // A stack pass drops repeats and spike tips; the cyclic ends are then trimmed the same way.
  std::vector<LonLat> out;
  out.reserve(ring.size());
  for (const LonLat& p : ring) {
    while (out.size() >= 2 && !(out.back() == p) && folds(out[out.size() - 2], out.back(), p)) out.pop_back();
    if (!out.empty() && out.back() == p) continue;
    out.push_back(p);
  }
  std::size_t begin = 0, end = out.size();
  for (bool changed = true; changed && end - begin >= 2;) {
    changed = false;
    if (out[end - 1] == out[begin]) {
      --end, changed = true;
    } else if (end - begin >= 3 && folds(out[end - 2], out[end - 1], out[begin])) {
      --end, changed = true;  // ... x, y | z ...: the tip y at the seam
    } else if (end - begin >= 3 && folds(out[end - 1], out[begin], out[begin + 1])) {
      ++begin, changed = true;  // ... x | y, z ...
    }
  }
  ring.assign(out.begin() + static_cast<std::ptrdiff_t>(begin), out.begin() + static_cast<std::ptrdiff_t>(end));
  if (!ring.empty()) ring.push_back(ring.front());
}

}  // namespace geovor
