#include "solvers/refine/refine.h"

#include <ceres/normal_prior.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <chrono>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "core/eval/metrics.h"
#include "core/synthetic/synthetic.h"
#include "problems/extra_terms.h"
#include "tests/synthetic_sequences.h"

namespace nrsfm {
namespace {

SyntheticSequence Sequence(int frames, int points, int bases, double noise,
                           double missing = 0.0, std::uint64_t seed = 5) {
  return testing_util::RandomBasisSequence(frames, points, bases, noise,
                                           missing, seed);
}

// Adds N(0, sigma²) to every rotation, weight and basis entry.
Model Perturbed(const Model& model, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  Model out = model;
  auto perturb = [&](auto& matrix) {
    for (Eigen::Index i = 0; i < matrix.size(); ++i)
      matrix.data()[i] += normal(rng);
  };
  perturb(out.rotations);
  perturb(out.weights);
  perturb(out.basis);
  return out;
}

// The same reconstruction in another gauge: object frame rotated by Q
// (R_t → R_t Qᵀ, S_k → Q S_k) and bases mixed by A (l_t → A l_t,
// [S_1 … S_K] → [S_1 … S_K] (A⁻¹ ⊗ I_3)). Every projection is unchanged.
Model Regauged(const Model& model) {
  const int k = model.num_bases;
  const Eigen::Matrix3d q =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -1).normalized())
          .toRotationMatrix();
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(k, k);
  for (int i = 0; i < k; ++i) {
    for (int j = 0; j < k; ++j) a(i, j) += 0.3 * std::sin(1.0 + i + 2.0 * j);
  }
  const Eigen::MatrixXd a_inverse = a.inverse();
  Model out = model;
  for (int v = 0; v < model.NumViews(); ++v) {
    out.SetRotation(
        v / model.num_cameras, v % model.num_cameras,
        model.Rotation(v / model.num_cameras, v % model.num_cameras) *
            q.transpose());
  }
  out.weights = a * model.weights;
  for (int j = 0; j < k; ++j) {
    Eigen::Matrix3Xd shape = Eigen::Matrix3Xd::Zero(3, model.num_points);
    for (int i = 0; i < k; ++i) shape += a_inverse(i, j) * model.BasisShape(i);
    out.SetBasisShape(j, q * shape);
  }
  return out;
}

double MaxAbsDifference(const Model& a, const Model& b) {
  return std::max({(a.rotations - b.rotations).cwiseAbs().maxCoeff(),
                   (a.translations - b.translations).cwiseAbs().maxCoeff(),
                   (a.weights - b.weights).cwiseAbs().maxCoeff(),
                   (a.basis - b.basis).cwiseAbs().maxCoeff()});
}

TEST(SolverOptions, CheckNamesTheBadField) {
  EXPECT_TRUE(SolverOptions().Check().ok());
  auto expect_error = [](SolverOptions options, const std::string& text) {
    const Status status = options.Check();
    EXPECT_FALSE(status.ok()) << text;
    EXPECT_NE(status.message().find(text), std::string::npos)
        << status.message();
  };
  SolverOptions o;
  o.max_iterations = -1;
  expect_error(o, "solver options: max_iterations must be >= 0, got -1");
  o = SolverOptions();
  o.gradient_tolerance = -1e-3;
  expect_error(o, "gradient_tolerance must be >= 0");
  o = SolverOptions();
  o.function_tolerance = std::nan("");
  expect_error(o, "function_tolerance must be >= 0");
  o = SolverOptions();
  o.num_threads = 0;
  expect_error(o, "num_threads must be >= 1, got 0");
  o = SolverOptions();
  o.max_seconds = -1.0;
  expect_error(o, "max_seconds");
  o = SolverOptions();
  o.initial_trust_region_radius = 0.0;
  expect_error(o, "initial_trust_region_radius must be positive");
}

