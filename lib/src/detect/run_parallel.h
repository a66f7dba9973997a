// A parallel loop over index ranges on a given number of threads.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cstddef>
#include <map>
#include <memory>
#include <mutex>

namespace untangle {

// The arena of `threads` threads (> 0), made once and kept for the life of the process. oneTBB
// 2021 (Debian 12's 2021.8) can hang for good in an arena's initialisation when arenas are
// created and destroyed at a high rate (uxlfoundation/oneTBB#1281: creating, using and destroying
// arenas from one thread reproduces it); an arena made per loop hung a dump of 1,500 random
// tangles in update_crossings after about 300 scenes. Never destroyed (kept past exit on
// purpose), and safe to enter from several threads at once.
inline tbb::task_arena& arena_of(int threads) {
  static std::mutex mutex;
  static auto* arenas = new std::map<int, std::unique_ptr<tbb::task_arena>>;
  const std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<tbb::task_arena>& arena = (*arenas)[threads];
  if (!arena) arena = std::make_unique<tbb::task_arena>(threads);
  return *arena;
}

// Calls body(begin, end) on subranges of [0, n) of at least `grain` indices, on `threads` threads
// (0: all cores, 1: inline on the caller's thread). Bodies write into index slots of their own,
// so the result does not depend on the thread count.
template <class Body>
void run_parallel(int threads, std::size_t n, std::size_t grain, const Body& body) {
  if (threads == 1) {
    if (n > 0) body(std::size_t{0}, n);
    return;
  }
  auto loop = [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
  };
  if (threads > 0) {
    arena_of(threads).execute(loop);
  } else {
    loop();
  }
}

}  // namespace untangle
