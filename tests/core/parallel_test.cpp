#include "geovor/core/parallel.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <system_error>
#include <thread>
#include <numeric>
#include <stdexcept>
#include <string>

namespace geovor {
namespace {

TEST(ParallelFor, SlicesCoverTheRangeOnce) {
  for (const std::size_t n : {0u, 1u, 2u, 7u, 1000u}) {
    for (const unsigned threads : {1u, 2u, 3u, 8u, 64u}) {
      std::vector<std::atomic<int>> hits(n);
      std::vector<std::size_t> begins(threads, SIZE_MAX);
      parallel_for(n, threads, [&](unsigned slice, std::size_t begin, std::size_t end) {
        ASSERT_LT(slice, threads);
        begins[slice] = begin;
        for (std::size_t i = begin; i < end; ++i) hits[i]++;
      });
      for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(hits[i].load(), 1) << n << " " << threads << " " << i;
      // Contiguous slices in order: slice i starts at n i / slices.
      const std::size_t slices = std::min<std::size_t>(threads, n);
      for (std::size_t i = 0; i < slices; ++i) EXPECT_EQ(begins[i], n * i / slices);
    }
  }
}

TEST(ParallelFor, TheFirstSlicesExceptionReachesTheCaller) {
  std::atomic<int> finished{0};
  try {
    parallel_for(100, 4, [&](unsigned slice, std::size_t, std::size_t) {
      if (slice == 1 || slice == 3) throw std::runtime_error("slice " + std::to_string(slice));
      ++finished;
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "slice 1");
  }
  EXPECT_EQ(finished.load(), 2);  // the other slices ran to their end
}

TEST(ParallelChunks, ChunksCoverTheRangeOnceOnBoundedWorkers) {
  for (const std::size_t n : {0u, 1u, 2u, 7u, 1000u, 1025u}) {
    for (const std::size_t chunk : {0u, 1u, 3u, 64u, 5000u}) {
      for (const unsigned threads : {1u, 2u, 3u, 8u}) {
        std::vector<std::atomic<int>> hits(n);
        std::atomic<int> calls{0};
        parallel_chunks(n, chunk, threads, [&](unsigned worker, std::size_t begin, std::size_t end) {
          ASSERT_LT(worker, threads);
          const std::size_t c = std::max<std::size_t>(chunk, 1);
          EXPECT_EQ(begin % c, 0u);                    // chunks start on multiples of the chunk
          EXPECT_EQ(end, std::min(n, begin + c));      // and are whole but for the last
          for (std::size_t i = begin; i < end; ++i) hits[i]++;
          ++calls;
        });
        for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(hits[i].load(), 1) << n << " " << chunk << " " << threads << " " << i;
        const std::size_t c = std::max<std::size_t>(chunk, 1);
        EXPECT_EQ(static_cast<std::size_t>(calls.load()), n == 0 ? 0 : (n - 1) / c + 1);
      }
    }
  }
}

TEST(ParallelChunks, AThrowingChunkStopsTheRestAndReachesTheCaller) {
  for (const unsigned threads : {1u, 2u, 4u}) {
    std::atomic<int> started{0};
    try {
      parallel_chunks(1000, 1, threads, [&](unsigned, std::size_t begin, std::size_t) {
        ++started;
        if (begin == 10) throw std::runtime_error("chunk 10");
      });
      FAIL() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "chunk 10");
    }
    // With one worker, chunks run in order and none after the throw; with more, the others
    // finish the chunks they hold (how many is a race).
    if (threads == 1) EXPECT_EQ(started.load(), 11);
    EXPECT_GE(started.load(), 11);
  }
}

// The address space capped just above what the process maps: a new thread's stack (8 MiB) cannot
// be mapped, so pthread_create fails as under a container's memory limit.
class NoNewThreads {
 public:
  NoNewThreads() {
    getrlimit(RLIMIT_AS, &old_);
    std::ifstream status("/proc/self/status");
    std::string key;
    std::size_t kib = 0;
    while (status >> key)
      if (key == "VmSize:" && status >> kib) break;
    rlimit capped = old_;
    capped.rlim_cur = (kib + 2048) * 1024;  // 2 MiB of room for the test's own allocations
    active_ = kib > 0 && setrlimit(RLIMIT_AS, &capped) == 0;
  }
  ~NoNewThreads() { setrlimit(RLIMIT_AS, &old_); }
  bool active() const { return active_; }

