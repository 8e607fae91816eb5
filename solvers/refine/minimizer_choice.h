// Which minimiser runs a refinement (SolverOptions::minimizer), and Ceres'
// linear solver when Ceres runs it (SolverOptions::linear_solver).
//
// minimizer = structured: the Levenberg–Marquardt minimiser of our own
// (solvers/refine/structured_solver.h); ceres: Ceres' trust-region
// minimiser with the linear solver named, or for auto the rule of
// problems/linear_solver_choice.h (ChooseLinearSolver) with its structured
// choice replaced by ITERATIVE_SCHUR (CGNR when points are coupled); auto:
// the rule from the problem's structure, where "structured" names the
// structured minimiser.
#ifndef NRSFM_SOLVERS_REFINE_MINIMIZER_CHOICE_H_
#define NRSFM_SOLVERS_REFINE_MINIMIZER_CHOICE_H_

#include "problems/linear_solver_choice.h"
#include "problems/problem_builder.h"
#include "solvers/refine/solver_options.h"

namespace nrsfm {

enum class Minimizer {
  kCeres,       // ceres::Solve with ceres_linear_solver
  kStructured,  // SolveStructured (solvers/refine/structured_solver.h)
};

struct MinimizerChoice {
  Minimizer minimizer = Minimizer::kCeres;
  // The linear solver Ceres runs with (never kAuto or kStructured): for
  // kCeres always; for kStructured only when fallback is set and the
  // structured layout does not fit the problem (a free block of a kind the
  // layout does not know): ITERATIVE_SCHUR, or CGNR when points are coupled.
  LinearSolverChoice ceres_linear_solver = LinearSolverChoice::kIterativeSchur;
  // kStructured chosen by `auto`: a problem it does not fit runs on Ceres
  // instead. Asked for by name it is an error.
  bool fallback = false;
};

// `requested` is SolverOptions::linear_solver (with minimizer = auto); the
// problem's structure is looked at (DescribePointBlocks) only for kAuto.
MinimizerChoice ChooseMinimizer(LinearSolverChoice requested,
                                ProblemBuilder* builder);
// Both options; they have passed SolverOptions::Check().
MinimizerChoice ChooseMinimizer(MinimizerOption minimizer,
                                LinearSolverChoice requested,
                                ProblemBuilder* builder);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_MINIMIZER_CHOICE_H_
