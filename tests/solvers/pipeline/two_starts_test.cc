// Two refinements in lockstep (solvers/pipeline/two_starts.h) with scripted
// refinements: the abandon rule decides at the same iteration whether the
// two run at once or in turns, a refinement that gets below the converged
// cost goes on, reports reach the caller in order, and a stop request ends
// both.
#include "solvers/pipeline/two_starts.h"

#include <gtest/gtest.h>

#include <functional>
#include <thread>
#include <utility>
#include <vector>

namespace nrsfm {
namespace {

// A refinement whose cost after iteration i is cost(i), converging (ending
// by a tolerance) after `converge_at` iterations (-1: never, up to 200).
RaceRefinement Scripted(std::function<double(int)> cost, int converge_at,
                        int* ran) {
  return [cost, converge_at, ran](const SolverOptions& solver) {
    RaceOutcome outcome;
    outcome.usable = true;
    for (int i = 0;; ++i) {
      if (i > 0) std::this_thread::yield();  // some iterations take longer
      solver.progress(IterationReport{i, cost(i), 0.0});
      outcome.final_cost = cost(i);
      outcome.iterations = i;
      *ran = i;
      if (solver.stop_requested()) return outcome;  // stopped: not converged
      if (i == converge_at || i == 200) {
        outcome.converged = i == converge_at;
        return outcome;
      }
    }
  };
}

TEST(TwoStarts, TheOneFallingBehindIsAbandonedAtTheSameIterationInEitherMode) {
  for (const bool concurrent : {false, true}) {
    SCOPED_TRACE(concurrent);
    // First converges after 5 iterations at cost 1; the second stays at 10:
    // abandoned after 2 · 5 + 10 = 20 iterations.
    int ran_first = -1, ran_second = -1;
    std::vector<std::pair<int, double>> reports;
    SolverOptions solver;
    const std::thread::id caller = std::this_thread::get_id();
    bool on_caller = true;
    solver.progress = [&](const IterationReport& r) {
      reports.emplace_back(r.iteration, r.cost);
      on_caller &= std::this_thread::get_id() == caller;
    };
    RunTwoRefinements(
        solver, concurrent,
        Scripted([](int i) { return 1.0 + 1.0 / (1 + i); }, 5, &ran_first),
        Scripted([](int) { return 10.0; }, -1, &ran_second));
    EXPECT_EQ(ran_first, 5);
    EXPECT_EQ(ran_second, RaceIterations(5));
    EXPECT_TRUE(on_caller);
    // The first's reports, then the second's.
    ASSERT_EQ(reports.size(), 6u + 21u);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(reports[i].first, i);
    for (int i = 0; i < 21; ++i)
      EXPECT_EQ(reports[6 + i], std::make_pair(i, 10.0));

    // The same with the roles swapped: the first is abandoned.
    RunTwoRefinements(SolverOptions(), concurrent,
                      Scripted([](int) { return 10.0; }, -1, &ran_first),
                      Scripted([](int) { return 1.0; }, 3, &ran_second));
    EXPECT_EQ(ran_second, 3);
    EXPECT_EQ(ran_first, RaceIterations(3));
  }
}

TEST(TwoStarts, OneThatGetsBelowTheConvergedCostGoesOn) {
  for (const bool concurrent : {false, true}) {
    int ran_first = -1, ran_second = -1;
    // The second passes below cost 1 at iteration 30: at 2 · 5 + 10 = 20 it
    // is still above it and is abandoned. Passing below it at iteration 15
    // instead, it goes on to its own convergence at 40.
    RunTwoRefinements(
        SolverOptions(), concurrent,
        Scripted([](int) { return 1.0; }, 5, &ran_first),
        Scripted([](int i) { return i < 30 ? 5.0 : 0.5; }, 40, &ran_second));
    EXPECT_EQ(ran_second, 20) << concurrent;
    RunTwoRefinements(
        SolverOptions(), concurrent,
        Scripted([](int) { return 1.0; }, 5, &ran_first),
        Scripted([](int i) { return i < 15 ? 5.0 : 0.5; }, 40, &ran_second));
    EXPECT_EQ(ran_second, 40) << concurrent;
    // A refinement that does not converge (iteration limit) abandons nothing.
    RunTwoRefinements(SolverOptions(), concurrent,
                      Scripted([](int) { return 1.0; }, -1, &ran_first),
                      Scripted([](int) { return 5.0; }, -1, &ran_second));
    EXPECT_EQ(ran_first, 200);
    EXPECT_EQ(ran_second, 200);
  }
}

TEST(TwoStarts, AStopRequestEndsBoth) {
  for (const bool concurrent : {false, true}) {
    int ran_first = -1, ran_second = -1, reports = 0;
    SolverOptions solver;
    solver.progress = [&reports](const IterationReport&) { ++reports; };
    solver.stop_requested = [&reports] { return reports >= 3; };
    RunTwoRefinements(solver, concurrent,
                      Scripted([](int) { return 1.0; }, -1, &ran_first),
                      Scripted([](int) { return 2.0; }, -1, &ran_second));
    // The third report is the first's iteration 2, and the first waits for
    // the answer after it: it stops there, however the threads are
    // scheduled. The second stops after its current iteration: at most one
    // ahead of the first (the lockstep), and it ran (the counters start at
    // -1); taking turns, it was waiting after its iteration 1.
    EXPECT_EQ(ran_first, 2) << concurrent;
    if (concurrent) {
      EXPECT_GE(ran_second, 0);
      EXPECT_LE(ran_second, 3);
    } else {
      EXPECT_EQ(ran_second, 1);
    }
    EXPECT_EQ(reports, 3 + ran_second + 1) << concurrent;
    // Asked before the starts: each runs its iteration 0 and no further.
    ran_first = -1;
    ran_second = -1;
    solver.stop_requested = [] { return true; };
    RunTwoRefinements(solver, concurrent,
                      Scripted([](int) { return 1.0; }, -1, &ran_first),
                      Scripted([](int) { return 2.0; }, -1, &ran_second));
    EXPECT_EQ(ran_first, 0);
    EXPECT_EQ(ran_second, 0);
  }
}

}  // namespace
}  // namespace nrsfm
