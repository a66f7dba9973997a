// A parallel loop over index ranges on a given number of threads.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cstddef>

namespace untangle {

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
    tbb::task_arena arena(threads);
    arena.execute(loop);
  } else {
    loop();
  }
}

}  // namespace untangle
