// Splitting a loop over threads without changing its result: the index range
// is cut into contiguous pieces, one per thread, in a fixed way that depends
// only on n, the thread count and the grain, so a body that writes only its
// own items (or per-worker partial results combined in worker order) gives
// the same output for a given thread count on every run.
//
// The pieces run on a process-wide pool of worker threads that are started
// once and then wait for work (starting threads per loop cost more than the
// short loops of the solvers' inner iterations). A loop started while the
// pool is busy — from one of its own pieces, or from another thread of the
// caller's — runs its pieces one after another on the calling thread, with
// the same split and worker indices, so its result does not change.
#ifndef NRSFM_CORE_MATH_PARALLEL_FOR_H_
#define NRSFM_CORE_MATH_PARALLEL_FOR_H_

#include <algorithm>
#include <functional>

namespace nrsfm {
namespace internal {

// Runs piece(0) … piece(count − 1), each on its own thread when the pool is
// free (piece 0 on the calling thread), else all on the calling thread, and
// returns when all have finished.
void RunPieces(int count, const std::function<void(int)>& piece);

}  // namespace internal

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
  internal::RunPieces(threads, [&](int i) {
    body(static_cast<int>(static_cast<long long>(n) * i / threads),
         static_cast<int>(static_cast<long long>(n) * (i + 1) / threads), i);
  });
}

// Runs body(begin, end, piece) over [0, n) cut into P = min(pieces,
// max(1, n / grain)) contiguous ranges, range p = [n·p/P, n·(p+1)/P), on at
// most `threads` threads, and returns P. The split does not depend on the
// thread count: a reduction that keeps one partial result per piece and
// adds them in piece order gives the same bits with any number of threads.
template <typename Body>
int ParallelForPieces(int n, int pieces, int threads, int grain,
                      const Body& body) {
  const int count = std::max(1, std::min(pieces, n / std::max(1, grain)));
  ParallelForWorker(count, threads, /*grain=*/1, [&](int first, int last, int) {
    for (int p = first; p < last; ++p) {
      body(static_cast<int>(static_cast<long long>(n) * p / count),
           static_cast<int>(static_cast<long long>(n) * (p + 1) / count), p);
    }
  });
  return count;
}

// The same without the worker index: body(begin, end).
template <typename Body>
void ParallelFor(int n, int threads, int grain, const Body& body) {
  ParallelForWorker(n, threads, grain,
                    [&](int begin, int end, int) { body(begin, end); });
}

}  // namespace nrsfm

#endif  // NRSFM_CORE_MATH_PARALLEL_FOR_H_
