// Reconstruct(): the whole pipeline the nrsfm tool and the benchmarks run —
// a closed-form start (solvers/initialize.h) and the refinement of the one
// Ceres problem (solvers/refine.h).
#ifndef NRSFM_SOLVERS_RECONSTRUCT_H_
#define NRSFM_SOLVERS_RECONSTRUCT_H_

#include "core/measurements.h"
#include "core/model.h"
#include "core/status.h"
#include "problems/problem_options.h"
#include "solvers/initialize.h"
#include "solvers/refine.h"
#include "solvers/solver_options.h"

namespace nrsfm {

// Everything a reconstruction needs, each fact once.
struct ReconstructOptions {
  StartOptions start;      // the closed-form start, including K (start.num_bases)
  ProblemOptions problem;  // what the Ceres problem holds and refines
  SolverOptions solver;    // how it is solved

  // Each part's Check(), with the part named in the message.
  Status Check() const;
};

struct ReconstructResult {
  Model model;               // the refined model (the start if refine.usable is false)
  StartSummary start;        // the start kept: method, its RMS, its time
  RefineSummary refine;      // the refinement: costs, RMS, iterations, times
  double total_seconds = 0;  // wall time of Reconstruct()
};

// With start.method = auto, both the factorization and the rigid starts are
// refined and the lower refined cost is kept (a usable solution before an
// unusable one); result->start.method says which. A start's own reprojection
// error does not tell which basin it is in: on superquadric data (F = 80,
// P = 60, K = 4) the rigid start fits better (RMS 0.003 vs 0.046) but
// refines to e3D 0.79, the factorisation start to e3D 4e-11. Costs one extra
// refinement.
// Errors on invalid options or measurements and when the start fails (see
// Initialize); a refinement that is not usable is reported in
// result->refine.usable, with result->model left at the start.
Status Reconstruct(const ReconstructOptions& options,
                   const Measurements& measurements, ReconstructResult* result);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_RECONSTRUCT_H_
