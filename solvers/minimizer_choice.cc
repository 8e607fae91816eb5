#include "solvers/minimizer_choice.h"

namespace nrsfm {

MinimizerChoice ChooseMinimizer(LinearSolverChoice requested,
                                ProblemBuilder* builder) {
  const bool automatic = requested == LinearSolverChoice::kAuto;
  const LinearSolverChoice choice =
      automatic ? ChooseLinearSolver(DescribeProblem(builder)) : requested;
  MinimizerChoice result;
  if (choice == LinearSolverChoice::kStructured) {
    result.minimizer = Minimizer::kStructured;
    result.ceres_linear_solver = LinearSolverChoice::kIterativeSchur;
    result.fallback = automatic;
  } else {
    result.minimizer = Minimizer::kCeres;
    result.ceres_linear_solver = choice;
  }
  return result;
}

}  // namespace nrsfm
