// Reconstruct(): the whole pipeline the CLI and the benchmarks run — the
// closed-form start (solvers/initialize.h) followed by the refinement of the
// one Ceres problem (solvers/refine.h).
#ifndef NRSFM_SOLVERS_RECONSTRUCT_H_
#define NRSFM_SOLVERS_RECONSTRUCT_H_

#include "core/measurements.h"
#include "core/model.h"
#include "core/status.h"
#include "solvers/initialize.h"
#include "solvers/refine.h"

namespace nrsfm {

struct ReconstructOptions {
  InitializeOptions init;  // the start, including K (init.num_bases)
  RefineOptions refine;    // the refinement

  // Both parts' Check(), with the part named in the message.
  Status Check() const;
};

struct ReconstructResult {
  Model model;               // the refined model (the start if refine.usable is false)
  InitializeSummary init;    // the start: method used, its RMS, its time
  RefineSummary refine;      // the refinement: costs, RMS, iterations, times
  double total_seconds = 0;  // wall time of Reconstruct()
  // With init.method = auto: the final refined cost reached from each start
  // (-1 = that start failed or was not run).
  double factorization_refined_cost = -1;
  double rigid_refined_cost = -1;
};

// With init.method = auto, both starts are refined and the lower refined cost
// is kept (a usable solution before an unusable one); result->init.used says
// which. A start's own reprojection error does not tell which basin it is in:
// on superquadric data (F = 80, P = 60, K = 4) the rigid start fits better
// (RMS 0.003 vs 0.046) but refines to e3D 0.79, the factorisation start to
// e3D 4e-11. Costs one extra refinement.
// Errors on invalid options or measurements and when the start fails (see
// Initialize); a refinement that is not usable is reported in
// result->refine.usable, with result->model left at the start.
Status Reconstruct(const ReconstructOptions& options,
                   const Measurements& measurements, ReconstructResult* result);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_RECONSTRUCT_H_
