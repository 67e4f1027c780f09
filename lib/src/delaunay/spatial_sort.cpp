#include "geovor/delaunay/spatial_sort.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace geovor {
namespace {

constexpr int kBits = 20;
constexpr std::uint32_t kCells = 1u << kBits;

// Classic (x, y) -> distance along the Hilbert curve of a kCells x kCells grid.
std::uint64_t hilbert_2d(std::uint32_t x, std::uint32_t y) {
  std::uint64_t d = 0;
  for (std::uint32_t s = kCells / 2; s > 0; s /= 2) {
    const std::uint32_t rx = (x & s) ? 1 : 0;
    const std::uint32_t ry = (y & s) ? 1 : 0;
    d += std::uint64_t{s} * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = kCells - 1 - x;
        y = kCells - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

std::uint32_t to_cell(double u) {  // u in [-1, 1]
  const double c = (u + 1.0) * 0.5 * kCells;
  if (!(c > 0)) return 0;
  return c >= kCells ? kCells - 1 : static_cast<std::uint32_t>(c);
}

// splitmix64: a portable generator, so orders are identical on every platform.
std::uint64_t splitmix(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

void sort_by_key(std::span<const Vec3> points, std::uint32_t* first, std::uint32_t* last) {
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  keyed.reserve(static_cast<std::size_t>(last - first));
  for (auto* it = first; it != last; ++it) keyed.emplace_back(hilbert_key(points[*it]), *it);
  std::sort(keyed.begin(), keyed.end());
  for (std::size_t i = 0; i < keyed.size(); ++i) first[i] = keyed[i].second;
}

}  // namespace

std::uint64_t hilbert_key(const Vec3& p) noexcept {
  const double ax = std::fabs(p.x), ay = std::fabs(p.y), az = std::fabs(p.z);
  // Faces in the order +z, +x, +y, -x, -y, -z: consecutive faces share an edge.
  int face;
  double u, v;
  if (az >= ax && az >= ay) {
    face = p.z >= 0 ? 0 : 5;
    u = p.x / az, v = p.y / az;
  } else if (ax >= ay) {
    face = p.x >= 0 ? 1 : 3;
    u = p.y / ax, v = p.z / ax;
  } else {
    face = p.y >= 0 ? 2 : 4;
    u = p.z / ay, v = p.x / ay;
  }
  return (std::uint64_t(face) << (2 * kBits)) | hilbert_2d(to_cell(u), to_cell(v));
}

std::vector<std::uint32_t> hilbert_order(std::span<const Vec3> points) {
  std::vector<std::uint32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0u);
  sort_by_key(points, order.data(), order.data() + order.size());
  return order;
}

std::vector<std::uint32_t> brio_order(std::span<const Vec3> points, std::uint64_t seed) {
  std::vector<std::uint32_t> order(points.size());
  std::iota(order.begin(), order.end(), 0u);
  std::uint64_t state = seed;
  for (std::size_t i = order.size(); i > 1; --i) {
    const std::size_t j = splitmix(state) % i;
    std::swap(order[i - 1], order[j]);
  }
  // Rounds: [0, n/2^k), ..., [n/4, n/2), [n/2, n); the first round is small enough to sort whole.
  constexpr std::size_t kFirstRound = 64;
  std::size_t end = order.size();
  while (end > 0) {
    const std::size_t begin = end > kFirstRound ? end / 2 : 0;
    sort_by_key(points, order.data() + begin, order.data() + end);
    end = begin;
  }
  return order;
}

}  // namespace geovor
