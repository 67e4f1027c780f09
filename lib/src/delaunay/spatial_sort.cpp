#include "geovor/delaunay/spatial_sort.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

namespace geovor {
namespace {

constexpr int kBits = 16;  // the finest grid: 2^16 x 2^16 cells per face
constexpr std::uint32_t kCells = 1u << kBits;

// The Hilbert curve, read four levels at a time. While descending, the classic algorithm swaps
// and/or complements the coordinates; those transforms commute, so two bits of state (swap,
// complement) say where we are, and a table maps (state, 4 bits of x, 4 bits of y) to the next
// 8 bits of the distance along the curve and the next state.
struct HilbertTable {
  std::uint8_t digits[4][256];
  std::uint8_t next[4][256];
  HilbertTable() {
    for (unsigned state = 0; state < 4; ++state)
      for (unsigned xy = 0; xy < 256; ++xy) {
        unsigned swap = state & 1u, complement = state >> 1, d = 0;
        for (int level = 3; level >= 0; --level) {
          unsigned rx = ((xy >> 4) >> level) & 1u, ry = (xy >> level) & 1u;
          rx ^= complement, ry ^= complement;
          if (swap) std::swap(rx, ry);
          d = (d << 2) | ((3u * rx) ^ ry);
          if (ry == 0) {
            complement ^= rx;
            swap ^= 1u;
          }
        }
        digits[state][xy] = static_cast<std::uint8_t>(d);
        next[state][xy] = static_cast<std::uint8_t>(swap | (complement << 1));
      }
  }
};

// Distance along the Hilbert curve of the grid of the top `bits` bits of x and y (kBits wide).
std::uint64_t hilbert_2d(std::uint32_t x, std::uint32_t y, int bits) {
  static const HilbertTable table;
  const int steps = (bits + 3) / 4;  // round up to whole steps; the extra levels are dropped
  std::uint64_t d = 0;
  unsigned state = 0;
  for (int step = 0; step < steps; ++step) {
    const int shift = kBits - 4 * (step + 1);
    const unsigned xy = (((x >> shift) & 15u) << 4) | ((y >> shift) & 15u);
    d = (d << 8) | table.digits[state][xy];
    state = table.next[state][xy];
  }
  return d >> (2 * (4 * steps - bits));  // drop the extra low levels
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

struct Keyed {
  std::uint64_t key;
  std::uint32_t index;
};

// Stable LSD radix sort on the low `bits` bits of the keys, in as few passes of at most 12 bits
// as possible (4096 buckets keep the scatter cache-friendly), all histograms in one read; about
// 5x faster than std::sort here. A pass where every key has the same digit is skipped.
void radix_sort(std::vector<Keyed>& a, int bits) {
  const int passes = std::max(1, (bits + 11) / 12);
  const int digit = (bits + passes - 1) / passes;
  const std::size_t buckets = std::size_t{1} << digit;
  std::vector<std::size_t> count(buckets * static_cast<std::size_t>(passes), 0);
  for (const Keyed& x : a)
    for (int p = 0; p < passes; ++p) ++count[p * buckets + ((x.key >> (p * digit)) & (buckets - 1))];
  std::vector<Keyed> tmp(a.size());
  for (int p = 0; p < passes; ++p) {
    std::size_t* c = count.data() + p * buckets;
    if (std::find(c, c + buckets, a.size()) != c + buckets) continue;
    std::size_t sum = 0;
    for (std::size_t b = 0; b < buckets; ++b) {
      const std::size_t here = c[b];
      c[b] = sum;
      sum += here;
    }
    const int shift = p * digit;
    for (const Keyed& x : a) tmp[c[(x.key >> shift) & (buckets - 1)]++] = x;
    a.swap(tmp);
  }
}

std::vector<std::uint32_t> indices_by_key(std::vector<Keyed>& keyed, int bits) {
  radix_sort(keyed, bits);
  std::vector<std::uint32_t> order(keyed.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].index;
  return order;
}

int key_bits(int bits) { return 3 + 2 * bits; }  // face and Hilbert position: key < 6 * 4^bits

// A grid of about 4 cells per point is fine enough: points sharing a cell keep input order.
int bits_for(std::size_t n) {
  int bits = 4;
  while (bits < kBits && (std::size_t{6} << (2 * bits)) < 4 * n) ++bits;
  return bits;
}

std::uint64_t hilbert_key_bits(const Vec3& p, int bits) noexcept {
  const double ax = std::fabs(p.x), ay = std::fabs(p.y), az = std::fabs(p.z);
  // Faces in the order +z, +x, +y, -x, -y, -z: consecutive faces share an edge.
  int face;
  double u, v;
  if (az >= ax && az >= ay) {
    face = p.z >= 0 ? 0 : 5;
    const double inv = 1.0 / az;
    u = p.x * inv, v = p.y * inv;
  } else if (ax >= ay) {
    face = p.x >= 0 ? 1 : 3;
    const double inv = 1.0 / ax;
    u = p.y * inv, v = p.z * inv;
  } else {
    face = p.y >= 0 ? 2 : 4;
    const double inv = 1.0 / ay;
    u = p.z * inv, v = p.x * inv;
  }
  return (std::uint64_t(face) << (2 * bits)) | hilbert_2d(to_cell(u), to_cell(v), bits);
}

}  // namespace

std::uint64_t hilbert_key(const Vec3& p) noexcept { return hilbert_key_bits(p, kBits); }

std::vector<std::uint32_t> hilbert_order(std::span<const Vec3> points, std::vector<std::uint64_t>* keys) {
  const int bits = bits_for(points.size());
  std::vector<Keyed> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    keyed[i] = {hilbert_key_bits(points[i], bits), static_cast<std::uint32_t>(i)};
  std::vector<std::uint32_t> order = indices_by_key(keyed, key_bits(bits));
  if (keys) {
    keys->resize(keyed.size());
    for (std::size_t k = 0; k < keyed.size(); ++k) (*keys)[k] = keyed[k].key;
  }
  return order;
}

std::vector<std::uint32_t> brio_order(std::span<const Vec3> points, std::uint64_t seed) {
  // Each point draws its round from a geometric law (about half the points in the last round, a
  // quarter in the one before...), and one sort by (round, Hilbert key) gives all rounds in order.
  // Keys are computed in input order: reading the points in shuffled order costs a cache miss each.
  const std::size_t n = points.size();
  const int bits = bits_for(n);
  int last_round = 0;
  while ((std::size_t{64} << last_round) < n) ++last_round;
  std::vector<Keyed> keyed(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t state = seed ^ (0x9e3779b97f4a7c15ULL * (i + 1));
    const std::uint64_t r = splitmix(state);
    const int level = r == 0 ? 64 : __builtin_ctzll(r);  // P(level >= j) = 2^-j
    const std::uint64_t round = static_cast<std::uint64_t>(last_round - std::min(level, last_round));
    keyed[i] = {(round << key_bits(bits)) | hilbert_key_bits(points[i], bits), static_cast<std::uint32_t>(i)};
  }
  return indices_by_key(keyed, key_bits(bits) + 6);  // at most 2^6 rounds
}

}  // namespace geovor
