#include "geovor/locate/walk_graph.hpp"

#include <algorithm>
#include <cstring>
#include <new>

#include <sys/mman.h>

#include "geovor/core/default_init.hpp"
#include "geovor/core/error.hpp"
#include "geovor/core/parallel.hpp"
#include "geovor/delaunay/spatial_sort.hpp"

namespace geovor {
namespace {

template <class T, class A>
std::size_t bytes_of(const std::vector<T, A>& v) {
  return v.capacity() * sizeof(T);
}

using U32s = WalkGraph::U32s;
using Keyed = std::pair<std::uint64_t, std::uint32_t>;

// Sites per chunk of the loops whose cost varies (walks around sites, first touches of pages).
constexpr std::size_t kChunk = 16384;

// Slices for a loop over n items: at most one per 2^16 items (a thread costs more than fewer).
unsigned slices_for(std::size_t n, unsigned threads) {
  return static_cast<unsigned>(std::min<std::size_t>(thread_count(threads), n / (std::size_t{1} << 16) + 1));
}
using KeyedVector = std::vector<Keyed, DefaultInitAllocator<Keyed>>;

// Sorts distinct pairs on `threads` threads (a sample sort): splitters sampled from the whole
// array cut it into one bucket per thread, each thread scatters its slice into the buckets, then
// each bucket is sorted by one thread. Every pass is parallel, each page of the result first
// touched by a thread that fills it; the result is the sorted array, whatever the threads.
void sort_distinct(KeyedVector& v, unsigned threads) {
  const std::size_t n = v.size();
  const std::size_t t = std::min<std::size_t>(thread_count(threads), n / (std::size_t{1} << 14) + 1);
  if (t == 1) {
    std::sort(v.begin(), v.end());
    return;
  }
  std::vector<Keyed> samples(64 * t);
  for (std::size_t i = 0; i < samples.size(); ++i) samples[i] = v[i * n / samples.size()];
  std::sort(samples.begin(), samples.end());
  std::vector<Keyed> splitters(t - 1);
  for (std::size_t b = 1; b < t; ++b) splitters[b - 1] = samples[b * samples.size() / t];
  auto bucket_of = [&](const Keyed& x) {
    return static_cast<std::size_t>(std::upper_bound(splitters.begin(), splitters.end(), x) - splitters.begin());
  };
  std::vector<std::size_t> count(t * t, 0);  // [slice * t + bucket]
  parallel_for(n, static_cast<unsigned>(t), [&](unsigned slice, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) ++count[slice * t + bucket_of(v[i])];
  });
  std::vector<std::size_t> at(t * t), bucket_begin(t + 1, 0);  // where each slice writes each bucket
  for (std::size_t b = 0, pos = 0; b < t; ++b) {
    bucket_begin[b] = pos;
    for (std::size_t slice = 0; slice < t; ++slice) at[slice * t + b] = pos, pos += count[slice * t + b];
    bucket_begin[b + 1] = pos;
  }
  KeyedVector out(n);
  parallel_for(n, static_cast<unsigned>(t), [&](unsigned slice, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) out[at[slice * t + bucket_of(v[i])]++] = v[i];
  });
  parallel_for(t, static_cast<unsigned>(t), [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t b = begin; b < end; ++b)
      std::sort(out.begin() + static_cast<std::ptrdiff_t>(bucket_begin[b]), out.begin() + static_cast<std::ptrdiff_t>(bucket_begin[b + 1]));
  });
  v.swap(out);
}

}  // namespace

template <class T>
T* WalkGraph::HugePageAllocator<T>::allocate(std::size_t n) {
  constexpr std::size_t kHuge = std::size_t{2} << 20;
  const std::size_t bytes = n * sizeof(T);
  const std::size_t align = bytes >= kHuge ? kHuge : 64;
  void* p = std::aligned_alloc(align, (bytes + align - 1) / align * align);
  if (p == nullptr) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
  if (bytes >= kHuge) madvise(p, (bytes + align - 1) / align * align, MADV_HUGEPAGE);  // a hint: failure is harmless
#endif
  return static_cast<T*>(p);
}
template struct WalkGraph::HugePageAllocator<std::uint64_t>;