TEST(ProblemOptions, CheckNamesTheBadField) {
  EXPECT_TRUE(ProblemOptions().Check().ok());
  auto expect_error = [](ProblemOptions options, const std::string& text) {
    const Status status = options.Check();
    EXPECT_FALSE(status.ok()) << text;
    EXPECT_NE(status.message().find(text), std::string::npos)
        << status.message();
  };
  ProblemOptions o;
  o.robust_scale = -2.0;
  expect_error(o, "problem options: robust_scale must be positive");
  o = ProblemOptions();
  o.constant_rotations = o.constant_translations = o.constant_weights =
      o.constant_basis = o.constant_scales = true;
  expect_error(o, "nothing to refine");
  o = ProblemOptions();
  o.term_weights["temporal_shape"] = -1.0;
  expect_error(o, "term weight temporal_shape must be finite and >= 0, got -1");
  o = ProblemOptions();
  o.term_weights["temporal_shape"] = std::nan("");
  expect_error(o, "term weight temporal_shape must be finite");
  o = ProblemOptions();
  o.term_weights["temporal_shap"] = 1.0;
  expect_error(o, "no term \"temporal_shap\"");
}

TEST(Refine, BadInputIsAnErrorAndLeavesTheModel) {
  SyntheticSequence s = Sequence(10, 12, 2, 0.0);
  Model model;
  model.Resize(10, 1, 11, 2);
  const Model before = model;
  RefineSummary summary;
  const Status status = Refine(ProblemOptions(), SolverOptions(),
                               s.measurements, &model, &summary);
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find("does not match the measurements"),
            std::string::npos)
      << status.message();
  EXPECT_EQ(MaxAbsDifference(model, before), 0.0);
  SolverOptions huge;
  huge.linear_solver = LinearSolverChoice::kDenseQr;
  SyntheticSequence big = Sequence(300, 110, 5, 0.0);
  Model truth = big.truth;
  const Status refused =
      Refine(ProblemOptions(), huge, big.measurements, &truth, &summary);
  EXPECT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("dense Jacobian would take"),
            std::string::npos);
}

TEST(Refine, ModelAtTheOptimumDoesNotMove) {
  // Noise-free: the truth has zero cost.
  SyntheticSequence exact = Sequence(40, 20, 3, 0.0);
  Model model = exact.truth;
  RefineSummary summary;
  ASSERT_TRUE(Refine(ProblemOptions(), SolverOptions(), exact.measurements,
                     &model, &summary)
                  .ok());
  EXPECT_TRUE(summary.usable) << summary.message;
  EXPECT_LT(summary.initial_cost, 1e-28);
  EXPECT_LT(MaxAbsDifference(model, exact.truth), 1e-12);

  // Noisy: refine once to the optimum, then again from there.
  SyntheticSequence noisy = Sequence(40, 20, 3, 0.01);
  Model optimum = noisy.truth;
  ASSERT_TRUE(Refine(ProblemOptions(), SolverOptions(), noisy.measurements,
                     &optimum, &summary)
                  .ok());
  ASSERT_TRUE(summary.usable);
  const double cost = summary.final_cost;
  Model again = optimum;
  ASSERT_TRUE(Refine(ProblemOptions(), SolverOptions(), noisy.measurements,
                     &again, &summary)
                  .ok());
  EXPECT_TRUE(summary.usable);
  EXPECT_NEAR(summary.initial_cost, cost, 1e-14 * cost);
  EXPECT_LE(summary.final_cost, cost);
  EXPECT_GT(summary.final_cost, cost * (1.0 - 1e-9));
  EXPECT_LT(MaxAbsDifference(again, optimum), 1e-6);
}