 private:
  rlimit old_{};
  bool active_ = false;
};

#if defined(__SANITIZE_ADDRESS__)
#define GEOVOR_NO_AS_LIMIT 1  // ASan maps shadow memory as it goes
#endif

#ifndef GEOVOR_NO_AS_LIMIT
// Exits 0 when all of the work is done, on the calling thread alone, with no thread creatable.
[[noreturn]] void run_without_new_threads() {
  std::vector<int> hits(1000, 0);
  std::vector<std::thread::id> ran(16);
  std::size_t items = 0, written = 0;
  int task = 0;
  bool refused = false;
  {
    NoNewThreads limit;
    if (!limit.active()) std::exit(2);
    try {
      std::thread([] {}).join();
    } catch (const std::system_error&) {
      refused = true;  // the limit does bite
    }
    parallel_for(hits.size(), 16, [&](unsigned slice, std::size_t begin, std::size_t end) {
      ran[slice] = std::this_thread::get_id();
      for (std::size_t i = begin; i < end; ++i) hits[i]++;
    });
    TaskGroup group;
    group.run([&] { task = 1; });
    group.wait();
    ordered_pipeline<long>(
        8, 16,
        [&](long& item) {
          item = static_cast<long>(items);
          return items++ < 100;
        },
        [](long& item, unsigned) { item *= 2; },
        [&](long& item) {
          if (item != 2 * static_cast<long>(written++)) std::exit(3);
        });
  }
  for (const std::thread::id& id : ran)
    if (id != std::this_thread::get_id()) std::exit(4);
  const bool ok = refused && task == 1 && written == 100 && std::accumulate(hits.begin(), hits.end(), 0) == 1000;
  std::exit(ok ? 0 : 5);
}

#endif

TEST(ParallelFor, RunsOnTheCallingThreadWhenNoThreadCanBeCreated) {
#ifdef GEOVOR_NO_AS_LIMIT
  GTEST_SKIP() << "an address-space limit breaks the sanitizer";
#else
  // In a fresh process (threadsafe death tests re-execute the binary): glibc reuses the stacks of
  // joined threads, which the earlier tests would leave for it.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(run_without_new_threads(), ::testing::ExitedWithCode(0), "");
#endif
}

TEST(TaskGroup, RunsBesideTheCallerAndRethrowsOnWait) {
  TaskGroup group;
  std::atomic<int> sum{0};
  for (int i = 1; i <= 5; ++i) group.run([&sum, i] { sum += i; });
  group.run([] { throw std::invalid_argument("task"); });
  EXPECT_THROW(group.wait(), std::invalid_argument);
  EXPECT_EQ(sum.load(), 15);
  group.run([&sum] { sum += 100; });  // reusable after wait()
  group.wait();
  EXPECT_EQ(sum.load(), 115);
}

struct Item {
  std::size_t index = 0;
  std::vector<int> buffer;  // kept between uses
  long value = 0;
};

TEST(OrderedPipeline, WritesEveryItemInStreamOrder) {
  for (const unsigned threads : {1u, 2u, 3u, 16u}) {
    for (const std::size_t window : {1u, 2u, 5u, 64u}) {
      const std::size_t n = 500;
      std::size_t next = 0;
      std::vector<long> out;
      ordered_pipeline<Item>(
          threads, window,
          [&](Item& item) {
            if (next == n) return false;
            item.index = next++;
            item.buffer.assign(item.index % 7 + 1, static_cast<int>(item.index));
            return true;
          },
          [&](Item& item, unsigned worker) {
            ASSERT_LT(worker, threads);
            item.value = std::accumulate(item.buffer.begin(), item.buffer.end(), 0L);
          },
          [&](Item& item) { out.push_back(item.value); });
      ASSERT_EQ(out.size(), n) << threads << " " << window;
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(out[i], static_cast<long>(i) * static_cast<long>(i % 7 + 1));
    }
  }
}

// An exception in any stage stops the pipeline; the items before it have been written.
TEST(OrderedPipeline, AFailureStopsAfterTheItemsBeforeIt) {
  for (const int stage : {0, 1, 2}) {
    for (const unsigned threads : {1u, 2u, 4u}) {
      std::size_t next = 0;
      std::vector<std::size_t> out;
      try {
        ordered_pipeline<Item>(
            threads, 8,
            [&](Item& item) {
              if (stage == 0 && next == 37) throw std::runtime_error("read");
              item.index = next++;
              return true;  // an endless stream: only the failure ends it
            },
            [&](Item& item, unsigned) {
              if (stage == 1 && item.index == 37) throw std::runtime_error("work");
            },
            [&](Item& item) {
              if (stage == 2 && item.index == 37) throw std::runtime_error("write");
              out.push_back(item.index);
            });
        FAIL() << "no exception";
      } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), stage == 0 ? "read" : stage == 1 ? "work" : "write");
      }
      ASSERT_EQ(out.size(), 37u) << stage << " " << threads;
      for (std::size_t i = 0; i < out.size(); ++i) EXPECT_EQ(out[i], i);
    }
  }
}

TEST(OrderedPipeline, AnEmptyStreamWritesNothing) {
  int writes = 0;
  ordered_pipeline<Item>(
      4, 4, [](Item&) { return false; }, [](Item&, unsigned) {}, [&](Item&) { ++writes; });
  EXPECT_EQ(writes, 0);
}

}  // namespace
}  // namespace geovor
