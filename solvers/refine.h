// Refine(): Levenberg–Marquardt refinement of a whole model against the
// measurements — the one Ceres problem of DESIGN.md §2 (problems/
// problem_builder.h), minimising
//
//   cost = ½ Σ_{visible (t, c, p)} ρ( ||s_tc Π R_tc S_t[:, p] + T_tc − w_tcp||² )
//
// plus the extra terms whose weight is non-zero (problems/extra_terms.h)
// over the free blocks (ρ = identity, Huber or Cauchy). The gauge freedoms
// (global rotation, K × K mixing, depth reflection) are left free; LM damping
// copes with the rank deficiency (problems/problem_builder.h).
//
// LinearSolverChoice / ParseLinearSolver come from
// problems/linear_solver_choice.h, RobustLoss / ParseRobustLoss from
// problems/problem_builder.h; both are included here.
#ifndef NRSFM_SOLVERS_REFINE_H_
#define NRSFM_SOLVERS_REFINE_H_

#include <functional>
#include <string>

#include "core/measurements.h"
#include "core/model.h"
#include "core/status.h"
#include "problems/linear_solver_choice.h"
#include "problems/problem_builder.h"

namespace nrsfm {

// Progress callback payload, once per LM iteration (iteration 0 = the start).
struct IterationReport {
  int iteration = 0;     // 0, 1, 2, …
  double cost = 0.0;     // Ceres cost ½ Σ ρ(‖r‖²) after the iteration
  double seconds = 0.0;  // wall time since the solve started
};

struct RefineOptions {
  int max_iterations = 100;            // LM iterations, ≥ 0
  double function_tolerance = 1e-10;   // stop when |Δcost| / cost < this, ≥ 0
  double gradient_tolerance = 1e-12;   // stop when max|projected gradient| < this, ≥ 0
  double parameter_tolerance = 1e-10;  // stop when |Δx| < this · (|x| + this), ≥ 0
  double max_seconds = 0.0;            // wall-time limit of the solve, 0 = none, ≥ 0
  // Ceres threads, ≥ 1. 1 is bitwise deterministic; with more, Ceres 2.1 sums
  // per-thread partial costs in scheduling order and runs agree only to
  // ~1e-13 (tests/solvers/refine_test.cc).
  int num_threads = 1;
  LinearSolverChoice linear_solver = LinearSolverChoice::kAuto;  // see problems/linear_solver_choice.h
  RobustLoss robust_loss = RobustLoss::kNone;  // on the reprojection term only
  double robust_scale = 1.0;           // a > 0, input units (where ρ stops being quadratic)
  // Which kinds of block are free (false = held at their current value).
  bool refine_rotations = true;        // ω_tc
  bool refine_translations = true;     // T_tc
  bool refine_weights = true;          // l_t
  bool refine_basis = true;            // b_p
  bool refine_scales = true;           // s_tc of cameras c ≥ 1 (multi-camera only)
  bool refine_rig = true;              // rig rotations and scales (rigidity term only)
  // Extra terms (problems/extra_terms.h, docs/extra_terms.md), 0 = off:
  double smoothness_weight = 0.0;          // Delaunay smoothness λ_s, dimensionless, ≥ 0
  int smoothness_reference_frame = -1;     // frame triangulated, -1 = most visible points
  double rigidity_weight = 0.0;            // multi-camera rigidity λ_r, (input units / rad)², ≥ 0, M ≥ 2
  double temporal_weights_weight = 0.0;    // l_t − l_{t−1} λ_l, (input units)², ≥ 0
  double temporal_rotations_weight = 0.0;  // log(R_t R_{t−1}ᵀ) λ_R, (input units / rad)², ≥ 0
  double temporal_shape_weight = 0.0;      // S_t − S_{t−1} (object frame) λ_S, dimensionless, ≥ 0
  double rotation_acceleration_weight = 0.0;  // Δ angular velocity λ_A, dimensionless, ≥ 0
  int verbosity = 0;                   // 0 silent, ≥ 1 one VLOG(1) line per iteration
  std::function<void(const IterationReport&)> progress;  // optional, per iteration

  // Errors on a negative count, tolerance or time, num_threads < 1, a non-positive
  // or non-finite robust_scale, a negative or non-finite term weight, and
  // when no kind of block is free.
  Status Check() const;
};

struct RefineSummary {
  bool usable = false;          // Ceres IsSolutionUsable() and a finite model
  std::string message;          // Ceres' termination message (or why not usable)
  double initial_cost = 0.0;    // Ceres cost ½ Σ ρ(‖r‖²) at the start
  double final_cost = 0.0;      // … at the end (= initial_cost when not usable)
  double initial_reprojection_rms = 0.0;  // core/metrics.h ReprojectionRms, input units
  double reprojection_rms = 0.0;          // … of the final model
  int iterations = 0;           // LM iterations (successful and not)
  int num_residual_blocks = 0;  // observations in the problem
  int num_extra_residual_blocks = 0;  // residual blocks of the extra terms
  double seconds = 0.0;         // wall time of the whole Refine() call
  // Where the time went (seconds): building the problem, Ceres' preprocessing,
  // residual and Jacobian evaluation, linear solves, the minimizer as a whole.
  double build_seconds = 0.0;
  double preprocessor_seconds = 0.0;
  double residual_seconds = 0.0;
  double jacobian_seconds = 0.0;
  double linear_solver_seconds = 0.0;
  double minimizer_seconds = 0.0;
  std::string linear_solver;    // name of the solver used ("iterative_schur", …)
  std::string ceres_report;     // ceres::Solver::Summary::FullReport()
};

// Refines `model` in place from its current values. Errors (model unchanged)
// on invalid options, measurements or model, on sizes that differ, or on a
// linear solver that cannot handle the problem. A solve that fails or gives
// a non-finite model returns OK with summary->usable = false and the model
// restored to its input values.
Status Refine(const RefineOptions& options, const Measurements& measurements,
              Model* model, RefineSummary* summary);

// The solve of Refine() for a problem the caller built: `builder` holds the
// reprojection terms (AddReprojectionTerms, where the refine_* flags and the
// robust loss of `options` would apply) plus any other term added through
// its accessors. Uses the solver fields of `options` (iterations,
// tolerances, time, threads, linear solver, verbosity, progress), fills
// `summary` like Refine() (costs include every term; build_seconds is the
// solver set-up only) and restores the model when the solution is not usable.
Status SolveProblem(const RefineOptions& options, ProblemBuilder* builder,
                    RefineSummary* summary);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_REFINE_H_