// The gauge (global rotation, K × K mixing) leaves the problem
// rank-deficient; every linear solver still converges from a perturbed start.
TEST(Refine, GaugeFreedomsDoNotStopConvergenceWithAnySolver) {
  SyntheticSequence s = Sequence(30, 15, 3, 0.0);
  const Model start = Perturbed(Regauged(s.truth), 0.03, 1);
  const double spread = s.measurements.W.cwiseAbs().maxCoeff();
  ASSERT_GT(ReprojectionRms(s.measurements, start), 1e-2 * spread);
  for (LinearSolverChoice choice :
       {LinearSolverChoice::kAuto, LinearSolverChoice::kDenseSchur,
        LinearSolverChoice::kSparseSchur, LinearSolverChoice::kIterativeSchur,
        LinearSolverChoice::kSparseNormalCholesky, LinearSolverChoice::kCgnr,
        LinearSolverChoice::kDenseQr}) {
    Model model = start;
    SolverOptions options;
    options.linear_solver = choice;
    options.max_iterations = 200;
    RefineSummary summary;
    ASSERT_TRUE(
        Refine(ProblemOptions(), options, s.measurements, &model, &summary)
            .ok());
    EXPECT_TRUE(summary.usable)
        << LinearSolverName(choice) << ": " << summary.message;
    EXPECT_LT(summary.reprojection_rms, 1e-8 * spread)
        << LinearSolverName(choice) << ": " << summary.message;
    EXPECT_LT(ComputeE3D(CameraFrameShapes(s.truth), CameraFrameShapes(model)),
              1e-6)
        << LinearSolverName(choice);
    if (choice == LinearSolverChoice::kAuto) {
      EXPECT_EQ(summary.linear_solver, "structured");
    } else {
      EXPECT_EQ(summary.linear_solver, LinearSolverName(choice));
    }
  }
}

TEST(Refine, ConstantBlocksStayPut) {
  SyntheticSequence s = Sequence(30, 15, 2, 0.0);
  const Model start = Perturbed(s.truth, 0.02, 2);
  {
    // Basis only: every other block exactly as given.
    Model model = start;
    model.rotations = s.truth.rotations;
    model.weights = s.truth.weights;
    ProblemOptions options;
    options.constant_rotations = options.constant_translations =
        options.constant_weights = true;
    RefineSummary summary;
    ASSERT_TRUE(
        Refine(options, SolverOptions(), s.measurements, &model, &summary)
            .ok());
    EXPECT_EQ(model.rotations, s.truth.rotations);
    EXPECT_EQ(model.weights, s.truth.weights);
    EXPECT_EQ(model.translations, start.translations);
    // With the motion exact, the basis alone reaches zero cost.
    EXPECT_LT(summary.reprojection_rms, 1e-10);
    EXPECT_LT((model.basis - s.truth.basis).cwiseAbs().maxCoeff(), 1e-8);
  }
  {
    // Poses only (rotations and translations).
    Model model = start;
    model.basis = s.truth.basis;
    model.weights = s.truth.weights;
    ProblemOptions options;
    options.constant_weights = options.constant_basis = true;
    RefineSummary summary;
    ASSERT_TRUE(
        Refine(options, SolverOptions(), s.measurements, &model, &summary)
            .ok());
    EXPECT_EQ(model.basis, s.truth.basis);
    EXPECT_EQ(model.weights, s.truth.weights);
    EXPECT_EQ(summary.linear_solver, "sparse_normal_cholesky");
    EXPECT_LT(summary.reprojection_rms, 1e-10);
  }
}

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

TEST(Refine, RobustLossResistsGrossOutliers) {
  SyntheticSequence s = Sequence(40, 20, 2, 0.0, 0.0, 7);
  // 3 % of the observations moved by 0.5 (the shapes are unit cubes).
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> frame(0, 39), point(0, 19);
  for (int i = 0; i < 24; ++i) {
    s.measurements.W(2 * frame(rng), point(rng)) += 0.5;
  }
  const Model start = Perturbed(s.truth, 0.01, 5);
  double e3d[2];
  for (const bool robust : {false, true}) {
    Model model = start;
    ProblemOptions options;
    if (robust) {
      options.robust_loss = RobustLoss::kCauchy;
      options.robust_scale = 0.01;
    }
    RefineSummary summary;
    ASSERT_TRUE(
        Refine(options, SolverOptions(), s.measurements, &model, &summary)
            .ok());
    EXPECT_TRUE(summary.usable);
    e3d[robust] =
        ComputeE3D(CameraFrameShapes(s.truth), CameraFrameShapes(model));
  }
  EXPECT_GT(e3d[0], 1e-2);
  EXPECT_LT(e3d[1], 1e-4);
}

