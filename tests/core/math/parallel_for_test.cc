// core/math/parallel_for.h: the split, every item once, per-worker sums that do
// not depend on how the pieces were scheduled, nested and concurrent loops.
#include "core/math/parallel_for.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <thread>
#include <vector>

namespace nrsfm {
namespace {

TEST(ParallelFor, SplitsTheRangeAsDocumented) {
  // n = 10, 3 threads, grain 2: ranges [0, 3), [3, 6), [6, 10).
  std::vector<int> begins(3, -1), ends(3, -1);
  ParallelForWorker(10, 3, 2, [&](int begin, int end, int worker) {
    begins[worker] = begin;
    ends[worker] = end;
  });
  EXPECT_EQ(begins, (std::vector<int>{0, 3, 6}));
  EXPECT_EQ(ends, (std::vector<int>{3, 6, 10}));
  // Too few items for two pieces of the grain: one piece on the caller.
  int calls = 0;
  ParallelForWorker(7, 4, 4, [&](int begin, int end, int worker) {
    ++calls;
    EXPECT_EQ(begin, 0);
    EXPECT_EQ(end, 7);
    EXPECT_EQ(worker, 0);
  });
  EXPECT_EQ(calls, 1);
}

TEST(ParallelFor, EveryItemOnceForAnyThreadCount) {
  for (int threads : {1, 2, 3, 8}) {
    for (int n : {0, 1, 5, 64, 1000}) {
      std::vector<std::atomic<int>> hits(n);
      for (auto& h : hits) h = 0;
      ParallelFor(n, threads, 1, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) ++hits[i];
      });
      for (int i = 0; i < n; ++i)
        EXPECT_EQ(hits[i], 1) << threads << " " << n << " " << i;
    }
  }
}

// Per-worker partial sums of values whose floating-point sum depends on the
// order, combined in worker order.
double OrderedSum(int threads) {
  const int n = 10000;
  std::vector<double> partial(threads, 0.0);
  ParallelForWorker(n, threads, 1, [&](int begin, int end, int worker) {
    for (int i = begin; i < end; ++i)
      partial[worker] += std::sin(i) * 1e-3 + 1e3 * (i % 7);
  });
  double sum = 0.0;
  for (double p : partial) sum += p;
  return sum;
}

TEST(ParallelFor, RepeatsBitForBitForAGivenThreadCount) {
  for (int threads : {1, 2, 4}) {
    const double first = OrderedSum(threads);
    for (int run = 0; run < 20; ++run)
      EXPECT_EQ(OrderedSum(threads), first) << threads;
  }
}

TEST(ParallelFor, NestedAndConcurrentLoopsGiveTheSameResult) {
  const double expected = OrderedSum(2);
  // A loop inside a piece of another runs inline with the same split.
  std::vector<double> inner(4, 0.0);
  ParallelFor(4, 4, 1, [&](int begin, int end) {
    for (int i = begin; i < end; ++i) inner[i] = OrderedSum(2);
  });
  for (double v : inner) EXPECT_EQ(v, expected);
  // Loops started from several threads at once: one gets the pool, the
  // others run inline; all agree.
  std::vector<double> results(6, 0.0);
  std::vector<std::thread> callers;
  for (int c = 0; c < 6; ++c) {
    callers.emplace_back([&, c] {
      for (int run = 0; run < 10; ++run) results[c] = OrderedSum(2);
    });
  }
  for (std::thread& t : callers) t.join();
  for (double v : results) EXPECT_EQ(v, expected);
}

}  // namespace
}  // namespace nrsfm
