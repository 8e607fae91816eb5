#include "problems/problem_builder.h"

#include <ceres/autodiff_cost_function.h>
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "core/eval/metrics.h"
#include "core/synthetic/synthetic.h"
#include "problems/linear_solver_choice.h"
#include "tests/problems/reprojection_error_oracle.h"

namespace nrsfm {
namespace {

// F = 4 frames, P = 5 points, K = 2, M cameras; noisy so residuals are not 0.
SyntheticSequence SmallSequence(int cameras = 1) {
  RandomBasisOptions options;
  options.num_frames = 4;
  options.num_points = 5;
  options.num_bases = 2;
  options.noise_stddev = 0.05;
  options.seed = 3;
  SyntheticSequence sequence;
  EXPECT_TRUE(GenerateRandomBasis(options, &sequence).ok());
  if (cameras == 1) return sequence;
  // Two cameras: camera 1 sees the same frames through a second rotation
  // and scale (rows interleaved per frame as in core/model/measurements.h).
  const Model mono = sequence.truth;
  Model& truth = sequence.truth;
  truth.Resize(mono.num_frames, cameras, mono.num_points, mono.num_bases);
  truth.weights = mono.weights;
  truth.basis = mono.basis;
  for (int t = 0; t < mono.num_frames; ++t) {
    truth.rotations.col(truth.View(t, 0)) = mono.rotations.col(t);
    truth.rotations.col(truth.View(t, 1)) =
        mono.rotations.col(t) + Eigen::Vector3d(0.3, 0, 0);
    truth.scales(truth.View(t, 1)) = 1.2;
  }
  Measurements& m = sequence.measurements;
  m.num_cameras = cameras;
  m.W.resize(2 * truth.NumViews(), truth.num_points);
  for (int t = 0; t < truth.num_frames; ++t) {
    for (int c = 0; c < cameras; ++c) {
      m.W.middleRows(m.Row(t, c), 2) = truth.Project(t, c);
    }
  }
  m.visible =
      VisibilityMask::Constant(truth.NumViews(), truth.num_points, true);
  return sequence;
}

// Ceres cost of the problem at the model's current values.
double Cost(ProblemBuilder* builder) {
  double cost = 0.0;
  EXPECT_TRUE(builder->problem()->Evaluate(ceres::Problem::EvaluateOptions(),
                                           &cost, nullptr, nullptr, nullptr));
  return cost;
}

TEST(ProblemBuilder, CountsWithEveryEntryVisible) {
  SyntheticSequence s = SmallSequence();
  ProblemBuilder builder(&s.measurements, &s.truth);
  ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());
  ceres::Problem& problem = *builder.problem();
  // One block of 2 residuals per (frame, point): 4 · 5.
  EXPECT_EQ(builder.num_reprojection_terms(), 20);
  EXPECT_EQ(problem.NumResidualBlocks(), 20);
  EXPECT_EQ(problem.NumResiduals(), 40);
  // 4 rotations + 4 translations + 4 weights + 5 basis columns, no scale.
  EXPECT_EQ(problem.NumParameterBlocks(), 17);
  EXPECT_EQ(problem.NumParameters(), 4 * 3 + 4 * 2 + 4 * 2 + 5 * 6);
  EXPECT_EQ(problem.ParameterBlockSize(builder.WeightsBlock(2)), 2);
  EXPECT_EQ(problem.ParameterBlockSize(builder.BasisBlock(4)), 6);
  EXPECT_EQ(builder.PointBlocks().size(), 5u);
  EXPECT_EQ(builder.NonPointBlocks().size(), 12u);
  EXPECT_TRUE(builder.PointBlocksAreIndependent());
  // The blocks are the model's storage.
  EXPECT_EQ(builder.BasisBlock(3), s.truth.basis.col(3).data());
  EXPECT_EQ(builder.RotationBlock(1, 0), s.truth.rotations.col(1).data());
}

TEST(ProblemBuilder, MissingEntriesHaveNoResidual) {
  SyntheticSequence s = SmallSequence();
  Measurements& m = s.measurements;
  // Frame 1 sees nothing; point 3 only in frame 0; one more hole at (2, 0).
  m.visible.row(1).setConstant(false);
  m.visible.col(3).setConstant(false);
  m.visible(0, 3) = true;
  m.visible(2, 0) = false;
  const int visible = m.NumVisible();  // 20 − 5 − 2 − 1 = 12
  ASSERT_EQ(visible, 12);
  ProblemBuilder builder(&m, &s.truth);
  ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());
  ceres::Problem& problem = *builder.problem();
  EXPECT_EQ(problem.NumResidualBlocks(), 12);
  EXPECT_EQ(problem.NumResiduals(), 24);
  // Frame 1's blocks are absent: 3 rotations, 3 translations, 3 weights, 5
  // points.
  EXPECT_FALSE(problem.HasParameterBlock(builder.RotationBlock(1, 0)));
  EXPECT_FALSE(problem.HasParameterBlock(builder.WeightsBlock(1)));
  EXPECT_TRUE(problem.HasParameterBlock(builder.BasisBlock(3)));
  EXPECT_EQ(problem.NumParameterBlocks(), 3 + 3 + 3 + 5);
  EXPECT_EQ(problem.NumParameters(), 3 * 3 + 3 * 2 + 3 * 2 + 5 * 6);

