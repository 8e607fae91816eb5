// Splitting a loop over threads without changing its result: the index range
// is cut into contiguous pieces, one per thread, in a fixed way that depends
// only on n, the thread count and the grain, so a body that writes only its
// own items (or per-worker partial results combined in worker order) gives
// the same output for a given thread count on every run.
#ifndef NRSFM_CORE_PARALLEL_FOR_H_
#define NRSFM_CORE_PARALLEL_FOR_H_

#include <algorithm>
#include <thread>
#include <vector>

namespace nrsfm {

// Runs body(begin, end, worker) over [0, n) split into at most `threads`
// contiguous ranges of at least `grain` items each (fewer ranges when n is
// small); worker < threads, range w = [n·w/T, n·(w+1)/T) for the T used.
// threads ≤ 1 (or n < 2·grain) runs body(0, n, 0) on the calling thread.
template <typename Body>
void ParallelForWorker(int n, int threads, int grain, const Body& body) {
  threads = std::max(1, std::min(threads, n / std::max(1, grain)));
  if (threads <= 1) {
    body(0, n, 0);
    return;
  }
  std::vector<std::thread> workers;
  for (int i = 1; i < threads; ++i) {
    workers.emplace_back([&, i] { body(n * i / threads, n * (i + 1) / threads, i); });
  }
  body(0, n / threads, 0);
  for (std::thread& w : workers) w.join();
}

// The same without the worker index: body(begin, end).
template <typename Body>
void ParallelFor(int n, int threads, int grain, const Body& body) {
  ParallelForWorker(n, threads, grain,
                    [&](int begin, int end, int) { body(begin, end); });
}

}  // namespace nrsfm

#endif  // NRSFM_CORE_PARALLEL_FOR_H_
