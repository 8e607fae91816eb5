#include "problems/linear_solver_choice.h"

#include <gtest/gtest.h>

#include "core/synthetic/synthetic.h"
#include "problems/problem_builder.h"
#include "tests/synthetic_sequences.h"

namespace nrsfm {
namespace {

SyntheticSequence Sequence(int frames, int points, int bases) {
  return testing_util::RandomBasisSequence(frames, points, bases);
}

TEST(LinearSolverChoice, NamesRoundTripAndBadNamesAreErrors) {
  for (LinearSolverChoice choice :
       {LinearSolverChoice::kAuto, LinearSolverChoice::kDenseSchur,
        LinearSolverChoice::kSparseSchur, LinearSolverChoice::kIterativeSchur,
        LinearSolverChoice::kSparseNormalCholesky, LinearSolverChoice::kCgnr,
        LinearSolverChoice::kDenseQr}) {
    LinearSolverChoice parsed;
    ASSERT_TRUE(ParseLinearSolver(LinearSolverName(choice), &parsed).ok());
    EXPECT_EQ(parsed, choice);
  }
  LinearSolverChoice parsed;
  const Status status = ParseLinearSolver("DENSE_SCHUR", &parsed);
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find("\"DENSE_SCHUR\""), std::string::npos);
  EXPECT_NE(status.message().find("iterative_schur"), std::string::npos);
}

TEST(LinearSolverChoice, DescribeCountsFreeParametersAndSchurFill) {
  SyntheticSequence s = Sequence(10, 12, 2);
  ProblemBuilder builder(&s.measurements, &s.truth);
  ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());
  const ProblemStructure structure = DescribeProblem(&builder);
  EXPECT_EQ(structure.num_point_blocks, 12);
  EXPECT_EQ(structure.num_point_parameters, 12 * 6);
  EXPECT_EQ(structure.num_other_parameters, 10 * (3 + 2 + 2));
  EXPECT_EQ(structure.num_residuals, 2 * 10 * 12);
  EXPECT_TRUE(structure.points_are_independent);
  // Every point sees every frame: the reduced matrix is full, 70².
  EXPECT_EQ(structure.schur_matrix_entries, 70.0 * 70.0);
  // The rule's part alone: the same counts, the scan left out.
  builder.problem()->SetParameterBlockConstant(builder.BasisBlock(3));
  const ProblemStructure points = DescribePointBlocks(&builder);
  EXPECT_EQ(points.num_point_blocks, 11);
  EXPECT_EQ(points.num_point_parameters, 11 * 6);
  EXPECT_TRUE(points.points_are_independent);
  EXPECT_EQ(points.num_residuals, 0);
  EXPECT_EQ(DescribeProblem(&builder).num_point_blocks, 11);
}

TEST(LinearSolverChoice, SchurSolversEliminateThePoints) {
  SyntheticSequence s = Sequence(10, 12, 2);
  ProblemBuilder builder(&s.measurements, &s.truth);
  ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());
  for (LinearSolverChoice choice :
       {LinearSolverChoice::kDenseSchur, LinearSolverChoice::kSparseSchur,
        LinearSolverChoice::kIterativeSchur}) {
    ceres::Solver::Options options;
    LinearSolverChoice used;
    ASSERT_TRUE(ConfigureLinearSolver(choice, &builder, &options, &used).ok());
    EXPECT_EQ(used, choice);
    ASSERT_NE(options.linear_solver_ordering, nullptr);
    // Points, then rotations, translations and weights (one group each).
    EXPECT_EQ(options.linear_solver_ordering->NumGroups(), 4);
    EXPECT_EQ(options.linear_solver_ordering->GroupSize(0), 12);
    EXPECT_EQ(options.linear_solver_ordering->GroupSize(1), 10);
    EXPECT_EQ(
        options.linear_solver_ordering->GroupId(builder.RotationBlock(3, 0)),
        1);
    EXPECT_EQ(
        options.linear_solver_ordering->GroupId(builder.TranslationBlock(3, 0)),
        2);
    EXPECT_EQ(options.linear_solver_ordering->GroupId(builder.WeightsBlock(3)),
              3);
    for (int p = 0; p < 12; ++p) {
      EXPECT_EQ(options.linear_solver_ordering->GroupId(builder.BasisBlock(p)),
                0);
    }
    std::string error;
    EXPECT_TRUE(options.IsValid(&error)) << error;
  }
  ceres::Solver::Options options;
  LinearSolverChoice used;
  ASSERT_TRUE(ConfigureLinearSolver(LinearSolverChoice::kCgnr, &builder,
                                    &options, &used)
                  .ok());
  EXPECT_EQ(options.linear_solver_type, ceres::CGNR);
  // No elimination: the kinds first, the points last.
  ASSERT_NE(options.linear_solver_ordering, nullptr);
  EXPECT_EQ(options.linear_solver_ordering->NumGroups(), 4);
  EXPECT_EQ(
      options.linear_solver_ordering->GroupId(builder.RotationBlock(0, 0)), 0);
  EXPECT_EQ(options.linear_solver_ordering->GroupId(builder.BasisBlock(0)), 3);
}

TEST(LinearSolverChoice, AutoRule) {
  ProblemStructure drink;  // (F, P, K) = (1102, 41, 12)
  drink.num_point_blocks = 41;
  drink.num_point_parameters = 41 * 36;
  drink.num_other_parameters = 1102 * 17;
  drink.num_residuals = 2 * 1102 * 41;
  drink.schur_matrix_entries = 1102.0 * 17 * 1102 * 17;
  EXPECT_EQ(ChooseLinearSolver(drink), LinearSolverChoice::kStructured);

  ProblemStructure tiny = drink;  // (F, P, K) = (30, 15, 3): the same
  tiny.num_point_blocks = 15;
  tiny.num_point_parameters = 15 * 9;
  tiny.num_other_parameters = 30 * 8;
  tiny.num_residuals = 2 * 30 * 15;
  tiny.schur_matrix_entries = 240.0 * 240.0;
  EXPECT_EQ(ChooseLinearSolver(tiny), LinearSolverChoice::kStructured);

  ProblemStructure poses_only = drink;  // every point block constant
  poses_only.num_point_blocks = 0;
  poses_only.num_point_parameters = 0;
  EXPECT_EQ(ChooseLinearSolver(poses_only),
            LinearSolverChoice::kSparseNormalCholesky);

  ProblemStructure coupled = drink;  // e.g. a smoothness term between points
  coupled.points_are_independent = false;
  EXPECT_EQ(ChooseLinearSolver(coupled), LinearSolverChoice::kStructured);
}

TEST(LinearSolverChoice, DenseSolversThatWouldExhaustMemoryAreRefused) {
  // (300, 110, 5): J is 66000 x 4650 — 2.5 GB as a dense matrix.
  SyntheticSequence s = Sequence(300, 110, 5);
  ProblemBuilder builder(&s.measurements, &s.truth);
  ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());
  ceres::Solver::Options options;
  LinearSolverChoice used;
  const Status status = ConfigureLinearSolver(LinearSolverChoice::kDenseQr,
                                              &builder, &options, &used);
  EXPECT_FALSE(status.ok());
  EXPECT_NE(status.message().find("dense Jacobian would take 2.46 GB"),
            std::string::npos)
      << status.message();
  // Its reduced matrix (3000²) is fine for DENSE_SCHUR.
  EXPECT_TRUE(ConfigureLinearSolver(LinearSolverChoice::kDenseSchur, &builder,
                                    &options, &used)
                  .ok());
}

}  // namespace
}  // namespace nrsfm
