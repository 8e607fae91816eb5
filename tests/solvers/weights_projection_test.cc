// The weights' side of the structured solver's step
// (solvers/weights_projection.h): the projection is the weights' exact
// minimiser (no gradient left in them, a lower cost), the same bits for any
// thread count; the balance leaves the cost and the shapes as they are and
// equalises the two Grams; which problems allow which.
#include "solvers/weights_projection.h"

#include <gtest/gtest.h>

#include <random>

#include "core/synthetic.h"
#include "problems/extra_terms.h"
#include "problems/problem_builder.h"
#include "solvers/structured_jacobian.h"
#include "solvers/structured_layout.h"

namespace nrsfm {
namespace {

// The layout Refine() gives the structured solver (solvers/refine.cc).
StructuredLayout Layout(ProblemBuilder* builder) {
  const Model& model = *builder->model();
  StructuredLayout layout;
  layout.groups.resize(model.num_frames);
  for (int t = 0; t < model.num_frames; ++t) {
    for (int c = 0; c < model.num_cameras; ++c) {
      layout.groups[t].push_back(builder->RotationBlock(t, c));
      layout.groups[t].push_back(builder->TranslationBlock(t, c));
      if (c > 0) layout.groups[t].push_back(builder->ScaleBlock(t, c));
    }
    layout.groups[t].push_back(builder->WeightsBlock(t));
  }
  layout.eliminated = builder->PointBlocks();
  return layout;
}

// A noisy one-camera shoe (with self-occlusion: missing entries) and a
// model off the truth in every block.
struct Scene {
  SyntheticSequence sequence;
  Model model;
};

Scene MakeScene() {
  ShoeOptions shoe;
  shoe.num_frames = 30;
  shoe.num_points = 40;
  shoe.num_cameras = 1;
  shoe.noise_stddev = 0.01;
  Scene scene;
  EXPECT_TRUE(GenerateShoe(shoe, &scene.sequence).ok());
  scene.model = scene.sequence.truth;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  Model& model = scene.model;
  for (Eigen::Index i = 0; i < model.rotations.size(); ++i)
    model.rotations.data()[i] += 0.05 * normal(rng);
  for (Eigen::Index i = 0; i < model.weights.size(); ++i)
    model.weights.data()[i] += 0.3 * normal(rng);
  for (Eigen::Index i = 0; i < model.basis.size(); ++i)
    model.basis.data()[i] += 0.05 * normal(rng);
  return scene;
}

// The offsets (reduced vector) of the free weights blocks.
std::vector<int> WeightsOffsets(ProblemBuilder* builder,
                                const structured::StructuredBlocks& blocks) {
  std::vector<int> offsets;
  for (int t = 0; t < builder->model()->num_frames; ++t) {
    for (const structured::Block& b : blocks.blocks) {
      if (b.values == builder->WeightsBlock(t)) offsets.push_back(b.offset);
    }
  }
  return offsets;
}

double WeightsGradientNorm(const structured::StructuredJacobian& jacobian,
                           const std::vector<int>& offsets, int k) {
  Eigen::VectorXd reduced, eliminated;
  jacobian.Gradient(&reduced, &eliminated);
  double sum = 0.0;
  for (const int o : offsets) sum += reduced.segment(o, k).squaredNorm();
  return std::sqrt(sum);
}

TEST(WeightsProjection, ProjectsToTheWeightsMinimiser) {
  Eigen::MatrixXd projected[2];
  for (const int threads : {1, 2}) {
    SCOPED_TRACE(threads);
    Scene scene = MakeScene();
    const Measurements& m = scene.sequence.measurements;
    ASSERT_LT(m.NumVisible(), m.NumViews() * m.num_points);  // some hidden
    ProblemOptions problem;
    problem.term_weights[kTemporalShapeTerm] = 1.0;
    problem.term_weights[kRotationAccelerationTerm] = 2.0;
    ProblemBuilder builder(&m, &scene.model);
    ASSERT_TRUE(builder.AddReprojectionTerms(problem).ok());
    ASSERT_TRUE(AddExtraTerms(problem, &builder).ok());
    structured::StructuredBlocks blocks;
    std::string error;
    ASSERT_TRUE(structured::LayOutBlocks(Layout(&builder), builder.problem(),
                                         &blocks, &error))
        << error;
    structured::StructuredJacobian jacobian(blocks, threads);
    ASSERT_TRUE(jacobian.uses_panel());
    structured::WeightsProjection projection;
    projection.Build(blocks, *jacobian.panel());
    ASSERT_TRUE(projection.projects());
    ASSERT_TRUE(projection.balances());
    const int k = scene.model.num_bases;
    const std::vector<int> offsets = WeightsOffsets(&builder, blocks);
    ASSERT_EQ(static_cast<int>(offsets.size()), m.num_frames);

    double before = 0.0, after = 0.0;
    ASSERT_TRUE(jacobian.Evaluate(true, &before));
    const double gradient_before = WeightsGradientNorm(jacobian, offsets, k);
    ASSERT_GT(gradient_before, 1.0);
    ASSERT_TRUE(projection.Project(jacobian.residuals(), threads));
    ASSERT_TRUE(jacobian.Evaluate(true, &after));
    // The cost is quadratic in the weights: at their minimiser the weights'
    // gradient vanishes (to round-off and the ridge of 1e-10).
    EXPECT_LT(WeightsGradientNorm(jacobian, offsets, k),
              1e-8 * gradient_before);
    EXPECT_LT(after, 0.5 * before);
    projected[threads - 1] = scene.model.weights;
  }
  EXPECT_EQ(projected[0], projected[1]);  // the same bits
}

TEST(WeightsProjection, BalanceKeepsTheCostAndEqualisesTheGrams) {
  Scene scene = MakeScene();
  Model& model = scene.model;
  // A gauge far from balanced: weights small, basis large.
  model.weights *= 1e-3;
  model.basis *= 1e3;
  const Measurements& m = scene.sequence.measurements;
  ProblemOptions problem;
  problem.term_weights[kTemporalShapeTerm] = 1.0;
  ProblemBuilder builder(&m, &model);
  ASSERT_TRUE(builder.AddReprojectionTerms(problem).ok());
  ASSERT_TRUE(AddExtraTerms(problem, &builder).ok());
  structured::StructuredBlocks blocks;
  std::string error;
  ASSERT_TRUE(structured::LayOutBlocks(Layout(&builder), builder.problem(),
                                       &blocks, &error))
      << error;
  structured::StructuredJacobian jacobian(blocks, 2);
  structured::WeightsProjection projection;
  projection.Build(blocks, *jacobian.panel());
  ASSERT_TRUE(projection.balances());
  double before = 0.0, after = 0.0;
  ASSERT_TRUE(jacobian.Evaluate(false, &before));
  const Model start = model;
  Eigen::MatrixXd a;
  ASSERT_TRUE(projection.Balance(&a));
  ASSERT_TRUE(jacobian.Evaluate(false, &after));
  EXPECT_NEAR(after, before, 1e-10 * before);
  const int k = model.num_bases;
  Eigen::MatrixXd gram_w = model.weights * model.weights.transpose();
  Eigen::MatrixXd gram_b = Eigen::MatrixXd::Zero(k, k);
  for (int p = 0; p < m.num_points; ++p) {
    const Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic>> b(
        builder.PointBlocks()[p], 3, k);
    gram_b += b.transpose() * b;
  }
  EXPECT_LT((gram_w - gram_b).norm(), 1e-9 * gram_b.norm());
  // Every frame's shape is unchanged.
  for (int t = 0; t < m.num_frames; ++t) {
    EXPECT_LT((model.ShapeInObject(t) - start.ShapeInObject(t)).norm(),
              1e-9 * start.ShapeInObject(t).norm());
  }
  // Mixing back with A⁻¹ gives the start's weights and basis.
  projection.Mix(a.inverse());
  EXPECT_LT((model.weights - start.weights).norm(),
            1e-9 * start.weights.norm());
  EXPECT_LT((model.basis - start.basis).norm(), 1e-9 * start.basis.norm());
}

TEST(WeightsProjection, WhichProblemsAllowWhich) {
  struct Case {
    const char* name;
    std::string term;
    RobustLoss loss;
    bool projects, balances;
  };
  // The deformation prior holds the first weight apart (a mask): no
  // mixing; a robust loss leaves the reprojection residuals out of the panel.
  const Case cases[] = {
      {"temporal shape", kTemporalShapeTerm, RobustLoss::kNone, true, true},
      {"smoothness", kSmoothnessTerm, RobustLoss::kNone, true, true},
      {"deformation", kDeformationTerm, RobustLoss::kNone, true, false},
      {"temporal weights", kTemporalTerm, RobustLoss::kNone, false, false},
      {"Huber loss", kTemporalShapeTerm, RobustLoss::kHuber, false, false},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    Scene scene = MakeScene();
    const Measurements& m = scene.sequence.measurements;
    ProblemOptions problem;
    problem.term_weights[c.term] = 1.0;
    problem.robust_loss = c.loss;
    ProblemBuilder builder(&m, &scene.model);
    ASSERT_TRUE(builder.AddReprojectionTerms(problem).ok());
    ASSERT_TRUE(AddExtraTerms(problem, &builder).ok());
    structured::StructuredBlocks blocks;
    std::string error;
    ASSERT_TRUE(structured::LayOutBlocks(Layout(&builder), builder.problem(),
                                         &blocks, &error))
        << error;
    structured::StructuredJacobian jacobian(blocks, 1);
    structured::WeightsProjection projection;
    if (jacobian.panel() != nullptr) {
      projection.Build(blocks, *jacobian.panel());
    }
    EXPECT_EQ(projection.projects(), c.projects);
    EXPECT_EQ(projection.balances(), c.balances);
  }
}

}  // namespace
}  // namespace nrsfm
