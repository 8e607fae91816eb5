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

TEST(MinimizerChoice, TheMinimizerOptionNamesTheMinimizer) {
  SyntheticSequence s = Sequence();
  ProblemBuilder builder(&s.measurements, &s.truth);
  ASSERT_TRUE(builder.AddReprojectionTerms(ProblemOptions()).ok());
  // structured: ours, no fallback; ceres with auto: Ceres with the
  // structured choice's fallback solver (the points here are independent).
  MinimizerChoice choice = ChooseMinimizer(MinimizerOption::kStructured,
                                           LinearSolverChoice::kAuto, &builder);
  EXPECT_EQ(choice.minimizer, Minimizer::kStructured);
  EXPECT_FALSE(choice.fallback);
  choice = ChooseMinimizer(MinimizerOption::kCeres, LinearSolverChoice::kAuto,
                           &builder);
  EXPECT_EQ(choice.minimizer, Minimizer::kCeres);
  EXPECT_FALSE(choice.fallback);
  EXPECT_EQ(choice.ceres_linear_solver, LinearSolverChoice::kIterativeSchur);
  choice = ChooseMinimizer(MinimizerOption::kCeres,
                           LinearSolverChoice::kDenseSchur, &builder);
  EXPECT_EQ(choice.minimizer, Minimizer::kCeres);
  EXPECT_EQ(choice.ceres_linear_solver, LinearSolverChoice::kDenseSchur);
  // auto: the linear_solver option alone decides, as before.
  choice = ChooseMinimizer(MinimizerOption::kAuto, LinearSolverChoice::kAuto,
                           &builder);
  EXPECT_EQ(choice.minimizer, Minimizer::kStructured);
  EXPECT_TRUE(choice.fallback);
}

TEST(MinimizerChoice, ALinearSolverTheMinimizerDoesNotUseIsAnError) {
  SolverOptions options;
  options.minimizer = MinimizerOption::kStructured;
  options.linear_solver = LinearSolverChoice::kDenseQr;
  Status status = options.Check();
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find(
                "linear_solver = dense_qr is one of Ceres' linear solvers: it "
                "applies with minimizer = ceres, not structured"),
            std::string::npos)
      << status.message();
  options.minimizer = MinimizerOption::kCeres;
  options.linear_solver = LinearSolverChoice::kStructured;
  status = options.Check();
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("linear_solver = structured is the "
                                  "structured minimizer"),
            std::string::npos)
      << status.message();
  options.linear_solver = LinearSolverChoice::kAuto;
  EXPECT_TRUE(options.Check().ok());
  MinimizerOption parsed;
  EXPECT_TRUE(ParseMinimizer("ceres", &parsed).ok());
  EXPECT_EQ(parsed, MinimizerOption::kCeres);
  status = ParseMinimizer("fast", &parsed);
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("expected one of auto, structured, ceres"),
            std::string::npos)
      << status.message();
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