TEST(Refine, RunTimeKAboveTheStaticRange) {
  // K = 17: the dynamic cost function.
  SyntheticSequence s = Sequence(60, 55, 17, 0.0);
  Model model = Perturbed(s.truth, 0.005, 6);
  SolverOptions options;
  options.max_iterations = 200;
  RefineSummary summary;
  ASSERT_TRUE(
      Refine(ProblemOptions(), options, s.measurements, &model, &summary).ok());
  EXPECT_TRUE(summary.usable) << summary.message;
  EXPECT_LT(summary.reprojection_rms, 1e-8);
}

TEST(Refine, SolveProblemRunsACallerBuiltProblem) {
  SyntheticSequence s = Sequence(30, 15, 2, 0.01);
  const Model start = Perturbed(s.truth, 0.02, 9);
  // Reprojection terms only: the same result as Refine(), bit for bit.
  Model by_refine = start, by_solve = start;
  RefineSummary refine_summary, solve_summary;
  ASSERT_TRUE(Refine(ProblemOptions(), SolverOptions(), s.measurements,
                     &by_refine, &refine_summary)
                  .ok());
  {
    ProblemBuilder builder(&s.measurements, &by_solve);
    ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());
    ASSERT_TRUE(SolveProblem(SolverOptions(), &builder, &solve_summary).ok());
  }
  EXPECT_EQ(MaxAbsDifference(by_refine, by_solve), 0.0);
  EXPECT_EQ(refine_summary.final_cost, solve_summary.final_cost);
  EXPECT_EQ(solve_summary.num_residual_blocks, 30 * 15);

  // Plus a term of the caller's: a prior T_0 = (5, 5) of weight 1e4. With the
  // shape held (otherwise a shift of every basis shape, absorbed by the
  // translations, would satisfy it at no cost) it fights the data; the
  // summary's cost includes it and frame 0's translation follows it.
  Model model = start;
  ProblemBuilder builder(&s.measurements, &model);
  ProblemOptions hold_shape;
  hold_shape.constant_basis = true;
  hold_shape.constant_weights = true;
  ASSERT_TRUE(builder.AddReprojectionTerms(hold_shape).ok());
  builder.AddResidualBlock(
      std::make_unique<ceres::NormalPrior>(100.0 * Eigen::Matrix2d::Identity(),
                                           Eigen::Vector2d(5, 5)),
      nullptr, {builder.TranslationBlock(0, 0)});
  RefineSummary summary;
  ASSERT_TRUE(SolveProblem(SolverOptions(), &builder, &summary).ok());
  EXPECT_TRUE(summary.usable);
  double cost = 0.0;
  ASSERT_TRUE(builder.problem()->Evaluate(ceres::Problem::EvaluateOptions(),
                                          &cost, nullptr, nullptr, nullptr));
  EXPECT_NEAR(summary.final_cost, cost, 1e-12 * cost);
  const double data_cost =
      0.5 * summary.num_residual_blocks * std::pow(summary.reprojection_rms, 2);
  EXPECT_GT(summary.final_cost, data_cost + 0.1);
  EXPECT_GT(model.translations.col(0).norm(), 7.0);
}

