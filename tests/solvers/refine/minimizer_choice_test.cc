#include "solvers/refine/minimizer_choice.h"

#include <gtest/gtest.h>

#include "core/synthetic/synthetic.h"
#include "problems/problem_builder.h"
#include "problems/problem_options.h"
#include "tests/synthetic_sequences.h"

namespace nrsfm {
namespace {

SyntheticSequence Sequence() {
  return testing_util::RandomBasisSequence(20, 10, 2);
}

TEST(MinimizerChoice, StructuredIsAMinimizerOfItsOwn) {
  SyntheticSequence s = Sequence();
  ProblemBuilder builder(&s.measurements, &s.truth);
  ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());

  // auto takes it for free, independent points; Ceres is the fallback.
  MinimizerChoice choice = ChooseMinimizer(LinearSolverChoice::kAuto, &builder);
  EXPECT_EQ(choice.minimizer, Minimizer::kStructured);
  EXPECT_TRUE(choice.fallback);
  EXPECT_EQ(choice.ceres_linear_solver, LinearSolverChoice::kIterativeSchur);

  // Asked for by name: no fallback.
  choice = ChooseMinimizer(LinearSolverChoice::kStructured, &builder);
  EXPECT_EQ(choice.minimizer, Minimizer::kStructured);
  EXPECT_FALSE(choice.fallback);

  // Any other name is a linear solver of Ceres' minimiser, as given.
  for (LinearSolverChoice linear :
       {LinearSolverChoice::kDenseSchur, LinearSolverChoice::kSparseSchur,
        LinearSolverChoice::kIterativeSchur,
        LinearSolverChoice::kSparseNormalCholesky, LinearSolverChoice::kCgnr,
        LinearSolverChoice::kDenseQr}) {
    choice = ChooseMinimizer(linear, &builder);
    EXPECT_EQ(choice.minimizer, Minimizer::kCeres) << LinearSolverName(linear);
    EXPECT_EQ(choice.ceres_linear_solver, linear) << LinearSolverName(linear);
  }
}

TEST(MinimizerChoice, AutoWithoutFreePointsRunsCeres) {
  SyntheticSequence s = Sequence();
  ProblemBuilder builder(&s.measurements, &s.truth);
  ProblemOptions options;
  options.constant_basis = true;
  ASSERT_TRUE(builder.AddReprojectionTerms(options).ok());
  const MinimizerChoice choice =
      ChooseMinimizer(LinearSolverChoice::kAuto, &builder);
  EXPECT_EQ(choice.minimizer, Minimizer::kCeres);
  EXPECT_EQ(choice.ceres_linear_solver,
            ChooseLinearSolver(DescribeProblem(&builder)));
  EXPECT_NE(choice.ceres_linear_solver, LinearSolverChoice::kStructured);
}

}  // namespace
}  // namespace nrsfm