WalkGraph::WalkGraph(const DelaunayHierarchy& h, unsigned threads) : source_(&h) {
  const int num_levels = h.num_levels();
  levels_.resize(static_cast<std::size_t>(num_levels));
  revisions_.resize(static_cast<std::size_t>(num_levels));
  // Arrays below are written on the threads before they are read: none is filled with zeros first
  // (each page is first touched by a thread that writes it).
  std::vector<U32s> site_of(static_cast<std::size_t>(num_levels));  // in node order
  std::vector<U32s> node_of(static_cast<std::size_t>(num_levels));
  // Hilbert order of each level's live sites, and their record offsets.
  for (int l = 0; l < num_levels; ++l) {
    const SphericalDelaunay& dt = h.level(l);
    revisions_[static_cast<std::size_t>(l)] = dt.revision();
    const std::size_t capacity = dt.site_capacity();
    const unsigned t = slices_for(capacity, threads);
    // The live sites in id order: counted by slice, then listed.
    std::vector<std::size_t> live_at(t + 1, 0);
    parallel_for(capacity, t, [&](unsigned slice, std::size_t begin, std::size_t end) {
      std::size_t count = 0;
      for (std::size_t s = begin; s < end; ++s) count += dt.is_live(static_cast<SiteId>(s));
      live_at[slice + 1] = count;
    });
    for (unsigned slice = 0; slice < t; ++slice) live_at[slice + 1] += live_at[slice];
    U32s live(live_at[t]);
    parallel_for(capacity, t, [&](unsigned slice, std::size_t begin, std::size_t end) {
      std::size_t at = live_at[slice];
      for (std::size_t s = begin; s < end; ++s)
        if (dt.is_live(static_cast<SiteId>(s))) live[at++] = static_cast<SiteId>(s);
    });
    // The base in the order of the full-resolution curve keys, so that a query's key finds its
    // place among them (curve_start()); the levels above in hilbert_order()'s.
    U32s order;
    std::vector<std::uint64_t, DefaultInitAllocator<std::uint64_t>> keys;
    if (l == 0) {
      KeyedVector keyed(live.size());
      // The keys on every thread, then sorted on every thread: the same order (the pairs are
      // distinct) whatever the number of threads.
      parallel_for(live.size(), threads, [&](unsigned, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) keyed[i] = {hilbert_key(dt.site(live[i])), static_cast<std::uint32_t>(i)};
      });
      sort_distinct(keyed, threads);
      order.resize(keyed.size());
      keys.resize(keyed.size());
      parallel_for(keyed.size(), threads, [&](unsigned, std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) keys[i] = keyed[i].first, order[i] = keyed[i].second;
      });
    } else {
      std::vector<Vec3> pts;
      pts.reserve(live.size());
      for (const SiteId s : live) pts.push_back(dt.site(s));
      const std::vector<std::uint32_t> o = hilbert_order(pts);
      order.assign(o.begin(), o.end());
    }
    U32s& sites = site_of[static_cast<std::size_t>(l)];
    U32s& nodes = node_of[static_cast<std::size_t>(l)];
    sites.resize(live.size());
    nodes.resize(capacity);
    parallel_for(capacity, t, [&](unsigned, std::size_t begin, std::size_t end) {
      std::fill(nodes.begin() + static_cast<std::ptrdiff_t>(begin), nodes.begin() + static_cast<std::ptrdiff_t>(end), kNoIndex);
    });
    // The words of each record on every thread (its degree: a walk around the site, scattered
    // reads), in chunks taken in turn; then their offsets, by slice.
    U32s words(order.size());
    parallel_chunks(order.size(), kChunk, threads, [&](unsigned, std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const SiteId s = live[order[i]];
        sites[i] = s;
        std::uint32_t d = static_cast<std::uint32_t>(live.size() - 1);
        if (dt.num_triangles() > 0) {
          d = 0;
          const HalfedgeId e0 = dt.site_edge(s);
          HalfedgeId e = e0;
          do ++d, e = dt.next_around_site(e);
          while (e != e0);
        }
        words[i] = (36 + 4 * d + 7) / 8;
      }
    });
    const unsigned u = slices_for(order.size(), threads);
    std::vector<std::uint64_t> offset_at(u + 1, 0);
    parallel_for(order.size(), u, [&](unsigned slice, std::size_t begin, std::size_t end) {
      std::uint64_t sum = 0;
      for (std::size_t i = begin; i < end; ++i) sum += words[i];
      offset_at[slice + 1] = sum;
    });
    for (unsigned slice = 0; slice < u; ++slice) offset_at[slice + 1] += offset_at[slice];
    const std::uint64_t total = offset_at[u];
    if (total >= kNoIndex) throw Error(ErrorCode::InvalidArgument, "walk graph: too many sites");
    parallel_for(order.size(), u, [&](unsigned slice, std::size_t begin, std::size_t end) {
      std::uint64_t offset = offset_at[slice];
      for (std::size_t i = begin; i < end; ++i) {
        nodes[sites[i]] = static_cast<std::uint32_t>(offset);
        const std::uint32_t w = words[i];
        words[i] = static_cast<std::uint32_t>(offset);  // from here on, the record's offset
        offset += w;
      }
    });
    if (l == 0)
      for (std::size_t i = 0; i < order.size(); i += kCurveSample) curve_keys_.push_back(keys[i]), curve_nodes_.push_back(words[i]);
    levels_[static_cast<std::size_t>(l)].words.resize(total);  // not written: each record below writes its words
    levels_[static_cast<std::size_t>(l)].num_nodes = static_cast<std::uint32_t>(sites.size());
  }
  for (int l = 0; l < num_levels; ++l) {
    const SphericalDelaunay& dt = h.level(l);
    const U32s& sites = site_of[static_cast<std::size_t>(l)];
    const U32s& nodes = node_of[static_cast<std::size_t>(l)];
    unsigned char* words = reinterpret_cast<unsigned char*>(levels_[static_cast<std::size_t>(l)].words.data());
    // Each record is written by one thread, every byte of it: disjoint words. Chunks taken in
    // turn: the first touch of fresh pages costs more on some threads than on others.
    parallel_chunks(sites.size(), kChunk, threads, [&](unsigned, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const SiteId s = sites[k];
      unsigned char* rec = words + 8 * std::size_t{nodes[s]};
      const Vec3 p = dt.lifted_site(s);
      std::memcpy(rec, &p.x, 8);
      std::memcpy(rec + 8, &p.y, 8);
      std::memcpy(rec + 16, &p.z, 8);
      std::uint32_t fields[3] = {kNoIndex, s, 0};
      if (l + 1 < num_levels && h.up(l, s) != kNoIndex) fields[0] = node_of[static_cast<std::size_t>(l) + 1][h.up(l, s)];
      if (l > 0) fields[1] = node_of[static_cast<std::size_t>(l) - 1][h.down(l, s)];
      unsigned char* adj = rec + 36;
      auto add = [&](std::uint32_t w) {
        std::memcpy(adj + 4 * fields[2], &w, 4);
        ++fields[2];
      };
      if (dt.num_triangles() == 0) {  // fewer than 3 sites: each is the others' neighbour
        for (const SiteId t : sites)
          if (t != s) add(nodes[t]);
      } else {
        const HalfedgeId e0 = dt.site_edge(s);
        HalfedgeId e = e0;
        do {
          add(nodes[dt.triangles()[next_halfedge(e)]]);
          e = dt.next_around_site(e);
        } while (e != e0);
      }
      std::memcpy(rec + 24, fields, 12);
      std::memset(adj + 4 * fields[2], 0, (8 - (36 + 4 * fields[2]) % 8) % 8);  // the padding to the next word
    }
    });
  }
  if (num_levels > 0) node_of_ = std::move(node_of[0]);
}

std::uint32_t WalkGraph::curve_start(const Vec3& q) const {
  if (curve_keys_.empty()) return kNoIndex;
  const std::uint64_t key = hilbert_key(q);
  const std::size_t i = static_cast<std::size_t>(std::upper_bound(curve_keys_.begin(), curve_keys_.end(), key) - curve_keys_.begin());
  if (i == 0) return curve_nodes_.front();
  if (i == curve_keys_.size()) return curve_nodes_.back();
  // The sampled nodes on either side of q's place on the curve: the nearer one.
  const std::uint32_t a = curve_nodes_[i - 1], b = curve_nodes_[i];
  return dot(q, point(0, a)) >= dot(q, point(0, b)) ? a : b;
}

std::size_t WalkGraph::memory_bytes() const {
  std::size_t bytes = bytes_of(revisions_) + bytes_of(node_of_) + bytes_of(curve_keys_) + bytes_of(curve_nodes_);
  for (const Level& l : levels_) bytes += bytes_of(l.words);
  return bytes;
}

}  // namespace geovor