// One thread is bitwise deterministic. Two threads are not quite: Ceres 2.1
// sums the per-thread partial costs in scheduling order, so the LM radius
// (and then the steps) can differ in the last bits.
TEST(Refine, OneThreadIsBitwiseDeterministicTwoThreadsAgreeClosely) {
  SyntheticSequence s = Sequence(40, 20, 3, 0.01);
  const Model start = Perturbed(s.truth, 0.02, 8);
  for (const int threads : {1, 2}) {
    SolverOptions options;
    options.num_threads = threads;
    Model first = start, second = start;
    RefineSummary summary;
    ASSERT_TRUE(
        Refine(ProblemOptions(), options, s.measurements, &first, &summary)
            .ok());
    ASSERT_TRUE(
        Refine(ProblemOptions(), options, s.measurements, &second, &summary)
            .ok());
    if (threads == 1) {
      EXPECT_EQ(MaxAbsDifference(first, second), 0.0);
    } else {
      EXPECT_LT(MaxAbsDifference(first, second), 1e-7);
    }
  }
}

TEST(Refine, AKeptProblemGivesTheSameBitsAsAFreshOne) {
  // Two starts of one problem refined one after the other in a KeptProblem
  // (the second skips the build and the layout) against each refined in a
  // problem of its own; then options with a term (nothing kept), other
  // observation weights, another K and other tracks (rebuilt), and equal
  // tracks in another object (reused).
  SyntheticSequence s = Sequence(30, 25, 3, 0.01, 0.1);
  const Model start_a = Perturbed(s.truth, 0.05, 1);
  const Model start_b = Perturbed(s.truth, 0.05, 2);
  ProblemOptions with_term;
  with_term.term_weights[kTemporalTerm] = 0.1;
  ProblemOptions weighted;
  weighted.observation_weights =
      Eigen::ArrayXXd::Constant(s.measurements.NumViews(), 25, 2.0);
  SyntheticSequence fewer = Sequence(30, 25, 2, 0.01, 0.1);
  // Equal tracks in another object: reused; other tracks of the same sizes:
  // rebuilt.
  const Measurements copy = s.measurements;
  SyntheticSequence other = Sequence(30, 25, 3, 0.01, 0.1, /*seed=*/9);
  struct Run {
    const ProblemOptions* options;
    const Measurements* measurements;
    Model start;
    int reuses;  // after it
  };
  const ProblemOptions plain;
  const std::vector<Run> runs = {
      {&plain, &s.measurements, start_a, 0},
      {&plain, &s.measurements, start_b, 1},
      {&plain, &s.measurements, start_a, 2},
      {&with_term, &s.measurements, start_b, 2},  // a term: none kept
      {&with_term, &s.measurements, start_a, 2},  // a term: none kept
      {&plain, &s.measurements, start_b, 2},
      {&plain, &s.measurements, start_a, 3},
      {&weighted, &s.measurements, start_b, 3},  // other weights: rebuilt
      {&plain, &fewer.measurements, Perturbed(fewer.truth, 0.05, 3), 3},
      {&plain, &copy, start_a, 3},
      {&plain, &s.measurements, start_b, 4},
      {&plain, &other.measurements, Perturbed(other.truth, 0.05, 4), 4},
  };
  KeptProblem kept;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    SCOPED_TRACE("run " + std::to_string(i));
    const Run& run = runs[i];
    Model reused = run.start, fresh = run.start;
    RefineSummary with, without;
    ASSERT_TRUE(Refine(*run.options, SolverOptions(), *run.measurements,
                       &reused, &with, &kept)
                    .ok());
    ASSERT_TRUE(Refine(*run.options, SolverOptions(), *run.measurements, &fresh,
                       &without)
                    .ok());
    EXPECT_EQ(kept.reuses(), run.reuses);
    EXPECT_TRUE(with.usable);
    EXPECT_EQ(with.iterations, without.iterations);
    EXPECT_EQ(with.final_cost, without.final_cost);
    EXPECT_EQ(MaxAbsDifference(reused, fresh), 0.0);
  }
}

}  // namespace
}  // namespace nrsfm
