/// \file parallel.hpp
/// \brief geovor's one way to run threads: a parallel loop over slices or chunks, a group of background
/// tasks, and an ordered pipeline (read in order, work in parallel, write in order).
///
/// Guarantees shared by all of them:
/// - A worker's exception reaches the caller: it is rethrown once every thread has stopped (the
///   first by slice, task or item order). Nothing calls std::terminate.
/// - A thread that cannot be created (a memory or process limit) is not an error: its work runs
///   on the threads that exist, down to the calling thread alone. Results do not depend on how
///   many threads ran.
/// - No thread outlives the call (or the TaskGroup).
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <memory>
#include <thread>
#include <vector>

namespace geovor {

/// The threads to use when `requested` are asked for: `requested`, or one per core when 0.
unsigned thread_count(unsigned requested);

namespace detail {
void run_slices(unsigned slices, const std::function<void(unsigned)>& slice);
void run_ordered_pipeline(unsigned workers, std::size_t window, const std::function<bool(std::size_t)>& read,
                          const std::function<void(std::size_t, unsigned)>& work,
                          const std::function<void(std::size_t)>& write);
}  // namespace detail

/// Runs work(slice, begin, end) over [0, n) cut into `threads` contiguous slices of nearly equal
/// length (slice i is [n i / threads, n (i + 1) / threads)); slice 0 runs on the calling thread.
/// threads == 0 means one per core; at most n slices are made (none when n == 0).
template <class Work>
void parallel_for(std::size_t n, unsigned threads, Work&& work) {
  if (n == 0) return;
  const std::size_t slices = std::min<std::size_t>(thread_count(threads), n);
  if (slices == 1) {
    work(0u, std::size_t{0}, n);
    return;
  }
  detail::run_slices(static_cast<unsigned>(slices), [&](unsigned i) {
    work(i, n * i / slices, n * (i + 1) / slices);
  });
}

/// Runs work(worker, begin, end) over [0, n) in chunks of `chunk` indices (the last one
/// shorter), which `threads` workers take in turn as each finishes its last: for work whose
/// cost varies along the range, or that shares the cores with other tasks, where parallel_for's
/// equal slices finish far apart. Worker 0 is the calling thread. Which worker runs which chunk
/// varies from run to run: results must not depend on it (per-worker state is scratch, or
/// merged in an order-independent way). threads == 0 means one per core. After a chunk throws,
/// no new chunk starts; the exception reaches the caller as parallel_for's do.
template <class Work>
void parallel_chunks(std::size_t n, std::size_t chunk, unsigned threads, Work&& work) {
  if (n == 0) return;
  chunk = std::max<std::size_t>(chunk, 1);
  const std::size_t chunks = (n - 1) / chunk + 1;
  const std::size_t workers = std::min<std::size_t>(thread_count(threads), chunks);
  std::atomic<std::size_t> next{0};
  auto take = [&](unsigned worker) {
    for (;;) {
      const std::size_t c = next.fetch_add(1, std::memory_order_relaxed);
      if (c >= chunks) return;
      try {
        work(worker, c * chunk, std::min(n, (c + 1) * chunk));
      } catch (...) {
        next.store(chunks, std::memory_order_relaxed);
        throw;
      }
    }
  };
  if (workers == 1) {
    take(0u);
    return;
  }
  detail::run_slices(static_cast<unsigned>(workers), take);
}

/// Tasks that run beside the calling thread until wait() (or the destructor) joins them. A task
/// that cannot get a thread runs at once, in run(). wait() rethrows the first task's exception;
/// the destructor joins and drops exceptions (so wait() is how a caller learns of them).
class TaskGroup {
 public:
  TaskGroup() = default;
  TaskGroup(const TaskGroup&) = delete;
  TaskGroup& operator=(const TaskGroup&) = delete;
  ~TaskGroup();

  void run(std::function<void()> task);
  void wait();

 private:
  std::vector<std::thread> threads_;
  std::vector<std::unique_ptr<std::exception_ptr>> errors_;  // one per task, in run() order (stable addresses)
};

/// An ordered pipeline over a stream of items, in a ring of `window` reusable Items (their
/// buffers are kept from one use to the next):
/// - read(item) fills the next item and returns false at the end of the stream; calls are serial
///   and in stream order, on the workers;
/// - work(item, worker) runs on `threads` workers in parallel (worker < threads: an index for
///   per-worker state);
/// - write(item) runs on the calling thread, serially, in stream order.
/// At most `window` items (at least threads + 1 are used) are between read and write. With one
/// thread (or none creatable) it is the plain loop read, work, write. An exception from any stage
/// stops the pipeline; the items before it in stream order have been written, and it is rethrown.
template <class Item, class Read, class Work, class Write>
void ordered_pipeline(unsigned threads, std::size_t window, Read&& read, Work&& work, Write&& write) {
  threads = thread_count(threads);
  window = std::max<std::size_t>(window, std::size_t{threads} + 1);
  std::vector<Item> items(threads == 1 ? 1 : window);
  detail::run_ordered_pipeline(
      threads, items.size(), [&](std::size_t slot) { return static_cast<bool>(read(items[slot])); },
      [&](std::size_t slot, unsigned worker) { work(items[slot], worker); },
      [&](std::size_t slot) { write(items[slot]); });
}

}  // namespace geovor
