#pragma once
// One fork/join helper for every threaded loop of cw4d (the slicer's sweeps and scenes, the
// rasterizer): body(t) runs for t = 0 .. threads - 1, t = 0 on the calling thread and the
// others on threads of their own; every started thread is joined on every path (also when
// starting one throws), and the first exception a body threw is rethrown to the caller.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace cw4d {

/// std::thread::hardware_concurrency() when `requested` is 0 (at least 1), else `requested`.
inline unsigned resolve_threads(unsigned requested) {
  return requested > 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
}

template <class Body>
void fork_join(unsigned threads, Body&& body) {
  if (threads <= 1) {
    body(0u);
    return;
  }
  std::exception_ptr failure;
  std::mutex failure_lock;
  auto guarded = [&](unsigned t) {
    try {
      body(t);
    } catch (...) {
      std::lock_guard<std::mutex> lock(failure_lock);
      if (!failure) failure = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  struct JoinAll {
    std::vector<std::thread>& pool;
    ~JoinAll() {
      for (auto& th : pool)
        if (th.joinable()) th.join();
    }
  } join_all{pool};  // (declared after what the threads use: joins before it is gone)
  pool.reserve(threads - 1);
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(guarded, t);
  guarded(0u);
  for (auto& th : pool) th.join();
  if (failure) std::rethrow_exception(failure);
}

/// f(i) for every i in [0, n), each exactly once, on up to `threads` workers taking indices in
/// turn from a shared counter; exceptions as fork_join.
template <class F>
void parallel_for(std::size_t n, unsigned threads, F&& f) {
  const unsigned workers = static_cast<unsigned>(std::min<std::size_t>(threads, n));
  if (workers <= 1) {
    for (std::size_t i = 0; i < n; ++i) f(i);
    return;
  }
  std::atomic<std::size_t> next{0};
  fork_join(workers, [&](unsigned) {
    for (std::size_t i = next++; i < n; i = next++) f(i);
  });
}

}  // namespace cw4d
