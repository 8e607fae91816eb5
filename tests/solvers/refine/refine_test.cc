#include "solvers/refine/refine.h"

#include <ceres/normal_prior.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "core/eval/metrics.h"
#include "problems/extra_terms.h"
#include "tests/solvers/refine/refine_test_util.h"

namespace nrsfm {
namespace {

using testing_util::Perturbed;
using testing_util::Sequence;

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
