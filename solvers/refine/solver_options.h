// How the one Ceres problem is solved: Levenberg–Marquardt with a linear
// solver chosen from the problem's structure (problems/linear_solver_choice.h).
// Refine() (solvers/refine/refine.h) and the corrective triple's small solves
// (solvers/start/corrective_triple.cc) both run Ceres through SolveCeres().
#ifndef NRSFM_SOLVERS_REFINE_SOLVER_OPTIONS_H_
#define NRSFM_SOLVERS_REFINE_SOLVER_OPTIONS_H_

#include <ceres/problem.h>
#include <ceres/solver.h>

#include <functional>
#include <string>

#include "core/model/status.h"
#include "problems/linear_solver_choice.h"

namespace nrsfm {

// Progress callback payload, once per LM iteration (iteration 0 = the start).
struct IterationReport {
  int iteration = 0;     // 0, 1, 2, …
  double cost = 0.0;     // Ceres cost ½ Σ ρ(‖r‖²) after the iteration
  double seconds = 0.0;  // wall time since the solve started
};

// Which minimiser solves the problem (solvers/refine/minimizer_choice.h):
// the structured one — Levenberg–Marquardt of our own on the same Ceres
// problem, the points eliminated and conjugate gradients over the frame
// chain with a preconditioner that is exact for the temporal terms; yoga 21
// LM steps / 2.5 s against 113 / 885 s with Ceres' ITERATIVE_SCHUR
// (docs/performance.md) — or ceres::Solve with `linear_solver`. auto: the
// structured one where its layout fits the problem, else Ceres.
enum class MinimizerOption { kAuto, kStructured, kCeres };
// "auto", "structured", "ceres"; an error lists them.
Status ParseMinimizer(const std::string& name, MinimizerOption* option);
const char* MinimizerName(MinimizerOption option);

// std::thread::hardware_concurrency(), or 1 when it is unknown.
int DefaultNumThreads();

struct SolverOptions {
  // LM iterations, ≥ 0: a safety limit; a solve normally ends by a tolerance
  // (measured in docs/performance.md). Reconstruct() warns when it is reached.
  int max_iterations = 500;
  // Stop when an accepted step lowers the cost by less than this fraction of
  // itself (the reprojection RMS then changes by less than half of it), ≥ 0
  // (the choice of 1e-7 is measured in docs/performance.md).
  double function_tolerance = 1e-7;
  // stop when max|projected gradient| < this, ≥ 0
  double gradient_tolerance = 1e-12;
  // stop when |Δx| < this · (|x| + this), ≥ 0
  double parameter_tolerance = 1e-10;
  double max_seconds = 0.0;  // wall-time limit of the solve, 0 = none, ≥ 0
  // Threads, ≥ 1; by default every core (DefaultNumThreads()). The
  // structured solver (the default) gives the same bits for any count (its
  // sums are added in pieces fixed by the problem); Ceres 2.1's own solvers
  // sum per-thread partial costs in scheduling order, so with more than one
  // thread their runs agree only to rounding. 1 is bitwise deterministic
  // everywhere.
  int num_threads = DefaultNumThreads();
  MinimizerOption minimizer = MinimizerOption::kAuto;
  // Ceres' linear solver, for minimizer = ceres (auto: the rule of
  // problems/linear_solver_choice.h; with minimizer = auto, "structured"
  // still names the structured minimiser).
  LinearSolverChoice linear_solver = LinearSolverChoice::kAuto;
  // LM's first trust-region radius, > 0. Ceres' default is 1e4; the gauge
  // freedoms make its first, nearly undamped steps huge and rejected, so
  // refinements start at 1e2 (docs/performance.md).
  double initial_trust_region_radius = 1e2;
  int verbosity = 0;  // 0 silent, ≥ 1 one VLOG(1) line per iteration
  // The structured solver's conjugate gradients
  // (solvers/refine/structured_solver.h) on each LM step's reduced system: stop
  // when ‖residual‖ ≤ this · ‖rhs‖, in (0, 1), or after max_cg_iterations (≥ 1)
  // iterations. Ceres' own solvers do not read them.
  double cg_relative_tolerance = 0.1;
  int max_cg_iterations = 500;
  std::function<void(const IterationReport&)>
      progress;  // optional, per iteration
  // Optional: asked after every LM iteration (after `progress`; also after
  // iteration 0, before the first step). Returning true ends the solve
  // there: Refine() keeps the last accepted iterate (usable as after any
  // stop), RefineSummary::stopped is true and converged false. Reconstruct()
  // also asks before each start and then returns the error "stopped on
  // request" instead of computing another start. Called on the thread that
  // called Refine()/Reconstruct().
  std::function<bool()> stop_requested;

  // Errors on a negative count, tolerance or time, num_threads < 1, an
  // initial_trust_region_radius that is not positive and finite, and a
  // linear solver the minimiser does not use (minimizer = structured with a
  // Ceres linear solver, minimizer = ceres with linear_solver = structured).
  Status Check() const;
};

// The Ceres options of `options` (iterations, tolerances, time limit,
// threads, first radius; silent). The linear solver is left at Ceres'
// default: set it with ConfigureLinearSolver (problems/
// linear_solver_choice.h) or directly; progress and verbosity are Refine()'s.
ceres::Solver::Options ToCeresOptions(const SolverOptions& options);

// Solves `problem` with ToCeresOptions(options), on which `configure` sets
// what SolverOptions does not hold (the linear solver and its ordering,
// callbacks, …): the options are checked (ceres::Solver::Options::IsValid)
// before ceres::Solve. Errors with the error of `configure`, or "invalid
// Ceres options: <reason>"; `summary` is Ceres' own.
Status SolveCeres(
    const SolverOptions& options,
    const std::function<Status(ceres::Solver::Options*)>& configure,
    ceres::Problem* problem, ceres::Solver::Summary* summary);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_SOLVER_OPTIONS_H_
