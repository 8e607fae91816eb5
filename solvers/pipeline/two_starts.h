// Two refinements from two starts, run side by side in lockstep, with the
// rule that abandons the one that is falling behind (Reconstruct(),
// solvers/pipeline/reconstruct.h, refines the factorization and the rigid start
// of the same problem and keeps the lower cost).
//
// Each refinement runs on a thread of its own and waits, after every LM
// iteration, until the other has done as many iterations (or has ended):
// with RunTwoRefinements' `concurrent` they run at the same time, otherwise
// they take turns, one iteration each. Either way every decision below sees
// the same iteration counts and costs, so the outcome is the same for a
// given number of threads per refinement, however the threads are
// scheduled.
//
// The rule: once one refinement has converged (ended by a tolerance) after
// n iterations at cost C, the other goes on only while it has run fewer
// than kRaceIterations(n) = 2n + 10 iterations or its cost is below C; past
// that it is abandoned (its summary says stopped). The starts' own costs do
// not tell which ends lower (docs/factorization.md, section 7); the rule
// only ends a refinement that has had twice the other's iterations and
// still not reached its cost (why: docs/performance.md).
#ifndef NRSFM_SOLVERS_PIPELINE_TWO_STARTS_H_
#define NRSFM_SOLVERS_PIPELINE_TWO_STARTS_H_

#include <functional>

#include "solvers/refine/solver_options.h"

namespace nrsfm {

inline int RaceIterations(int converged_iterations) {
  return 2 * converged_iterations + 10;
}

// What a refinement reports when it ends.
struct RaceOutcome {
  bool converged = false;  // ended by a tolerance
  bool usable = false;
  double final_cost = 0.0;
  int iterations = 0;
};

// One of the two: `run` starts and refines with the solver options it is
// given (their progress and stop_requested are the race's; it must call
// Refine()/SolveProblem() with them) and returns its outcome, or usable =
// false when its start failed.
using RaceRefinement = std::function<RaceOutcome(const SolverOptions& solver)>;

// Runs `first` and `second` as described in the header, each with `solver`
// (its num_threads as given). The caller's `solver.progress` receives the
// first refinement's reports and then the second's, on the calling thread,
// and `solver.stop_requested` is asked on the calling thread after each
// (and after each of the second's reports while they wait for the first's
// end); each refinement waits for that answer after every iteration, so
// when it returns true both stop after their current iteration.
// `solver.max_seconds` limits each refinement's wall time from its own start;
// taking turns, that time includes the other's iterations, so a limit is
// reached after about half the iterations it allows alone.
void RunTwoRefinements(const SolverOptions& solver, bool concurrent,
                       const RaceRefinement& first,
                       const RaceRefinement& second);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_TWO_STARTS_H_