  // The cost is ½ Σ over the visible entries, consistent with
  // core/eval/metrics.h: ReprojectionRms = sqrt(2 · cost / N).
  EXPECT_NEAR(std::sqrt(2.0 * Cost(&builder) / visible),
              ReprojectionRms(m, s.truth), 1e-12);
}

TEST(ProblemBuilder, ScaleBlocksOnlyForExtraCameras) {
  SyntheticSequence s = SmallSequence(/*cameras=*/2);
  ProblemBuilder builder(&s.measurements, &s.truth);
  ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());
  ceres::Problem& problem = *builder.problem();
  EXPECT_EQ(problem.NumResidualBlocks(), 4 * 2 * 5);
  // 8 rotations + 8 translations + 4 weights + 5 points + 4 scales (camera 1).
  EXPECT_EQ(problem.NumParameterBlocks(), 8 + 8 + 4 + 5 + 4);
  for (int t = 0; t < 4; ++t) {
    EXPECT_TRUE(problem.HasParameterBlock(builder.ScaleBlock(t, 1)));
    EXPECT_EQ(problem.ParameterBlockSize(builder.ScaleBlock(t, 1)), 1);
    // Camera 0's scale (always 1) is not a block.
    EXPECT_FALSE(
        problem.HasParameterBlock(s.truth.scales.data() + s.truth.View(t, 0)));
  }
  // The truth of noise-free two-camera data has zero cost.
  EXPECT_LT(Cost(&builder), 1e-25);
}

TEST(ProblemBuilder, ConstantFlagsHoldEachKind) {
  SyntheticSequence s = SmallSequence(/*cameras=*/2);
  ProblemOptions options;
  options.constant_rotations = true;
  options.constant_weights = true;
  options.constant_scales = true;
  ProblemBuilder builder(&s.measurements, &s.truth);
  ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
  ceres::Problem& problem = *builder.problem();
  for (int t = 0; t < 4; ++t) {
    EXPECT_TRUE(problem.IsParameterBlockConstant(builder.RotationBlock(t, 1)));
    EXPECT_FALSE(
        problem.IsParameterBlockConstant(builder.TranslationBlock(t, 1)));
    EXPECT_TRUE(problem.IsParameterBlockConstant(builder.WeightsBlock(t)));
    EXPECT_TRUE(problem.IsParameterBlockConstant(builder.ScaleBlock(t, 1)));
  }
  EXPECT_FALSE(problem.IsParameterBlockConstant(builder.BasisBlock(0)));
  // Free parameters: translations 8·2 and basis 5·6.
  const ProblemStructure structure = DescribeProblem(&builder);
  EXPECT_EQ(structure.num_point_blocks, 5);
  EXPECT_EQ(structure.num_point_parameters, 30);
  EXPECT_EQ(structure.num_other_parameters, 16);
  EXPECT_EQ(structure.num_residuals, 80);
}

TEST(ProblemBuilder, ObservationWeightsScaleTheCostAndZeroDrops) {
  SyntheticSequence s = SmallSequence();
  ProblemBuilder unweighted(&s.measurements, &s.truth);
  ASSERT_TRUE(unweighted.AddReprojectionTerms(ProblemOptions()).ok());
  const double base = Cost(&unweighted);
  ASSERT_GT(base, 1e-6);

  ProblemOptions options;
  options.observation_weights = Eigen::ArrayXXd::Constant(4, 5, 4.0);
  options.observation_weights(0, 0) = 0.0;
  ProblemBuilder weighted(&s.measurements, &s.truth);
  ASSERT_TRUE(weighted.AddReprojectionTerms(options).ok());
  EXPECT_EQ(weighted.problem()->NumResidualBlocks(), 19);
  const Eigen::Vector2d e00 =
      s.truth.Project(0, 0).col(0) - s.measurements.Observation(0, 0, 0);
  EXPECT_NEAR(Cost(&weighted), 4.0 * (base - 0.5 * e00.squaredNorm()), 1e-12);
}

