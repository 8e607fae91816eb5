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

MinimizerChoice ChooseMinimizer(MinimizerOption minimizer,
                                LinearSolverChoice requested,
                                ProblemBuilder* builder) {
  switch (minimizer) {
    case MinimizerOption::kAuto:
      return ChooseMinimizer(requested, builder);
    case MinimizerOption::kStructured:
      return ChooseMinimizer(LinearSolverChoice::kStructured, builder);
    case MinimizerOption::kCeres:
      break;
  }
  MinimizerChoice choice = ChooseMinimizer(requested, builder);
  if (choice.minimizer == Minimizer::kStructured) {
    // auto's structured choice, on Ceres: its fallback linear solver.
    choice.minimizer = Minimizer::kCeres;
    choice.fallback = false;
  }
  return choice;
}

}  // namespace nrsfm
