// Refine(): Levenberg–Marquardt refinement of a whole model against the
// measurements, the one Ceres problem of docs/problem.md:
//
//   cost = ½ Σ_{visible (t, c, p)} w_obs ρ( ||s_tc Π R_tc S_t[:, p] + T_tc −
//   w_tcp||² )
//          + Σ_terms λ · (the term's cost)
//
// over the blocks `problem` does not hold constant (ρ = identity, Huber or
// Cauchy; the extra terms of problems/extra_terms.h whose weight is
// non-zero). The gauge freedoms (global rotation, K × K mixing, depth
// reflection, basis shift) are left free; LM damping copes with the rank
// deficiency (docs/model.md).
#ifndef NRSFM_SOLVERS_REFINE_REFINE_H_
#define NRSFM_SOLVERS_REFINE_REFINE_H_

#include <memory>
#include <string>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "problems/problem_builder.h"
#include "problems/problem_options.h"
#include "solvers/refine/solver_options.h"
#include "solvers/refine/structured_solver.h"

namespace nrsfm {

struct RefineSummary {
  bool usable = false;  // Ceres IsSolutionUsable() and a finite model
  std::string message;  // the solver's termination message (or why not usable)
  // Stopped by a tolerance (function, gradient or parameter), not by the
  // iteration or time limit.
  bool converged = false;
  // Ended because SolverOptions::stop_requested returned true.
  bool stopped = false;
  double initial_cost = 0.0;  // Ceres cost ½ Σ ρ(‖r‖²) at the start
  double final_cost = 0.0;    // … at the end (= initial_cost when not usable)
  // Measurements-vs-model RMS (core/eval/metrics.h), input units
  double initial_reprojection_rms = 0.0;
  double reprojection_rms = 0.0;  // … of the final model
  int iterations = 0;             // LM iterations (successful and not)
  int num_residual_blocks = 0;    // reprojection residual blocks (observations)
  double seconds = 0.0;           // wall time of the whole Refine() call
  // Where the time went (seconds): building the problem, Ceres' preprocessing,
  // residual and Jacobian evaluation, linear solves, the minimizer as a whole.
  double build_seconds = 0.0;
  double preprocessor_seconds = 0.0;
  double residual_seconds = 0.0;
  double jacobian_seconds = 0.0;
  double linear_solver_seconds = 0.0;
  double minimizer_seconds = 0.0;
  // Of seconds and minimizer_seconds, the time spent in the caller's
  // SolverOptions::progress and stop_requested (where Reconstruct()'s two
  // starts wait for each other, solvers/pipeline/two_starts.h):
  // minimizer_seconds − callback_seconds is the solver's own time.
  double callback_seconds = 0.0;
  std::string linear_solver;  // name of the solver used ("iterative_schur",
                              // "structured", …)
  std::string ceres_report;   // Ceres' FullReport(), or the structured solver's
                              // one-line report
};

// A problem that Refine() built without extra terms, kept for the next
// Refine() of equal measurements (bit for bit) with equal options of the
// data term, no extra term and a model of the same sizes: that one then
// skips the build, the choice of the minimiser and the structured solver's
// layout (it still checks its options and model as a build does), and
// refines its model's values in the kept storage (Reconstruct() refines its
// two starts one after the other this way when both would not fit in memory
// at once). Holds its own copies of the measurements and the model (the
// blocks' storage). A Refine() that does not fit frees it first and builds
// (and keeps) a new one; one with an extra term keeps none. Not
// thread-safe; movable.
class KeptProblem {
 public:
  KeptProblem();
  ~KeptProblem();
  KeptProblem(KeptProblem&&) noexcept;
  KeptProblem& operator=(KeptProblem&&) noexcept;

  // Refine() calls that reused a kept problem, over the object's life (the
  // builds not counted).
  int reuses() const { return reuses_; }

  struct State;  // solvers/refine/refine.cc

 private:
  friend Status Refine(const ProblemOptions&, const SolverOptions&,
                       const Measurements&, Model*, RefineSummary*,
                       KeptProblem*);
  std::unique_ptr<State> state_;
  int reuses_ = 0;
};

// Refines `model` in place from its current values. Errors (model unchanged)
// on invalid options, measurements or model, on sizes that differ, on an
// extra term the data cannot take (problems/extra_terms.h), or on a linear
// solver that cannot handle the problem. A solve that fails or gives a
// non-finite model returns OK with summary->usable = false and the model
// restored to its input values.
Status Refine(const ProblemOptions& problem, const SolverOptions& solver,
              const Measurements& measurements, Model* model,
              RefineSummary* summary);
// The same with the problem kept in `kept` (see KeptProblem), or reused from
// it when it fits.
Status Refine(const ProblemOptions& problem, const SolverOptions& solver,
              const Measurements& measurements, Model* model,
              RefineSummary* summary, KeptProblem* kept);

// The solve of Refine() for a problem the caller built: `builder` holds the
// reprojection terms (AddReprojectionTerms) plus any other term added
// through its accessors. Fills `summary` like Refine() (costs include every
// term; build_seconds is the solver set-up only) and restores the model when
// the solution is not usable.
Status SolveProblem(const SolverOptions& solver, ProblemBuilder* builder,
                    RefineSummary* summary);

// The blocks of the builder's problem as Refine() gives them to the
// structured solver: one group per frame (its views' rotations, translations
// and scales, then its weights), the rig blocks shared, the points
// eliminated.
StructuredLayout MakeStructuredLayout(ProblemBuilder* builder);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_REFINE_H_