TEST(ProblemBuilder, RobustLossScaleIsInInputUnitsUnderAnyWeight) {
  // One outlier: move observation (2, 1) 10 units away, then compare its
  // cost with the Huber formula w·(2a|e| − a²)/2 and Cauchy w·a²·log(1 +
  // |e|²/a²)/2.
  SyntheticSequence s = SmallSequence();
  s.measurements.W(2 * 2, 1) += 10.0;
  const double a = 0.5;
  const double w = 2.5;
  const Eigen::Vector2d e =
      s.truth.Project(2, 0).col(1) - s.measurements.Observation(2, 0, 1);
  // Every other entry is an inlier (|e| < a): its cost is unchanged.
  for (RobustLoss loss : {RobustLoss::kHuber, RobustLoss::kCauchy}) {
    ProblemOptions plain;
    ProblemBuilder reference(&s.measurements, &s.truth);
    ASSERT_TRUE(reference.AddReprojectionTerms(plain).ok());
    ProblemOptions options;
    options.robust_loss = loss;
    options.robust_scale = a;
    options.observation_weights = Eigen::ArrayXXd::Ones(4, 5);
    options.observation_weights(2, 1) = w;
    ProblemBuilder builder(&s.measurements, &s.truth);
    ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
    // Cost of every block but the outlier, from the plain problem.
    double inliers = Cost(&reference) - 0.5 * e.squaredNorm();
    if (loss == RobustLoss::kCauchy) {
      // Cauchy also bends inliers: recompute them through the loss.
      inliers = 0.0;
      for (int t = 0; t < 4; ++t) {
        for (int p = 0; p < 5; ++p) {
          if (t == 2 && p == 1) continue;
          const double sq = (s.truth.Project(t, 0).col(p) -
                             s.measurements.Observation(t, 0, p))
                                .squaredNorm();
          inliers += 0.5 * a * a * std::log1p(sq / (a * a));
        }
      }
    } else {
      for (int t = 0; t < 4; ++t) {
        for (int p = 0; p < 5; ++p) {
          const double n = (s.truth.Project(t, 0).col(p) -
                            s.measurements.Observation(t, 0, p))
                               .norm();
          if (!(t == 2 && p == 1)) {
            ASSERT_LT(n, a);
          }
        }
      }
    }
    const double outlier =
        loss == RobustLoss::kHuber
            ? 0.5 * w * (2.0 * a * e.norm() - a * a)
            : 0.5 * w * a * a * std::log1p(e.squaredNorm() / (a * a));
    EXPECT_NEAR(Cost(&builder), inliers + outlier, 1e-10)
        << RobustLossName(loss);
  }
}

// The builder's problem against one of the tests' autodiff oracle
// (tests/problems/reprojection_error_oracle.h) on the same blocks: the same
// residuals wired to the same blocks give the same cost and gradient.
TEST(ProblemBuilder, CostAndGradientEqualTheAutodiffOracle) {
  for (const int k : {3, 17}) {
    RandomBasisOptions options;
    options.num_frames = 6;
    options.num_points = 8;
    options.num_bases = k;
    options.noise_stddev = 0.02;
    options.missing_fraction = 0.2;
    SyntheticSequence s;
    ASSERT_TRUE(GenerateRandomBasis(options, &s).ok());
    Model model = s.truth;
    model.basis.array() += 0.01;
    model.rotations.array() -= 0.02;
    ProblemBuilder builder(&s.measurements, &model);
    ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());
    ceres::Problem::Options reference_options;
    reference_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem reference(reference_options);
    const Measurements& m = s.measurements;
    for (int t = 0; t < m.num_frames; ++t) {
      for (int p = 0; p < m.num_points; ++p) {
        if (!m.visible(t, p)) continue;
        reference.AddResidualBlock(DynamicReprojectionError::Create(
                                       k, false, m.Observation(t, 0, p), 1.0),
                                   nullptr, model.rotations.col(t).data(),
                                   model.translations.col(t).data(),
                                   model.weights.col(t).data(),
                                   model.basis.col(p).data());
      }
    }
    ceres::Problem::EvaluateOptions evaluate;
    builder.problem()->GetParameterBlocks(&evaluate.parameter_blocks);
    ASSERT_EQ(reference.NumParameterBlocks(),
              static_cast<int>(evaluate.parameter_blocks.size()));
    for (double* block : evaluate.parameter_blocks) {
      if (builder.problem()->IsParameterBlockConstant(block))
        reference.SetParameterBlockConstant(block);
      const ceres::Manifold* manifold = builder.problem()->GetManifold(block);
      if (manifold != nullptr)
        reference.SetManifold(block, const_cast<ceres::Manifold*>(manifold));
    }
    std::vector<double> gradients[2];
    double costs[2];
    ASSERT_TRUE(builder.problem()->Evaluate(evaluate, &costs[0], nullptr,
                                            &gradients[0], nullptr));
    ASSERT_TRUE(reference.Evaluate(evaluate, &costs[1], nullptr, &gradients[1],
                                   nullptr));
    EXPECT_GT(costs[0], 0.0);
    EXPECT_NEAR(costs[0], costs[1], 1e-14 * costs[0]) << "K = " << k;
    ASSERT_EQ(gradients[0].size(), gradients[1].size());
    for (size_t i = 0; i < gradients[0].size(); ++i) {
      EXPECT_NEAR(gradients[0][i], gradients[1][i], 1e-12) << "K = " << k;
    }
  }
}

