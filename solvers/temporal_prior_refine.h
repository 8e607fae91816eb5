// RefineWithTemporalPrior(): Refine() (solvers/refine.h) plus a temporal
// smoothness prior on the camera-frame shapes, for sequences sampled densely
// in time (motion capture, video):
//
//   cost = ½ Σ_visible ||s Π R_tc S_t[:, p] + T_tc − w_tcp||²
//        + ½ λ Σ_{t=0}^{F−2} Σ_p ||R_{t+1} S_{t+1}[:, p] − R_t S_t[:, p]||²
//
// (camera 0, R_t = R(ω_t0), S_t = Σ_k l_tk S_k). The prior is in input units
// like the data term, so λ is dimensionless: λ = 1 weighs a frame-to-frame
// 3D displacement like a reprojection error of the same size. It is
// invariant to every gauge of the model (global rotation, K × K mixing of
// weights and basis, their relative scale), so it cannot be reduced by
// moving along a gauge; it fixes the depth of what the images leave
// ambiguous by preferring the smoothest camera-frame motion.
// Optionally a ridge on the shape, + ½ μ Σ_t Σ_p ||S_t[:, p]||² (μ =
// shape_magnitude_weight, dimensionless; gauge-invariant like the above).
// The image fixes x and y of every point, so it acts on depth only: it keeps
// the refinement from the degenerate optimum at infinite depth that appears
// when K is smaller than the data need (a huge depth component, times the
// small out-of-plane part of each R_t, acts as an extra basis).
// One residual block of 3 per (t, p): blocks ω_t, ω_{t+1}, l_t, l_{t+1}, b_p;
// each uses one point block, so the points stay Schur-eliminable.
// Automatic differentiation with K fixed at compile time for K ≤ 16.
//
// This is a research strategy of the benchmark (issue 7); the library's
// own temporal priors (DESIGN.md §2) are a separate issue.
#ifndef NRSFM_SOLVERS_TEMPORAL_PRIOR_REFINE_H_
#define NRSFM_SOLVERS_TEMPORAL_PRIOR_REFINE_H_

#include "core/measurements.h"
#include "core/model.h"
#include "core/status.h"
#include "solvers/refine.h"

namespace nrsfm {

struct TemporalPriorOptions {
  double camera_shape_weight = 0.0;     // λ above, dimensionless, ≥ 0 (0 = off)
  double shape_magnitude_weight = 0.0;  // μ above, dimensionless, ≥ 0 (0 = off; both 0 = plain Refine)
  Status Check() const;
};

// As Refine(); the summary's costs include the prior. Only the options of
// Refine that matter for this solve are used: iterations, tolerances, time,
// threads, linear solver, robust loss (data term only). Every block is free.
Status RefineWithTemporalPrior(const RefineOptions& options,
                               const TemporalPriorOptions& prior,
                               const Measurements& measurements, Model* model,
                               RefineSummary* summary);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_TEMPORAL_PRIOR_REFINE_H_
