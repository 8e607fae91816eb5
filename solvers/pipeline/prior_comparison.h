// The full priors against a weaker alternative, decided by the fit: two
// refinements of one start with different terms (docs/priors.md, fact 3).
#ifndef NRSFM_SOLVERS_PIPELINE_PRIOR_COMPARISON_H_
#define NRSFM_SOLVERS_PIPELINE_PRIOR_COMPARISON_H_

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "problems/problem_options.h"
#include "solvers/refine/refine.h"
#include "solvers/refine/solver_options.h"

namespace nrsfm {

struct PriorComparison {
  // The full refinement's reprojection RMS over the alternative's; -1 when
  // they were not compared (a stop asked for, or the alternative failed).
  double fit_ratio = -1;
  bool kept_full = true;  // false: `model` is the alternative's
};

// Refines `model` (the start) with `full` and with `alternative`, side by
// side when `side_by_side` (each on one thread), else one after the other,
// and keeps the full refinement when its reprojection RMS is within
// `max_fit_ratio` (≥ 1) of the alternative's, or when the alternative is not
// usable. The alternative reports no progress and asks for no stop of
// `solver`'s; it stops once it has run as many iterations as the full
// refinement took to converge — in lockstep, so that the same inputs give
// the same result at any thread count and timing — and, when it is kept,
// goes on to its end. `model` and `summary` are the kept refinement's.
// Errors as Refine() on the full problem.
Status RefineFullOrAlternative(const ProblemOptions& full,
                               const ProblemOptions& alternative,
                               const SolverOptions& solver, bool side_by_side,
                               double max_fit_ratio,
                               const Measurements& measurements, Model* model,
                               RefineSummary* summary,
                               PriorComparison* comparison);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_PIPELINE_PRIOR_COMPARISON_H_
