// The structured Levenberg-Marquardt solver
// (solvers/refine/structured_solver.h) against Ceres' exact sparse Cholesky on
// the same problem with temporal terms coupling the frames: the same optimum,
// and the `auto` rule picks it.
#include "solvers/refine/structured_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "core/eval/metrics.h"
#include "core/synthetic/synthetic.h"
#include "problems/extra_terms.h"
#include "problems/problem_builder.h"
#include "solvers/refine/refine.h"
#include "solvers/refine/schur_elimination.h"
#include "solvers/refine/structured_jacobian.h"
#include "solvers/refine/structured_layout.h"
#include "tests/solvers/refine/dense_oracle.h"

namespace nrsfm {
namespace {

struct Case {
  SyntheticSequence sequence;
  Model start;
};

Case MakeCase(double missing) {
  // A smooth sequence (the superquadric turns slowly and deforms in time),
  // the kind the temporal terms are for.
  SuperquadricOptions options;
  options.num_frames = 25;
  options.num_points = 20;
  options.noise_stddev = 0.005;
  options.missing_fraction = missing;
  options.seed = 3;
  Case c;
  EXPECT_TRUE(GenerateSuperquadric(options, &c.sequence).ok());
  c.start = c.sequence.truth;
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 0.05);
  for (Eigen::Index i = 0; i < c.start.rotations.size(); ++i)
    c.start.rotations.data()[i] += normal(rng);
  for (Eigen::Index i = 0; i < c.start.basis.size(); ++i)
    c.start.basis.data()[i] += normal(rng);
  return c;
}

ProblemOptions Terms() {
  ProblemOptions problem;
  problem.term_weights["temporal_shape"] = 0.5;
  problem.term_weights["rotation_acceleration"] = 10.0;
  problem.term_weights["temporal"] = 0.1;
  return problem;
}

TEST(StructuredSolver, ReachesTheOptimumOfTheExactSolver) {
  for (const double missing : {0.0, 0.2}) {
    const Case c = MakeCase(missing);
    SolverOptions exact;
    exact.linear_solver = LinearSolverChoice::kSparseNormalCholesky;
    exact.max_iterations = 200;
    // Both crawl along the gauge valley at the default 1e-10; a relative
    // cost change of 1e-7 per step is converged for this comparison.
    exact.function_tolerance = 1e-7;
    SolverOptions structured = exact;
    structured.linear_solver = LinearSolverChoice::kStructured;
    Model a = c.start, b = c.start;
    RefineSummary sa, sb;
    ASSERT_TRUE(Refine(Terms(), exact, c.sequence.measurements, &a, &sa).ok());
    ASSERT_TRUE(
        Refine(Terms(), structured, c.sequence.measurements, &b, &sb).ok());
    ASSERT_TRUE(sa.usable && sb.usable) << sa.message << " / " << sb.message;
    EXPECT_EQ(sb.linear_solver, "structured");
    std::printf(
        "missing %.1f: exact %d iterations cost %.10e (%s), structured %d "
        "iterations cost %.10e (%s)\n",
        missing, sa.iterations, sa.final_cost, sa.message.c_str(),
        sb.iterations, sb.final_cost, sb.message.c_str());
    EXPECT_LT(sb.final_cost, 0.5 * sb.initial_cost);
    // Same optimum: costs to 1e-4 relative (the structured solver's steps are
    // inexact, CG to 0.1 of the right-hand side, so the two stop at slightly
    // different points of the flat gauge valley), shapes to 1e-3 of their size.
    EXPECT_NEAR(sb.final_cost, sa.final_cost, 1e-4 * sa.final_cost) << missing;
    EXPECT_LT(ComputeE3D(CameraFrameShapes(a), CameraFrameShapes(b)), 1e-3)
        << missing;
  }
}

TEST(StructuredSolver, AutoChoosesItWhenThePointsCanBeEliminated) {
  const Case c = MakeCase(0.0);
  Model model = c.start;
  RefineSummary summary;
  ASSERT_TRUE(Refine(Terms(), SolverOptions(), c.sequence.measurements, &model,
                     &summary)
                  .ok());
  EXPECT_EQ(summary.linear_solver, "structured");
  model = c.start;
  ASSERT_TRUE(Refine(ProblemOptions(), SolverOptions(), c.sequence.measurements,
                     &model, &summary)
                  .ok());
  EXPECT_EQ(summary.linear_solver, "structured");
}

TEST(StructuredSolver, EliminatesPointsThatTheSmoothnessTermCouples) {
  // The Delaunay smoothness term couples neighbouring points: the structured
  // solver eliminates them with one sparse factorisation, its products over
  // the grid of edges × frames formed at once (and those of the temporal
  // shape and deformation priors over theirs). With exact linear solves
  // (conjugate gradients to 1e-10) its LM steps are those of Ceres' exact
  // sparse Cholesky, so the two follow one path: the same cost after the
  // same iterations. `auto` picks it (it took CGNR before).
  for (const double missing : {0.0, 0.2}) {
    const Case c = MakeCase(missing);
    ProblemOptions terms = Terms();
    terms.term_weights[kSmoothnessTerm] = 0.05;
    terms.term_weights[kDeformationTerm] = 0.01;
    SolverOptions exact;
    exact.linear_solver = LinearSolverChoice::kSparseNormalCholesky;
    exact.max_iterations = 15;
    SolverOptions automatic = exact;
    automatic.linear_solver = LinearSolverChoice::kAuto;
    automatic.cg_relative_tolerance = 1e-10;
    Model a = c.start, b = c.start;
    RefineSummary sa, sb;
    ASSERT_TRUE(Refine(terms, exact, c.sequence.measurements, &a, &sa).ok());
    ASSERT_TRUE(
        Refine(terms, automatic, c.sequence.measurements, &b, &sb).ok());
    ASSERT_TRUE(sa.usable && sb.usable) << sa.message << " / " << sb.message;
    EXPECT_EQ(sb.linear_solver, "structured");
    EXPECT_EQ(sb.iterations, sa.iterations);
    EXPECT_LT(sb.final_cost, 0.2 * sb.initial_cost);
    EXPECT_NEAR(sb.final_cost, sa.final_cost, 1e-7 * sa.final_cost) << missing;
    EXPECT_LT(ComputeE3D(CameraFrameShapes(a), CameraFrameShapes(b)), 1e-5)
        << missing;
    // The same bits for one and two threads.
    automatic.num_threads = 2;
    Model d = c.start;
    RefineSummary sd;
    ASSERT_TRUE(
        Refine(terms, automatic, c.sequence.measurements, &d, &sd).ok());
    EXPECT_EQ(sd.final_cost, sb.final_cost);
    EXPECT_EQ(d.basis, b.basis);
  }
}

// Terms() and the two other terms of bilinear form.
ProblemOptions GridTerms() {
  ProblemOptions terms = Terms();
  terms.term_weights[kSmoothnessTerm] = 0.05;
  terms.term_weights[kDeformationTerm] = 0.3;
  return terms;
}

TEST(StructuredSolver, SumsTheTermsOfBilinearFormAsGrids) {
  // Three terms have the bilinear form r = s D λ: the smoothness one row per
  // frame (l_t) and one column per stencil (b_i − Σ_j w_ij b_j, columns of
  // different lengths and signs), the temporal shape prior one row per pair
  // of frames (l_t − l_(t−1)) and one column per point (b_p), the
  // deformation prior one row per frame (l_t masked) and one column per
  // point. The layout recognises each as a full grid, and leaves every other
  // residual block to the block-by-block passes.
  const Case c = MakeCase(0.2);
  const ProblemOptions terms = GridTerms();
  Model model = c.start;
  const int f = model.num_frames, p = model.num_points;
  for (const bool constant_weights : {false, true}) {
    ProblemBuilder builder(&c.sequence.measurements, &model);
    ASSERT_TRUE(builder.AddReprojectionTerms(terms).ok());
    std::vector<int> counts;
    ASSERT_TRUE(AddExtraTerms(terms, &builder, &counts).ok());
    if (constant_weights) {
      // One frame's weights held: neither term is a grid of free blocks.
      builder.problem()->SetParameterBlockConstant(builder.WeightsBlock(4));
    }
    structured::StructuredBlocks blocks;
    std::string error;
    ASSERT_TRUE(structured::LayOutBlocks(MakeStructuredLayout(&builder),
                                         builder.problem(), &blocks, &error))
        << error;
    int in_grid = 0;
    for (const structured::Residual& r : blocks.residuals) in_grid += r.in_grid;
    if (constant_weights) {
      EXPECT_TRUE(blocks.grids.empty());
      EXPECT_EQ(in_grid, 0);
      continue;
    }
    ASSERT_EQ(blocks.grids.size(), 3u);
    const int num_stencils = counts[0] / f;  // the smoothness term first
    ASSERT_EQ(counts[0], num_stencils * f);
    int found = 0;
    for (const structured::BilinearGrid& grid : blocks.grids) {
      EXPECT_EQ(grid.num_bases, model.num_bases);
      if (grid.rows[0].size() == 1 && grid.mask[0] == 1.0) {  // smoothness
        found += 1;
        EXPECT_EQ(static_cast<int>(grid.rows.size()), f);
        EXPECT_EQ(static_cast<int>(grid.columns.size()), num_stencils);
        for (const structured::BilinearGrid::Column& column : grid.columns) {
          // A point, then its neighbours with weights summing to 1.
          ASSERT_GE(column.points.size(), 2u);
          double sum = 0.0;
          for (const auto& term : column.points) sum += term.sign;
          EXPECT_EQ(column.points[0].sign, 1.0);
          EXPECT_NEAR(sum, 0.0, 1e-12);
        }
        EXPECT_EQ(grid.mask, Eigen::VectorXd::Ones(model.num_bases));
      } else if (grid.rows[0].size() == 2) {  // the temporal shape prior
        found += 10;
        EXPECT_EQ(static_cast<int>(grid.rows.size()), f - 1);
        EXPECT_EQ(static_cast<int>(grid.columns.size()), p);
        EXPECT_EQ(grid.rows[0][0].sign, 1.0);
        EXPECT_EQ(grid.rows[0][1].sign, -1.0);
      } else {  // the deformation prior: basis shape 1 masked out
        found += 100;
        EXPECT_EQ(static_cast<int>(grid.rows.size()), f);
        EXPECT_EQ(static_cast<int>(grid.columns.size()), p);
        EXPECT_EQ(grid.mask[0], 0.0);
        EXPECT_EQ(grid.mask.tail(model.num_bases - 1).sum(),
                  model.num_bases - 1.0);
      }
    }
    EXPECT_EQ(found, 111);
    EXPECT_EQ(in_grid, num_stencils * f + (f - 1) * p + f * p);
    EXPECT_EQ(blocks.not_in_grid.size(), blocks.residuals.size() - in_grid);
  }
}

// diag(JᵀJ) with the grids' residuals' part from the grids' sums
// (SchurElimination::AddGridColumnSquaredNorms; their
// Jacobians are not stored) against the column norms of Ceres' own Jacobian
// of the same problem: the smoothness, temporal shape and deformation terms
// as grids, with and without the reprojection panel.
TEST(StructuredSolver, ColumnNormsOfTheGridsAreThoseOfTheJacobian) {
  const Case c = MakeCase(0.2);
  const ProblemOptions terms = GridTerms();
  Model model = c.start;
  ProblemBuilder builder(&c.sequence.measurements, &model);
  ASSERT_TRUE(builder.AddReprojectionTerms(terms).ok());
  ASSERT_TRUE(AddExtraTerms(terms, &builder).ok());
  structured::StructuredBlocks blocks;
  std::string error;
  ASSERT_TRUE(structured::LayOutBlocks(MakeStructuredLayout(&builder),
                                       builder.problem(), &blocks, &error))
      << error;
  ASSERT_EQ(blocks.grids.size(), 3u);
  const DenseJacobian dense = EvaluateDense(blocks, builder.problem());
  const double cost = dense.cost;
  const Eigen::VectorXd expected = dense.jacobian.colwise().squaredNorm();
  for (const bool panel : {true, false}) {
    structured::StructuredJacobian jacobian(blocks, 2, panel);
    EXPECT_EQ(jacobian.uses_panel(), panel);
    double structured_cost = 0.0;
    ASSERT_TRUE(jacobian.Evaluate(true, &structured_cost));
    EXPECT_NEAR(structured_cost, cost, 1e-12 * cost);
    Eigen::VectorXd reduced, eliminated;
    jacobian.ColumnSquaredNorms(&reduced, &eliminated);
    structured::SchurElimination schur(blocks, jacobian, 2);
    schur.ComputeGram();
    schur.AddGridColumnSquaredNorms(&reduced, &eliminated);
    Eigen::VectorXd got(dense.jacobian.cols());
    got << reduced, eliminated;
    EXPECT_LT((got - expected).cwiseAbs().maxCoeff(),
              1e-10 * expected.cwiseAbs().maxCoeff())
        << (panel ? "panel" : "residual by residual");
  }
}

TEST(StructuredSolver, SameResultForTheSameThreadCount) {
  const Case c = MakeCase(0.1);
  SolverOptions options;
  options.num_threads = 2;
  Model a = c.start, b = c.start;
  RefineSummary sa, sb;
  ASSERT_TRUE(Refine(Terms(), options, c.sequence.measurements, &a, &sa).ok());
  ASSERT_TRUE(Refine(Terms(), options, c.sequence.measurements, &b, &sb).ok());
  EXPECT_EQ(sa.final_cost, sb.final_cost);
  EXPECT_EQ(a.basis, b.basis);
  EXPECT_EQ(a.rotations, b.rotations);
}

}  // namespace
}  // namespace nrsfm
