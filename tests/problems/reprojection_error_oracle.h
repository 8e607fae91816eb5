// Reprojection error of one visible observation (frame t, camera c, point p),
// the data term of docs/problem.md, as an automatically differentiated
// functor:
//
// clang-format off
//   r = sqrt(w_obs) · ( s_tc · Π · R(ω_tc) · X + T_tc − w_tcp ),   2 residuals,
//   X = Σ_k l_tk · b_p[3k : 3k+3]     (point p of the shape S_t, object frame)
// clang-format on
//
// Π = [I_2 0] (scaled orthographic), R(ω) the rotation of the angle-axis ω
// (ceres/rotation.h convention: axis · angle in radians), w_obs ≥ 0 the
// observation's weight (its cost is multiplied by w_obs).
//
// Parameter blocks, in this order (the Model column of each,
// core/model/model.h):
// clang-format off
//   rotation     ω_tc   3    Model::rotations.col(View(t, c))
//   translation  T_tc   2    Model::translations.col(View(t, c))  (input units)
//   weights      l_t    K    Model::weights.col(t)
//   basis        b_p    3K   Model::basis.col(p) = [S_1[:,p]; …; S_K[:,p]]
//   scale        s_tc   1    Model::scales(View(t, c)), only for cameras c ≥ 1
//                            of multi-camera data; otherwise s_tc = 1 and the
//                            block does not exist.
// clang-format on
//
// ReprojectionError<K> fixes K at compile time (fixed-size Jets);
// DynamicReprojectionError takes K at run time (any K).
//
// These functors are the tests' oracle of the residual and its Jacobian: the
// library has one reprojection Jacobian, the hand-written one of
// problems/reprojection_cost_function.h, which the tests compare with these
// (ReprojectionError<K> for a few K: each K costs compile time), and
// nrsfm_residual_benchmark times against them (docs/performance.md).
#ifndef NRSFM_TESTS_PROBLEMS_REPROJECTION_ERROR_ORACLE_H_
#define NRSFM_TESTS_PROBLEMS_REPROJECTION_ERROR_ORACLE_H_

#include <ceres/autodiff_cost_function.h>
#include <ceres/dynamic_autodiff_cost_function.h>
#include <ceres/rotation.h>
#include <glog/logging.h>

#include <Eigen/Core>

namespace nrsfm {

namespace internal {

// r = sqrt_weight · (scale · Π R(rotation) Σ_k weights[k] basis[3k:3k+3]
//                    + translation − observation); `scale` may be nullptr (1).
template <typename T>
void EvaluateReprojection(int num_bases, const double observation[2],
                          double sqrt_weight, const T* rotation,
                          const T* translation, const T* weights,
                          const T* basis, const T* scale, T* residuals) {
  T point[3] = {T(0.0), T(0.0), T(0.0)};
  for (int k = 0; k < num_bases; ++k) {
    point[0] += weights[k] * basis[3 * k + 0];
    point[1] += weights[k] * basis[3 * k + 1];
    point[2] += weights[k] * basis[3 * k + 2];
  }
  T rotated[3];
  ceres::AngleAxisRotatePoint(rotation, point, rotated);
  for (int i = 0; i < 2; ++i) {
    const T projected = scale == nullptr ? rotated[i] : scale[0] * rotated[i];
    residuals[i] = sqrt_weight * (projected + translation[i] - observation[i]);
  }
}

}  // namespace internal

// K known at compile time. Blocks: rotation (3), translation (2), weights (K),
// basis (3K) and, in the scaled form, scale (1).
template <int K>
class ReprojectionError {
 public:
  static_assert(K >= 1, "K must be at least 1");

  ReprojectionError(const Eigen::Vector2d& observation, double sqrt_weight)
      : observation_{observation.x(), observation.y()},
        sqrt_weight_(sqrt_weight) {}

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* weights,
                  const T* basis, T* residuals) const {
    internal::EvaluateReprojection(K, observation_, sqrt_weight_, rotation,
                                   translation, weights, basis,
                                   static_cast<const T*>(nullptr), residuals);
    return true;
  }

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* weights,
                  const T* basis, const T* scale, T* residuals) const {
    internal::EvaluateReprojection(K, observation_, sqrt_weight_, rotation,
                                   translation, weights, basis, scale,
                                   residuals);
    return true;
  }

  // Camera without a scale block (monocular, or camera 0).
  static ceres::CostFunction* Create(const Eigen::Vector2d& observation,
                                     double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<ReprojectionError, 2, 3, 2, K,
                                           3 * K>(
        new ReprojectionError(observation, sqrt_weight));
  }
  // Camera c ≥ 1 of multi-camera data: the extra scale block.
  static ceres::CostFunction* CreateScaled(const Eigen::Vector2d& observation,
                                           double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<ReprojectionError, 2, 3, 2, K, 3 * K,
                                           1>(
        new ReprojectionError(observation, sqrt_weight));
  }

 private:
  double observation_[2];
  double sqrt_weight_;
};

// Any K ≥ 1 at run time. Same blocks and
// order as ReprojectionError<K>.
class DynamicReprojectionError {
 public:
  DynamicReprojectionError(int num_bases, bool with_scale,
                           const Eigen::Vector2d& observation,
                           double sqrt_weight)
      : num_bases_(num_bases),
        with_scale_(with_scale),
        observation_{observation.x(), observation.y()},
        sqrt_weight_(sqrt_weight) {
    CHECK_GE(num_bases, 1);
  }

  template <typename T>
  bool operator()(T const* const* parameters, T* residuals) const {
    internal::EvaluateReprojection(
        num_bases_, observation_, sqrt_weight_, parameters[0], parameters[1],
        parameters[2], parameters[3], with_scale_ ? parameters[4] : nullptr,
        residuals);
    return true;
  }

  static ceres::CostFunction* Create(int num_bases, bool with_scale,
                                     const Eigen::Vector2d& observation,
                                     double sqrt_weight) {
    // Stride 8: derivatives in passes of 8 parameters.
    auto* cost =
        new ceres::DynamicAutoDiffCostFunction<DynamicReprojectionError, 8>(
            new DynamicReprojectionError(num_bases, with_scale, observation,
                                         sqrt_weight));
    cost->AddParameterBlock(3);
    cost->AddParameterBlock(2);
    cost->AddParameterBlock(num_bases);
    cost->AddParameterBlock(3 * num_bases);
    if (with_scale) cost->AddParameterBlock(1);
    cost->SetNumResiduals(2);
    return cost;
  }

 private:
  int num_bases_;
  bool with_scale_;
  double observation_[2];
  double sqrt_weight_;
};

}  // namespace nrsfm

#endif  // NRSFM_TESTS_PROBLEMS_REPROJECTION_ERROR_ORACLE_H_
