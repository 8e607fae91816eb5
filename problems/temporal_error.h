// Temporal smoothness priors for video-like input (DESIGN.md §2), one
// residual block per pair of consecutive frames (t − 1, t), t = 1 … F − 1:
//
//   weights:   r = sqrt(λ_l) · (l_t − l_{t−1}),                 K residuals
//   rotations: r = sqrt(λ_R) · log( R(ω_tc) R(ω_{t−1,c})ᵀ ),    3 residuals,
//              one block per camera c
//
// l_t the frame's basis weights (Model::weights.col(t), dimensionless), ω_tc
// the view's angle-axis (radians); log = the angle-axis of the relative
// rotation, whose norm is the angle turned between the two frames.
// Weights: λ_l in (input units)² per unit of weight change; λ_R in (input
// units / rad)²: λ = 1 weighs a weight change of 1, or a turn of 1 rad,
// between consecutive frames like a reprojection error of one input unit.
// The rotation prior is invariant to the global rotation gauge; the weights
// prior is not invariant to the scale gauge (it favours smaller weights and
// a larger basis), so keep λ_l small against the data term.
#ifndef NRSFM_PROBLEMS_TEMPORAL_ERROR_H_
#define NRSFM_PROBLEMS_TEMPORAL_ERROR_H_

#include <ceres/autodiff_cost_function.h>
#include <ceres/dynamic_autodiff_cost_function.h>
#include <glog/logging.h>

#include "problems/relative_rotation.h"

namespace nrsfm {

// Blocks: l_t (K), l_{t−1} (K). K at run time.
class WeightsTemporalError {
 public:
  WeightsTemporalError(int num_bases, double sqrt_weight)
      : num_bases_(num_bases), sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(T const* const* parameters, T* residuals) const {
    for (int k = 0; k < num_bases_; ++k) {
      residuals[k] = sqrt_weight_ * (parameters[0][k] - parameters[1][k]);
    }
    return true;
  }

  // Caller owns the result.
  static ceres::CostFunction* Create(int num_bases, double sqrt_weight) {
    CHECK_GE(num_bases, 1);
    auto* cost = new ceres::DynamicAutoDiffCostFunction<WeightsTemporalError>(
        new WeightsTemporalError(num_bases, sqrt_weight));
    cost->AddParameterBlock(num_bases);
    cost->AddParameterBlock(num_bases);
    cost->SetNumResiduals(num_bases);
    return cost;
  }

 private:
  int num_bases_;
  double sqrt_weight_;
};

// Blocks: ω_tc (3), ω_{t−1,c} (3).
class RotationTemporalError {
 public:
  explicit RotationTemporalError(double sqrt_weight) : sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* rotation, const T* previous_rotation,
                  T* residuals) const {
    RelativeAngleAxis<T>(rotation, previous_rotation, nullptr, residuals);
    for (int i = 0; i < 3; ++i) residuals[i] *= sqrt_weight_;
    return true;
  }

  // Caller owns the result.
  static ceres::CostFunction* Create(double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<RotationTemporalError, 3, 3, 3>(
        new RotationTemporalError(sqrt_weight));
  }

 private:
  double sqrt_weight_;
};

}  // namespace nrsfm

#endif  // NRSFM_PROBLEMS_TEMPORAL_ERROR_H_