// A difference b_0 − b_1 of two basis columns (K = 2): one residual block
// over two point blocks, like a smoothness term.
struct Difference {
  template <typename T>
  bool operator()(const T* b0, const T* b1, T* r) const {
    for (int i = 0; i < 6; ++i) r[i] = b0[i] - b1[i];
    return true;
  }
};

TEST(ProblemBuilder, ExtraTermsPlugInThroughTheBlockAccessors) {
  // What a smoothness term between two points does to the structure.
  SyntheticSequence s = SmallSequence();
  ProblemBuilder builder(&s.measurements, &s.truth);
  ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());
  EXPECT_TRUE(builder.PointBlocksAreIndependent());
  builder.AddResidualBlock(
      std::make_unique<ceres::AutoDiffCostFunction<Difference, 6, 6, 6>>(
          new Difference),
      nullptr, {builder.BasisBlock(0), builder.BasisBlock(1)});
  EXPECT_FALSE(builder.PointBlocksAreIndependent());
  // The points are still eliminated, together
  // (solvers/refine/schur_elimination.h).
  EXPECT_EQ(ChooseLinearSolver(DescribeProblem(&builder)),
            LinearSolverChoice::kStructured);
}

TEST(ProblemBuilder, ErrorsInsteadOfAborts) {
  SyntheticSequence s = SmallSequence();
  {
    ProblemOptions options;
    options.observation_weights = Eigen::ArrayXXd::Ones(3, 5);
    ProblemBuilder builder(&s.measurements, &s.truth);
    const Status status = builder.AddReprojectionTerms(options);
    EXPECT_FALSE(status.ok());
    EXPECT_NE(
        status.message().find("observation_weights is 3 x 5, expected 4 x 5"),
        std::string::npos)
        << status.message();
  }
  {
    ProblemOptions options;
    options.robust_scale = 0.0;
    ProblemBuilder builder(&s.measurements, &s.truth);
    EXPECT_FALSE(builder.AddReprojectionTerms(options).ok());
  }
  {
    ProblemOptions options;
    options.observation_weights = Eigen::ArrayXXd::Ones(4, 5);
    options.observation_weights(1, 1) = -1.0;
    EXPECT_FALSE(options.Check().ok());
  }
  {
    Model other = s.truth;
    other.Resize(4, 1, 6, 2);
    ProblemBuilder builder(&s.measurements, &other);
    const Status status = builder.AddReprojectionTerms(ProblemOptions());
    EXPECT_FALSE(status.ok());
    EXPECT_NE(status.message().find("does not match"), std::string::npos);
    EXPECT_EQ(builder.problem()->NumResidualBlocks(), 0);
  }
  {
    SyntheticSequence two = SmallSequence(2);
    two.truth.scales(two.truth.View(1, 0)) = 2.0;
    ProblemBuilder builder(&two.measurements, &two.truth);
    const Status status = builder.AddReprojectionTerms(ProblemOptions());
    EXPECT_FALSE(status.ok());
    EXPECT_NE(status.message().find("scale of camera 0 must be 1"),
              std::string::npos);
  }
  RobustLoss loss;
  EXPECT_TRUE(ParseRobustLoss("cauchy", &loss).ok());
  EXPECT_EQ(loss, RobustLoss::kCauchy);
  EXPECT_STREQ(RobustLossName(RobustLoss::kHuber), "huber");
  const Status bad = ParseRobustLoss("tukey", &loss);
  EXPECT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("\"tukey\""), std::string::npos);
}

}  // namespace
}  // namespace nrsfm
