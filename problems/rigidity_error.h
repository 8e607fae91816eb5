// Multi-camera rigidity (the `rigidity` extra term, docs/problem.md; after
// Torresani et al. 2001's multi-view input): M synchronised cameras on
// a rigid rig see the object at a fixed relative pose, so for every frame t
// and camera c ≥ 1 one residual block ties the view's relative rotation and
// scale to the rig's shared ones:
//
//   r[0:3] = sqrt(λ) · log( R(ω_tc) R(ω_t0)ᵀ R(ω_rig_c)ᵀ )   (radians)
//   r[3]   = sqrt(λ) · (s_tc − s_rig_c)                      (dimensionless)
//
// log = the angle-axis of the discrepancy rotation (its norm is the angle
// between R_tc R_t0ᵀ and R_rig_c), s_tc the view's projection scale relative
// to camera 0 (s_t0 = 1), λ ≥ 0 the term's weight in (input units / rad)²:
// λ = 1 weighs a 1 rad rig discrepancy (or a scale ratio off by 1) like a
// reprojection error of one input unit. Invariant to the global rotation
// gauge (R_tc → R_tc Q for every view).
//
// Blocks: ω_tc (3), ω_t0 (3), ω_rig_c (3) = Model::rig_rotations.col(c − 1),
// s_tc (1) = Model::scales(View(t, c)), s_rig_c (1) = Model::rig_scales(c − 1).
#ifndef NRSFM_PROBLEMS_RIGIDITY_ERROR_H_
#define NRSFM_PROBLEMS_RIGIDITY_ERROR_H_

#include <ceres/autodiff_cost_function.h>

#include "problems/relative_rotation.h"

namespace nrsfm {

class RigidityError {
 public:
  explicit RigidityError(double sqrt_weight) : sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* rotation_c, const T* rotation_0,
                  const T* rig_rotation, const T* scale_c, const T* rig_scale,
                  T* residuals) const {
    RelativeAngleAxis(rotation_c, rotation_0, rig_rotation, residuals);
    for (int i = 0; i < 3; ++i) residuals[i] *= sqrt_weight_;
    residuals[3] = sqrt_weight_ * (scale_c[0] - rig_scale[0]);
    return true;
  }

  // Caller owns the result.
  static ceres::CostFunction* Create(double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<RigidityError, 4, 3, 3, 3, 1, 1>(
        new RigidityError(sqrt_weight));
  }

 private:
  double sqrt_weight_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_RIGIDITY_ERROR_H_
