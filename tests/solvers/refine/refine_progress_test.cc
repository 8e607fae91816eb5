// Refine()'s report of a solve and the caller's control of it: the
// summary and the progress callback, a stop request, and the time spent in
// the callbacks.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <vector>

#include "core/eval/metrics.h"
#include "solvers/refine/refine.h"
#include "tests/solvers/refine/refine_test_util.h"

namespace nrsfm {
namespace {

using testing_util::Perturbed;
using testing_util::Sequence;

TEST(Refine, SummaryAndProgressCallback) {
  SyntheticSequence s = Sequence(30, 15, 3, 0.01);
  Model model = Perturbed(s.truth, 0.02, 3);
  std::vector<IterationReport> reports;
  SolverOptions options;
  options.verbosity = 1;
  options.progress = [&reports](const IterationReport& r) {
    reports.push_back(r);
  };
  RefineSummary summary;
  ASSERT_TRUE(
      Refine(ProblemOptions(), options, s.measurements, &model, &summary).ok());
  EXPECT_TRUE(summary.usable);
  EXPECT_NE(summary.message.find("tolerance"), std::string::npos)
      << summary.message;
  ASSERT_EQ(static_cast<int>(reports.size()), summary.iterations + 1);
  for (int i = 0; i < static_cast<int>(reports.size()); ++i) {
    EXPECT_EQ(reports[i].iteration, i);
    if (i > 0) {
      EXPECT_LE(reports[i].cost, reports[i - 1].cost);
      EXPECT_GE(reports[i].seconds, reports[i - 1].seconds);
    }
  }
  EXPECT_EQ(reports.front().cost, summary.initial_cost);
  EXPECT_EQ(reports.back().cost, summary.final_cost);
  EXPECT_LT(summary.final_cost, 0.1 * summary.initial_cost);
  // Cost and RMS agree (no robust loss, unit weights): rms² = 2 cost / N.
  EXPECT_EQ(summary.num_residual_blocks, 30 * 15);
  EXPECT_NEAR(summary.reprojection_rms,
              std::sqrt(2.0 * summary.final_cost / summary.num_residual_blocks),
              1e-12);
  EXPECT_EQ(summary.reprojection_rms, ReprojectionRms(s.measurements, model));
  EXPECT_NEAR(
      summary.initial_reprojection_rms,
      std::sqrt(2.0 * summary.initial_cost / summary.num_residual_blocks),
      1e-12);
  EXPECT_GT(summary.seconds, 0.0);
  EXPECT_GE(summary.seconds, summary.build_seconds + summary.minimizer_seconds);
  // The report of the solver that ran: `auto` takes the structured one here
  // (problems/linear_solver_choice.h); Ceres' own FullReport otherwise.
  EXPECT_EQ(summary.linear_solver, "structured");
  EXPECT_EQ(summary.ceres_report.find("structured Levenberg-Marquardt: " +
                                      std::to_string(summary.iterations) +
                                      " iterations"),
            0u)
      << summary.ceres_report;
  options.linear_solver = LinearSolverChoice::kIterativeSchur;
  model = Perturbed(s.truth, 0.02, 3);
  ASSERT_TRUE(
      Refine(ProblemOptions(), options, s.measurements, &model, &summary).ok());
  EXPECT_NE(summary.ceres_report.find("LEVENBERG_MARQUARDT"),
            std::string::npos);
}

// stop_requested ends the solve after the iteration it first answers true,
// with Ceres' solvers and with the structured one; the model keeps the last
// accepted iterate, so its cost is below the start's.
TEST(Refine, StopRequestedEndsTheSolveAfterThatIteration) {
  SyntheticSequence s = Sequence(30, 15, 3, 0.01);
  for (const LinearSolverChoice choice :
       {LinearSolverChoice::kIterativeSchur, LinearSolverChoice::kStructured}) {
    Model model = Perturbed(s.truth, 0.02, 3);
    int reports = 0;
    SolverOptions options;
    options.linear_solver = choice;
    options.progress = [&reports](const IterationReport&) { ++reports; };
    options.stop_requested = [&reports] { return reports >= 3; };
    RefineSummary summary;
    ASSERT_TRUE(
        Refine(ProblemOptions(), options, s.measurements, &model, &summary)
            .ok());
    SCOPED_TRACE(summary.linear_solver);
    EXPECT_TRUE(summary.stopped);
    EXPECT_FALSE(summary.converged);
    EXPECT_TRUE(summary.usable);
    EXPECT_EQ(summary.message, "stopped on request");
    EXPECT_EQ(summary.iterations, 2);
    EXPECT_EQ(reports, 3);  // iterations 0, 1, 2
    EXPECT_LT(summary.final_cost, summary.initial_cost);
    EXPECT_EQ(summary.reprojection_rms, ReprojectionRms(s.measurements, model));
  }
  // Without a request the same solve runs to a tolerance.
  Model model = Perturbed(s.truth, 0.02, 3);
  SolverOptions options;
  options.stop_requested = [] { return false; };
  RefineSummary summary;
  ASSERT_TRUE(
      Refine(ProblemOptions(), options, s.measurements, &model, &summary).ok());
  EXPECT_FALSE(summary.stopped);
  EXPECT_TRUE(summary.converged);
}

// The time spent in the caller's callbacks is measured apart
// (RefineSummary::callback_seconds: where Reconstruct()'s two starts wait for
// each other), with Ceres' solvers and with the structured one.
TEST(Refine, TimeInTheCallbacksIsReportedApart) {
  SyntheticSequence s = Sequence(30, 15, 3, 0.01);
  for (const LinearSolverChoice choice :
       {LinearSolverChoice::kIterativeSchur, LinearSolverChoice::kStructured}) {
    Model model = Perturbed(s.truth, 0.02, 3);
    int calls = 0;
    const auto nap = [&calls] {
      ++calls;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    };
    SolverOptions options;
    options.linear_solver = choice;
    options.progress = [&nap](const IterationReport&) { nap(); };
    options.stop_requested = [&nap] {
      nap();
      return false;
    };
    RefineSummary summary;
    ASSERT_TRUE(
        Refine(ProblemOptions(), options, s.measurements, &model, &summary)
            .ok());
    SCOPED_TRACE(summary.linear_solver);
    EXPECT_GE(calls, 2 * summary.iterations);
    EXPECT_GE(summary.callback_seconds, 0.002 * calls);
    EXPECT_LE(summary.callback_seconds, summary.seconds);
    // Without callbacks nothing is counted.
    model = Perturbed(s.truth, 0.02, 3);
    options.progress = nullptr;
    options.stop_requested = nullptr;
    ASSERT_TRUE(
        Refine(ProblemOptions(), options, s.measurements, &model, &summary)
            .ok());
    EXPECT_EQ(summary.callback_seconds, 0.0);
  }
}
}  // namespace
}  // namespace nrsfm
