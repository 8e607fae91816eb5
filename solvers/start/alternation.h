// From rigid to non-rigid: the alternation of Torresani et al. (2001, the
// "iterative optimisation") that turns per-frame rotations and scales and a
// rigid shape into a start with K basis shapes, shared by the rigid start
// (solvers/start/rigid_start.h) and the corrective-triple start
// (solvers/start/triple_start.h). docs/factorization.md has the derivation.
//
// Input: `centered`, a one-camera Measurements whose W (2F × P) has the
// per-frame translation removed and every missing entry filled; only its
// visible entries enter the fits.
//   1. Start model: R_t and l_t1 = s_t from the given rotations and scales,
//      S_1 = the rigid shape; for k ≥ 2, S_k = 0 and
//      l_tk ~ N(0, initial_deformation²), drawn from Random(seed)
//      (core/math/random.h, NormalUnpaired()).
//   2. `rounds` rounds of: basis by linear least squares (then centred, the
//      shift moved into δT; solvers/start/basis_weight_fit.h); weights and a
//      per-frame translation correction δT_t jointly by linear least squares;
//      every basis k ≥ 2 rescaled to the norm of S_1 (l_tk inversely; the fit
//      is unchanged) to keep the K × K gauge well conditioned; then, with
//      `update_rotations`, per frame up to 3 Gauss-Newton steps on the
//      rotation (those of RefineRotation in solvers/start/pose_fit.h, formed
//      from the second moments of the frame's points and tracks), each kept
//      only if it lowers that frame's cost. Rounds stop early when the cost
//      drops by less than 1e-10 (relative).
// Every step is an exact minimiser or a step kept only when it helps, so the
// cost never increases: the returned model's RMS is at most rigid_rms (up to
// the 1e-12 relative damping of the linear solves). δT_t corrects the centring
// of frames with missing entries; it stays 0 for a frame that sees every point.
#ifndef NRSFM_SOLVERS_START_ALTERNATION_H_
#define NRSFM_SOLVERS_START_ALTERNATION_H_

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/model/measurements.h"
#include "core/model/model.h"
#include "core/model/status.h"

namespace nrsfm {

struct AlternationOptions {
  int rounds = 20;  // rounds of step 2, ≥ 0 (0 = the model of step 1)
  // std of the random initial l_tk, k ≥ 2, finite, ≥ 0
  double initial_deformation = 0.01;

  Status Check() const;
};

struct AlternationSummary {
  // RMS over visible entries of the step-1 model, input units
  double rigid_rms = 0.0;
};

// What every start built on the alternation needs: one camera (CHECKed),
// valid options, K ≥ 1, 2F ≥ 3 and P ≥ 4.
Status CheckAlternationInput(const Measurements& centered, int num_bases,
                             const AlternationOptions& options);

// Fills `model` (Resize'd to F, 1, P, K; unit scales; translations = δT, to
// be added to the translations removed from `centered`). `rotations` and
// `scales` have F entries, `rigid_shape` is 3 × P. CHECKs the sizes and
// options (callers validate them). The fits of points and frames run on up
// to `num_threads` threads; the result does not depend on it.
void AlternateFromRigid(const Measurements& centered, int num_bases,
                        const std::vector<Eigen::Matrix3d>& rotations,
                        const Eigen::VectorXd& scales,
                        const Eigen::Matrix3Xd& rigid_shape,
                        const AlternationOptions& options, std::uint64_t seed,
                        bool update_rotations, Model* model,
                        AlternationSummary* summary, int num_threads = 1);

}  // namespace nrsfm

#endif  // NRSFM_SOLVERS_START_ALTERNATION_H_
