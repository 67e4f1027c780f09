#include "geovor/core/parallel.hpp"

#include <condition_variable>
#include <memory>
#include <mutex>
#include <system_error>
#include <utility>

namespace geovor {

unsigned thread_count(unsigned requested) {
  return requested > 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
}

namespace detail {
namespace {

// Starts `thread` in `pool`; false when the system refuses a thread (the caller runs its work).
template <class F>
bool try_start(std::vector<std::thread>& pool, F&& thread) {
  try {
    pool.emplace_back(std::forward<F>(thread));
    return true;
  } catch (const std::system_error&) {
    return false;
  }
}

}  // namespace

void run_slices(unsigned slices, const std::function<void(unsigned)>& slice) {
  std::vector<std::exception_ptr> errors(slices);
  auto guarded = [&](unsigned i) {
    try {
      slice(i);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  unsigned started = 1;
  while (started < slices && try_start(pool, [&guarded, i = started] { guarded(i); })) ++started;
  guarded(0);
  for (unsigned i = started; i < slices; ++i) guarded(i);  // the slices no thread could take
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

void run_ordered_pipeline(unsigned workers, std::size_t window, const std::function<bool(std::size_t)>& read,
                          const std::function<void(std::size_t, unsigned)>& work,
                          const std::function<void(std::size_t)>& write) {
  auto sequential = [&] {
    while (read(0)) {
      work(0, 0);
      write(0);
    }
  };
  if (workers <= 1 || window <= 1) return sequential();

  // Item t (in stream order) lives in slot t % window. Workers take items in order, read them one
  // at a time (read_mutex) once their slot has been written out, then work on them in parallel.
  std::mutex mutex, read_mutex;
  std::condition_variable changed;
  std::size_t next_item = 0;               // the next item a worker takes
  std::size_t written = 0;                 // items written by the caller
  std::size_t end = SIZE_MAX;              // the item read() said does not exist, or the failed one + 1
  bool stop = false;                       // the caller stops the workers
  std::vector<char> ready(window, 0);
  std::vector<std::exception_ptr> errors(window);

  auto finish_item = [&](std::size_t slot, std::exception_ptr error) {
    {
      std::lock_guard lock(mutex);
      errors[slot] = std::move(error);
      ready[slot] = 1;
    }
    changed.notify_all();
  };
  auto worker = [&](unsigned w) {
    for (;;) {
      std::size_t item;
      {
        std::lock_guard read_lock(read_mutex);
        {
          std::unique_lock lock(mutex);
          changed.wait(lock, [&] { return stop || next_item >= end || next_item < written + window; });
          if (stop || next_item >= end) return;
          item = next_item++;
        }
        bool more = false;
        std::exception_ptr error;
        try {
          more = read(item % window);
        } catch (...) {
          error = std::current_exception();
        }
        if (!more) {
          {
            std::lock_guard lock(mutex);
            end = error ? item + 1 : item;
          }
          if (error) finish_item(item % window, std::move(error));
          else changed.notify_all();
          return;
        }
      }
      std::exception_ptr error;
      try {
        work(item % window, w);
      } catch (...) {
        error = std::current_exception();
      }
      finish_item(item % window, std::move(error));
    }
  };

  std::vector<std::thread> pool;
  // Stops and joins the workers however the caller's loop ends.
  struct Joiner {
    std::vector<std::thread>& pool;
    std::mutex& mutex;
    std::condition_variable& changed;
    bool& stop;
    ~Joiner() {
      {
        std::lock_guard lock(mutex);
        stop = true;
      }
      changed.notify_all();
      for (std::thread& t : pool) t.join();
    }
  } joiner{pool, mutex, changed, stop};
  for (unsigned w = 0; w < workers; ++w)
    if (!try_start(pool, [&worker, w] { worker(w); })) break;
  if (pool.empty()) return sequential();

  for (std::size_t item = 0;; ++item) {
    const std::size_t slot = item % window;
    {
      std::unique_lock lock(mutex);
      changed.wait(lock, [&] { return ready[slot] || item >= end; });
      if (!ready[slot]) return;  // item >= end: the stream is over
      ready[slot] = 0;
    }
    if (errors[slot]) std::rethrow_exception(std::exchange(errors[slot], nullptr));
    write(slot);
    {
      std::lock_guard lock(mutex);
      written = item + 1;
    }
    changed.notify_all();
  }
}

}  // namespace detail

TaskGroup::~TaskGroup() {
  for (std::thread& t : threads_)
    if (t.joinable()) t.join();
}

void TaskGroup::run(std::function<void()> task) {
  std::exception_ptr* error = errors_.emplace_back(std::make_unique<std::exception_ptr>()).get();
  auto guarded = [error, task = std::move(task)] {
    try {
      task();
    } catch (...) {
      *error = std::current_exception();
    }
  };
  if (!detail::try_start(threads_, guarded)) guarded();
}

void TaskGroup::wait() {
  for (std::thread& t : threads_)
    if (t.joinable()) t.join();
  threads_.clear();
  const std::vector<std::unique_ptr<std::exception_ptr>> errors = std::exchange(errors_, {});
  for (const auto& e : errors)
    if (*e) std::rethrow_exception(*e);
}

}  // namespace geovor
