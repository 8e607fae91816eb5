// The reprojection residuals as one dense panel in the two passes of the
// Schur complement's product (solvers/refine/reprojection_panel.h) against the
// same products formed residual by residual (StructuredJacobian::MultiplyJ and
// its transposes, which never use the panel): two cameras with a scale,
// self-occlusion (missing entries), observation weights, a term that is not
// a reprojection residual, free and constant translations and scales.
#include "solvers/refine/reprojection_panel.h"

#include <gtest/gtest.h>

#include <random>

#include "core/synthetic/synthetic.h"
#include "problems/extra_terms.h"
#include "problems/problem_builder.h"
#include "solvers/refine/band_preconditioner.h"
#include "solvers/refine/refine.h"
#include "solvers/refine/schur_elimination.h"
#include "solvers/refine/structured_jacobian.h"
#include "solvers/refine/structured_layout.h"

namespace nrsfm {
namespace {

double RelativeDifference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).norm() / b.norm();
}

// diag(JᵀJ) of `jacobian` (which uses the panel: its views' Grams and Gram
// sums) against `reference` (residual by residual), each column to 1e-12 of
// its own value, and the preconditioners of both: M⁻¹ v for
// M = JᵀJ + diag(JᵀJ), whose solves are as accurate as the columns' scales
// allow, whatever they are. Both evaluated at the same values; returns the
// panel's diag (reduced columns) and M⁻¹ v.
void ExpectSameDiagonalAndPreconditioner(
    const structured::StructuredBlocks& blocks,
    const structured::StructuredJacobian& jacobian,
    const structured::StructuredJacobian& reference, int threads,
    const Eigen::VectorXd& v, Eigen::VectorXd* d_reduced,
    Eigen::VectorXd* applied) {
  Eigen::VectorXd d_eliminated, expected_reduced, expected_eliminated;
  jacobian.ColumnSquaredNorms(d_reduced, &d_eliminated);
  reference.ColumnSquaredNorms(&expected_reduced, &expected_eliminated);
  EXPECT_LT((*d_reduced - expected_reduced)
                .cwiseQuotient(expected_reduced)
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
  EXPECT_LT(RelativeDifference(d_eliminated, expected_eliminated), 1e-12);
  structured::SchurElimination schur(blocks, jacobian, threads);
  schur.ComputeGram();
  structured::SchurElimination reference_schur(blocks, reference, threads);
  reference_schur.ComputeGram();
  structured::BandPreconditioner preconditioner(blocks, jacobian, threads);
  structured::BandPreconditioner expected_preconditioner(blocks, reference,
                                                         threads);
  preconditioner.Build(1.0, expected_reduced, schur.grid_grams());
  expected_preconditioner.Build(1.0, expected_reduced,
                                reference_schur.grid_grams());
  Eigen::VectorXd expected_applied;
  preconditioner.Apply(v, applied);
  expected_preconditioner.Apply(v, &expected_applied);
  EXPECT_LT(RelativeDifference(*applied, expected_applied), 1e-12);
}

TEST(ReprojectionPanel, PassesEqualTheProductsResidualByResidual) {
  ShoeOptions shoe;
  shoe.num_frames = 12;
  shoe.num_points = 30;
  shoe.noise_stddev = 0.01;
  SyntheticSequence sequence;
  ASSERT_TRUE(GenerateShoe(shoe, &sequence).ok());
  const Measurements& m = sequence.measurements;
  ASSERT_EQ(m.num_cameras, 2);
  ASSERT_LT(m.NumVisible(), m.NumViews() * m.num_points);  // some hidden
  // The views' Grams from J̃ point by point.
  ASSERT_FALSE(structured::ReprojectionPanel::ViewGramsFromMoments(
      m.num_points, sequence.truth.num_bases));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(0.5, 2.0);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (const bool constant : {false, true}) {
    SCOPED_TRACE(constant ? "constant translations and scales" : "all free");
    Model model = sequence.truth;
    for (Eigen::Index i = 0; i < model.rotations.size(); ++i)
      model.rotations.data()[i] += 0.05 * normal(rng);
    for (Eigen::Index i = 0; i < model.basis.size(); ++i)
      model.basis.data()[i] += 0.05 * normal(rng);
    ProblemOptions problem;
    problem.constant_translations = constant;
    problem.constant_scales = constant;
    problem.observation_weights.resize(m.NumViews(), m.num_points);
    for (Eigen::Index i = 0; i < problem.observation_weights.size(); ++i)
      problem.observation_weights.data()[i] = uniform(rng);
    problem.term_weights[kRotationAccelerationTerm] = 2.0;
    ProblemBuilder builder(&m, &model);
    ASSERT_TRUE(builder.AddReprojectionTerms(problem).ok());
    ASSERT_TRUE(AddExtraTerms(problem, &builder).ok());
    structured::StructuredBlocks blocks;
    std::string error;
    ASSERT_TRUE(structured::LayOutBlocks(MakeStructuredLayout(&builder),
                                         builder.problem(), &blocks, &error))
        << error;
    ASSERT_TRUE(blocks.grids.empty());
    for (const int threads : {1, 2}) {
      structured::StructuredJacobian jacobian(blocks, threads);
      ASSERT_TRUE(jacobian.uses_panel());
      structured::StructuredJacobian reference(blocks, threads,
                                               /*allow_panel=*/false);
      ASSERT_FALSE(reference.uses_panel());
      double cost = 0.0, reference_cost = 0.0;
      ASSERT_TRUE(jacobian.Evaluate(true, &cost));
      ASSERT_TRUE(reference.Evaluate(true, &reference_cost));
      EXPECT_EQ(cost, reference_cost);
      Eigen::VectorXd v(blocks.num_reduced), e(blocks.num_eliminated);
      for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = normal(rng);
      for (Eigen::Index i = 0; i < e.size(); ++i) e[i] = normal(rng);

      // First pass: J_pᵀ J_f v.
      Eigen::VectorXd rows, projected, jv, expected;
      jacobian.MultiplyJReducedAndJtEliminated(v, &rows, &projected);
      reference.MultiplyJ(&v, nullptr, &jv);
      reference.MultiplyJtEliminated(jv, &expected);
      EXPECT_LT(RelativeDifference(projected, expected), 1e-12);
      // Second pass: J_fᵀ (J_f v − J_p e).
      Eigen::VectorXd out, both, expected_out;
      jacobian.SubtractJEliminatedAndMultiplyJtReduced(e, &rows, &out);
      const Eigen::VectorXd minus_e = -e;
      reference.MultiplyJ(&v, &minus_e, &both);
      reference.MultiplyJtReduced(both, &expected_out);
      EXPECT_LT(RelativeDifference(out, expected_out), 1e-12);
      // The second pass alone: J_fᵀ (−J_p e).
      Eigen::VectorXd alone, je, expected_alone;
      jacobian.SubtractJEliminatedAndMultiplyJtReduced(e, nullptr, &alone);
      reference.MultiplyJ(nullptr, &minus_e, &je);
      reference.MultiplyJtReduced(je, &expected_alone);
      EXPECT_LT(RelativeDifference(alone, expected_alone), 1e-12);
      // The gradient Jᵀ r.
      Eigen::VectorXd g_reduced, g_eliminated, r_reduced, r_eliminated;
      jacobian.Gradient(&g_reduced, &g_eliminated);
      reference.MultiplyJtReduced(reference.residuals(), &r_reduced);
      reference.MultiplyJtEliminated(reference.residuals(), &r_eliminated);
      EXPECT_LT(RelativeDifference(g_reduced, r_reduced), 1e-12);
      EXPECT_LT(RelativeDifference(g_eliminated, r_eliminated), 1e-12);
      // The linear model's terms (J δ)·r and ||J δ||².
      double dot = 0.0, squared = 0.0;
      jacobian.StepProducts(v, e, &dot, &squared);
      Eigen::VectorXd j_step;
      reference.MultiplyJ(&v, &e, &j_step);
      EXPECT_NEAR(dot, j_step.dot(jacobian.residuals()),
                  1e-12 * j_step.norm() * jacobian.residuals().norm());
      EXPECT_NEAR(squared, j_step.squaredNorm(), 1e-12 * j_step.squaredNorm());
      // The Gram blocks J_pᵀ J_p (the panel's part at once): C̃ with μ D_p
      // = I inverts (J_pᵀ J_p + I) e.
      structured::SchurElimination schur(blocks, jacobian, threads);
      schur.ComputeGram();
      schur.Factor(1.0, Eigen::VectorXd::Ones(blocks.num_eliminated));
      Eigen::VectorXd jpe, gram_e, solved;
      reference.MultiplyJ(nullptr, &e, &jpe);
      reference.MultiplyJtEliminated(jpe, &gram_e);
      schur.SolveEliminated(gram_e + e, &solved);
      EXPECT_LT(RelativeDifference(solved, e), 1e-12);
      // diag(JᵀJ) and the preconditioner, the panel's part from its views'
      // Grams.
      Eigen::VectorXd d_reduced, applied;
      ExpectSameDiagonalAndPreconditioner(blocks, jacobian, reference, threads,
                                          v, &d_reduced, &applied);
    }
  }
}

// The views' Grams (in the preconditioner) and diag(JᵀJ) against a
// Jacobian without the panel, for constant blocks of each kind, shared
// (global) blocks in the border and the corner, blocks of one view in
// neighbouring groups and points far from the origin; the Grams from the
// moments (P 150, two column pieces) and from J̃ point by point (P 40); the
// same bits for 1, 2 and 5 threads.
class ViewGrams : public testing::TestWithParam<int> {};

TEST_P(ViewGrams, ForEveryLayout) {
  ShoeOptions shoe;
  shoe.num_frames = 20;
  shoe.num_points = GetParam();
  shoe.noise_stddev = 0.01;
  SyntheticSequence sequence;
  ASSERT_TRUE(GenerateShoe(shoe, &sequence).ok());
  const Measurements& m = sequence.measurements;
  EXPECT_EQ(structured::ReprojectionPanel::ViewGramsFromMoments(
                m.num_points, sequence.truth.num_bases),
            m.num_points == 150);
  std::mt19937 rng(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.5, 2.0);
  enum Layout { kFrames, kSharedScales, kSharedWeights, kSpanning };
  struct Case {
    const char* name;
    Layout layout = kFrames;
    bool constant_rotations = false, constant_weights = false,
         constant_others = false;
    double offset = 0.0;
  };
  const Case cases[] = {
      {"frame groups"},
      {"constant rotations", kFrames, true},
      {"constant weights", kFrames, false, true},
      {"only weights free", kFrames, true, false, true},
      {"shared camera-1 translations and scales", kSharedScales},
      {"shared weights", kSharedWeights},
      {"camera-1 blocks in neighbouring groups", kSpanning},
      {"points 10^6 from the origin", kFrames, false, false, false, 1e6},
  };
  for (const Case& test : cases) {
    SCOPED_TRACE(test.name);
    Model model = sequence.truth;
    model.basis.array() += test.offset;
    for (Eigen::Index i = 0; i < model.rotations.size(); ++i)
      model.rotations.data()[i] += 0.05 * normal(rng);
    for (Eigen::Index i = 0; i < model.basis.size(); ++i)
      model.basis.data()[i] += 0.05 * normal(rng);
    ProblemOptions problem;
    problem.constant_rotations = test.constant_rotations;
    problem.constant_weights = test.constant_weights;
    problem.constant_translations = test.constant_others;
    problem.constant_scales = test.constant_others;
    problem.observation_weights.resize(m.NumViews(), m.num_points);
    for (Eigen::Index i = 0; i < problem.observation_weights.size(); ++i)
      problem.observation_weights.data()[i] = uniform(rng);
    ProblemBuilder builder(&m, &model);
    ASSERT_TRUE(builder.AddReprojectionTerms(problem).ok());
    const int num_frames = model.num_frames;
    StructuredLayout layout;
    layout.groups.resize(num_frames);
    for (int t = 0; t < num_frames; ++t) {
      std::vector<double*>& group = layout.groups[t];
      group.push_back(builder.RotationBlock(t, 0));
      group.push_back(builder.TranslationBlock(t, 0));
      group.push_back(builder.RotationBlock(t, 1));
      if (test.layout == kSharedScales) {
        layout.globals.push_back(builder.TranslationBlock(t, 1));
        layout.globals.push_back(builder.ScaleBlock(t, 1));
      } else if (test.layout == kSpanning) {
        layout.groups[std::min(t + 1, num_frames - 1)].push_back(
            builder.TranslationBlock(t, 1));
        layout.groups[std::max(t - 1, 0)].push_back(builder.ScaleBlock(t, 1));
      } else {
        group.push_back(builder.TranslationBlock(t, 1));
        group.push_back(builder.ScaleBlock(t, 1));
      }
      if (test.layout == kSharedWeights) {
        layout.globals.push_back(builder.WeightsBlock(t));
      } else {
        group.push_back(builder.WeightsBlock(t));
      }
    }
    layout.eliminated = builder.PointBlocks();
    structured::StructuredBlocks blocks;
    std::string error;
    ASSERT_TRUE(
        structured::LayOutBlocks(layout, builder.problem(), &blocks, &error))
        << error;
    Eigen::VectorXd v(blocks.num_reduced);
    for (Eigen::Index i = 0; i < v.size(); ++i) v[i] = normal(rng);
    Eigen::VectorXd first_applied, first_diagonal;
    for (const int threads : {1, 2, 5}) {
      structured::StructuredJacobian jacobian(blocks, threads);
      ASSERT_TRUE(jacobian.uses_panel());
      structured::StructuredJacobian reference(blocks, threads,
                                               /*allow_panel=*/false);
      double cost = 0.0, reference_cost = 0.0;
      ASSERT_TRUE(jacobian.Evaluate(true, &cost));
      ASSERT_TRUE(reference.Evaluate(true, &reference_cost));
      Eigen::VectorXd d_reduced, applied;
      ExpectSameDiagonalAndPreconditioner(blocks, jacobian, reference, threads,
                                          v, &d_reduced, &applied);
      if (threads == 1) {
        first_applied = applied;
        first_diagonal = d_reduced;
      } else {
        EXPECT_TRUE((applied.array() == first_applied.array()).all());
        EXPECT_TRUE((d_reduced.array() == first_diagonal.array()).all());
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(ReprojectionPanel, ViewGrams,
                         testing::Values(150, 40));

TEST(ReprojectionPanel, NotBuiltForRobustResiduals) {
  // A robust loss corrects each residual's Jacobian by its own residual:
  // those residuals have no basis factor and stay one by one.
  ShoeOptions shoe;
  shoe.num_frames = 6;
  shoe.num_points = 20;
  shoe.num_cameras = 1;
  SyntheticSequence sequence;
  ASSERT_TRUE(GenerateShoe(shoe, &sequence).ok());
  Model model = sequence.truth;
  ProblemOptions problem;
  problem.robust_loss = RobustLoss::kHuber;
  ProblemBuilder builder(&sequence.measurements, &model);
  ASSERT_TRUE(builder.AddReprojectionTerms(problem).ok());
  structured::StructuredBlocks blocks;
  std::string error;
  ASSERT_TRUE(structured::LayOutBlocks(MakeStructuredLayout(&builder),
                                       builder.problem(), &blocks, &error))
      << error;
  structured::ReprojectionPanel panel;
  EXPECT_FALSE(panel.Build(blocks));
  for (int i = 0; i < static_cast<int>(blocks.residuals.size()); ++i)
    EXPECT_FALSE(panel.Holds(i));
  structured::StructuredJacobian jacobian(blocks, 1);
  EXPECT_FALSE(jacobian.uses_panel());
}

}  // namespace
}  // namespace nrsfm
