// Which minimiser runs a refinement, decided apart from Ceres' linear solver.
//
// SolverOptions::linear_solver names both: "structured" is not a Ceres
// linear solver but a Levenberg–Marquardt minimiser of its own
// (solvers/refine/structured_solver.h); every other name is a linear solver of
// Ceres' trust-region minimiser (problems/linear_solver_choice.h). `auto`
// resolves by the rule there (ChooseLinearSolver), from the problem's
// structure.
#ifndef NRSFM_SOLVERS_REFINE_MINIMIZER_CHOICE_H_
#define NRSFM_SOLVERS_REFINE_MINIMIZER_CHOICE_H_

#include "problems/linear_solver_choice.h"
#include "problems/problem_builder.h"

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

// `requested` is SolverOptions::linear_solver; the problem's structure is
// looked at (DescribePointBlocks) only for kAuto.
MinimizerChoice ChooseMinimizer(LinearSolverChoice requested,
                                ProblemBuilder* builder);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_MINIMIZER_CHOICE_H_
