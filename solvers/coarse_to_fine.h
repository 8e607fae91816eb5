// Strategies around Reconstruct() against poor local minima (001 §3.4.2,
// "coarse-to-fine"): several starts and/or growing K one basis at a time.
//
// Coarse-to-fine K. Reconstruct with K = start_num_bases; then, for
// K' = start_num_bases + 1 … K: append one basis shape S_K' = 0 with weights
// l_tK' = new_weight_stddev · n_t, n_t ~ N(0, 1) i.i.d. (seeded), and refine
// the whole model (intermediate_max_iterations LM iterations); the last K is
// refined with options.refine. Each new basis starts at zero, so the step
// begins exactly at the previous optimum and only descends from it: the
// larger model explains what the smaller could not without re-deciding the
// rotations, the mostly rigid part the coarse model already fixed.
//
// Several starts. num_starts > 1 runs the pipeline (plain or coarse-to-fine)
// from num_starts closed-form starts: start 0 with options.start as given, the
// others with the rigid start (001 §3.4.2) and seeds options.start.seed + i
// (different random initial weights). The result with the lowest final Ceres
// cost is kept; every start's cost is in the summary.
//
// Every refinement uses options.refine as given, extra terms included
// (e.g. the temporal shape prior); the costs compared between starts then
// include them.
#ifndef NRSFM_SOLVERS_COARSE_TO_FINE_H_
#define NRSFM_SOLVERS_COARSE_TO_FINE_H_

#include <cstdint>
#include <vector>

#include "core/measurements.h"
#include "core/status.h"
#include "solvers/reconstruct.h"

namespace nrsfm {

struct RobustReconstructOptions {
  bool coarse_to_fine = true;        // grow K from start_num_bases (see above)
  int start_num_bases = 1;           // K of the first reconstruction, ≥ 1
  int intermediate_max_iterations = 50;  // LM iterations per intermediate K, ≥ 0
  double new_weight_stddev = 0.01;   // std of a new basis' initial weights, × RMS of the existing weights, > 0
  int num_starts = 1;                // closed-form starts tried, ≥ 1
  std::uint64_t seed = 1;            // for the new weights (mt19937_64 + Box-Muller)

  Status Check() const;
};

struct RobustReconstructSummary {
  std::vector<double> start_final_costs;  // final Ceres cost of each start, in order
  int best_start = 0;                     // index of the kept start
};

// Reconstructs with options.start.num_bases = K bases by the strategy above.
// `result->start` is the kept start's closed-form summary (at K =
// start_num_bases when coarse-to-fine), `result->refine` the last refinement,
// result->total_seconds the wall time of the whole call. Errors as
// Reconstruct(); a start that fails is skipped (error only if all fail).
Status RobustReconstruct(const ReconstructOptions& options,
                         const RobustReconstructOptions& robust,
                         const Measurements& measurements,
                         ReconstructResult* result,
                         RobustReconstructSummary* summary = nullptr);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_COARSE_TO_FINE_H_
