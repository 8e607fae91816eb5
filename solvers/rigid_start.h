// The rigid start with iterative optimisation of Torresani et al.
// (001 §3.4.2), monocular.
//
// Input: `centered`, a one-camera Measurements whose W (2F × P) has the
// per-frame translation removed and every missing entry filled (e.g. by the
// low-rank completion); its visibility mask says which entries are real.
//   1. Tomasi-Kanade: rank-3 SVD of the whole centred W, Q̂_rig = U D^{1/2},
//      B̂_rig = D^{1/2} Vᵀ; metric upgrade of the 2 × 3 blocks of Q̂_rig
//      (solvers/metric_upgrade.h) gives G, each frame's scaled rotation
//      Q̂_t G ≈ s_t Π R_t (solvers/pose_fit.h) and the rigid shape
//      S_rig = G⁻¹ B̂_rig.
//   2. Start model: S_1 = S_rig, l_t1 = s_t; for k ≥ 2, S_k = 0 and
//      l_tk ~ N(0, initial_deformation²) (seeded; mt19937_64 with our own
//      Box-Muller transform, so the draws do not depend on the standard
//      library's std::normal_distribution).
//   3. `refine_iterations` rounds of (001 §3.4.2 steps 1-3), on the visible
//      entries only (solvers/basis_weight_fit.h, solvers/pose_fit.h):
//      basis by linear least squares (then centred, the shift moved into
//      δT), weights and a per-frame translation correction δT_t jointly by
//      linear least squares, then per frame up to 3 Gauss-Newton steps of
//      the exponential-coordinate linearisation (001 eq. 15), each kept only
//      if it lowers that frame's cost. δT_t corrects the centring of frames
//      with missing entries (it stays 0 for a frame that sees every point,
//      whose translation is its 2D mean). After the weights step every basis
//      k ≥ 2 is rescaled to the norm of S_1 (l_tk inversely; the fit is
//      unchanged) to keep the K × K gauge well conditioned. Rounds stop
//      early when the cost drops by less than 1e-10 (relative).
// Every step is an exact minimiser (or a step kept only when it helps), so
// the centred cost never increases: final_rms ≤ rigid_rms, the RMS of the
// rigid Tomasi-Kanade model of step 1 (up to the 1e-12 relative damping of
// the linear solves).
#ifndef NRSFM_SOLVERS_RIGID_START_H_
#define NRSFM_SOLVERS_RIGID_START_H_

#include <cstdint>

#include "core/measurements.h"
#include "core/model.h"
#include "core/status.h"
#include "solvers/corrective_triple.h"

namespace nrsfm {

struct RigidStartOptions {
  // Step 1 alternative: the rotations of the rank-3K corrective triple
  // (solvers/corrective_triple.h) and the least-squares rigid shape for
  // them, instead of Tomasi-Kanade's rank-3 factorisation; step 3 then
  // keeps those rotations (basis and weights only).
  bool rotations_from_triple = false;
  CorrectiveTripleOptions triple;

  int refine_iterations = 20;         // rounds of step 3, ≥ 0 (0 = the rigid model of step 2)
  double initial_deformation = 0.01;  // std of the random initial l_tk, k ≥ 2 (≥ 0)
  std::uint64_t seed = 1;             // seed of those random weights

  Status Check() const;
};

struct RigidStartSummary {
  bool metric_upgrade_was_indefinite = false;  // see solvers/metric_upgrade.h
  double metric_upgrade_conditioning = 0.0;    // see solvers/metric_upgrade.h
  CorrectiveTripleSummary triple;              // rotations_from_triple only
  double rigid_rms = 0.0;  // RMS over visible entries of the step-2 model
  double final_rms = 0.0;  // RMS over visible entries of the returned model
  int iterations = 0;      // rounds of step 3 run
};

// Fills `model` (Resize'd to F, 1, P, K; unit scales; translations = δT,
// to be added to the translations removed from `centered`).
// Errors when K < 1, 3 > 2F or P < 4, when the centred tracks have rank < 3
// (no rotation or a flat object) or when the metric upgrade fails.
Status RigidStart(const Measurements& centered, int num_bases,
                  const RigidStartOptions& options, Model* model,
                  RigidStartSummary* summary);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_RIGID_START_H_
