// The rigid start (Torresani et al. 2001, "iterative optimisation";
// docs/factorization.md), monocular: Tomasi-Kanade's rigid factorisation
// for the rotations, then the basis/weights/rotations alternation of
// solvers/start/alternation.h.
//
// Input: `centered`, a one-camera Measurements whose W (2F × P) has the
// per-frame translation removed and every missing entry filled (e.g. by the
// low-rank completion); its visibility mask says which entries are real.
//   1. Tomasi-Kanade: rank-3 SVD of the whole centred W, Q̂_rig = U D^{1/2},
//      B̂_rig = D^{1/2} Vᵀ; metric upgrade of the 2 × 3 blocks of Q̂_rig
//      (solvers/start/metric_upgrade.h) gives G, each frame's scaled rotation
//      Q̂_t G ≈ s_t Π R_t (solvers/start/pose_fit.h) and the rigid shape
//      S_rig = G⁻¹ B̂_rig.
//   2. AlternateFromRigid (solvers/start/alternation.h) from R_t, s_t and
//   S_rig,
//      with rotation updates.
#ifndef NRSFM_SOLVERS_START_RIGID_START_H_
#define NRSFM_SOLVERS_START_RIGID_START_H_

#include <cstdint>

#include "core/math/svd.h"
#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"
#include "solvers/start/alternation.h"

namespace nrsfm {

struct RigidStartSummary {
  // see solvers/start/metric_upgrade.h
  bool metric_upgrade_was_indefinite = false;
  AlternationSummary alternation;  // RMS of the rigid and the returned model
};

// Fills `model` (Resize'd to F, 1, P, K; unit scales; translations = δT,
// to be added to the translations removed from `centered`); `seed` seeds the
// random initial weights. Errors on invalid options, when K < 1, 3 > 2F or
// P < 4, when the centred tracks have rank < 3 (no rotation or a flat
// object) or when the metric upgrade fails. `svd`: StartSvd(centered.W, K)
// (solvers/start/metric_upgrade.h) when the caller has it, else null and it is
// computed here.
// The alternation runs on up to `num_threads` threads; the start does not
// depend on it.
Status RigidStart(const Measurements& centered, int num_bases,
                  const AlternationOptions& options, std::uint64_t seed,
                  Model* model, RigidStartSummary* summary,
                  const ThinSvd* svd = nullptr, int num_threads = 1);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_RIGID_START_H_
