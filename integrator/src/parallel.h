#pragma once
// The integrator's parallel loop.

#include <atomic>
#include <cstddef>
#include <vector>

#include <tbb/parallel_for.h>
#ifdef ACDF_THREAD_SANITIZER
#include <thread>

#include <tbb/task_arena.h>
#endif

namespace acdf {

// Runs job(i) for every i < count (a tile, a probe row, a light path), on TBB's workers. Under
// ThreadSanitizer the same calls run on plain std::threads that take indices from an atomic
// counter, as many as the current task arena allows: libtbb is not instrumented, so TSan cannot
// see its scheduler's synchronisation and reports its reuse of task memory as races, which would
// bury real ones.
template <class Job>
void forEachInParallel(std::size_t count, const Job& job) {
#ifdef ACDF_THREAD_SANITIZER
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t i = next++; i < count; i = next++) job(i);
  };
  std::vector<std::jthread> helpers;
  for (int i = 1; i < tbb::this_task_arena::max_concurrency(); ++i) helpers.emplace_back(work);
  work();
#else
  tbb::parallel_for(std::size_t{0}, count, job);
#endif
}

}  // namespace acdf
