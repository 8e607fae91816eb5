#include "solvers/refine/minimizer_choice.h"

namespace nrsfm {

MinimizerChoice ChooseMinimizer(LinearSolverChoice requested,
                                ProblemBuilder* builder) {
  const bool automatic = requested == LinearSolverChoice::kAuto;
  ProblemStructure structure;
  if (automatic) structure = DescribePointBlocks(builder);
  const LinearSolverChoice choice =
      automatic ? ChooseLinearSolver(structure) : requested;
  MinimizerChoice result;
  if (choice == LinearSolverChoice::kStructured) {
    result.minimizer = Minimizer::kStructured;
    // Ceres' Schur solvers cannot eliminate points that residuals couple.
    result.ceres_linear_solver = structure.points_are_independent
                                     ? LinearSolverChoice::kIterativeSchur
                                     : LinearSolverChoice::kCgnr;
    result.fallback = automatic;
  } else {
    result.minimizer = Minimizer::kCeres;
    result.ceres_linear_solver = choice;
  }
  return result;
}

}  // namespace nrsfm
